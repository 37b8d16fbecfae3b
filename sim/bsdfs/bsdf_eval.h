// Next-event estimation's view of a surface (sim/tracer/next_event.h): the
// non-delta lobes of sim/bsdfs/lobes.h — diffuse reflection and
// transmission, the glossy lobe, ABg reflection and transmission and the
// tabulated BSDF — asked in world space what a vertex sends towards a
// direction the estimator chose, and a connection direction drawn from
// them. A thin adapter: every value and density comes from sim/bsdfs
// (lobe_evaluate, lobe_pdf, lobe_sample, weight_at); what is added here is
// the frames the tracer's scatter() uses and the stratified draw. The
// mirror and the dielectric send light along single directions that a
// connection never hits, so the photons themselves carry them.
//
// Conventions as sim/bsdfs/material.h's scatter(): `wi` points away from the
// surface towards where the photon came from, `wo` where the light goes,
// both unit, in world space; the frame's normals face the front side and
// are turned to wi's side here; the diffuse lobes use the geometric normal,
// the others the shading normal (the glossy lobe with the frame's tangent,
// as scatter() gives it only that one), and a direction that
// the shading frame puts on the other side of the geometry than the lobe
// sends it carries nothing (scatter() loses such photons). The lobes'
// weights are taken at the angle of incidence to the geometric normal
// (Material::over_incidence), as the tracer chooses lobes.
#pragma once

#include <cstddef>
#include <cstdint>

#include "photometry/vec3.h"
#include "sim/bsdfs/material.h"
#include "sim/scene.h"

namespace gonio::sim {

// Lobes as bits (1 << Lobe), to restrict a connection to some of them.
inline constexpr unsigned lobe_bit(Lobe lobe) { return 1u << static_cast<unsigned>(lobe); }
inline constexpr unsigned kNonDeltaLobes = lobe_bit(Lobe::DiffuseReflect) | lobe_bit(Lobe::DiffuseTransmit) |
                                           lobe_bit(Lobe::Glossy) | lobe_bit(Lobe::AbgReflect) |
                                           lobe_bit(Lobe::AbgTransmit) | lobe_bit(Lobe::Tabulated);
// Whether a lobe is one connections are made for.
inline constexpr bool connectable(Lobe lobe) { return (lobe_bit(lobe) & kNonDeltaLobes) != 0; }

// Σ over the non-delta lobes (of `lobes`) of weight_at(θi) ·
// lobe_evaluate — f(wi, wo) · |cos θo| [1/sr]: the power one photon's
// scattering event sends per steradian towards wo, per unit of its power
// (its lobe choice, absorption and the lobes' own survival included). ∫ of
// it over the sphere is the part of the photon's power these lobes scatter
// on average (Σ weight · lobe_albedo). `m` prepared (sim/bsdfs/lobes.h).
double non_delta_f_cos(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo,
                       unsigned lobes = kNonDeltaLobes);

// Whether the material has any of `lobes` (weights at normal incidence).
bool has_connectable_lobes(const Material& m, unsigned lobes = kNonDeltaLobes);
// The non-delta lobes that read the shading frame (all but the diffuse).
inline constexpr unsigned kShadingFrameLobes =
    kNonDeltaLobes & ~(lobe_bit(Lobe::DiffuseReflect) | lobe_bit(Lobe::DiffuseTransmit));

// The lobes' total weight at the photon's incidence (0: none).
double non_delta_weight(const Material& m, const SurfaceFrame& frame, const Vec3& wi,
                        unsigned lobes = kNonDeltaLobes);

// A connection direction drawn from two uniforms in [0, 1) — a mixture of
// the non-delta lobes in proportion to their weights at this incidence —
// with its density over the sphere and non_delta_f_cos there. u1 chooses
// the lobe and is then stretched to [0, 1) within it; the diffuse lobes
// map (u1', u2) to a cosine-weighted direction about the geometric normal
// (either side), so that a stratified pair gives stratified directions; the
// other lobes draw with their own sampler (lobe_sample) from a stream keyed
// by (u1, u2). pdf 0 (and f_cos 0) where the draw leaves nothing to book.
// Requires non_delta_weight(m, frame, wi, lobes) > 0.
struct ConnectionDirection {
  Vec3 wo;               // unit
  double pdf = 0.0;      // density of the mixture at wo [1/sr]
  double f_cos = 0.0;    // non_delta_f_cos(m, frame, wi, wo, lobes) [1/sr]
  Lobe lobe = Lobe::Absorb;  // the lobe drawn from
};
ConnectionDirection connection_direction(const Material& m, const SurfaceFrame& frame, const Vec3& wi, double u1,
                                         double u2, unsigned lobes = kNonDeltaLobes);
// connection_direction for n draws (u1[i], u2[i]) at one vertex into
// out[0, n): the same directions, densities and values bit for bit, the
// vertex's bases and the lobes' weights computed once (next-event
// estimation's connections of one vertex).
void connection_directions(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const double* u1,
                           const double* u2, std::size_t n, ConnectionDirection* out,
                           unsigned lobes = kNonDeltaLobes);
// The density connection_direction draws wo with [1/sr]: Σ (w_k / W) ·
// lobe_pdf_k.
double connection_pdf(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo,
                      unsigned lobes = kNonDeltaLobes);

}  // namespace gonio::sim
