// The peer's scenes rebuilt in Gonio (samples/peer_scenes.h) load as their
// facts say, and the LED-in-a-tube's light that leaves without touching the
// tube is the closed form: I0 = Φ / (2π (1 − cos 60°)) below γ = atan(25/50),
// nothing elsewhere.
#include "samples/peer_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "io/model/gltf.h"
#include "photometry/frame.h"
#include "sim/simulation.h"
#include "tests/support/test_support.h"

namespace gonio::samples {
namespace {

constexpr double kPi = std::numbers::pi;

class PeerScenes : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    const Status written = write_peer_samples(dir_->path().string());
    ASSERT_TRUE(written.ok()) << to_string(written.error());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static sim::SceneDesc load(std::vector<Finding>* findings) {
    const std::string path = (dir_->path() / "led-housing" / "led-housing.gltf").string();
    Result<sim::SceneDesc> scene = io::load_gltf(path, findings);
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : to_string(scene.error()));
    return scene.ok() ? std::move(scene).value() : sim::SceneDesc{};
  }
  static test::TempDir* dir_;
};
test::TempDir* PeerScenes::dir_ = nullptr;

TEST_F(PeerScenes, LedHousingLoadsAsItsFactsSay) {
  std::vector<Finding> findings;
  const sim::SceneDesc s = load(&findings);
  // The one finding: the cone's hard edge, which is meant.
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_EQ(findings[0].code, "spot-cone");
  EXPECT_EQ(findings[0].severity, Severity::Warning);

  ASSERT_EQ(s.emitters.size(), 1u);
  const sim::Emitter& e = s.emitters[0];
  EXPECT_EQ(e.kind, sim::Emitter::Kind::Point);
  EXPECT_NEAR(e.flux_lm, 1000.0, 1e-9);
  EXPECT_NEAR(length(e.position), 0.0, 1e-12);
  // Aimed at the nadir (−Y), C0 on +X.
  EXPECT_NEAR(e.frame.up.y, 1.0, 1e-12);
  EXPECT_NEAR(e.frame.c0.x, 1.0, 1e-12);
  ASSERT_TRUE(e.profile);
  EXPECT_NEAR(e.profile->candela.front(), 1000.0 / kPi, 1e-9);

  ASSERT_EQ(s.meshes.size(), 1u);
  double r_min = 1.0, r_max = 0.0, y_min = 1.0, y_max = -1.0;
  for (const auto& p : s.meshes[0].positions) {
    const double r = std::hypot(double(p.x), double(p.z));
    r_min = std::min(r_min, r);
    r_max = std::max(r_max, r);
    y_min = std::min(y_min, double(p.y));
    y_max = std::max(y_max, double(p.y));
  }
  EXPECT_NEAR(r_min, 0.025, 1e-7);
  EXPECT_NEAR(r_max, 0.025, 1e-7);
  EXPECT_NEAR(y_min, -0.050, 1e-7);
  EXPECT_NEAR(y_max, 0.0, 1e-7);
  const sim::Material& m = s.materials.at(s.meshes[0].material);
  EXPECT_DOUBLE_EQ(m.diffuse_reflect, 0.85);
  EXPECT_EQ(m.glossy + m.mirror + m.dielectric + m.diffuse_transmit, 0.0);
}

// The tube made black: what escapes is the direct part alone. Its flux is
// Φ (1 − cos 26.57°) / (1 − cos 60°) = 211.146 lm, and the far field's photon
// counts per texel follow the closed form's integral over each texel (χ²).
TEST_F(PeerScenes, LedHousingDirectPartIsTheClosedForm) {
  std::vector<Finding> findings;
  sim::SceneDesc s = load(&findings);
  ASSERT_EQ(s.meshes.size(), 1u);
  s.materials.at(s.meshes[0].material).diffuse_reflect = 0.0;

  const std::uint64_t photons = 1 << 18;
  sim::SimulationSettings settings;
  settings.photons_per_iteration = photons;
  settings.iterations = 1;
  settings.face_size = 16;
  settings.seed = 7;
  settings.threads = 2;
  settings.sampler = sim::SamplerKind::Random;
  auto run = sim::simulate(s, settings);
  ASSERT_TRUE(run.ok()) << run.error().message;
  const sim::FarField f = run->far_field();

  const LedHousing p;
  const double edge = std::atan(p.radius_m / p.length_m);
  const double direct_lm = 1000.0 * (1.0 - std::cos(edge)) / (1.0 - std::cos(kPi / 3));
  EXPECT_NEAR(direct_lm, 211.146, 0.001);
  const double share = direct_lm / 1000.0;
  // Binomial: 4σ of the escaped share.
  EXPECT_NEAR(f.total_flux_lm(), direct_lm, 4.0 * 1000.0 * std::sqrt(share * (1 - share) / photons));

  // Expected photons per texel: ∫ I dΩ over the texel / photon power, by 12 × 12 sub-rectangles.
  const sim::CubeMapGrid& grid = f.grid();
  const int n = grid.face_size(), k = 12;
  double chi2 = 0.0, pooled_observed = 0.0, pooled_expected = 0.0;
  int dof = 0;
  for (std::size_t t = 0; t < grid.texel_count(); ++t) {
    const int face = static_cast<int>(t / (n * n)), y = static_cast<int>(t % (n * n)) / n,
              x = static_cast<int>(t % (n * n)) % n;
    const double step = 2.0 / n / k;
    double lm = 0.0;
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        const double a0 = -1.0 + 2.0 * x / n + i * step, b0 = -1.0 + 2.0 * y / n + j * step;
        const Vec3 d = normalize(sim::CubeMapGrid::direction(face, a0 + 0.5 * step, b0 + 0.5 * step));
        const double gamma_deg = std::acos(std::clamp(-d.y, -1.0, 1.0)) * 180.0 / kPi;
        lm += led_housing_direct_cd(p, gamma_deg) * sim::CubeMapGrid::solid_angle(a0, b0, a0 + step, b0 + step);
      }
    const double expected = lm / (1000.0 / photons);
    const double observed = static_cast<double>(f.photons(t));
    if (expected < 20.0) {
      // Outside the direct cone (and the texels its rim cuts thinly): pooled.
      pooled_observed += observed;
      pooled_expected += expected;
      continue;
    }
    chi2 += (observed - expected) * (observed - expected) / expected;
    ++dof;
  }
  // The pool is mostly the upper hemisphere and the tube's shadow, where
  // nothing may arrive: its photons are those of the thin rim texels.
  EXPECT_LT(pooled_observed, pooled_expected + 5.0 * std::sqrt(pooled_expected) + 5.0);
  ASSERT_GT(dof, 20);
  const double reduced = chi2 / dof;
  EXPECT_LT(reduced, 1.0 + 5.0 * std::sqrt(2.0 / dof)) << "dof " << dof;
  EXPECT_GT(reduced, 1.0 - 5.0 * std::sqrt(2.0 / dof)) << "dof " << dof;
}

}  // namespace
}  // namespace gonio::samples
