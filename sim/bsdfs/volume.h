// Volume scattering inside a closed part: the Henyey–Greenstein phase
// function. The tracer (sim/tracer/tracer.cpp) draws a photon's free path inside a
// part whose material has Material::scattering_per_m > 0 with
// μt = μs + μa (μa: Material::attenuation_per_m); where it ends inside, the
// photon is absorbed with chance μa/μt (booked at that part in the ledger)
// or scattered into a direction drawn from this phase function, and goes on
// from there; where it reaches the part's surface first, the surface
// scatters it as usual. A part is "inside" for a free path that ends on the
// back face of one of its triangles (as for Beer–Lambert absorption): parts
// must be closed, and geometry nested inside a scattering part is not seen
// as inside it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "photometry/vec3.h"
#include "sim/samplers/random.h"
#include "sim/samplers/sampling.h"

namespace gonio::sim {

// p(cos Θ) = (1 − g²) / (4π (1 + g² − 2g cos Θ)^{3/2})  [1/sr], Θ the angle
// between the old and the new direction of travel; ∫ p dω = 1, mean cos Θ = g.
double henyey_greenstein(double g, double cos_theta);
// cos Θ drawn with that density (by inversion; uniform for |g| < 10⁻⁶).
double sample_henyey_greenstein_cos(double g, double u);
// The new unit direction of travel for a photon travelling along unit
// `direction`.
Vec3 sample_henyey_greenstein(const Vec3& direction, double g, PhotonRandom& rng);

// The tracer's volume event (issue 43): the same density as
// sample_henyey_greenstein, from uniforms the caller drew, with no library
// call, one division for cos Θ, one square root. cos Θ for u = x/w in
// [0, 1) (0 ≤ x < w; w = 1 for a plain uniform) by the same inverse CDF as
// sample_henyey_greenstein_cos, written over one denominator: with
// D = w(1 − g) + 2gx (= w·d, d = 1 − g + 2gu),
//   cos Θ = ((1 + g²) D² − ((1 − g²) w)²) / (2g D²),
// so the caller's rescaling of u (scatter_or_absorb) costs no division.
inline double henyey_greenstein_cos_of_ratio(double g, double x, double w) {
  if (std::abs(g) < 1e-6) return 1.0 - 2.0 * (x / w);
  const double d = w * (1.0 - g) + 2.0 * g * x;
  const double d2 = d * d;
  const double a = (1.0 - g * g) * w;
  return std::clamp(((1.0 + g * g) * d2 - a * a) / (2.0 * g * d2), -1.0, 1.0);
}
// The new unit direction for a photon travelling along unit `direction`,
// cos Θ = `cos_theta`, the azimuth about `direction` the turn v in [0, 1)
// (sincos_turn: a table and a polynomial); the frame is Duff et al.'s
// branchless basis (basis_from_normal); the result is brought back to unit
// length by one Newton step of 1/√x at 1 (w(1.5 − 0.5 w·w)), which leaves
// an error of the order of the square of the input's: unit to rounding in,
// unit to rounding out, no drift over many events.
inline Vec3 turn_about(const Vec3& direction, double cos_theta, double v) {
  const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  double sin_phi, cos_phi;
  sincos_turn(v, &sin_phi, &cos_phi);
  const Basis b = basis_from_normal(direction);
  const Vec3 w = b.to_world(Vec3{s * cos_phi, s * sin_phi, cos_theta});
  return w * (1.5 - 0.5 * dot(w, w));
}

// A volume event inside a medium of scattering μs > 0 and absorption μa ≥ 0
// [1/m] for a photon travelling along unit `direction`, from one draw of
// `rng` (a pair of uniforms (u, v), 32 bits each): absorbed where
// u·(μs + μa) < μa (chance μa/μt; the test the tracer made before with a
// draw of its own), false; otherwise true and `*scattered` the new
// direction, cos Θ drawn from u' = (u·μt − μa)/μs — uniform in [0, 1)
// given that u was not absorbed, so independent of the decision — and the
// azimuth from v.
inline bool scatter_or_absorb(const Vec3& direction, double scattering_per_m, double attenuation_per_m, double g,
                              PhotonRandom& rng, Vec3* scattered) {
  double u, v;
  rng.uniform_pair(&u, &v);
  const double over = u * (scattering_per_m + attenuation_per_m) - attenuation_per_m;
  if (over < 0.0) return false;
  *scattered = turn_about(direction, henyey_greenstein_cos_of_ratio(g, over, scattering_per_m), v);
  return true;
}

namespace volume_detail {
// The ziggurat's tables for 256 layers of equal area v under e^−x and the
// base layer's right end r (Marsaglia and Tsang's constants): layer i
// (1 … 255) spans [0, x_i) with x_255 = r > … > x_1, f[i] = e^(−x_i); the
// abscissa is j·w[i] for a 53-bit j, accepted at once where j < k[i]
// (within the next layer's width); layer 0 is the base strip with the tail.
struct ExponentialZiggurat {
  static constexpr double kR = 7.69711747013104972;
  static constexpr double kV = 3.949659822581572e-3;
  std::uint64_t k[256];
  double w[256], f[256];
  ExponentialZiggurat();
};
extern const ExponentialZiggurat kExponentialZiggurat;
// The draws after a first one (`bits`) that was not accepted at once.
double standard_exponential_rest(PhotonRandom& rng, std::uint64_t bits);
}  // namespace volume_detail

// A standard exponential variate (density e^−x, x ≥ 0; the free path in
// units of the mean free path) without a logarithm on the common path:
// Marsaglia and Tsang's ziggurat ("The ziggurat method for generating
// random variables", 2000) of 256 layers, from one 64-bit draw — the layer
// from its low 8 bits, the abscissa from its top 53, disjoint bits (Doornik
// 2005) — accepted at once with chance 0.978 (counted over 10⁷ draws);
// otherwise the wedge's test (one exp) or, from the base layer, the tail
// beyond r = 7.6971 as r − ln u (the exponential forgets), with further
// draws. Exact in distribution up to the 2⁻⁵³ steps of a layer's
// abscissa. Low-discrepancy draws (sim/samplers/random.h): −ln u by
// inversion from one draw, as before.
inline double standard_exponential(PhotonRandom& rng) {
  if (rng.low_discrepancy()) return -std::log(rng.uniform_open0());
  const std::uint64_t bits = rng.next_u64();
  const unsigned i = static_cast<unsigned>(bits & 0xffU);
  const std::uint64_t j = bits >> 11;
  if (j < volume_detail::kExponentialZiggurat.k[i])
    return static_cast<double>(static_cast<std::int64_t>(j)) * volume_detail::kExponentialZiggurat.w[i];
  return volume_detail::standard_exponential_rest(rng, bits);
}

}  // namespace gonio::sim
