// What identifies a loaded scene: the bench's reference cache key
// (tools/bench/bench_reference.h) and the ranks' agreement before an MPI run
// (tools/run/distributed_run.h) both compare it.
#pragma once

#include <string>

#include "sim/scene.h"

namespace gonio::app {

// A hash of everything in a scene that the tracer reads, field by field of
// sim/scene.h: geometry, shading normals and tangents, instances; every
// material field (lobe weights and roughness, ABg, the measured BSDF's basis
// and rows, the weights over incidence, volume scattering, the reflectance
// and transmittance spectra, dispersion as n(λ) or Abbe number); emitters
// with their profiles, ray sets and spectra over γ; the frame. Names (and
// what sim::prepare derives) are left out: they do not change a photon.
std::string scene_hash(const sim::SceneDesc& scene);

}  // namespace gonio::app
