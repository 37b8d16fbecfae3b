#include "sim/detectors/cube_map.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

namespace gonio::sim {
namespace {

constexpr double kFourPi = 4.0 * std::numbers::pi;

TEST(CubeMap, FacesFollowOpenExrLayout) {
  // Face centres and the top-left corner of each face, as OpenEXR's
  // CubeMap::direction gives them (checked against libOpenEXR 3.1).
  const Vec3 centres[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const Vec3 top_left[6] = {{1, 1, -1}, {-1, 1, 1}, {-1, 1, 1}, {-1, -1, -1}, {1, 1, 1}, {-1, 1, -1}};
  for (int f = 0; f < 6; ++f) {
    EXPECT_EQ(CubeMapGrid::direction(f, 0, 0), centres[f]) << "face " << f;
    EXPECT_EQ(CubeMapGrid::direction(f, -1, -1), top_left[f]) << "face " << f;
  }
}

TEST(CubeMap, LocateInvertsDirection) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int f = 0; f < 6; ++f) {
    for (int i = 0; i < 200; ++i) {
      const double a = u(rng) * 0.999, b = u(rng) * 0.999;
      const Vec3 d = CubeMapGrid::direction(f, a, b) * 3.7;
      const CubePoint p = CubeMapGrid::locate(d);
      ASSERT_EQ(p.face, f);
      EXPECT_NEAR(p.a, a, 1e-12);
      EXPECT_NEAR(p.b, b, 1e-12);
    }
  }
}

TEST(CubeMap, SolidAnglesSumToTheSphere) {
  for (int n : {1, 2, 3, 16, 64}) {
    CubeMapGrid g(n);
    double sum = 0.0;
    for (std::size_t t = 0; t < g.texel_count(); ++t) sum += g.texel_solid_angle(t);
    EXPECT_NEAR(sum, kFourPi, 1e-12) << "face size " << n;
  }
  EXPECT_NEAR(CubeMapGrid::solid_angle(-1, -1, 1, 1), kFourPi / 6.0, 1e-14);
}

TEST(CubeMap, CornerTexelsAreSmallerThanCentreTexels) {
  // The documented 5.2x spread of texel solid angles (3√3 in the limit).
  CubeMapGrid g(256);
  const double corner = g.texel_solid_angle(g.index(0, 0, 0));
  const double centre = g.texel_solid_angle(g.index(0, 128, 128));
  EXPECT_NEAR(centre / corner, 3.0 * std::sqrt(3.0), 0.05);
}

TEST(CubeMap, TexelOfTexelDirectionIsTheTexel) {
  CubeMapGrid g(32);
  for (std::size_t t = 0; t < g.texel_count(); ++t) ASSERT_EQ(g.texel_of(g.texel_direction(t)), t);
}

TEST(CubeMap, UniformDirectionsFillTexelsInProportionToSolidAngle) {
  // Monte Carlo check that texel_of and texel_solid_angle agree.
  CubeMapGrid g(4);
  std::vector<double> hits(g.texel_count(), 0.0);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  const int samples = 2'000'000;
  for (int i = 0; i < samples; ++i) hits[g.texel_of({n01(rng), n01(rng), n01(rng)})] += 1.0;
  for (std::size_t t = 0; t < g.texel_count(); ++t) {
    const double expected = samples * g.texel_solid_angle(t) / kFourPi;
    EXPECT_NEAR(hits[t], expected, 5.0 * std::sqrt(expected)) << "texel " << t;
  }
}

TEST(CubeMap, FaceSizeFromAngularStep) {
  // 2.5° steps need texels of at most 1.25°: 2·atan(1/n) <= 1.25° → n = 128.
  EXPECT_EQ(CubeMapGrid::face_size_for_step(2.5), 128);
  EXPECT_EQ(CubeMapGrid::face_size_for_step(5.0), 64);
  EXPECT_EQ(CubeMapGrid::face_size_for_step(90.0, 1.0), 1);
  EXPECT_EQ(CubeMapGrid::face_size_for_step(89.0, 1.0), 2);
}

}  // namespace
}  // namespace gonio::sim
