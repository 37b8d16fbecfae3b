#include "sim/bsdfs/material.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "photometry/format.h"
#include "sim/bsdfs/abg.h"
#include "sim/bsdfs/glossy_energy.h"
#include "sim/bsdfs/lobes.h"
#include "sim/bsdfs/tabulated_bsdf.h"
#include "sim/samplers/sampling.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;

Status fail(const Material& m, const char* what) {
  Error e;
  e.message = "material '" + m.name + "': " + what;
  return e;
}

bool finite_nonneg(double x) { return std::isfinite(x) && x >= 0.0; }

}  // namespace

Status validate(const Material& m) {
  for (double w : {m.diffuse_reflect, m.diffuse_transmit, m.mirror, m.glossy, m.dielectric, m.abg_reflect.tis,
                   m.abg_transmit.tis, m.tabulated})
    if (!finite_nonneg(w)) return fail(m, "lobe weights must be finite and >= 0");
  if (m.total() > 1.0 + 1e-9) return fail(m, "lobe weights sum to more than 1");
  for (std::size_t k = 0; k < m.over_incidence.size(); ++k) {
    const IncidenceTable& t = m.over_incidence[k];
    if (t.empty()) continue;
    const std::string lobe = to_string(static_cast<Lobe>(k + 1));
    if (t.factor.size() != t.theta_deg.size())
      return fail(m, (lobe + " over incidence: as many factors as angles are needed").c_str());
    for (std::size_t i = 0; i < t.theta_deg.size(); ++i) {
      if (!(t.theta_deg[i] >= 0.0 && t.theta_deg[i] <= 90.0) || (i > 0 && !(t.theta_deg[i] > t.theta_deg[i - 1])))
        return fail(m, (lobe + " over incidence: angles must increase within 0..90 degrees").c_str());
      if (!finite_nonneg(t.factor[i]))
        return fail(m, (lobe + " over incidence: factors must be finite and >= 0").c_str());
    }
  }
  if (m.angular()) {
    // The weights are linear in θ between the union of the tables' angles,
    // so their sum is largest at one of those angles.
    std::vector<double> angles{0.0, 90.0};
    for (const IncidenceTable& t : m.over_incidence) angles.insert(angles.end(), t.theta_deg.begin(), t.theta_deg.end());
    for (double a : angles) {
      const LobeCdf c = lobe_cdf(m, std::cos(a * kPi / 180.0));
      if (c.bounds[kLobeCount - 2] > 1.0 + 1e-9)
        return fail(m, ("lobe weights over incidence sum to " + format_number(c.bounds[kLobeCount - 2]) +
                        " at " + format_number(a) + " degrees, more than 1")
                           .c_str());
    }
  }
  for (const AbgScatter* a : {&m.abg_reflect, &m.abg_transmit})
    if (a->tis > 0.0 && !abg_parameters_valid(a->b, a->g))
      return fail(m, "ABg B must be finite and > 0 and g within 0..6");
  if (m.tabulated > 0.0 && !m.table) return fail(m, "the tabulated lobe has no table");
  if (!finite_nonneg(m.scattering_per_m)) return fail(m, "scattering must be finite and >= 0 per metre");
  if (!(m.scattering_g > -1.0 && m.scattering_g < 1.0))
    return fail(m, "the phase function's g must lie strictly between -1 and 1");
  if (m.glossy > 0.0) {
    if (!(std::isfinite(m.glossy_mx) && m.glossy_mx > 0.0 && std::isfinite(m.glossy_my) &&
          m.glossy_my > 0.0))
      return fail(m, "glossy roughness mx, my must be finite and > 0");
    if (!(m.glossy_f0 >= 0.0 && m.glossy_f0 <= 1.0)) return fail(m, "glossy f0 must lie in 0..1");
  }
  if (!(std::isfinite(m.ior) && m.ior > 0.0)) return fail(m, "ior must be finite and > 0");
  if (!finite_nonneg(m.attenuation_per_m))
    return fail(m, "attenuation must be finite and >= 0 per metre");
  return Ok{};
}

const char* to_string(Lobe lobe) {
  switch (lobe) {
    case Lobe::Absorb: return "absorb";
    case Lobe::DiffuseReflect: return "diffuse reflection";
    case Lobe::DiffuseTransmit: return "diffuse transmission";
    case Lobe::Mirror: return "mirror";
    case Lobe::Glossy: return "glossy";
    case Lobe::Dielectric: return "dielectric";
    case Lobe::AbgReflect: return "ABg reflection";
    case Lobe::AbgTransmit: return "ABg transmission";
    case Lobe::Tabulated: return "tabulated";
  }
  return "?";
}

double lobe_weight(const Material& m, Lobe lobe) {
  switch (lobe) {
    case Lobe::DiffuseReflect: return m.diffuse_reflect;
    case Lobe::DiffuseTransmit: return m.diffuse_transmit;
    case Lobe::Mirror: return m.mirror;
    case Lobe::Glossy: return m.glossy;
    case Lobe::Dielectric: return m.dielectric;
    case Lobe::AbgReflect: return m.abg_reflect.tis;
    case Lobe::AbgTransmit: return m.abg_transmit.tis;
    case Lobe::Tabulated: return m.tabulated;
    case Lobe::Absorb: break;
  }
  return 1.0 - m.total();
}

Lobe choose_lobe(const Material& m, double u) { return choose_lobe(lobe_cdf(m), u); }

LobeCdf lobe_cdf(const Material& m) {
  LobeCdf c;
  double sum = 0.0;
  for (int k = 0; k < kLobeCount - 1; ++k) c.bounds[k] = sum += lobe_weight(m, static_cast<Lobe>(k + 1));
  return c;
}

LobeCdf lobe_cdf(const Material& m, double cos_theta_i) {
  LobeCdf c;
  double sum = 0.0;
  for (int k = 0; k < kLobeCount - 1; ++k)
    c.bounds[k] = sum += lobe_weight(m, static_cast<Lobe>(k + 1)) *
                         m.over_incidence[static_cast<std::size_t>(k)].at(cos_theta_i);
  return c;
}

double beckmann_d(double mx, double my, const Vec3& h) {
  if (h.z <= 0.0) return 0.0;
  const double z2 = h.z * h.z;
  const double e = (h.x * h.x / (mx * mx) + h.y * h.y / (my * my)) / z2;
  return std::exp(-e) / (kPi * mx * my * z2 * z2);
}

double schlick_fresnel(double f0, double c) {
  const double k = 1.0 - std::clamp(c, 0.0, 1.0);
  const double k2 = k * k;
  return f0 + (1.0 - f0) * k2 * k2 * k;
}

namespace {

// Smith's Λ of the Beckmann distribution for a direction with
// a² = z² / r2 (r2 = mx² x² + my² y²; a = 1 / (roughness · tan θ)):
// (erf(a) − 1)/2 + exp(−a²)/(2a√π), written with erfc so that the two
// small terms of large a do not cancel against 1. From a = 5.5 on,
// Λ < 6·10⁻¹⁷ vanishes beside 1 in G = 1/(1 + Λ) and is 0.
double lambda_of(double z2, double r2) {
  if (!(z2 < 30.25 * r2)) return 0.0;  // includes r2 = 0: along the normal
  const double a = std::sqrt(z2 / r2);
  if (!(a > 0.0)) return std::numeric_limits<double>::infinity();
  return std::max(0.0, 0.5 * (std::exp(-a * a) * std::numbers::inv_sqrtpi / a - std::erfc(a)));
}

}  // namespace

double beckmann_lambda(double mx, double my, const Vec3& w) {
  if (!(w.z > 0.0)) return std::numeric_limits<double>::infinity();
  return lambda_of(w.z * w.z, mx * mx * w.x * w.x + my * my * w.y * w.y);
}

double smith_g1(double mx, double my, const Vec3& w) {
  return 1.0 / (1.0 + beckmann_lambda(mx, my, w));
}

double smith_g2(double mx, double my, const Vec3& wi, const Vec3& wo) {
  return 1.0 / (1.0 + beckmann_lambda(mx, my, wi) + beckmann_lambda(mx, my, wo));
}

double glossy_brdf(const Material& m, const Vec3& wi, const Vec3& wo) {
  if (wi.z <= 0.0 || wo.z <= 0.0) return 0.0;
  const Vec3 h = normalize(wi + wo);
  const double ih = dot(wi, h);
  return schlick_fresnel(m.glossy_f0, ih) * beckmann_d(m.glossy_mx, m.glossy_my, h) *
         smith_g2(m.glossy_mx, m.glossy_my, wi, wo) / (4.0 * wi.z * wo.z);
}

Vec3 sample_beckmann_half_vector(double mx, double my, double u, double cos_2piv,
                                 double sin_2piv) {
  // (cos φh, sin φh) ∝ (mx cos 2πv, my sin 2πv): Walter's φh without the
  // arctangent's quadrant ambiguity.
  double cx = mx * cos_2piv, sy = my * sin_2piv;
  const double inv = 1.0 / std::sqrt(cx * cx + sy * sy);
  cx *= inv;
  sy *= inv;
  const double tan2 = -std::log(u) / (cx * cx / (mx * mx) + sy * sy / (my * my));
  const double cos_t = 1.0 / std::sqrt(1.0 + tan2);
  const double sin_t = std::sqrt(tan2) * cos_t;
  return {sin_t * cx, sin_t * sy, cos_t};
}

namespace {

// ξ > a with density ∝ exp(−ξ²)(ξ − a), by rejection from one of two
// closed-form proposals (acceptance ≥ 0.34 for every a); −1 after 256
// rejections (chance < 10⁻⁴⁵).
double sample_slope_tail(double a, PhotonRandom& rng) {
  for (int k = 0; k < 256; ++k) {
    if (a < 0.7) {
      // ξ ∝ ξ exp(−ξ²) on ξ > a (inverted in closed form), kept with (ξ − a)/ξ.
      const double xi = std::sqrt(a * a - std::log(rng.uniform_open0()));
      if (rng.uniform() * xi < xi - a) return xi;
    } else {
      // ξ − a = s ∝ s exp(−2as) (a sum of two exponentials), kept with exp(−s²).
      const double s = -std::log(rng.uniform_open0() * rng.uniform_open0()) / (2.0 * a);
      if (rng.uniform() < std::exp(-s * s)) return a + s;
    }
  }
  return -1.0;
}

// The visible half vectors of wi (wi.z > 0), given Λ(wi).
//
// In slopes stretched by the roughness, (P, Q) = (tan θh cos φh / mx,
// tan θh sin φh / my) and h ∝ (mx P, my Q, 1), Walter's formulas draw the
// Gaussian exp(−P² − Q²)/π. The visible normals have that density times
// G1(wi) (1 + t)⁺, where 1 + t = (wi·h) / ((wi·n)(h·n)) and t = X / a with
// X the stretched slope along k = (mx wi.x, my wi.y). Walter's h and its
// mirror image h' (P, Q → −P, −Q: t → −t) are equally likely, so keeping
// h with probability (1 + t)/2 (capped at 1) and h' otherwise is exact
// where |t| ≤ 1. Where |t| > 1 the pair's visible density is (1 + |t|)/2
// against Walter's 1: the excess, (X/a − 1) over X > a, holds Λ(wi) of
// mass against Walter's 1 and is drawn as a second component with
// probability Λ / (1 + Λ): X from the tail, the slope across k from
// Walter's draw. Returns the zero vector in the (never observed) case that
// the tail's rejection gives up.
Vec3 visible_half_vector(double mx, double my, const Vec3& wi, double lambda_i,
                         PhotonRandom& rng) {
  // Walter's formulas in stretched slopes: tan²θh (cos²φh/mx² + sin²φh/my²)
  // = −log u is P² + Q², and (P, Q) points along (cos 2πv, sin 2πv).
  double c, s;
  sample_unit_circle(rng, &c, &s);
  const double r = std::sqrt(-std::log(rng.uniform_open0()));
  const double p = r * c, q = r * s;
  const double kx = mx * wi.x, ky = my * wi.y;
  if (lambda_i > 0.0 && rng.uniform() * (1.0 + lambda_i) >= 1.0) {
    // Λ > 0 implies k ≠ 0.
    const double k = std::sqrt(kx * kx + ky * ky);
    const double ex = kx / k, ey = ky / k;
    const double y = ey * p - ex * q;
    const double x = sample_slope_tail(wi.z / k, rng);
    if (x < 0.0) return {};
    return normalize(Vec3{mx * (ex * x + ey * y), my * (ey * x - ex * y), 1.0});
  }
  // Keep h where 2 uniform() < 1 + t = 1 + (kx P + ky Q) / wi.z, written
  // without dividing (and without a branch: the choice is a coin toss).
  const double keep = std::copysign(1.0, wi.z + kx * p + ky * q - 2.0 * rng.uniform() * wi.z);
  return normalize(Vec3{keep * mx * p, keep * my * q, 1.0});
}

}  // namespace

Vec3 sample_visible_half_vector(double mx, double my, const Vec3& wi, PhotonRandom& rng) {
  if (!(wi.z > 0.0)) return {};
  return visible_half_vector(mx, my, wi, beckmann_lambda(mx, my, wi), rng);
}

double visible_half_vector_pdf(double mx, double my, const Vec3& wi, const Vec3& h) {
  const double ih = dot(wi, h);
  if (!(wi.z > 0.0) || !(ih > 0.0)) return 0.0;
  return smith_g1(mx, my, wi) * beckmann_d(mx, my, h) * ih / wi.z;
}

double glossy_pdf(const Material& m, const Vec3& wi, const Vec3& wo) {
  if (!(wi.z > 0.0)) return 0.0;
  const Vec3 sum = wi + wo;
  const double len = length(sum);
  if (!(len > 0.0)) return 0.0;
  const Vec3 h = sum / len;
  if (!(dot(wi, h) > 0.0)) return 0.0;
  // D_wi(h) / (4 wo·h) with wo·h = wi·h.
  return smith_g1(m.glossy_mx, m.glossy_my, wi) * beckmann_d(m.glossy_mx, m.glossy_my, h) /
         (4.0 * wi.z);
}

GlossySample sample_glossy(const Material& m, const Vec3& wi, PhotonRandom& rng) {
  if (!(wi.z > 0.0)) return {wi, 0.0, 0.0};
  const double mx = m.glossy_mx, my = m.glossy_my;
  const double lambda_i = beckmann_lambda(mx, my, wi);
  if (!(lambda_i < std::numeric_limits<double>::infinity())) return {wi, 0.0, 0.0};  // G1 = 0
  const Vec3 h = visible_half_vector(mx, my, wi, lambda_i, rng);
  const double ih = dot(wi, h);
  if (!(ih > 0.0)) return {h, 0.0, 0.0};
  const Vec3 wo = 2.0 * ih * h - wi;
  if (!(wo.z > 0.0)) return {wo, 0.0, 0.0};
  // f cos θo / pdf = F D G2 / (4 (wi·n)(wo·n)) · (wo·n) · 4 (wi·n) / (G1 D).
  const double masking = (1.0 + lambda_i) / (1.0 + lambda_i + beckmann_lambda(mx, my, wo));
  return {wo, schlick_fresnel(m.glossy_f0, ih) * masking, masking};
}

double fresnel_dielectric(double cos_i, double eta_i, double eta_t) {
  cos_i = std::clamp(cos_i, 0.0, 1.0);
  const double sin_t = eta_i / eta_t * std::sqrt(std::max(0.0, 1.0 - cos_i * cos_i));
  if (sin_t >= 1.0) return 1.0;
  const double cos_t = std::sqrt(std::max(0.0, 1.0 - sin_t * sin_t));
  const double rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  const double rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

bool refract(const Vec3& wi, const Vec3& n, double eta, Vec3* wt) {
  const double cos_i = dot(wi, n);
  const double sin2_t = eta * eta * std::max(0.0, 1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) return false;
  const double cos_t = std::sqrt(1.0 - sin2_t);
  *wt = -eta * wi + (eta * cos_i - cos_t) * n;
  return true;
}

namespace {

// Dielectric event about normal n on the incident side; false if the chosen
// direction ends on the wrong side of the geometric surface `ng_in`.
bool dielectric_event(const Vec3& wi, const Vec3& n, const Vec3& ng_in, double eta_i,
                      double eta_t, double u, Vec3* out) {
  const double cos_i = dot(wi, n);
  if (cos_i <= 0.0) return false;
  const double r = fresnel_dielectric(cos_i, eta_i, eta_t);
  if (u < r) {
    *out = reflect(wi, n);
    return dot(*out, ng_in) > 0.0;
  }
  Vec3 t;
  if (!refract(wi, n, eta_i / eta_t, &t)) return false;  // r == 1 handled above
  *out = t;
  return dot(t, ng_in) < 0.0;
}

}  // namespace

ScatterResult scatter(const Material& m, const SurfaceFrame& f, const Vec3& d, PhotonRandom& rng,
                      Polarization* polarization) {
  const Lobe lobe = choose_lobe(m, rng.uniform());
  return scatter(m, lobe, f, d, rng, polarization);
}

ScatterResult scatter(const Material& m, Lobe lobe, const SurfaceFrame& f, const Vec3& d,
                      PhotonRandom& rng, Polarization* polarization) {
  ScatterResult r{lobe, false, d};
  const bool front = dot(d, f.geometric_normal) < 0.0;
  // Normals on the side the photon arrives from.
  const Vec3 ng = front ? f.geometric_normal : -f.geometric_normal;
  Vec3 ns = front ? f.shading_normal : -f.shading_normal;
  if (dot(ns, ng) <= 0.0) ns = ng;
  const Vec3 wi = -d;

  switch (r.lobe) {
    case Lobe::Absorb:
      r.absorbed = true;
      return r;
    case Lobe::DiffuseReflect:
    case Lobe::DiffuseTransmit: {
      if (polarization) polarization->polarized = false;
      const Vec3 local = sample_cosine_hemisphere(rng);
      const Vec3 axis = r.lobe == Lobe::DiffuseReflect ? ng : -ng;
      // Unit to rounding: an orthonormal basis applied to a unit vector.
      r.direction = basis_from_normal(axis).to_world(local);
      return r;
    }
    case Lobe::Mirror: {
      Vec3 n = ns;
      Vec3 o = reflect(wi, n);
      if (dot(o, ng) <= 0.0) o = reflect(wi, n = ng);
      r.direction = normalize(o);
      if (polarization) reflect_field(*polarization, n);
      return r;
    }
    case Lobe::Glossy: {
      if (polarization) polarization->polarized = false;
      const Basis basis = basis_from_normal_tangent(ns, f.tangent);
      const GlossySample g = sample_glossy(m, basis.to_local(wi), rng);
      const Vec3 o = basis.to_world(g.wo);
      // Survival with chance F · masking (≤ 1). A photon lost to masking
      // (chance 1 − E(wi) in all) leaves in the compensating second lobe
      // where the material has one (sim/bsdfs/glossy_energy.h); one lost to
      // Fresnel is absorbed.
      bool masked = !(g.masking > 0.0) || dot(o, ng) <= 0.0;
      if (!masked) {
        const double u = rng.uniform();
        if (u < g.weight) {
          r.direction = normalize(o);
          return r;
        }
        masked = u >= g.masking;
      }
      r.absorbed = true;
      if (masked && m.tables && m.tables->glossy) {
        const double kappa = m.tables->glossy_kappa;
        if (kappa < 1.0 && rng.uniform() >= kappa) return r;
        const Vec3 ms = basis.to_world(sample_glossy_ms(*m.tables->glossy, rng));
        if (dot(ms, ng) <= 0.0) return r;
        r.direction = normalize(ms);
        r.absorbed = false;
      }
      return r;
    }
    case Lobe::AbgReflect:
    case Lobe::AbgTransmit: {
      if (polarization) polarization->polarized = false;
      const bool transmit = r.lobe == Lobe::AbgTransmit;
      const AbgTable* t = m.tables ? (transmit ? m.tables->abg_transmit : m.tables->abg_reflect).get() : nullptr;
      const Basis basis = basis_from_normal_tangent(ns, f.tangent);
      const Vec3 wl = basis.to_local(wi);
      r.absorbed = true;
      if (!t || rng.uniform() >= abg_albedo(*t, wl)) return r;
      const Vec3 o = basis.to_world(sample_abg(*t, transmit, wl, rng));
      if (transmit ? !(dot(o, ng) < 0.0) : !(dot(o, ng) > 0.0)) return r;
      r.direction = normalize(o);
      r.absorbed = false;
      return r;
    }
    case Lobe::Tabulated: {
      if (polarization) polarization->polarized = false;
      const Basis basis = basis_from_normal_tangent(ns, f.tangent);
      const Vec3 wl = basis.to_local(wi);
      r.absorbed = true;
      if (!m.table || rng.uniform() >= m.table->albedo(front, wl)) return r;
      double u[4];
      for (double& x : u) x = rng.uniform();
      const Vec3 l = m.table->sample(front, wl, u[0], u[1], u[2], u[3]);
      const Vec3 o = basis.to_world(l);
      // The side it leaves on is the table's choice; a direction that the
      // shading normal puts on the other side of the geometry is lost.
      if (!(l.z != 0.0) || (l.z > 0.0) != (dot(o, ng) > 0.0)) return r;
      r.direction = normalize(o);
      r.absorbed = false;
      return r;
    }
    case Lobe::Dielectric: {
      const double eta_i = front ? 1.0 : m.ior, eta_t = front ? m.ior : 1.0;
      if (polarization) {
        polarize_randomly(*polarization, d, rng);
        const double u = rng.uniform();
        // The shading normal first; the geometric one if that would send
        // the photon to the wrong side of the surface.
        for (int pass = 0; pass < 2; ++pass) {
          const Vec3& n = pass == 0 ? ns : ng;
          if (dot(d, n) >= 0.0) continue;
          const InterfaceOutcome e = interface_event(*polarization, d, n, eta_i, eta_t, u);
          const double side = dot(e.direction, ng);
          if (e.reflected ? side > 0.0 : side < 0.0) {
            r.direction = e.direction;
            *polarization = e.state;
            return r;
          }
        }
        r.direction = d;  // exactly grazing the geometric plane: pass by
        return r;
      }
      const double u = rng.uniform();
      Vec3 o = d;
      if (!dielectric_event(wi, ns, ng, eta_i, eta_t, u, &o) &&
          !dielectric_event(wi, ng, ng, eta_i, eta_t, u, &o))
        o = d;  // exactly grazing the geometric plane: pass by
      r.direction = normalize(o);
      return r;
    }
  }
  return r;
}

}  // namespace gonio::sim
