// The ABg scatter model (Harvey; TracePro, LightTools, FRED):
//   BSDF(wi, wo) = A / (B + |β − β0|^g)                                 [1/sr]
// with β = (wo.x, wo.y) the outgoing direction projected on the surface
// (|β| = sin θo) and β0 = −(wi.x, wi.y) the projection of the specular
// direction (reflection) or of the straight-through direction (transmission
// through a thin sheet: no refraction). Since cos θo dω is the area element
// d²β of the unit disc, the lobe's albedo is the kernel's integral over the
// part of the disc |β| < 1:
//   albedo(wi) = A ∫_{|β|<1} d²β / (B + |β − β0|^g),
// largest at normal incidence (β0 = 0) and falling towards grazing, where
// more of the lobe would leave the disc. Gonio's lobe weight is that total
// integrated scatter at normal incidence, TIS = A · I0(B, g) with
// I0 = 2π ∫_0^1 r dr / (B + r^g), so A = TIS / I0; the specular share is a
// mirror (or dielectric) lobe beside it, and the rest is absorbed.
// g = 0 is a Lambertian lobe; g = 2 with small B a Lorentzian peak of
// width √B about the specular direction.
//
// Sampling is exact: a photon survives with chance albedo(wi)/TIS(0)
// (tabulated over |β0|), then |β − β0| = r is drawn with density
// ∝ r / (B + r^g) on [0, 2] (by rejection within 512 fine intervals) and the
// angle about β0 uniformly, again until β lies in the disc.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "photometry/vec3.h"
#include "sim/samplers/random.h"

namespace gonio::sim {

struct AbgTable {
  double b = 0.0, g = 0.0;
  double i0 = 0.0;  // ∫_{|β|<1} d²β / (B + |β|^g)
  // Radial intervals on [0, 2] (bounds), the largest value of r/(B + r^g)
  // on each, the cumulative share of bound × width, and the mass
  // K(r) = ∫_0^r ρ dρ / (B + ρ^g) at each bound.
  std::vector<double> r, bound, cdf, mass;
  // The albedo per unit TIS at |β0| = k / 64, k = 0 … 64 (linear between).
  std::array<double, 65> albedo{};

  double kernel(double dist) const;                  // 1 / (B + dist^g)
  double radial_mass(double radius) const;           // K(radius), radius in [0, 2]
  double albedo_at(double beta0) const;              // per unit TIS
};

// Whether B and g are usable: B finite and > 0, g in [0, 6].
bool abg_parameters_valid(double b, double g);

// The table of (B, g), built once per process and shared (thread-safe).
std::shared_ptr<const AbgTable> abg_table(double b, double g);

// A = TIS / I0 and back.
double abg_a_from_tis(double tis, double b, double g);
double abg_tis_from_a(double a, double b, double g);

// The lobe per unit TIS in the local frame (wi.z > 0): f · |cos θo| [1/sr]
// for wo on the lobe's side (transmit: wo.z < 0), else 0; its albedo; the
// density of sample_abg over the sphere [1/sr] (= evaluate / albedo).
double abg_evaluate(const AbgTable& t, bool transmit, const Vec3& wi_local, const Vec3& wo_local);
double abg_albedo(const AbgTable& t, const Vec3& wi_local);
double abg_pdf(const AbgTable& t, bool transmit, const Vec3& wi_local, const Vec3& wo_local);
// A direction with density abg_pdf (the survival roulette is the caller's);
// the zero vector in the (never observed) case that rejection gives up.
Vec3 sample_abg(const AbgTable& t, bool transmit, const Vec3& wi_local, PhotonRandom& rng);

}  // namespace gonio::sim
