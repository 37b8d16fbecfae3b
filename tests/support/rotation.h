// The turn of a `rotate_deg = [x, y, z]` key (fixed parts, placed lenses) as
// the design files define it, written out for tests independently of
// sim::Affine: about the fixed X axis first, then Y, then Z (R = Rz·Ry·Rx),
// angles in degrees.
#pragma once

#include <array>
#include <cmath>
#include <numbers>

#include "photometry/vec3.h"

namespace gonio::test {

using Matrix3 = std::array<std::array<double, 3>, 3>;

inline Matrix3 multiply(const Matrix3& a, const Matrix3& b) {
  Matrix3 c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
  return c;
}

inline Matrix3 rotation_xyz_deg(double x_deg, double y_deg, double z_deg) {
  const double ax = x_deg * std::numbers::pi / 180, ay = y_deg * std::numbers::pi / 180,
               az = z_deg * std::numbers::pi / 180;
  const Matrix3 rx = {{{1, 0, 0}, {0, std::cos(ax), -std::sin(ax)}, {0, std::sin(ax), std::cos(ax)}}};
  const Matrix3 ry = {{{std::cos(ay), 0, std::sin(ay)}, {0, 1, 0}, {-std::sin(ay), 0, std::cos(ay)}}};
  const Matrix3 rz = {{{std::cos(az), -std::sin(az), 0}, {std::sin(az), std::cos(az), 0}, {0, 0, 1}}};
  return multiply(rz, multiply(ry, rx));
}

inline Vec3 apply(const Matrix3& m, const Vec3& v) {
  return Vec3{m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
              m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

}  // namespace gonio::test
