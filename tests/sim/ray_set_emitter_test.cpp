#include "sim/ray_set_emitter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "sim/emission.h"
#include "sim/random.h"

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

TEST(RaySetSampler, EmissionDrawsFromTheSetAndOversamplingIsFound) {
  SceneDesc scene;
  Emitter e;
  e.kind = Emitter::Kind::RaySet;
  e.name = "led";
  e.flux_lm = 8.0;
  e.rays = three_rays();
  scene.emitters.push_back(e);
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

}  // namespace
}  // namespace gonio::sim
