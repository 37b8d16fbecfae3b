// The whole pipeline on a bare emitter with a measured, asymmetric profile:
// photons → far field → resampled Type C table → IES and LDT files → read
// back. The files must give back the profile (VALIDATION.md: "bare emitter
// with a measured profile P: the output reproduces P and its flux").
// Slow: ctest label `validation`.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>

#include "io/ies.h"
#include "io/ldt.h"
#include "photometry/compare.h"
#include "photometry/flux.h"
#include "sim/simulation.h"
#include "tests/support/photometry_fixtures.h"
#include "tests/support/test_support.h"
#include "tools/simulation_outputs.h"

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
  }
  for (const WrittenFile& f : result->files) {
    EXPECT_TRUE(f.clean()) << f.path;
    EXPECT_LT(std::abs(f.flux_difference), 0.005) << f.path;
  }
}

}  // namespace
}  // namespace gonio::cli
