// Geometric checks of a luminaire model that the simulation relies on but
// cannot detect itself while tracing. The only file that includes CGAL
// (exact predicates) is model_check.cpp, in its own target gonio::io_model.
//
// Vertices are identified by exact position (glTF splits vertices at normal
// seams; the split copies are one vertex here). Per mesh, at most one finding
// per code, with counts and the first example, named by mesh and material:
//
//   degenerate-triangle       warning  zero-area triangles (repeated or
//                                      collinear vertices); left out of the
//                                      checks below
//   self-intersection         error in refractive meshes, warning elsewhere:
//                                      pairs of triangles that cross, overlap
//                                      or touch away from shared vertices
//                                      and edges (also T-junctions)
// Refractive meshes (material dielectric > 0) must bound a volume:
//   open-volume               error    boundary edges (light would enter the
//                                      medium and never leave it properly)
//   non-manifold-volume       error    edges shared by more than two triangles
//   inconsistent-orientation  error    neighbours wound in opposite senses
//   inverted-volume           error    closed and consistent but facing
//                                      inwards (outermost shells must face
//                                      out, cavities in)
// Self-intersection and closedness are not checked between different meshes.
//
// Cost: about 1.5 µs per triangle (2 M triangles of a curved grid in 3.0 s on
// one core of the shared build machine; the samples in milliseconds), mostly
// the box-intersection sweep and the exact predicates; floating-point
// filters decide neighbours in flat regions before the exact ones.
#pragma once

#include <vector>

#include "photometry/diagnostics.h"
#include "sim/scene.h"

namespace gonio::io {

// Findings for `scene`; `where.file` is scene.name. Empty when all is well.
std::vector<Finding> check_model(const sim::SceneDesc& scene);

}  // namespace gonio::io
