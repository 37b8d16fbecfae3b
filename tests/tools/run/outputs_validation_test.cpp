// The whole pipeline on a bare emitter with a measured, asymmetric profile:
// photons → far field → resampled Type C table → IES and LDT files → read
// back. The files must give back the profile (VALIDATION.md: "bare emitter
// with a measured profile P: the output reproduces P and its flux").
// Slow: ctest label `validation`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>

#include "io/photometric/ies.h"
#include "io/photometric/ldt.h"
#include "photometry/compare.h"
#include "photometry/flux.h"
#include "sim/simulation.h"
#include "tests/support/photometry_fixtures.h"
#include "tests/support/test_support.h"
#include "tools/run/simulation_outputs.h"

namespace gonio::cli {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A downlight tilted towards C0 and narrower in C90 than in C0: no symmetry
// at all (the C0 side is brighter than C180, C90 than C270).
photometry::Distribution asymmetric_profile() {
  photometry::Distribution d = test::sample_c(
      photometry::Symmetry::None, test::angles(0, 360, 5), test::angles(0, 180, 2.5), [](double c, double g) {
        if (g >= 90.0) return 0.0;
        const double s = std::sin(g * kDeg), cg = std::cos(g * kDeg);
        return 800.0 * cg * (1.0 + 0.6 * s * std::cos(c * kDeg) + 0.25 * s * std::sin(c * kDeg)) *
               (1.0 - 0.3 * s * s * std::sin(c * kDeg) * std::sin(c * kDeg));
      });
  d.lamps = {photometry::LampSet{1, "LED", 2000.0, "", "", photometry::kNaN}};
  return d;
}

// The lit hemisphere (γ < 90°; the profile is 0 beyond) of a file against
// the profile, at the 5° × 2.5° grid's directions, each weighted by the
// solid angle of its bin (C ± 2.5°, γ ± 1.25°; at γ = 0 the cap), with what
// photon noise alone predicts: a bin expecting n = N · I · Ω / Φ photons has
// a relative standard deviation of 1/√n.
struct HemisphereErrors {
  double rms = 0.0;            // RMS of (I_file − I) / I_peak
  double predicted_rms = 0.0;  // RMS of (I / I_peak) / √n
  double max_relative = 0.0;   // largest |I_file / I − 1| where I > 10 % of the peak
  double max_z = 0.0;          // largest |I_file − I| / (I / √n) there
};

HemisphereErrors hemisphere_errors(const photometry::Distribution& profile, const photometry::Distribution& file,
                                   double photons) {
  const photometry::Distribution p = photometry::expand_symmetry(profile), f = photometry::expand_symmetry(file);
  const double flux = photometry::total_flux_lm(profile);
  double peak = 0.0;
  for (double v : profile.candela) peak = std::max(peak, v);
  const double dc = 5.0 * kDeg, half = 1.25 * kDeg;
  double sum_w = 0.0, sum_e2 = 0.0, sum_var = 0.0;
  HemisphereErrors out;
  for (double c = 0.0; c < 360.0; c += 5.0) {
    for (double g = 0.0; g < 90.0; g += 2.5) {
      const double ip = photometry::interpolate(p, c, g), ifile = photometry::interpolate(f, c, g);
      const double lo = std::max(0.0, g * kDeg - half), w = dc * (std::cos(lo) - std::cos(g * kDeg + half));
      const double omega = g == 0.0 ? 2.0 * std::numbers::pi * (1.0 - std::cos(half)) : w;  // the cap is one bin
      const double n = photons * ip * omega / flux;
      const double e = (ifile - ip) / peak;
      sum_w += w;
      sum_e2 += w * e * e;
      sum_var += w * (ip / peak) * (ip / peak) / n;
      if (ip > 0.1 * peak) {
        out.max_relative = std::max(out.max_relative, std::abs(ifile / ip - 1.0));
        out.max_z = std::max(out.max_z, std::abs(ifile - ip) / ip * std::sqrt(n));
      }
    }
  }
  out.rms = std::sqrt(sum_e2 / sum_w);
  out.predicted_rms = std::sqrt(sum_var / sum_w);
  return out;
}

TEST(OutputsValidation, ABareEmitterGivesBackItsProfileInBothFormats) {
  const photometry::Distribution profile = asymmetric_profile();
  const double flux = photometry::total_flux_lm(profile);
  sim::SceneDesc scene;
  scene.name = "bare";
  sim::Emitter e;
  e.name = "led";
  e.flux_lm = flux;
  e.profile = std::make_shared<photometry::Distribution>(profile);
  scene.emitters = {e};

  sim::SimulationSettings settings;
  settings.photons_per_iteration = 2'500'000;
  settings.iterations = 4;  // 10⁷ photons
  settings.face_size = 128;
  settings.threads = 0;
  auto simulation = sim::simulate(scene, settings);
  ASSERT_TRUE(simulation.ok()) << simulation.error().message;

  test::TempDir dir;
  OutputRequest req;
  req.directory = dir.path().string();
  req.stem = "bare";
  req.formats = {OutputFormat::Ies, OutputFormat::Ldt};
  req.run = {"test", "bare.gltf", 10'000'000, 1, 100, "2024-01-01"};
  auto result = write_outputs(simulation->far_field(), scene, simulation->ledger(), req);
  ASSERT_TRUE(result.ok()) << result.error().message;
  EXPECT_EQ(result->symmetry, photometry::Symmetry::None) << result->symmetry_reason;

  auto ies = io::read_ies((dir / "bare.ies").string());
  auto ldt = io::read_ldt((dir / "bare.ldt").string());
  ASSERT_TRUE(ies.ok() && ldt.ok());
  for (const photometry::Distribution* d : {&ies->distribution, &ldt->distribution}) {
    auto cmp = photometry::compare(profile, *d);
    ASSERT_TRUE(cmp.ok());
    std::printf("bare emitter, %s: RMS %.3f %%, max %.3f %% of the peak at C %g, gamma %g; flux ratio %.5f\n",
                d == &ies->distribution ? "IES" : "LDT", 100 * cmp->rms_relative, 100 * cmp->max_relative,
                cmp->max_at_c_deg, cmp->max_at_gamma_deg, cmp->flux_ratio);
    EXPECT_LT(cmp->rms_relative, 0.02);
    EXPECT_NEAR(cmp->flux_ratio, 1.0, 0.005);  // nothing absorbed: the profile's flux
    // The whole sphere's RMS counts the dark half's exact zeros; the lit
    // hemisphere alone holds the simulation to its photon noise, which falls
    // as 1/√N: 0.74 % of the peak at N = 10⁷ by the bins' expected counts.
    // Measured over 52 seeds: 0.82–0.89 × that (a bin shares its edge texels
    // with its neighbours, which averages part of its noise away), so any
    // error beyond noise, a bias of a fraction of a per cent, breaks the
    // upper bound, and averaging that should not happen (a symmetry) the
    // lower one. Where I > 10 % of the peak the worst bin was 8.8 % off its
    // intensity and 4.1 of its own standard deviations 1/√n (of at most 2592
    // bins a Gaussian puts one beyond 5σ in fewer than one run in 600).
    const HemisphereErrors h = hemisphere_errors(profile, *d, 1e7);
    std::printf("  lit hemisphere: RMS %.3f %% of the peak (photon noise predicts %.3f %%, ratio %.2f); where I > 10 %% "
                "of the peak, max %.2f %% of the local intensity, %.2f sigma\n",
                100 * h.rms, 100 * h.predicted_rms, h.rms / h.predicted_rms, 100 * h.max_relative, h.max_z);
    EXPECT_LT(h.rms, 0.008);
    EXPECT_LE(h.rms, 1.0 * h.predicted_rms);
    EXPECT_GE(h.rms, 0.7 * h.predicted_rms);
    EXPECT_LT(h.max_relative, 0.12);
    EXPECT_LT(h.max_z, 5.0);
  }
  for (const WrittenFile& f : result->files) {
    EXPECT_TRUE(f.clean()) << f.path;
    EXPECT_LT(std::abs(f.flux_difference), 0.005) << f.path;
  }
}

}  // namespace
}  // namespace gonio::cli
