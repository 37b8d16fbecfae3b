// Unit vectors in 32 bits: the octahedral map (Meyer et al. 2010; Cigolle
// et al., "A Survey of Efficient Representations for Independent Unit
// Vectors", JCGT 2014) with 16-bit signed coordinates. The tracer keeps its
// shading normals and tangents this way: 4 bytes a corner instead of 12.
//
// The direction v/|v| is projected onto the octahedron |x| + |y| + |z| = 1,
// whose lower half is folded over the upper; the two coordinates of the
// result in [-1, 1] are rounded to multiples of 1/32767. The largest angle
// between a unit vector and its decoded copy is 6.4e-5 rad (0.004°), far below
// what a shading normal can carry (tests/sim/tracer/unit_vector_test.cpp). A zero,
// or not finite, vector has its own code and decodes to zero, so that a
// caller can still tell "no normal" apart.
#pragma once

#include <cmath>
#include <cstdint>

#include "photometry/vec3.h"
#include "sim/scene.h"

namespace gonio::sim {

struct PackedUnit {
  std::int16_t x = 0, y = 0;
};

inline constexpr std::int16_t kPackedZero = -32768;  // both coordinates: the zero vector

inline PackedUnit pack_unit(double x, double y, double z) {
  const double l1 = std::abs(x) + std::abs(y) + std::abs(z);
  if (!(l1 > 0.0) || !std::isfinite(l1)) return {kPackedZero, kPackedZero};
  double u = x / l1, v = y / l1;
  if (z < 0.0) {  // fold the lower half over the upper
    const double fu = (1.0 - std::abs(v)) * (u >= 0.0 ? 1.0 : -1.0);
    const double fv = (1.0 - std::abs(u)) * (v >= 0.0 ? 1.0 : -1.0);
    u = fu;
    v = fv;
  }
  // Rounded half away from zero, as std::lround, without its library call.
  const auto snorm = [](double c) {
    const double s = std::fmin(1.0, std::fmax(-1.0, c)) * 32767.0;
    return static_cast<std::int16_t>(s >= 0.0 ? static_cast<int>(s + 0.5) : -static_cast<int>(0.5 - s));
  };
  return {snorm(u), snorm(v)};
}

inline PackedUnit pack_unit(const Vec3f& v) { return pack_unit(v.x, v.y, v.z); }

// The unit vector a code stands for (zero for the zero code).
inline Vec3 unpack_unit(PackedUnit p) {
  if (p.x == kPackedZero && p.y == kPackedZero) return {0.0, 0.0, 0.0};
  const double u = p.x * (1.0 / 32767.0), v = p.y * (1.0 / 32767.0);
  Vec3 n{u, v, 1.0 - std::abs(u) - std::abs(v)};
  if (n.z < 0.0) {  // unfold
    const double t = -n.z;
    n.x += n.x >= 0.0 ? -t : t;
    n.y += n.y >= 0.0 ? -t : t;
  }
  return n * (1.0 / std::sqrt(dot(n, n)));
}

}  // namespace gonio::sim
