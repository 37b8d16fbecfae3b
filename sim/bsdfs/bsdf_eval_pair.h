// The value and the connection density of a vertex's non-delta lobes
// towards one direction together (sim/bsdfs/bsdf_eval.h): what next-event
// estimation's balance heuristic needs at a photon's own escape
// (sim/tracer/next_event.h). Its own header so that only the tracer sees it.
#pragma once

#include "sim/bsdfs/bsdf_eval.h"

namespace gonio::sim {

struct FCosAndPdf {
  double f_cos = 0.0;  // non_delta_f_cos(m, frame, wi, wo, lobes), bit for bit
  double pdf = 0.0;    // connection_pdf(m, frame, wi, wo, lobes), bit for bit
};
// The vertex's bases and the lobes' weights computed once for both (the two
// calls would each compute them).
FCosAndPdf non_delta_f_cos_and_pdf(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo,
                                   unsigned lobes = kNonDeltaLobes);

}  // namespace gonio::sim
