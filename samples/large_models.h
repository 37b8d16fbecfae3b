// Large luminaire models generated in code, CAD-sized, for the setup
// benchmarks (benchmarks/setup_benchmark.cpp) and scaling measurements:
// written as glTF 2.0 like the samples, deterministic bytes.
//
//   faceted reflector  a paraboloid of flat mirror facets (one open mesh)
//                      around an isotropic point lamp at its focus
//   lens array         one closed PMMA lens (960 triangles) placed on a
//                      square grid by EXT_mesh_gpu_instancing (one node, a
//                      translation per copy), a point lamp under them: the
//                      file and the loaded scene hold the lens once
//   glass part         one closed glass sphere (a refractive volume) with a
//                      point lamp inside
#pragma once

#include <cstddef>
#include <string>

#include "samples/luminaires.h"

namespace gonio::samples {

enum class LargeModel { FacetedReflector, LensArray, GlassPart };

// "faceted-reflector", "lens-array" or "glass-part".
std::string large_model_name(LargeModel kind);

// The model with about `triangles` triangles in all (lens array: as placed,
// copies of the lens counted), at least a few hundred. Named
// "<name>-<triangles>".
Sample large_model(LargeModel kind, std::size_t triangles);

}  // namespace gonio::samples
