#include "sim/bsdf_eval.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim/sampling.h"

namespace gonio::sim {
namespace {

constexpr double kInvPi = std::numbers::inv_pi;

// The normals on wi's side (as scatter()).
struct Sided {
  Vec3 ng, ns;
};
Sided sided(const SurfaceFrame& f, const Vec3& wi) {
  const bool front = dot(wi, f.geometric_normal) > 0.0;
  Sided s{front ? f.geometric_normal : -f.geometric_normal, front ? f.shading_normal : -f.shading_normal};
  if (dot(s.ns, s.ng) <= 0.0) s.ns = s.ng;
  return s;
}

// The glossy lobe's f cos θo (no weight), 0 below the geometric surface.
double glossy_f_cos(const Material& m, const Sided& s, const Vec3& tangent, const Vec3& wi, const Vec3& wo) {
  if (dot(wo, s.ng) <= 0.0) return 0.0;
  const Basis b = basis_from_normal_tangent(s.ns, tangent);
  const Vec3 li = b.to_local(wi), lo = b.to_local(wo);
  return glossy_brdf(m, li, lo) * std::max(0.0, lo.z);
}

// Walter's density of wo reflected about h ~ D(h) cos θh, over the sphere.
double walter_pdf(const Material& m, const Sided& s, const Vec3& tangent, const Vec3& wi, const Vec3& wo) {
  const Basis b = basis_from_normal_tangent(s.ns, tangent);
  const Vec3 li = b.to_local(wi), lo = b.to_local(wo);
  const Vec3 sum = li + lo;
  const double len = length(sum);
  if (!(len > 0.0)) return 0.0;
  const Vec3 h = sum / len;
  const double oh = dot(lo, h);
  if (!(oh > 0.0) || !(h.z > 0.0)) return 0.0;
  return beckmann_d(m.glossy_mx, m.glossy_my, h) * h.z / (4.0 * oh);
}

}  // namespace

double non_delta_f_cos(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo, unsigned lobes) {
  const Sided s = sided(frame, wi);
  const double c = dot(wo, s.ng);
  const double kd = (lobes & kLobeDiffuseReflect) ? m.diffuse_reflect : 0.0;
  const double kt = (lobes & kLobeDiffuseTransmit) ? m.diffuse_transmit : 0.0;
  double f = c > 0.0 ? kd * c * kInvPi : -kt * c * kInvPi;
  if ((lobes & kLobeGlossy) && m.glossy > 0.0) f += m.glossy * glossy_f_cos(m, s, frame.tangent, wi, wo);
  return f;
}

ConnectionDirection connection_direction(const Material& m, const SurfaceFrame& frame, const Vec3& wi, double u1,
                                         double u2, unsigned lobes) {
  const Sided s = sided(frame, wi);
  const double total = non_delta_weight(m, lobes);
  const double kd = (lobes & kLobeDiffuseReflect) ? m.diffuse_reflect : 0.0;
  const double kt = (lobes & kLobeDiffuseTransmit) ? m.diffuse_transmit : 0.0;
  const double ks = (lobes & kLobeGlossy) ? m.glossy : 0.0;
  ConnectionDirection out;
  double u = u1 * total;
  if (u < kd || u < kd + kt) {
    const bool reflect = u < kd;
    out.lobe = reflect ? kLobeDiffuseReflect : kLobeDiffuseTransmit;
    u = reflect ? u / kd : (u - kd) / kt;
    u = std::min(u, 1.0 - 0x1.0p-53);
    // Cosine-weighted from (u, u2): radius √u, angle 2πu2.
    double sn, cs;
    sincos_turn(u2, &sn, &cs);
    const double r = std::sqrt(u);
    const Vec3 local{r * cs, r * sn, std::sqrt(std::max(0.0, 1.0 - u))};
    out.wo = normalize(basis_from_normal(reflect ? s.ng : -s.ng).to_world(local));
  } else {
    out.lobe = kLobeGlossy;
    u = std::clamp((u - kd - kt) / ks, 0.0, 1.0 - 0x1.0p-53);
    double sn, cs;
    sincos_turn(u2, &sn, &cs);
    const Basis b = basis_from_normal_tangent(s.ns, frame.tangent);
    const Vec3 h = sample_beckmann_half_vector(m.glossy_mx, m.glossy_my, 1.0 - u, cs, sn);
    const Vec3 li = b.to_local(wi);
    const Vec3 lo = 2.0 * dot(li, h) * h - li;
    if (!(dot(li, h) > 0.0)) return out;
    out.wo = normalize(b.to_world(lo));
  }
  out.pdf = connection_pdf(m, frame, wi, out.wo, lobes);
  if (!(out.pdf > 0.0)) {
    out.pdf = 0.0;
    return out;
  }
  out.f_cos = non_delta_f_cos(m, frame, wi, out.wo, lobes);
  return out;
}

double connection_pdf(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo, unsigned lobes) {
  const Sided s = sided(frame, wi);
  const double total = non_delta_weight(m, lobes);
  const double kd = (lobes & kLobeDiffuseReflect) ? m.diffuse_reflect : 0.0;
  const double kt = (lobes & kLobeDiffuseTransmit) ? m.diffuse_transmit : 0.0;
  const double c = dot(wo, s.ng);
  double pdf = (kd * cosine_hemisphere_pdf(c) + kt * cosine_hemisphere_pdf(-c)) / total;
  if ((lobes & kLobeGlossy) && m.glossy > 0.0) pdf += m.glossy / total * walter_pdf(m, s, frame.tangent, wi, wo);
  return pdf;
}

}  // namespace gonio::sim
