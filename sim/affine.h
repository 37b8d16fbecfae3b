// Affine maps of 3D space (p ↦ L·p + offset): how shapes built around the
// origin are placed in a scene. Header-only plain data.
#pragma once

#include <cmath>

#include "photometry/vec3.h"

namespace gonio::sim {

struct Affine {
  double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // linear part, row-major
  Vec3 offset;                                          // translation [m]

  Vec3 linear(const Vec3& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  Vec3 point(const Vec3& p) const { return linear(p) + offset; }

  bool finite() const {
    for (const auto& row : m)
      for (double v : row)
        if (!std::isfinite(v)) return false;
    return std::isfinite(offset.x) && std::isfinite(offset.y) && std::isfinite(offset.z);
  }

  double determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
  // How normals transform: the inverse transpose of the linear part, up to
  // the positive factor |det| (normals are renormalised after it).
  Vec3 normal(const Vec3& n) const {
    // Cofactor matrix = det · inverse transpose.
    const double c[3][3] = {
        {m[1][1] * m[2][2] - m[1][2] * m[2][1], m[1][2] * m[2][0] - m[1][0] * m[2][2],
         m[1][0] * m[2][1] - m[1][1] * m[2][0]},
        {m[0][2] * m[2][1] - m[0][1] * m[2][2], m[0][0] * m[2][2] - m[0][2] * m[2][0],
         m[0][1] * m[2][0] - m[0][0] * m[2][1]},
        {m[0][1] * m[1][2] - m[0][2] * m[1][1], m[0][2] * m[1][0] - m[0][0] * m[1][2],
         m[0][0] * m[1][1] - m[0][1] * m[1][0]}};
    const double s = determinant() < 0.0 ? -1.0 : 1.0;
    return Vec3{c[0][0] * n.x + c[0][1] * n.y + c[0][2] * n.z,
                c[1][0] * n.x + c[1][1] * n.y + c[1][2] * n.z,
                c[2][0] * n.x + c[2][1] * n.y + c[2][2] * n.z} *
           s;
  }
};

// a ∘ b: first b, then a.
inline Affine operator*(const Affine& a, const Affine& b) {
  Affine r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
  r.offset = a.point(b.offset);
  return r;
}

inline Affine translation(const Vec3& t) {
  Affine a;
  a.offset = t;
  return a;
}

inline Affine scaling(double sx, double sy, double sz) {
  Affine a;
  a.m[0][0] = sx;
  a.m[1][1] = sy;
  a.m[2][2] = sz;
  return a;
}

// Right-handed rotation by `angle_rad` about `axis` (need not be unit).
inline Affine rotation(const Vec3& axis, double angle_rad) {
  const Vec3 u = normalize(axis);
  const double c = std::cos(angle_rad), s = std::sin(angle_rad), t = 1.0 - c;
  Affine a;
  a.m[0][0] = c + u.x * u.x * t;
  a.m[0][1] = u.x * u.y * t - u.z * s;
  a.m[0][2] = u.x * u.z * t + u.y * s;
  a.m[1][0] = u.y * u.x * t + u.z * s;
  a.m[1][1] = c + u.y * u.y * t;
  a.m[1][2] = u.y * u.z * t - u.x * s;
  a.m[2][0] = u.z * u.x * t - u.y * s;
  a.m[2][1] = u.z * u.y * t + u.x * s;
  a.m[2][2] = c + u.z * u.z * t;
  return a;
}

}  // namespace gonio::sim
