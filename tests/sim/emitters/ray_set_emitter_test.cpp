#include "sim/emitters/ray_set_emitter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "sim/emitters/emission.h"
#include "sim/samplers/random.h"
#include "sim/simulation.h"
#include "tests/sim/scenes.h"

namespace gonio::sim {
namespace {

// Three rays of flux 1, 2 and 5 lm.
std::shared_ptr<RaySet> three_rays() {
  auto r = std::make_shared<RaySet>();
  r->position_m = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}};
  r->direction = {{0.0f, 0.0f, 1.0f}, {0.0f, 1.0f, 0.0f}, {1.0f, 0.0f, 0.0f}};
  r->flux_lm = {1.0f, 2.0f, 5.0f};
  return r;
}

TEST(RaySetSampler, DrawsRaysInProportionToFlux) {
  auto s = make_ray_set_sampler(three_rays());
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_DOUBLE_EQ(s->total_flux_lm(), 8.0);
  // Kish: 8² / (1 + 4 + 25).
  EXPECT_NEAR(s->effective_ray_count(), 64.0 / 30.0, 1e-12);
  // Evenly spaced u: each ray's share of [0, 1) is its flux share.
  const int n = 80000;
  int counts[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i) {
    const RaySetSampler::Sample x = s->sample((i + 0.5) / n);
    ++counts[x.ray];
    if (x.ray == 1) {
      EXPECT_EQ(x.position.x, 1.0);
      EXPECT_EQ(x.direction.y, 1.0);
    }
  }
  EXPECT_NEAR(counts[0] / double(n), 1.0 / 8.0, 1e-3);
  EXPECT_NEAR(counts[1] / double(n), 2.0 / 8.0, 1e-3);
  EXPECT_NEAR(counts[2] / double(n), 5.0 / 8.0, 1e-3);
}

TEST(RaySetSampler, RefusesBrokenSets) {
  auto r = three_rays();
  r->flux_lm[1] = -1.0f;
  EXPECT_FALSE(make_ray_set_sampler(r).ok());
  r = three_rays();
  r->direction[0] = {0.0f, 0.0f, 2.0f};
  EXPECT_FALSE(make_ray_set_sampler(r).ok());
  r = three_rays();
  r->flux_lm = {0.0f, 0.0f, 0.0f};
  EXPECT_FALSE(make_ray_set_sampler(r).ok());
  EXPECT_FALSE(make_ray_set_sampler(std::make_shared<RaySet>()).ok());
}

// A scene of the three rays as one ray-set emitter of 8 lm.
SceneDesc three_ray_scene() {
  SceneDesc scene;
  Emitter e;
  e.kind = Emitter::Kind::RaySet;
  e.name = "led";
  e.flux_lm = 8.0;
  e.rays = three_rays();
  scene.emitters.push_back(e);
  return scene;
}

TEST(RaySetSampler, EmissionDrawsFromTheSetAndOversamplingIsFound) {
  const SceneDesc scene = three_ray_scene();
  auto emission = EmissionSampler::create(scene);
  ASSERT_TRUE(emission.ok()) << emission.error().message;
  PhotonRandom rng(1, 2);
  const EmittedPhoton p = emission->sample(rng);
  EXPECT_NEAR(length(p.direction), 1.0, 1e-12);
  EXPECT_FALSE(p.on_surface);
  // N_eff = 2.13: 2 photons are fine, 3 are not.
  EXPECT_TRUE(ray_set_photon_findings(scene, 2).empty());
  const auto findings = ray_set_photon_findings(scene, 3);
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_EQ(findings[0].code, "ray-set-oversampled");
}

// Issue 34, case 8 (flux-proportional drawing), a check independent of the
// sampler test above (which feeds the alias table evenly spaced u): a whole
// simulation of the three rays, photons drawn with the run's own random
// numbers, binned into the far field. Each ray points into its own texel;
// its texel holds N·φ_i/Σφ photons (binomial, within 5σ) and its flux
// φ_i (the far field's lumens). Drawing rays evenly would give each a third.
TEST(RaySetSampler, SimulatedFarFieldHoldsEachRaysShareOfTheFlux) {
  const SceneDesc scene = three_ray_scene();
  auto sim = simulate(scene, test_scenes::small_run(2, 40000, 2, 3));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const FarField f = sim->far_field();
  const double n = 80000.0;
  const double share[3] = {1.0 / 8.0, 2.0 / 8.0, 5.0 / 8.0};
  double total = 0.0;
  for (int r = 0; r < 3; ++r) {
    const Vec3f d = scene.emitters[0].rays->direction[static_cast<std::size_t>(r)];
    const std::size_t texel = f.grid().texel_of(to_double(d));
    const double photons = static_cast<double>(f.photons(texel));
    const double sigma = std::sqrt(n * share[r] * (1.0 - share[r]));
    EXPECT_NEAR(photons, n * share[r], 5.0 * sigma) << "ray " << r;
    EXPECT_NEAR(f.flux_lm(texel), 8.0 * share[r], 8.0 * 5.0 * sigma / n) << "ray " << r;
    total += photons;
  }
  EXPECT_EQ(total, n) << "every photon in one of the three texels";
}

}  // namespace
}  // namespace gonio::sim
