// Material evaluation for next-event estimation: the one place where a
// connection (a direction chosen by the estimator, not by the photon) asks
// what a surface sends that way. Only the non-delta lobes of sim::Material
// take part — diffuse reflection, diffuse transmission and the glossy lobe
// (sim/material.h); the mirror and the dielectric send light along single
// directions that a connection never hits, so the photons themselves carry
// them (sim/next_event.h).
//
// Conventions as sim/material.h's scatter(): `wi` points away from the
// surface towards where the photon came from, `wo` where the light goes,
// both unit, in world space; the frame's normals face the front side and
// are turned to wi's side here; diffuse lobes use the geometric normal, the
// glossy lobe the shading frame (and sends nothing below the geometric
// surface, where scatter() absorbs).
#pragma once

#include "photometry/vec3.h"
#include "sim/material.h"
#include "sim/scene.h"

namespace gonio::sim {

// The non-delta lobes as bits, to restrict a connection to some of them.
inline constexpr unsigned kLobeDiffuseReflect = 1, kLobeDiffuseTransmit = 2, kLobeGlossy = 4;
inline constexpr unsigned kNonDeltaLobes = 7;

// Σ over the non-delta lobes of weight · f(wi, wo) · |cos θo| [1/sr]: the
// power one photon's scattering event sends per steradian towards wo, per
// unit of its power (its lobe choice, absorption and the glossy lobe's
// survival included). ∫ of it over the sphere is the part of the photon's
// power these lobes scatter on average (kd + kt + ks · albedo_glossy(wi)).
// `lobes`: only those (bits above).
double non_delta_f_cos(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo,
                       unsigned lobes = kNonDeltaLobes);

// The lobes' total weight kd + kt + ks, or of those in `lobes` (0: none).
inline double non_delta_weight(const Material& m, unsigned lobes = kNonDeltaLobes) {
  return ((lobes & kLobeDiffuseReflect) ? m.diffuse_reflect : 0.0) +
         ((lobes & kLobeDiffuseTransmit) ? m.diffuse_transmit : 0.0) + ((lobes & kLobeGlossy) ? m.glossy : 0.0);
}

// A connection direction drawn from two uniforms in [0, 1) — a mixture of
// the non-delta lobes in proportion to their weights: cosine-weighted about
// the geometric normal on wi's side (diffuse reflection) or the far side
// (transmission), Walter's half vector D(h) cos θh reflected (glossy) — with
// its density over the sphere and non_delta_f_cos there. A stratified pair
// (u1, u2) gives stratified directions: u1 chooses the lobe and is then
// stretched to [0, 1) within it. pdf 0 (and f_cos 0) where the draw leaves
// nothing to book (a glossy reflection below the surface). `lobes`: the
// mixture of those alone, and f_cos theirs. Requires
// non_delta_weight(m, lobes) > 0.
struct ConnectionDirection {
  Vec3 wo;             // unit
  double pdf = 0.0;    // density of the mixture at wo [1/sr]
  double f_cos = 0.0;  // non_delta_f_cos(m, frame, wi, wo, lobes) [1/sr]
  unsigned lobe = 0;   // the lobe drawn from (one bit)
};
ConnectionDirection connection_direction(const Material& m, const SurfaceFrame& frame, const Vec3& wi, double u1,
                                         double u2, unsigned lobes = kNonDeltaLobes);
// The density connection_direction draws wo with [1/sr].
double connection_pdf(const Material& m, const SurfaceFrame& frame, const Vec3& wi, const Vec3& wo,
                      unsigned lobes = kNonDeltaLobes);

}  // namespace gonio::sim
