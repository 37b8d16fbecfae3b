// The large generated models (samples/large_models.h) as files for the
// benchmarks: written once per process into a temporary folder (removed at
// exit) and loaded with io::load_gltf like any model.
#pragma once

#include <cstddef>
#include <string>

#include "samples/large_models.h"
#include "sim/scene.h"

namespace gonio::bench {

// The model's .gltf path, written on first use. Aborts with a message where
// it cannot be written.
std::string large_model_file(samples::LargeModel kind, std::size_t triangles);

// The model as loaded, kept for the rest of the process. Aborts with a
// message where it cannot be loaded.
const sim::SceneDesc& large_model_scene(samples::LargeModel kind, std::size_t triangles);

}  // namespace gonio::bench
