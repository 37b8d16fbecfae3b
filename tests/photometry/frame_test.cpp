#include "photometry/frame.h"

#include <gtest/gtest.h>

#include <numbers>

namespace gonio::photometry {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

void expect_near(const Vec3& a, const Vec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-12);
  EXPECT_NEAR(a.y, b.y, 1e-12);
  EXPECT_NEAR(a.z, b.z, 1e-12);
}

TEST(Frame, DefaultGltfFrame) {
  const PhotometricFrame f;
  // Nadir −Y, C0 +X, C90 −Z.
  expect_near(f.to_world(direction_from_c_gamma(0.0, 0.0)), {0, -1, 0});
  expect_near(f.to_world(direction_from_c_gamma(0.0, 90 * kDeg)), {1, 0, 0});
  expect_near(f.to_world(direction_from_c_gamma(90 * kDeg, 90 * kDeg)), {0, 0, -1});
  expect_near(f.to_world(direction_from_c_gamma(0.0, 180 * kDeg)), {0, 1, 0});
  expect_near(cross(f.c0, f.c90), f.up);
}

TEST(Frame, CGammaRoundTrip) {
  for (double c = 0; c < 360; c += 15) {
    for (double g = 5; g < 180; g += 12.5) {
      const CGamma a = c_gamma_from_direction(direction_from_c_gamma(c * kDeg, g * kDeg));
      EXPECT_NEAR(a.c_rad, c * kDeg, 1e-12);
      EXPECT_NEAR(a.gamma_rad, g * kDeg, 1e-12);
    }
  }
  EXPECT_NEAR(c_gamma_from_direction({0, 0, -2}).gamma_rad, 0.0, 1e-15);
  EXPECT_NEAR(c_gamma_from_direction({0, 0, 3}).gamma_rad, std::numbers::pi, 1e-15);
}

TEST(Frame, CountsCounterClockwiseSeenFromAbove) {
  // Seen from above (looking down −up), C0 → C90 turns counter-clockwise:
  // (c0 × c90) points up, towards the viewer.
  const PhotometricFrame f = make_frame({0, 0, 1}, {1, 0, 0});
  expect_near(f.c90, {0, 1, 0});
  const PhotometricFrame g = make_frame({0, 1, 0}, {1, 0.3, 0});  // C0 not orthogonal
  EXPECT_NEAR(dot(g.c0, g.up), 0.0, 1e-15);
  expect_near(g.c90, {0, 0, -1});
}

}  // namespace
}  // namespace gonio::photometry
