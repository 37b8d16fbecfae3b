// Volume scattering inside a closed part: the Henyey–Greenstein phase
// function. The tracer (sim/tracer/tracer.cpp) draws a photon's free path inside a
// part whose material has Material::scattering_per_m > 0 with
// μt = μs + μa (μa: Material::attenuation_per_m); where it ends inside, the
// photon is absorbed with chance μa/μt (booked at that part in the ledger)
// or scattered into a direction drawn from this phase function, and goes on
// from there; where it reaches the part's surface first, the surface
// scatters it as usual. A part is "inside" for a free path that ends on the
// back face of one of its triangles (as for Beer–Lambert absorption): parts
// must be closed, and geometry nested inside a scattering part is not seen
// as inside it.
#pragma once

#include "photometry/vec3.h"
#include "sim/samplers/random.h"

namespace gonio::sim {

// p(cos Θ) = (1 − g²) / (4π (1 + g² − 2g cos Θ)^{3/2})  [1/sr], Θ the angle
// between the old and the new direction of travel; ∫ p dω = 1, mean cos Θ = g.
double henyey_greenstein(double g, double cos_theta);
// cos Θ drawn with that density (by inversion; uniform for |g| < 10⁻⁶).
double sample_henyey_greenstein_cos(double g, double u);
// The new unit direction of travel for a photon travelling along unit
// `direction`.
Vec3 sample_henyey_greenstein(const Vec3& direction, double g, PhotonRandom& rng);

}  // namespace gonio::sim
