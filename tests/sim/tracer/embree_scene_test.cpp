#include "sim/tracer/embree_scene.h"

#include <gtest/gtest.h>
#include <sys/prctl.h>

#include "sim/shapes.h"

namespace gonio::sim {
namespace {

TEST(EmbreeScene, HitsNameMeshTriangleDistanceAndFrontNormal) {
  Mesh a = disc(1.0, 8);  // y = 0, facing +Y
  Mesh b = box(1.0, 1.0, 1.0);
  transform(b, translation({0.0, 3.0, 0.0}));
  Mesh empty;
  auto scene = EmbreeScene::build({a, empty, b});
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  EXPECT_EQ(scene->triangle_count(), 8u + 12u);

  RayHit hit;
  ASSERT_TRUE(scene->intersect(ray_query({0.2, 1.0, 0.1}, {0, -1, 0}), &hit));
  EXPECT_EQ(hit.mesh, 0u);
  EXPECT_NEAR(hit.t, 1.0, 1e-6);
  // The normal points to the front (counter-clockwise) side: +Y.
  EXPECT_GT(hit.ng[1], 0.0f);
  EXPECT_NEAR(hit.ng[0], 0.0f, 1e-6);
  // Barycentrics locate the point on that triangle.
  const Vec3f p0 = a.positions[a.indices[3 * hit.triangle]];
  const Vec3f p1 = a.positions[a.indices[3 * hit.triangle + 1]];
  const Vec3f p2 = a.positions[a.indices[3 * hit.triangle + 2]];
  const float w = 1.0f - hit.u - hit.v;
  EXPECT_NEAR(w * p0.x + hit.u * p1.x + hit.v * p2.x, 0.2f, 1e-6);
  EXPECT_NEAR(w * p0.z + hit.u * p1.z + hit.v * p2.z, 0.1f, 1e-6);

  // From below the disc its front faces away; the box is mesh 2.
  ASSERT_TRUE(scene->intersect(ray_query({0.1, -1.0, 0.0}, {0, 1, 0}), &hit));
  EXPECT_EQ(hit.mesh, 0u);
  EXPECT_GT(hit.ng[1], 0.0f);  // still the front normal, now facing the ray's origin side away
  ASSERT_TRUE(scene->intersect(ray_query({0.0, 1.0, 0.0}, {0, 1, 0}), &hit));
  EXPECT_EQ(hit.mesh, 2u);
  EXPECT_NEAR(hit.t, 1.5, 1e-6);
  EXPECT_LT(hit.ng[1], 0.0f);  // the box's bottom face points down (outwards)

  EXPECT_FALSE(scene->intersect(ray_query({5.0, 1.0, 0.0}, {0, -1, 0}), &hit));
  RayQuery limited = ray_query({0.2, 1.0, 0.1}, {0, -1, 0});
  limited.t_far = 0.5f;
  EXPECT_FALSE(scene->intersect(limited, &hit));

  const Bounds& bb = scene->bounds();
  EXPECT_NEAR(bb.lower.y, 0.0, 1e-6);
  EXPECT_NEAR(bb.upper.y, 3.5, 1e-6);
  EXPECT_NEAR(bb.upper.x, 1.0, 1e-6);
}

TEST(EmbreeScene, RandomRayRateCountsHits) {
  // Random rays from inside a closed sphere always hit it.
  auto scene = EmbreeScene::build({sphere(1.0, 32, 16)});
  ASSERT_TRUE(scene.ok());
  const auto r = scene->measure_random_rays(20000, 1, 2);
  EXPECT_EQ(r.rays, 20000u);
  EXPECT_GT(r.hits, 0u);
  EXPECT_GT(r.rays_per_s(), 0.0);
  std::vector<RayQuery> rays(1000, ray_query({0, 0, 0}, {0, 1, 0}));
  EXPECT_EQ(scene->measure_rays(rays, 1).hits, 1000u);
}

// The quick tree for runs short for the model's size (fewer photons than
// half the unique triangles), the better one otherwise.
TEST(EmbreeScene, BvhQualityForTheRunsSize) {
  using Q = EmbreeSceneOptions::Quality;
  EXPECT_EQ(bvh_quality_for(1'000'000, 499'999), Q::Low);
  EXPECT_EQ(bvh_quality_for(1'000'000, 500'000), Q::High);
  EXPECT_EQ(bvh_quality_for(10'000'000, 10'000'000), Q::High);
  EXPECT_EQ(bvh_quality_for(0, 0), Q::High);
  EXPECT_STREQ(to_string(Q::Low), "low");
  EXPECT_STREQ(to_string(Q::Medium), "medium");
  EXPECT_STREQ(to_string(Q::High), "high");
}

// The quick tree is built with transparent huge pages off for the process
// (sim/tracer/embree_scene.cpp); whatever the setting was, it is that after.
TEST(EmbreeScene, BuildsLeaveTheProcesssHugePageSettingAsTheyFoundIt) {
  const int before = prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0);
  ASSERT_GE(before, 0);
  const Mesh b = box(1.0, 1.0, 1.0);
  for (int setting : {0, 1}) {
    ASSERT_EQ(prctl(PR_SET_THP_DISABLE, setting, 0, 0, 0), 0);
    for (auto quality : {EmbreeSceneOptions::Quality::Low, EmbreeSceneOptions::Quality::High}) {
      EmbreeSceneOptions options;
      options.quality = quality;
      auto scene = EmbreeScene::build({b}, options);
      ASSERT_TRUE(scene.ok());
      RayHit hit;
      EXPECT_TRUE(scene->intersect(ray_query({0.0, 0.0, -5.0}, {0, 0, 1}), &hit));
      EXPECT_EQ(prctl(PR_GET_THP_DISABLE, 0, 0, 0, 0), setting) << to_string(quality);
    }
  }
  prctl(PR_SET_THP_DISABLE, before, 0, 0, 0);
}

}  // namespace
}  // namespace gonio::sim
