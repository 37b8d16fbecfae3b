// Sampling warps from uniform numbers to directions and points, each with
// its density. Local directions use z as the pole (a surface normal).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "photometry/vec3.h"
#include "sim/samplers/random.h"

namespace gonio::sim {

// Right-handed orthonormal basis (t, b, n) with t × b = n.
struct Basis {
  Vec3 t, b, n;
  Vec3 to_world(const Vec3& l) const { return l.x * t + l.y * b + l.z * n; }
  Vec3 to_local(const Vec3& w) const { return {dot(w, t), dot(w, b), dot(w, n)}; }
};

// A basis around a unit normal, continuous except across n.z = 0 (Duff et al.
// 2017, "Building an orthonormal basis, revisited").
inline Basis basis_from_normal(const Vec3& n) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double b = n.x * n.y * a;
  return {{1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x}, {b, sign + n.y * n.y * a, -n.y}, n};
}

// A basis around a unit normal whose first axis follows `tangent` projected
// onto the tangent plane; falls back to basis_from_normal when the tangent is
// (nearly) parallel to the normal or zero.
inline Basis basis_from_normal_tangent(const Vec3& n, const Vec3& tangent) {
  const Vec3 t = tangent - dot(tangent, n) * n;
  const double len2 = dot(t, t);
  if (!(len2 > 1e-12)) return basis_from_normal(n);
  const Vec3 tu = t / std::sqrt(len2);
  return {tu, cross(n, tu), n};
}

// sin x and cos x for |x| ≤ π/8 by their Taylor series to x¹¹ and x¹²
// (truncation below 9·10⁻¹⁶): a third of a library sincos's time, and
// samplers that know their angle is small (an offset inside a grid cell) need
// no range reduction.
inline void sincos_small(double x, double* s, double* c) {
  const double x2 = x * x;
  *s = x * (1.0 + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 +
                                                                             x2 * (-1.0 / 39916800))))));
  *c = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 +
                                                                     x2 * (-1.0 / 3628800 +
                                                                           x2 * (1.0 / 479001600))))));
}

// sin and cos of 2πu for u in [0, 1): the octant's middle angle from a
// table, the offset from it (within ±π/8) by sincos_small: no range
// reduction and no library call.
inline void sincos_turn(double u, double* s, double* c) {
  // cos and sin of (2q + 1)π/8, q = 0…7.
  static constexpr double kCos[8] = {0.92387953251128674,  0.38268343236508978,  -0.38268343236508978,
                                     -0.92387953251128674, -0.92387953251128674, -0.38268343236508978,
                                     0.38268343236508978,  0.92387953251128674};
  static constexpr double kSin[8] = {0.38268343236508978,  0.92387953251128674,  0.92387953251128674,
                                     0.38268343236508978,  -0.38268343236508978, -0.92387953251128674,
                                     -0.92387953251128674, -0.38268343236508978};
  const double x = 8.0 * u;
  const int q = std::clamp(static_cast<int>(x), 0, 7);
  double sd, cd;
  sincos_small((x - q - 0.5) * (std::numbers::pi / 4.0), &sd, &cd);
  *c = kCos[q] * cd - kSin[q] * sd;
  *s = kSin[q] * cd + kCos[q] * sd;
}

// Uniform point (x, y) in the unit disc from two uniforms by Shirley and
// Chiu's concentric map (1997, "A low distortion map between disk and
// square"): area-preserving and continuous, so stratified squares become
// stratified disc regions.
inline void concentric_disc(double u, double v, double* x, double* y) {
  const double a = 2.0 * u - 1.0, b = 2.0 * v - 1.0;
  if (a == 0.0 && b == 0.0) {
    *x = 0.0;
    *y = 0.0;
    return;
  }
  // r and the angle φ as a fraction of a turn: φ = π/4 · b/a, or
  // π/2 − π/4 · a/b, in [−π/4, 3π/4].
  double r, turn;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    turn = 0.125 * (b / a);
  } else {
    r = b;
    turn = 0.25 - 0.125 * (a / b);
  }
  double s, c;
  sincos_turn(turn < 0.0 ? turn + 1.0 : turn, &s, &c);
  *x = r * c;
  *y = r * s;
}

// Uniform point (x, y) in the unit disc, by rejection from the square
// (π/4 of the tries are kept): no trigonometry, exact. Low-discrepancy
// draws (sim/samplers/random.h): the concentric map of two draws instead.
inline void sample_unit_disc(PhotonRandom& rng, double* x, double* y) {
  if (rng.low_discrepancy()) {
    double u, v;
    rng.uniform_pair(&u, &v);
    concentric_disc(u, v, x, y);
    return;
  }
  for (;;) {
    double u, v;
    rng.uniform_pair(&u, &v);
    const double a = 2.0 * u - 1.0, b = 2.0 * v - 1.0;
    if (a * a + b * b < 1.0) {
      *x = a;
      *y = b;
      return;
    }
  }
}

// Uniform unit vector (cos φ, sin φ), φ uniform in [0, 2π): a disc point
// normalised (the centre itself is rejected). Low-discrepancy draws: φ = 2πu
// from one draw.
inline void sample_unit_circle(PhotonRandom& rng, double* c, double* s) {
  if (rng.low_discrepancy()) {
    sincos_turn(rng.uniform(), s, c);
    return;
  }
  for (;;) {
    double a, b;
    sample_unit_disc(rng, &a, &b);
    const double r2 = a * a + b * b;
    if (r2 > 1e-12) {
      const double inv = 1.0 / std::sqrt(r2);
      *c = a * inv;
      *s = b * inv;
      return;
    }
  }
}

// Cosine-weighted direction on the hemisphere z > 0 (Malley's method: a
// uniform disc point lifted onto the hemisphere); density cos θ / π [1/sr].
inline Vec3 sample_cosine_hemisphere(PhotonRandom& rng) {
  double x, y;
  sample_unit_disc(rng, &x, &y);
  return {x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y))};
}
inline double cosine_hemisphere_pdf(double cos_theta) {
  return cos_theta > 0.0 ? cos_theta / std::numbers::pi : 0.0;
}

// Uniform direction on the unit sphere (Marsaglia 1972: from a disc point
// with s = x² + y², (2x√(1−s), 2y√(1−s), 1 − 2s)); density 1/(4π) [1/sr].
inline Vec3 sample_uniform_sphere(PhotonRandom& rng) {
  double x, y;
  sample_unit_disc(rng, &x, &y);
  const double s = x * x + y * y;
  const double k = 2.0 * std::sqrt(1.0 - s);
  return {k * x, k * y, 1.0 - 2.0 * s};
}
inline double uniform_sphere_pdf() { return 1.0 / (4.0 * std::numbers::pi); }

// Uniform point in a triangle as barycentric weights of its corners (density
// 1/area).
struct Barycentric {
  double b0, b1, b2;
};
inline Barycentric sample_uniform_triangle(double u1, double u2) {
  const double s = std::sqrt(u1);
  return {1.0 - s, s * (1.0 - u2), s * u2};
}

}  // namespace gonio::sim
