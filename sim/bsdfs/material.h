// Scattering of photons at surfaces: the lobes of sim::Material (the
// reference thesis' material model, section 5.2, with its glossy lobe made
// a microfacet BRDF that conserves energy, and a smooth dielectric),
// each sampling routine with its density, and the Russian roulette that
// keeps every photon's power equal on every lobe.
//
// Directions: `wi` points away from the surface towards where the photon
// came from; `wo` away from the surface where it goes. Local frames have the
// normal as z and the tangent (the direction of `glossy_mx`) as x.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "photometry/diagnostics.h"
#include "photometry/vec3.h"
#include "sim/bsdfs/polarization.h"
#include "sim/samplers/random.h"
#include "sim/scene.h"

namespace gonio::sim {

// Structural checks: weights finite, ≥ 0, summing to at most 1 (at every
// angle of incidence where Material::over_incidence varies them); roughness
// > 0; f0 in [0, 1]; ior finite and > 0; attenuation and scattering finite
// and ≥ 0, the phase function's g in (−1, 1); ABg B > 0 and
// g in [0, 6]; a tabulated lobe has its table; incidence tables well
// formed. The error names the material.
Status validate(const Material& material);

// The lobes (sim/bsdfs/lobes.h gives each one's evaluate, sample, pdf and
// albedo): AbgReflect and AbgTransmit are the ABg model (sim/bsdfs/abg.h),
// Tabulated a measured BSDF (sim/bsdfs/tabulated_bsdf.h).
enum class Lobe : std::uint8_t {
  Absorb,
  DiffuseReflect,
  DiffuseTransmit,
  Mirror,
  Glossy,
  Dielectric,
  AbgReflect,
  AbgTransmit,
  Tabulated
};
inline constexpr int kLobeCount = 9;  // with Absorb

const char* to_string(Lobe lobe);

// A lobe's weight in a material (Absorb: 1 − total()), at normal incidence
// where Material::over_incidence has a table for it.
double lobe_weight(const Material& m, Lobe lobe);

// The lobe that scatters a photon, for u uniform in [0, 1): each lobe with
// the probability of its weight, Absorb with 1 − total().
Lobe choose_lobe(const Material& m, double u);

// The same from cumulative weights computed once per material (the tracer's
// per-hit path): bounds[k] = weight of lobes 1..k+1 in Lobe order.
struct LobeCdf {
  double bounds[kLobeCount - 1];
};
LobeCdf lobe_cdf(const Material& m);
// The weights at an angle of incidence (Material::over_incidence applied;
// cos θi > 0); their sum is kept at most 1 by validate().
LobeCdf lobe_cdf(const Material& m, double cos_theta_i);
inline Lobe choose_lobe(const LobeCdf& cdf, double u) {
  int k = 0;
  while (k < kLobeCount - 1 && u >= cdf.bounds[k]) ++k;
  return static_cast<Lobe>((k + 1) % kLobeCount);  // past every lobe → Absorb
}

// --- Glossy lobe: a microfacet BRDF on the anisotropic Beckmann
// distribution with Schlick's Fresnel and Smith's height-correlated
// masking-shadowing (Walter et al. 2007; Heitz 2014 for the anisotropic Λ
// and the height-correlated G2):
//   f(wi, wo) = F(wi·h) D(h) G2(wi, wo) / (4 (wi·n)(wo·n))          [1/sr]
//   D(h) = exp(−tan²θh (cos²φh/mx² + sin²φh/my²)) / (π mx my cos⁴θh)
//   F(c) = f0 + (1 − f0)(1 − c)⁵
//   G2 = 1 / (1 + Λ(wi) + Λ(wo)),  G1(w) = 1 / (1 + Λ(w))
// The lobe's weight `glossy` (the thesis's ks) is the chance of choosing
// it; these functions describe the lobe alone, so the surface reflects
// ks · albedo(wi) through it.
//
// Energy. With the exact Λ (below), ∫ G1(wi) D(h) max(0, wi·h) dωh = wi·n (the
// facets' projected area is the surface's), and G2 ≤ G1(wi), F ≤ 1 give
// albedo(wi) = ∫ f cos θo dωo ≤ 1 for every roughness and incidence. For
// f0 = 1 it is 1 − 3·10⁻⁵ for mx = my ≤ 0.1 up to 60° from the normal and
// falls for rough lobes, 0.94 at mx = my = 0.5 and 0.46 at 1 (normal
// incidence), and near the horizon: this single-scattering model absorbs
// the light that would bounce between facets more than once.
//
// Against the thesis (section 5.2, Kurt et al. 2010 with α = ½):
//   f_thesis = F D / (4 (wo·h) √((wi·n)(wo·n))),
//   f / f_thesis = G2 (wo·h) / √((wi·n)(wo·n)).
// The two agree where G2 ≈ 1 and (wo·h)² ≈ (wi·n)(wo·n), i.e. near the
// mirror direction (h ≈ n) of a smooth lobe, which carries nearly all of
// such a lobe's light. Away from it, and for rough lobes, the thesis's lobe
// is brighter: it has no masking, and (wo·h)/√((wi·n)(wo·n)) grows beyond 1
// towards grazing directions, so its albedo exceeds 1 (≈ 1.3 at mx = my =
// 0.5, 85°). D, F, the parameters ks, mx, my, f0 and their meaning are the
// thesis's.

// D(h) for a unit half vector in the local frame [1/sr]: ∫ D cos θh dω = 1.
double beckmann_d(double mx, double my, const Vec3& h_local);
double schlick_fresnel(double f0, double cos_theta);
// Smith's Λ of the anisotropic Beckmann distribution for a unit direction w
// (exact, with erfc: Walter's rational approximation of G1 is off by up to
// 0.3 %, enough to break the projected-area identity above): with
// a = cos θ / (sin θ √(mx² cos²φ + my² sin²φ)),
//   Λ = (erf(a) − 1)/2 + exp(−a²) / (2a√π);
// 0 along the normal and wherever a ≥ 5.5 (Λ < 6·10⁻¹⁷ vanishes beside 1
// and is not computed), +∞ at or below the horizon.
double beckmann_lambda(double mx, double my, const Vec3& w_local);
// Masking of one direction, G1 = 1 / (1 + Λ), and the height-correlated
// masking-shadowing of a pair, G2 = 1 / (1 + Λ(wi) + Λ(wo)).
double smith_g1(double mx, double my, const Vec3& w_local);
double smith_g2(double mx, double my, const Vec3& wi_local, const Vec3& wo_local);
// f(wi, wo) in the local frame; 0 unless both are above the surface.
double glossy_brdf(const Material& m, const Vec3& wi_local, const Vec3& wo_local);

// Half vector drawn with density D(h) cos θh by Walter's formulas (thesis
// 5.2): φh = atan(my/mx · tan 2πv) (in the quadrant of 2πv),
// θh = atan √(−log u / (cos²φh/mx² + sin²φh/my²)); u in (0, 1]. The angle
// 2πv is given as its unit vector (cos 2πv, sin 2πv), which the tracer
// draws without trigonometry (sample_unit_circle).
Vec3 sample_beckmann_half_vector(double mx, double my, double u, double cos_2piv,
                                 double sin_2piv);

// Half vector among the facets that wi sees (wi.z > 0), with the visible-
// normal density (Heitz & d'Eon 2014)
//   D_wi(h) = G1(wi) D(h) max(0, wi·h) / (wi·n)                    [1/sr],
// built on Walter's draw above: Walter's h or its mirror image h' = (−hx,
// −hy, hz) (Walter's formulas at v + ½, exactly as likely), chosen in
// proportion to max(0, wi·h) and max(0, wi·h'); and, with probability
// Λ(wi) / (1 + Λ(wi)), a slope from the tail that masking lets through
// beyond what that choice reaches (closed form with rejection; Λ = 0, and
// this never happens, unless wi is within about atan(5.5 · roughness) of
// the horizon). Exact for every roughness and incidence; the zero vector
// for wi.z ≤ 0.
//
// Why not Walter's h alone: reflecting wi about it gives the sample weight
// f cos θo / pdf = F G2 (wi·h) / ((wi·n)(h·n)), which exceeds 1 for about
// half the samples at any oblique incidence. Surviving with min(w, 1)
// would lose (and reshape) 1.5 % of an mx = my = 0.09 lobe's light at 30°,
// 4.4 % at 60°, 29 % at 85° (benchmarks/glossy_study.cpp); carrying w as
// power creates light.
Vec3 sample_visible_half_vector(double mx, double my, const Vec3& wi_local, PhotonRandom& rng);
double visible_half_vector_pdf(double mx, double my, const Vec3& wi_local, const Vec3& h_local);

// Density of sample_glossy's outgoing direction over the whole sphere
// (directions below the surface are where it returns weight 0):
// D_wi(h) / (4 wo·h) = G1(wi) D(h) / (4 wi·n) for wi·h > 0, else 0 [1/sr].
double glossy_pdf(const Material& m, const Vec3& wi_local, const Vec3& wo_local);

struct GlossySample {
  Vec3 wo;         // local frame; may point below the surface (weight 0)
  double weight;   // f · cos θo / pdf = F(wi·h) G2(wi, wo) / G1(wi), in [0, 1]
  double masking;  // its masking part G2(wi, wo) / G1(wi) (0 below the surface): weight = F · masking
};
// wi reflected about a visible half vector.
GlossySample sample_glossy(const Material& m, const Vec3& wi_local, PhotonRandom& rng);

// --- Smooth dielectric interface.
// Unpolarised Fresnel reflectance (mean of s and p) for light arriving at
// cos θi > 0 from index eta_i onto index eta_t; 1 under total internal
// reflection.
double fresnel_dielectric(double cos_i, double eta_i, double eta_t);
// Mirror direction of wi about the unit normal n: 2(wi·n)n − wi.
inline Vec3 reflect(const Vec3& wi, const Vec3& n) { return 2.0 * dot(wi, n) * n - wi; }
// Refracted direction of wi through the unit normal n on wi's side, with
// eta = eta_i / eta_t; false under total internal reflection.
bool refract(const Vec3& wi, const Vec3& n, double eta, Vec3* wt);

// --- Volumes: Beer–Lambert internal transmittance over a path [m].
inline double internal_transmittance(double attenuation_per_m, double distance_m) {
  return std::exp(-attenuation_per_m * distance_m);
}

// --- One scattering event, as the tracer uses it.

// The surface where a photon hits: unit geometric normal of the triangle's
// front side, unit shading normal on the same side (= geometric without
// shading normals) and the tangent for anisotropic lobes (zero if none).
struct SurfaceFrame {
  Vec3 geometric_normal;
  Vec3 shading_normal;
  Vec3 tangent;
};

struct ScatterResult {
  Lobe lobe;             // the lobe chosen (Absorb: the photon ends here)
  bool absorbed;         // absorbed by the lobe choice or the roulette
  Vec3 direction;        // unit, where it goes on (unless absorbed)
};

// Scatters a photon travelling along unit `direction` into the surface.
// Photon power stays equal: the lobe is chosen by its weight (the rest is
// absorbed); diffuse lobes, the mirror and the dielectric (reflection with
// chance R, refraction with 1 − R) keep full power; the glossy lobe survives
// with chance w = f·cos/pdf ≤ 1 (sample_glossy), so it is exact and never
// raises a photon's power.
// Specular directions use the shading normal; a direction that would cross
// the geometric surface to the wrong side is recomputed with the geometric
// normal. Dielectrics: the front side faces air (n = 1), the back side the
// volume of index `ior`.
// `polarization` (optional) is the photon's state (sim/bsdfs/polarization.h): the
// dielectric then reflects with the photon's own R and updates the state,
// the mirror reflects the field, diffuse and glossy lobes depolarise.
// Without it the dielectric uses the unpolarised R̄ = (Rs + Rp)/2.
ScatterResult scatter(const Material& m, const SurfaceFrame& frame, const Vec3& direction,
                      PhotonRandom& rng, Polarization* polarization = nullptr);
// The same for a lobe already chosen (choose_lobe), so that callers can skip
// interpolating a shading frame for lobes that do not use it.
ScatterResult scatter(const Material& m, Lobe lobe, const SurfaceFrame& frame,
                      const Vec3& direction, PhotonRandom& rng,
                      Polarization* polarization = nullptr);
// Whether a lobe reads the shading normal (the specular lobes).
inline bool uses_shading_frame(Lobe lobe) {
  return lobe == Lobe::Mirror || lobe == Lobe::Glossy || lobe == Lobe::Dielectric ||
         lobe == Lobe::AbgReflect || lobe == Lobe::AbgTransmit || lobe == Lobe::Tabulated;
}
// Whether it reads SurfaceFrame::tangent (the anisotropic lobe's axes); the
// others leave it unread, so the tracer does not interpolate it for them.
inline bool uses_tangent(Lobe lobe) { return lobe == Lobe::Glossy; }

}  // namespace gonio::sim
