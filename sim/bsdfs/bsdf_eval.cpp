#include "sim/bsdfs/bsdf_eval.h"
#include "sim/bsdfs/bsdf_eval_pair.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

#include "sim/bsdfs/lobes.h"
#include "sim/samplers/random.h"
#include "sim/samplers/sampling.h"

namespace gonio::sim {
namespace {

constexpr Lobe kConnectable[] = {Lobe::DiffuseReflect, Lobe::DiffuseTransmit, Lobe::Glossy,
                                 Lobe::AbgReflect,     Lobe::AbgTransmit,     Lobe::Tabulated};

bool diffuse(Lobe lobe) { return lobe == Lobe::DiffuseReflect || lobe == Lobe::DiffuseTransmit; }

// A vertex as scatter() sees it: the normals on wi's side, whether that is
// the front, the incidence, and the two local bases (diffuse lobes about
// the geometric normal, the others the shading frame).
struct Vertex {
  Vec3 ng, ns;
  bool front = true;
  double cos_i = 0.0;
  Basis geometric, glossy, shading;
  Vertex(const SurfaceFrame& f, const Vec3& wi)
      : front(dot(wi, f.geometric_normal) > 0.0),
        geometric(basis_from_normal(front ? f.geometric_normal : -f.geometric_normal)),
        glossy(geometric),
        shading(geometric) {
    ng = front ? f.geometric_normal : -f.geometric_normal;
    ns = front ? f.shading_normal : -f.shading_normal;
    if (dot(ns, ng) <= 0.0) ns = ng;
    cos_i = std::clamp(dot(wi, ng), 0.0, 1.0);
    // scatter() hands the tangent to the glossy lobe alone (uses_tangent);
    // the ABg and tabulated lobes build their basis from the normal.
    glossy = basis_from_normal_tangent(ns, f.tangent);
    shading = basis_from_normal_tangent(ns, Vec3{});
    wi_geometric = geometric.to_local(wi);
    wi_glossy = glossy.to_local(wi);
    wi_shading = shading.to_local(wi);
  }
  const Basis& basis(Lobe lobe) const {
    return diffuse(lobe) ? geometric : lobe == Lobe::Glossy ? glossy : shading;
  }
  // wi in basis(lobe), computed once for all of a vertex's connections.
  const Vec3& local_wi(Lobe lobe) const {
    return diffuse(lobe) ? wi_geometric : lobe == Lobe::Glossy ? wi_glossy : wi_shading;
  }
  Vec3 wi_geometric, wi_glossy, wi_shading;
  // Whether wo leaves on the side of the geometry the lobe sends light to
  // (`local`: wo in the lobe's basis; the tabulated BSDF's side is its
  // own choice, the local z's sign).
  bool right_side(Lobe lobe, const Vec3& wo, const Vec3& local) const {
    const double c = dot(wo, ng);
    switch (lobe) {
      case Lobe::DiffuseTransmit:
      case Lobe::AbgTransmit: return c < 0.0;
      case Lobe::Tabulated: return local.z != 0.0 && (local.z > 0.0) == (c > 0.0);
      default: return c > 0.0;
    }
  }
};

double weight(const Material& m, const Vertex& v, Lobe lobe) { return weight_at(m, lobe, v.cos_i); }

double lobe_f_cos(const Material& m, const Vertex& v, Lobe lobe, const Vec3& wo) {
  const Basis& b = v.basis(lobe);
  const Vec3 lo = b.to_local(wo);
  if (!v.right_side(lobe, wo, lo)) return 0.0;
  return lobe_evaluate(m, lobe, v.local_wi(lobe), lo, v.front);
}

// The weights of kConnectable's lobes at v, 0 for a lobe not in `lobes`
// (and for a weight that is not positive: every sum below skips those).
using Weights = std::array<double, std::size(kConnectable)>;
Weights weights(const Material& m, const Vertex& v, unsigned lobes) {
  Weights w{};
  for (std::size_t k = 0; k < std::size(kConnectable); ++k)
    if (lobes & lobe_bit(kConnectable[k])) w[k] = std::max(0.0, weight(m, v, kConnectable[k]));
  return w;
}

double f_cos(const Material& m, const Vertex& v, const Weights& w, const Vec3& wo) {
  double f = 0.0;
  for (std::size_t k = 0; k < std::size(kConnectable); ++k)
    if (w[k] > 0.0) f += w[k] * lobe_f_cos(m, v, kConnectable[k], wo);
  return f;
}

double mixture_pdf(const Material& m, const Vertex& v, const Weights& w, const Vec3& wo) {
  double total = 0.0, pdf = 0.0;
  for (std::size_t k = 0; k < std::size(kConnectable); ++k) {
    if (!(w[k] > 0.0)) continue;
    total += w[k];
    const Basis& b = v.basis(kConnectable[k]);
    pdf += w[k] * lobe_pdf(m, kConnectable[k], v.local_wi(kConnectable[k]), b.to_local(wo), v.front);
  }
  return total > 0.0 ? pdf / total : 0.0;
}

// One connection direction at v, whose lobe weights are w.
ConnectionDirection draw(const Material& m, const Vertex& v, const Weights& w, double u1, double u2);

}  // namespace

double non_delta_f_cos(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo, unsigned lobes) {
  const Vertex v(frame, wi);
  return f_cos(m, v, weights(m, v, lobes), wo);
}

bool has_connectable_lobes(const Material& m, unsigned lobes) {
  for (Lobe lobe : kConnectable)
    if ((lobes & lobe_bit(lobe)) && lobe_weight(m, lobe) > 0.0) return true;
  return false;
}

double non_delta_weight(const Material& m, const SurfaceFrame& frame, const Vec3& wi, unsigned lobes) {
  const Vertex v(frame, wi);
  double total = 0.0;
  for (Lobe lobe : kConnectable)
    if (lobes & lobe_bit(lobe)) total += std::max(0.0, weight(m, v, lobe));
  return total;
}

ConnectionDirection connection_direction(const Material& m, const SurfaceFrame& frame, const Vec3& wi, double u1,
                                         double u2, unsigned lobes) {
  const Vertex v(frame, wi);
  return draw(m, v, weights(m, v, lobes), u1, u2);
}

void connection_directions(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const double* u1,
                           const double* u2, std::size_t n, ConnectionDirection* out, unsigned lobes) {
  if (n == 0) return;
  const Vertex v(frame, wi);
  const Weights w = weights(m, v, lobes);
  for (std::size_t i = 0; i < n; ++i) out[i] = draw(m, v, w, u1[i], u2[i]);
}

namespace {

ConnectionDirection draw(const Material& m, const Vertex& v, const Weights& w, double u1, double u2) {
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
  const Basis& b = v.basis(out.lobe);
  if (diffuse(out.lobe)) {
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
    const LobeSample s = lobe_sample(m, out.lobe, v.local_wi(out.lobe), rng, v.front);
    if (!(s.pdf > 0.0) || !(dot(s.wo, s.wo) > 0.0)) return out;
    out.wo = normalize(b.to_world(s.wo));
  }
  out.pdf = mixture_pdf(m, v, w, out.wo);
  if (!(out.pdf > 0.0)) {
    out.pdf = 0.0;
    return out;
  }
  out.f_cos = f_cos(m, v, w, out.wo);
  return out;
}

}  // namespace

FCosAndPdf non_delta_f_cos_and_pdf(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo,
                                   unsigned lobes) {
  const Vertex v(frame, wi);
  const Weights w = weights(m, v, lobes);
  return {f_cos(m, v, w, wo), mixture_pdf(m, v, w, wo)};
}

double connection_pdf(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo, unsigned lobes) {
  const Vertex v(frame, wi);
  return mixture_pdf(m, v, weights(m, v, lobes), wo);
}

}  // namespace gonio::sim
