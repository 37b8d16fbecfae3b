#include "sim/convergence.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <vector>

namespace gonio::sim {
namespace {

constexpr int kFace = 32;

std::shared_ptr<const Resampler> resampler() {
  static const auto r =
      std::make_shared<const Resampler>(kFace, photometry::PhotometricFrame{}, CGammaGrid{10.0, 10.0});
  return r;
}

// A far field of intensity f(direction) [cd] per texel centre; `photons`
// per texel (0: an exact map without photon statistics).
FarField map_of(const std::function<double(const Vec3&)>& f, std::uint64_t photons = 0) {
  FarField m(kFace);
  for (std::size_t t = 0; t < m.texel_count(); ++t)
    m.add(t, f(m.grid().texel_direction(t)) * m.grid().texel_solid_angle(t), photons);
  return m;
}

double lobe(const Vec3& d) { return 100.0 + 400.0 * std::max(0.0, -d.y) * std::max(0.0, -d.y); }

// Photons of equal power w [lm], Poisson in number, from intensity f [cd].
FarField poisson_map(const std::function<double(const Vec3&)>& f, double photon_lm, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  FarField m(kFace);
  for (std::size_t t = 0; t < m.texel_count(); ++t) {
    const double mean = f(m.grid().texel_direction(t)) * m.grid().texel_solid_angle(t) / photon_lm;
    const auto n = std::poisson_distribution<std::uint64_t>(mean)(rng);
    m.add(t, static_cast<double>(n) * photon_lm, n);
  }
  return m;
}

ConvergenceReference make(const FarField& reference) {
  auto r = ConvergenceReference::create(reference, resampler());
  EXPECT_TRUE(r.ok());
  return std::move(r.value());
}

TEST(Convergence, ADarkReferenceIsAnError) {
  EXPECT_FALSE(ConvergenceReference::create(FarField(kFace), resampler()).ok());
}

TEST(Convergence, MeanScalingIgnoresTheScaleButTheTableDoesNot) {
  const FarField exact = map_of(lobe);
  const ConvergenceReference ref = make(exact);
  EXPECT_EQ(ref.cube_map_noise(), 0.0);
  std::vector<double> x = texel_intensities(exact);
  for (double& v : x) v *= 1.02;
  const CubeMapError e = ref.cube_map_error(x);
  EXPECT_LT(e.raw_mse, 1e-28);
  EXPECT_TRUE(std::isnan(e.rmse) || e.rmse < 1e-13);
  // The reference itself: nothing left to see, so no number (never +∞ dB).
  const CubeMapError same = ref.cube_map_error(texel_intensities(exact));
  EXPECT_EQ(same.raw_mse, 0.0);
  EXPECT_TRUE(std::isnan(same.rmse) && std::isnan(same.psnr_db) && std::isnan(same.snr_db));
  const TableError t = ref.table_error(x);
  EXPECT_NEAR(t.flux_pct, 2.0, 1e-9);
  // 2 % of every bin: 2 % of the peak at the peak.
  EXPECT_NEAR(t.max_pct, 2.0, 1e-9);
  // 2 % × the RMS of R over the sphere, relative to its peak.
  double sum = 0.0, omega = 0.0;
  for (std::size_t b = 0; b < ref.table().flux_lm.size(); ++b) {
    sum += ref.table().solid_angle_sr[b] * std::pow(ref.table().intensity_cd(b), 2);
    omega += ref.table().solid_angle_sr[b];
  }
  EXPECT_NEAR(t.rms_pct, 2.0 * std::sqrt(sum / omega) / ref.peak_cd(), 1e-9);
}

// Flat reference, a map of ±δ in a checkerboard (mean unchanged):
// RMSE = δ, PSNR = SNR = −20 log10 δ.
TEST(Convergence, ClosedFormsOfAFlatReference) {
  const ConvergenceReference ref = make(map_of([](const Vec3&) { return 5.0; }));
  const double delta = 0.03;
  std::vector<double> x(ref.far_field().texel_count());
  for (std::size_t t = 0; t < x.size(); ++t) {
    const std::size_t xy = t % (kFace * kFace);
    x[t] = 5.0 * (1.0 + (((xy / kFace) + (xy % kFace)) % 2 == 0 ? delta : -delta));
  }
  const CubeMapError e = ref.cube_map_error(x);
  EXPECT_NEAR(e.rmse, delta, 1e-12);
  EXPECT_NEAR(e.psnr_db, -20.0 * std::log10(delta), 1e-9);
  EXPECT_NEAR(e.snr_db, -20.0 * std::log10(delta), 1e-9);
  const TableError t = ref.table_error(x);
  EXPECT_NEAR(t.flux_pct, 0.0, 1e-9);
  EXPECT_LT(t.max_pct, 100.0 * delta);
}

// The reference's estimated noise ν is its real noise: an exact map scores
// raw MSE ≈ ν against a Poisson reference, and a noisy map of a quarter of
// the photons scores a corrected MSE of ≈ 4ν (its own noise alone).
TEST(Convergence, ReferenceNoiseIsEstimatedAndTakenOut) {
  const double photon_lm = 0.05;  // ~100 photons per texel on average
  const FarField noisy_ref = poisson_map(lobe, photon_lm, 1);
  const ConvergenceReference ref = make(noisy_ref);
  const double nu = std::pow(ref.cube_map_noise(), 2);
  ASSERT_GT(nu, 0.0);
  const CubeMapError exact = ref.cube_map_error(texel_intensities(map_of(lobe)));
  EXPECT_NEAR(exact.raw_mse / nu, 1.0, 0.08);

  double ratio = 0.0, table_ratio = 0.0;
  const int runs = 4;
  for (int k = 0; k < runs; ++k) {
    const FarField test = poisson_map(lobe, 4.0 * photon_lm, 100 + k);
    const CubeMapError e = ref.cube_map_error(texel_intensities(test));
    ratio += e.rmse * e.rmse / (4.0 * nu) / runs;
    // The table: the map's own binned variance predicts its corrected error.
    const BinnedField own = resampler()->bin(test);
    double v = 0.0, omega = 0.0;
    for (std::size_t b = 0; b < own.flux_lm.size(); ++b) {
      v += own.variance_lm2[b] / own.solid_angle_sr[b];
      omega += own.solid_angle_sr[b];
    }
    const double predicted_pct = 100.0 * std::sqrt(v / omega) / ref.peak_cd();
    const TableError t = ref.table_error(texel_intensities(test));
    table_ratio += std::pow(t.rms_pct / predicted_pct, 2) / runs;
  }
  EXPECT_NEAR(ratio, 1.0, 0.06);
  EXPECT_NEAR(table_ratio, 1.0, 0.15);
  EXPECT_GT(ref.table_noise_pct(), 0.0);
}

TEST(Convergence, LogLogSlope) {
  const std::vector<double> x = {1e3, 4e3, 1.6e4, 6.4e4};
  std::vector<double> y;
  for (double v : x) y.push_back(3.0 / std::sqrt(v));
  EXPECT_NEAR(log_log_slope(x, y), -0.5, 1e-12);
  // Points that a log cannot take are left out.
  std::vector<double> x2 = x, y2 = y;
  x2.push_back(0.0);
  y2.push_back(1.0);
  x2.push_back(1e5);
  y2.push_back(std::nan(""));
  EXPECT_NEAR(log_log_slope(x2, y2), -0.5, 1e-12);
  EXPECT_TRUE(std::isnan(log_log_slope(std::vector<double>{1.0}, std::vector<double>{1.0})));
  EXPECT_TRUE(std::isnan(log_log_slope(std::vector<double>{2.0, 2.0}, std::vector<double>{1.0, 3.0})));
}

TEST(Convergence, Crossing) {
  const std::vector<double> x = {1, 4, 16, 64};
  const std::vector<double> y = {1.0, 0.5, 0.25, 0.125};  // x^-1/2
  EXPECT_NEAR(crossing(x, y, 0.2), 25.0, 1e-9);
  EXPECT_EQ(crossing(x, y, 2.0), 1.0);
  EXPECT_TRUE(std::isnan(crossing(x, y, 0.1)));
  // A bump above the level after a dip: the last crossing counts.
  const std::vector<double> bumpy = {1.0, 0.15, 0.3, 0.1};
  EXPECT_GT(crossing(x, bumpy, 0.2), 16.0);
  // NaN (lost in the reference's noise) counts as below.
  const std::vector<double> lost = {1.0, 0.5, std::nan(""), std::nan("")};
  EXPECT_EQ(crossing(x, lost, 0.2), 16.0);
}

}  // namespace
}  // namespace gonio::sim
