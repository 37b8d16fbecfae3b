// The value and the connection density of a vertex's non-delta lobes
// towards one direction together (sim/bsdfs/bsdf_eval.h): what next-event
// estimation's balance heuristic needs at a photon's own escape
// (sim/tracer/next_event.h). Its own header so that only the tracer sees it.
#pragma once

#include <array>
#include <cstddef>

#include "sim/bsdfs/bsdf_eval.h"
#include "sim/samplers/sampling.h"

namespace gonio::sim {

struct FCosAndPdf {
  double f_cos = 0.0;  // non_delta_f_cos(m, frame, wi, wo, lobes), bit for bit
  double pdf = 0.0;    // connection_pdf(m, frame, wi, wo, lobes), bit for bit
};
// The vertex's bases and the lobes' weights computed once for both (the two
// calls would each compute them).
FCosAndPdf non_delta_f_cos_and_pdf(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo,
                                   unsigned lobes = kNonDeltaLobes);

// A vertex as next-event estimation asks it (issue 43, cheaper
// connections): its normals on wi's side, the incidence, the local bases
// and wi in them, and the connectable lobes' weights there — built once per
// connected vertex and kept for the photon's own escape from it, where the
// balance heuristic asks f and p again (before, the vertex's bases and
// weights were built twice: for the draws and for that share). The shading
// bases (glossy lobe, ABg, tabulated) are built only where one of those
// lobes has weight: a diffuse vertex needs the geometric basis alone. Every
// value is the one the single queries above give, bit for bit.
struct ConnectionVertex {
  static constexpr std::size_t kLobes = 6;  // bsdf_eval.cpp's connectable lobes, in their order
  ConnectionVertex() = default;
  // wi unit, towards where the photon came from; the weights of `lobes`.
  ConnectionVertex(const Material& m, const SurfaceFrame& frame, const Vec3& wi, unsigned lobes = kNonDeltaLobes);
  Vec3 ng, ns;
  bool front = true;
  bool diffuse_only = true;  // no weight on a lobe reading the shading frame
  double cos_i = 0.0;
  Basis geometric, glossy, shading;
  Vec3 wi_geometric, wi_glossy, wi_shading;
  std::array<double, kLobes> w{};  // the lobes' weights, 0 outside `lobes`
  double total = 0.0;              // Σ w
};
// connection_directions at a prepared vertex (the same draws bit for bit).
void connection_directions(const Material& m, const ConnectionVertex& v, const double* u1, const double* u2,
                           std::size_t n, ConnectionDirection* out);
// non_delta_f_cos_and_pdf at a prepared vertex (bit for bit).
FCosAndPdf non_delta_f_cos_and_pdf(const Material& m, const ConnectionVertex& v, const Vec3& wo);

}  // namespace gonio::sim
