#include "sim/bsdfs/bsdf_eval.h"
#include "sim/bsdfs/bsdf_eval_pair.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numbers>
#include <tuple>

#include "sim/bsdfs/lobes.h"
#include "sim/samplers/random.h"
#include "sim/samplers/sampling.h"

namespace gonio::sim {
namespace {

constexpr Lobe kConnectable[] = {Lobe::DiffuseReflect, Lobe::DiffuseTransmit, Lobe::Glossy,
                                 Lobe::AbgReflect,     Lobe::AbgTransmit,     Lobe::Tabulated};

bool diffuse_lobe(Lobe lobe) { return lobe == Lobe::DiffuseReflect || lobe == Lobe::DiffuseTransmit; }
const Basis& basis(const ConnectionVertex& v, Lobe lobe) {
  return diffuse_lobe(lobe) ? v.geometric : lobe == Lobe::Glossy ? v.glossy : v.shading;
}
// wi in basis(lobe), computed once for all of a vertex's connections.
const Vec3& local_wi(const ConnectionVertex& v, Lobe lobe) {
  return diffuse_lobe(lobe) ? v.wi_geometric : lobe == Lobe::Glossy ? v.wi_glossy : v.wi_shading;
}
// Whether wo leaves on the side of the geometry the lobe sends light to
// (`local`: wo in the lobe's basis; the tabulated BSDF's side is its
// own choice, the local z's sign).
bool right_side(const ConnectionVertex& v, Lobe lobe, const Vec3& wo, const Vec3& local) {
  const double c = dot(wo, v.ng);
  switch (lobe) {
    case Lobe::DiffuseTransmit:
    case Lobe::AbgTransmit: return c < 0.0;
    case Lobe::Tabulated: return local.z != 0.0 && (local.z > 0.0) == (c > 0.0);
    default: return c > 0.0;
  }
}

double lobe_f_cos(const Material& m, const ConnectionVertex& v, Lobe lobe, const Vec3& wo) {
  const Basis& b = basis(v, lobe);
  const Vec3 lo = b.to_local(wo);
  if (!right_side(v, lobe, wo, lo)) return 0.0;
  return lobe_evaluate(m, lobe, local_wi(v, lobe), lo, v.front);
}

// The weights of kConnectable's lobes at a vertex (ConnectionVertex::w).
using Weights = std::array<double, std::size(kConnectable)>;
static_assert(std::tuple_size_v<Weights> == ConnectionVertex::kLobes);

double f_cos(const Material& m, const ConnectionVertex& v, const Weights& w, const Vec3& wo) {
  double f = 0.0;
  for (std::size_t k = 0; k < std::size(kConnectable); ++k)
    if (w[k] > 0.0) f += w[k] * lobe_f_cos(m, v, kConnectable[k], wo);
  return f;
}

double mixture_pdf(const Material& m, const ConnectionVertex& v, const Weights& w, const Vec3& wo) {
  double total = 0.0, pdf = 0.0;
  for (std::size_t k = 0; k < std::size(kConnectable); ++k) {
    if (!(w[k] > 0.0)) continue;
    total += w[k];
    const Basis& b = basis(v, kConnectable[k]);
    pdf += w[k] * lobe_pdf(m, kConnectable[k], local_wi(v, kConnectable[k]), b.to_local(wo), v.front);
  }
  return total > 0.0 ? pdf / total : 0.0;
}

// f_cos and mixture_pdf together (bit for bit the two): at a vertex whose
// weight lies on the diffuse lobes alone, wo in the geometric basis once
// for both, and each lobe's cos θo/π once for its value and its density.
FCosAndPdf pair(const Material& m, const ConnectionVertex& v, const Weights& w, const Vec3& wo) {
  if (!v.diffuse_only) return {f_cos(m, v, w, wo), mixture_pdf(m, v, w, wo)};
  static_assert(kConnectable[0] == Lobe::DiffuseReflect && kConnectable[1] == Lobe::DiffuseTransmit);
  const Vec3 lo = v.geometric.to_local(wo);
  const double c = dot(wo, v.ng);
  const bool lit = v.wi_geometric.z > 0.0;  // lobe_evaluate's and lobe_pdf's test
  double f = 0.0, total = 0.0, pdf = 0.0;
  if (w[0] > 0.0) {
    const double e = lit && lo.z > 0.0 ? lo.z / std::numbers::pi : 0.0;
    f += w[0] * (c > 0.0 ? e : 0.0);
    total += w[0];
    pdf += w[0] * e;
  }
  if (w[1] > 0.0) {
    const double e = lit && lo.z < 0.0 ? -lo.z / std::numbers::pi : 0.0;
    f += w[1] * (c < 0.0 ? e : 0.0);
    total += w[1];
    pdf += w[1] * e;
  }
  return {f, total > 0.0 ? pdf / total : 0.0};
}

// One connection direction at v, whose lobe weights are w.
ConnectionDirection draw(const Material& m, const ConnectionVertex& v, const Weights& w, double u1, double u2);

}  // namespace

double non_delta_f_cos(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo, unsigned lobes) {
  const ConnectionVertex v(m, frame, wi, lobes);
  return f_cos(m, v, v.w, wo);
}

bool has_connectable_lobes(const Material& m, unsigned lobes) {
  for (Lobe lobe : kConnectable)
    if ((lobes & lobe_bit(lobe)) && lobe_weight(m, lobe) > 0.0) return true;
  return false;
}

double non_delta_weight(const Material& m, const SurfaceFrame& frame, const Vec3& wi, unsigned lobes) {
  double total = 0.0;
  const ConnectionVertex v(m, frame, wi, lobes);
  for (double w : v.w) total += w;
  return total;
}

ConnectionDirection connection_direction(const Material& m, const SurfaceFrame& frame, const Vec3& wi, double u1,
                                         double u2, unsigned lobes) {
  const ConnectionVertex v(m, frame, wi, lobes);
  return draw(m, v, v.w, u1, u2);
}

void connection_directions(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const double* u1,
                           const double* u2, std::size_t n, ConnectionDirection* out, unsigned lobes) {
  if (n == 0) return;
  const ConnectionVertex v(m, frame, wi, lobes);
  for (std::size_t i = 0; i < n; ++i) out[i] = draw(m, v, v.w, u1[i], u2[i]);
}

namespace {

ConnectionDirection draw(const Material& m, const ConnectionVertex& v, const Weights& w, double u1, double u2) {
  double total = 0.0;
  for (std::size_t k = 0; k < std::size(kConnectable); ++k) total += w[k];
  ConnectionDirection out;
  if (!(total > 0.0)) return out;
  // The lobe: u1's band among the weights; u1 stretched to [0, 1) in it.
  double u = u1 * total;
  std::size_t last = 0;
  for (std::size_t j = 0; j < std::size(kConnectable); ++j)
    if (w[j] > 0.0) last = j;
  std::size_t k = 0;
  for (; k < last; ++k) {
    if (!(w[k] > 0.0)) continue;
    if (u < w[k]) break;
    u -= w[k];
  }
  out.lobe = kConnectable[k];
  u = std::clamp(u / w[k], 0.0, 1.0 - 0x1.0p-53);
  const Basis& b = basis(v, out.lobe);
  if (diffuse_lobe(out.lobe)) {
    // Cosine-weighted from (u, u2): radius √u, angle 2πu2 (lobe_pdf's
    // density, drawn stratified).
    double sn, cs;
    sincos_turn(u2, &sn, &cs);
    const double r = std::sqrt(u);
    const double z = std::sqrt(std::max(0.0, 1.0 - u));
    out.wo = normalize(b.to_world({r * cs, r * sn, out.lobe == Lobe::DiffuseReflect ? z : -z}));
  } else {
    // The lobe's own sampler, from a stream keyed by the pair.
    PhotonRandom rng(static_cast<std::uint64_t>(u1 * 0x1.0p53), static_cast<std::uint64_t>(u2 * 0x1.0p53));
    const LobeSample s = lobe_sample(m, out.lobe, local_wi(v, out.lobe), rng, v.front);
    if (!(s.pdf > 0.0) || !(dot(s.wo, s.wo) > 0.0)) return out;
    out.wo = normalize(b.to_world(s.wo));
  }
  const FCosAndPdf at = pair(m, v, w, out.wo);
  if (!(at.pdf > 0.0)) return out;
  out.pdf = at.pdf;
  out.f_cos = at.f_cos;
  return out;
}

}  // namespace

FCosAndPdf non_delta_f_cos_and_pdf(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo,
                                   unsigned lobes) {
  const ConnectionVertex v(m, frame, wi, lobes);
  return pair(m, v, v.w, wo);
}

ConnectionVertex::ConnectionVertex(const Material& m, const SurfaceFrame& frame, const Vec3& wi, unsigned lobes) {
  front = dot(wi, frame.geometric_normal) > 0.0;
  geometric = basis_from_normal(front ? frame.geometric_normal : -frame.geometric_normal);
  ng = front ? frame.geometric_normal : -frame.geometric_normal;
  ns = front ? frame.shading_normal : -frame.shading_normal;
  if (dot(ns, ng) <= 0.0) ns = ng;
  cos_i = std::clamp(dot(wi, ng), 0.0, 1.0);
  wi_geometric = geometric.to_local(wi);
  // The lobes' weights, 0 for a lobe not in `lobes` (and for a weight that
  // is not positive: every sum skips those).
  bool shading_lobes = false;
  for (std::size_t k = 0; k < std::size(kConnectable); ++k)
    if (lobes & lobe_bit(kConnectable[k])) {
      w[k] = std::max(0.0, weight_at(m, kConnectable[k], cos_i));
      if (w[k] > 0.0 && !diffuse_lobe(kConnectable[k])) shading_lobes = true;
    }
  diffuse_only = !shading_lobes;
  if (shading_lobes) {
    // scatter() hands the tangent to the glossy lobe alone (uses_tangent);
    // the ABg and tabulated lobes build their basis from the normal.
    glossy = basis_from_normal_tangent(ns, frame.tangent);
    shading = basis_from_normal_tangent(ns, Vec3{});
    wi_glossy = glossy.to_local(wi);
    wi_shading = shading.to_local(wi);
  }
  for (double x : w) total += x;
}

void connection_directions(const Material& m, const ConnectionVertex& v, const double* u1, const double* u2,
                           std::size_t n, ConnectionDirection* out) {
  for (std::size_t i = 0; i < n; ++i) out[i] = draw(m, v, v.w, u1[i], u2[i]);
}

FCosAndPdf non_delta_f_cos_and_pdf(const Material& m, const ConnectionVertex& v, const Vec3& wo) {
  return pair(m, v, v.w, wo);
}

double connection_pdf(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo, unsigned lobes) {
  const ConnectionVertex v(m, frame, wi, lobes);
  return mixture_pdf(m, v, v.w, wo);
}

}  // namespace gonio::sim
