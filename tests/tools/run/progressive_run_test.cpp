// The progressive loop of simulate and watch: the error estimate against its
// closed form, the stop at a target error, cancellation between slices, and
// that slicing changes no photon.
#include "tools/run/progressive_run.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "sim/convergence.h"
#include "sim/detectors/resample.h"
#include "sim/scene.h"

namespace gonio::app {
namespace {

// A bare isotropic point lamp of 1000 lm: every bin b of the grid gets
// Poisson n_b photons of mean N Ω_b / 4π, so I_b = Φ n_b / (N Ω_b) has
// variance Φ² n_b / (N Ω_b)², and the estimate times I_max / (Φ / 4π) is
// 100 · √(B / N) for B bins (less where texels are shared between bins).
sim::SceneDesc bare_lamp() {
  sim::SceneDesc scene;
  scene.name = "bare lamp";
  sim::Emitter e;
  e.name = "lamp";
  e.flux_lm = 1000.0;
  scene.emitters.push_back(e);
  return scene;
}

sim::CGammaGrid coarse_grid() {
  sim::CGammaGrid g;
  g.c_step_deg = 10.0;
  g.gamma_step_deg = 10.0;
  return g;
}

ProgressiveSettings settings(std::uint64_t photons, int iterations, double target) {
  ProgressiveSettings s;
  s.simulation.photons_per_iteration = photons;
  s.simulation.iterations = iterations;
  s.simulation.threads = 2;
  s.simulation.face_size = 32;
  s.target_error_pct = target;
  return s;
}

TEST(ProgressiveRun, TheEstimateIsTheClosedFormOfABareLamp) {
  const auto resampler = std::make_shared<const sim::Resampler>(32, photometry::PhotometricFrame{}, coarse_grid());
  const double bins = static_cast<double>(coarse_grid().bin_count());
  const double mean_cd = 1000.0 / (4.0 * std::acos(-1.0));  // Φ / 4π
  std::vector<double> estimates, peaks;
  auto run = run_progressive(bare_lamp(), settings(1 << 18, 4, 0.0), resampler.get(),
                             [&](const IterationReport& r, const sim::Simulation& s) {
                               estimates.push_back(r.estimated_rms_error_pct);
                               auto self = sim::ConvergenceReference::create(s.far_field(), resampler);
                               peaks.push_back(self.ok() ? self->peak_cd() : 0.0);
                               return true;
                             });
  ASSERT_TRUE(run.ok()) << run.error().message;
  ASSERT_EQ(estimates.size(), 4u);
  for (std::size_t k = 0; k < estimates.size(); ++k) {
    // Relative to the mean intensity instead of the (noisy) largest bin:
    // 100 √(B / N) if photons were counted straight into bins. Texels on a
    // bin edge are shared by fraction f (Var ∝ Σ f² ≤ Σ f), which makes the
    // binned intensity a little less noisy: at face 32 and 10° bins about
    // 0.84 of the closed form, never above it.
    const double n = static_cast<double>((k + 1) << 18);
    const double closed = 100.0 * std::sqrt(bins / n);
    const double ratio = estimates[k] * peaks[k] / mean_cd / closed;
    EXPECT_GT(ratio, 0.75) << "iteration " << k + 1;
    EXPECT_LT(ratio, 1.0) << "iteration " << k + 1;
    EXPECT_GT(peaks[k], mean_cd) << "the largest bin is above the mean";
  }
  // 1/√N, up to the peak's own fall towards the mean: four times the
  // photons, half the error.
  EXPECT_NEAR(estimates[3] * peaks[3] / (estimates[0] * peaks[0]), 0.5, 0.03);
  EXPECT_EQ(run->stopped_by, StopReason::Iterations);
  EXPECT_EQ(run->iterations_done, 4);
  EXPECT_DOUBLE_EQ(run->estimated_rms_error_pct, estimates.back());
  EXPECT_DOUBLE_EQ(estimated_rms_error_pct(run->simulation.far_field(), *resampler), estimates.back());
}

// The true RMS candela error of a bare lamp's run (every bin's intensity is
// Φ / 4π: the resampler splits a texel's flux by overlap), relative to the
// run's own peak as the estimates are [%].
double bare_lamp_error_pct(const sim::FarField& field, const sim::Resampler& resampler) {
  const double mean_cd = 1000.0 / (4.0 * std::acos(-1.0));
  const sim::BinnedField t = resampler.bin(field);
  double sum = 0.0, omega = 0.0, peak = 0.0;
  for (std::size_t b = 0; b < t.flux_lm.size(); ++b) {
    if (!(t.solid_angle_sr[b] > 0.0)) continue;
    const double d = t.intensity_cd(b) - mean_cd;
    sum += t.solid_angle_sr[b] * d * d;
    omega += t.solid_angle_sr[b];
    peak = std::max(peak, t.intensity_cd(b));
  }
  return 100.0 * std::sqrt(sum / omega) / peak;
}

TEST(ProgressiveRun, UnderSobolTheReplicatesEstimateTheTrueError) {
  // Sobol' points spread a bare lamp's directions far more evenly than
  // independent photons: the count-based estimate (which assumes them)
  // over-states the error several times, the replicates' spread does not.
  // Mean squared errors over seeds, true (against Φ / 4π) and estimated.
  const sim::Resampler resampler(32, photometry::PhotometricFrame{}, coarse_grid());
  double true_sq = 0.0, estimate_sq = 0.0, counted_sq = 0.0;
  const int seeds = 8;
  for (int seed = 1; seed <= seeds; ++seed) {
    ProgressiveSettings s = settings(1 << 16, 1, 0.0);
    s.simulation.sampler = sim::SamplerKind::Sobol;
    s.simulation.seed = static_cast<std::uint64_t>(seed);
    auto run = run_progressive(bare_lamp(), s, &resampler);
    ASSERT_TRUE(run.ok()) << run.error().message;
    ASSERT_EQ(run->simulation.sobol_replicates(), sim::kSobolReplicates);
    const double truth = bare_lamp_error_pct(run->simulation.far_field(), resampler);
    true_sq += truth * truth;
    estimate_sq += run->estimated_rms_error_pct * run->estimated_rms_error_pct;
    const double counted = estimated_rms_error_pct(run->simulation.far_field(), resampler);
    counted_sq += counted * counted;
    EXPECT_DOUBLE_EQ(run->estimated_rms_error_pct, estimated_rms_error_pct(run->simulation, resampler));
  }
  const double ratio = std::sqrt(estimate_sq / true_sq), counted_ratio = std::sqrt(counted_sq / true_sq);
  EXPECT_GT(ratio, 0.8);
  EXPECT_LT(ratio, 1.25);
  EXPECT_GT(counted_ratio, 1.5) << "the count-based estimate would have done";
  // The random sampler keeps the count-based estimate, which is right there.
  true_sq = estimate_sq = 0.0;
  for (int seed = 1; seed <= seeds; ++seed) {
    ProgressiveSettings s = settings(1 << 16, 1, 0.0);
    s.simulation.seed = static_cast<std::uint64_t>(seed);
    auto run = run_progressive(bare_lamp(), s, &resampler);
    ASSERT_TRUE(run.ok());
    EXPECT_EQ(run->simulation.sobol_replicates(), 0);
    const double truth = bare_lamp_error_pct(run->simulation.far_field(), resampler);
    true_sq += truth * truth;
    estimate_sq += run->estimated_rms_error_pct * run->estimated_rms_error_pct;
  }
  EXPECT_NEAR(std::sqrt(estimate_sq / true_sq), 1.0, 0.2);
}

TEST(ProgressiveRun, TheReplicatesEstimateIsTheirStandardError) {
  // Two replicate tables of one bin each, intensities 1 and 3 cd, the whole
  // 2 cd: s² = 2, s² / K = 1, so 1 cd of error on a 2 cd peak: 50 %.
  sim::BinnedField whole, a, b;
  for (sim::BinnedField* t : {&whole, &a, &b}) t->solid_angle_sr = {0.5};
  whole.flux_lm = {1.0};
  a.flux_lm = {0.5};
  b.flux_lm = {1.5};
  const std::vector<sim::BinnedField> tables = {a, b};
  EXPECT_DOUBLE_EQ(replicate_table_error_pct(whole, tables), 50.0);
}

TEST(ProgressiveRun, StopsOnceTheEstimateIsUnderTheTarget) {
  const sim::Resampler resampler(32, photometry::PhotometricFrame{}, coarse_grid());
  std::vector<double> estimates;
  std::vector<double> time_left;
  const double target = 5.0;  // reached after 100 to 250 k photons (see above)
  auto run = run_progressive(bare_lamp(), settings(1 << 14, 1000, target), &resampler,
                             [&](const IterationReport& r, const sim::Simulation&) {
                               estimates.push_back(r.estimated_rms_error_pct);
                               time_left.push_back(r.progress.remaining_s);
                               return true;
                             });
  ASSERT_TRUE(run.ok());
  EXPECT_EQ(run->stopped_by, StopReason::TargetError);
  EXPECT_LE(run->estimated_rms_error_pct, target);
  ASSERT_GE(estimates.size(), 2u);
  EXPECT_GT(estimates[estimates.size() - 2], target) << "it ran past the iteration that reached the target";
  EXPECT_LT(estimates.size(), 1000u);
  EXPECT_EQ(run->iterations_done, static_cast<int>(estimates.size()));
  EXPECT_EQ(run->simulation.stats().photons, estimates.size() << 14);
  EXPECT_EQ(time_left.back(), 0.0);
}

TEST(ProgressiveRun, AFieldWithoutFluxHasNoEstimate) {
  // Nothing escaped: no peak to be relative to, NaN (a target never stops on it).
  const sim::Resampler resampler(32, photometry::PhotometricFrame{}, coarse_grid());
  sim::FarField empty(32);
  EXPECT_TRUE(std::isnan(estimated_rms_error_pct(empty, resampler)));
}

TEST(ProgressiveRun, CancelStopsBetweenSlicesAndSlicingChangesNoPhoton) {
  int asked = 0;
  auto cancelled = run_progressive(bare_lamp(), settings(5 * kCancelSlicePhotons, 3, 0.0), nullptr, {},
                                   [&] { return ++asked > 3; });
  ASSERT_TRUE(cancelled.ok());
  EXPECT_EQ(cancelled->stopped_by, StopReason::Cancelled);
  EXPECT_EQ(cancelled->simulation.stats().photons, 3 * kCancelSlicePhotons);
  EXPECT_EQ(cancelled->iterations_done, 0);

  // Sliced (a cancel check that never fires) against whole iterations: the
  // same far field, texel by texel.
  auto sliced = run_progressive(bare_lamp(), settings(200'000, 2, 0.0), nullptr, {}, [] { return false; });
  auto whole = run_progressive(bare_lamp(), settings(200'000, 2, 0.0), nullptr);
  ASSERT_TRUE(sliced.ok() && whole.ok());
  const sim::FarField a = sliced->simulation.far_field(), b = whole->simulation.far_field();
  ASSERT_EQ(a.texel_count(), b.texel_count());
  for (std::size_t t = 0; t < a.texel_count(); ++t) {
    ASSERT_EQ(a.photons(t), b.photons(t)) << t;
    ASSERT_EQ(a.flux_lm(t), b.flux_lm(t)) << t;
  }
  EXPECT_EQ(sliced->iterations_done, 2);
}

TEST(ProgressiveRun, ASmallFirstIterationKeepsThePlan) {
  ProgressiveSettings s = settings(100'000, 3, 0.0);
  s.first_iteration_photons = 10'000;
  std::vector<std::uint64_t> done;
  auto run = run_progressive(bare_lamp(), s, nullptr, [&](const IterationReport& r, const sim::Simulation&) {
    done.push_back(r.progress.photons_done);
    EXPECT_EQ(r.progress.photons_total, 210'000u);
    return true;
  });
  ASSERT_TRUE(run.ok());
  EXPECT_EQ(done, (std::vector<std::uint64_t>{10'000, 110'000, 210'000}));
}

}  // namespace
}  // namespace gonio::app
