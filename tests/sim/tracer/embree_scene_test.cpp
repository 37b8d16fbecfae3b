#include "sim/tracer/embree_scene.h"

#include <gtest/gtest.h>
#include <sys/prctl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

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

// The packet query answers as the single-ray one, ray by ray, for every
// count (a partial last packet, masked lanes) and for rays that start on a
// surface, graze it or stop short of it (t_far). Mistakes it catches: a lane
// read from the wrong ray, an inactive lane's answer written back, tfar's
// "occluded" sign read the wrong way round, a packet wider than the buffer.
TEST(EmbreeScene, PacketsOfShadowRaysAnswerAsSingleRays) {
  Mesh a = sphere(1.0, 24, 12);
  Mesh b = box(0.5, 0.2, 0.5);
  transform(b, translation({0.3, 1.4, -0.2}));
  Mesh c = disc(0.8, 16);
  transform(c, translation({0.0, -1.6, 0.0}));
  // Every width this CPU runs (GONIO_PACKET_WIDTH caps it, for
  // measurement), each against single rays.
  for (const char* cap : {"", "8", "4", "1"}) {
    setenv("GONIO_PACKET_WIDTH", cap, 1);
    auto scene = EmbreeScene::build({a, b, c});
    unsetenv("GONIO_PACKET_WIDTH");
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    EXPECT_TRUE(scene->packet_width() == 1 || scene->packet_width() == 4 || scene->packet_width() == 8 ||
                scene->packet_width() == 16);
    if (*cap) {
      EXPECT_LE(scene->packet_width(), std::atoi(cap));
    }
    SCOPED_TRACE(scene->packet_width());

    std::uint64_t state = 12345;
    const auto uniform = [&state] {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      return static_cast<double>(state >> 11) * 0x1.0p-53;
    };
    std::vector<RayQuery> rays;
    for (int i = 0; i < 1000; ++i) {
      // Origins in a box around the scene, directions uniform; a fifth of the
      // rays limited to a random length.
      const Vec3 o{4.0 * uniform() - 2.0, 4.0 * uniform() - 2.0, 4.0 * uniform() - 2.0};
      const double z = 2.0 * uniform() - 1.0, phi = 6.283185307179586 * uniform();
      const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
      RayQuery q = ray_query(o, {r * std::cos(phi), r * std::sin(phi), z});
      if (i % 5 == 0) q.t_far = static_cast<float>(2.0 * uniform());
      rays.push_back(q);
    }
    std::size_t hits = 0;
    for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{3}, std::size_t{4}, std::size_t{7},
                                std::size_t{8}, std::size_t{15}, std::size_t{16}, std::size_t{17}, std::size_t{64},
                                std::size_t{1000}}) {
      std::vector<std::uint8_t> got(n + 1, 7);  // one past the end must stay untouched
      scene->occluded(rays.data(), n, got.data());
      for (std::size_t i = 0; i < n; ++i) {
        const bool one = scene->occluded(rays[i]);
        ASSERT_EQ(got[i], one ? 1 : 0) << "ray " << i << " of " << n;
        if (n == 1000 && one) ++hits;
      }
      EXPECT_EQ(got[n], 7) << n;
    }
    // Both answers occur (a test where every ray hits or none would not see a
    // lane mix-up).
    EXPECT_GT(hits, 100u);
    EXPECT_LT(hits, 900u);
  }
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
