// What identifies a loaded scene: the bench's reference cache key
// (tools/bench/bench_reference.h) and the ranks' agreement before an MPI run
// (tools/run/distributed_run.h) both compare it.
#pragma once

#include <string>

#include "sim/scene.h"

namespace gonio::cli {

// A hash of everything in a scene that the tracer reads: geometry, shading
// normals and tangents, materials, emitters with their profiles, the frame.
std::string scene_hash(const sim::SceneDesc& scene);

}  // namespace gonio::cli
