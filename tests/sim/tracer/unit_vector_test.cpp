#include "sim/tracer/unit_vector.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace gonio::sim {
namespace {

double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(length(cross(a, b)), dot(a, b));
}

// Over a million directions uniform on the sphere, the decoded vector is a
// unit vector within 7e-5 rad of the original (measured: 6.4e-5 at worst,
// 2.3e-5 on average; half the 16-bit grid's spacing on the octahedron,
// 1/32767 in a coordinate, stretched by at most ~2 onto the sphere).
TEST(UnitVector, RoundTripIsWithinTheGridsSpacing) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g;
  double worst = 0.0, sum = 0.0;
  const int n = 1'000'000;
  for (int k = 0; k < n; ++k) {
    Vec3 v{g(rng), g(rng), g(rng)};
    v = v * (1.0 / length(v));
    const Vec3 back = unpack_unit(pack_unit(v.x, v.y, v.z));
    EXPECT_NEAR(length(back), 1.0, 1e-15);
    const double a = angle_between(v, back);
    worst = std::max(worst, a);
    sum += a;
  }
  EXPECT_LT(worst, 7e-5);
  EXPECT_LT(sum / n, 2.6e-5);
  EXPECT_GT(worst, 1e-6);  // it is a 32-bit code, not the float vector
}

// The axes, and the edges where the lower half folds over the upper, come
// back exactly; the length of the input does not matter.
TEST(UnitVector, AxesAndFoldEdgesAreExact) {
  const Vec3 axes[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const Vec3& a : axes) {
    for (double scale : {1.0, 1e-30, 3e20}) {
      const Vec3 back = unpack_unit(pack_unit(scale * a.x, scale * a.y, scale * a.z));
      EXPECT_EQ(back.x, a.x);
      EXPECT_EQ(back.y, a.y);
      EXPECT_EQ(back.z, a.z);
    }
  }
  // On the equator z = 0 both halves meet: the code is the same either way.
  const double s = std::sqrt(0.5);
  const PackedUnit up = pack_unit(s, s, 0.0), down = pack_unit(s, s, -0.0);
  EXPECT_EQ(up.x, down.x);
  EXPECT_EQ(up.y, down.y);
  EXPECT_LT(angle_between(unpack_unit(up), {s, s, 0.0}), 1e-4);
}

// Zero and non-finite vectors have their own code, which decodes to zero:
// the tracer's "no usable normal here" stays visible.
TEST(UnitVector, ZeroAndNonFiniteDecodeToZero) {
  for (const Vec3& v : {Vec3{0, 0, 0}, Vec3{NAN, 0, 1}, Vec3{INFINITY, 0, 0}}) {
    const Vec3 back = unpack_unit(pack_unit(v.x, v.y, v.z));
    EXPECT_EQ(back.x, 0.0);
    EXPECT_EQ(back.y, 0.0);
    EXPECT_EQ(back.z, 0.0);
  }
  // No unit vector takes the zero code.
  const PackedUnit p = pack_unit(-1.0, -1e-9, -1e-9);
  EXPECT_FALSE(p.x == kPackedZero && p.y == kPackedZero);
  EXPECT_GT(length(unpack_unit(p)), 0.5);
}

}  // namespace
}  // namespace gonio::sim
