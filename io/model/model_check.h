// Geometric checks of a luminaire model that the simulation relies on but
// cannot detect itself while tracing. The only file that includes CGAL
// (exact predicates) is model_check.cpp, in its own target gonio::io_model_check.
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
// Cost: about 1.5 µs per triangle on one core (2 M triangles of a curved
// grid in 3.0 s on the shared build machine; the samples in milliseconds),
// mostly the box-intersection sweep and the exact predicates; floating-point
// filters decide neighbours in flat regions before the exact ones. Meshes
// are checked in parallel (TBB), and a large mesh's intersection search is
// split into slabs searched in parallel; the findings do not depend on the
// thread count (same findings, same order).
//
// Cache: with a cache folder, results are stored under a content hash of
// everything the checks read (positions, indices, refractive or not; and
// kModelCheckRevision) as `mesh-check-<hash>.json`, written atomically: one
// entry per large mesh, one for the model's small meshes together
// (io/model/model_check_cache.h). An unchanged model is not checked again (renamed
// parts or changed materials that stay refractive or not keep the entries),
// and a model edited in one large part is checked again in that part only.
// An unreadable or malformed entry, or one whose counts differ from its
// meshes, is ignored: they are checked again and the entry rewritten. A
// cache that cannot be written is not an error.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/scene.h"

namespace gonio::io {

// Bumped whenever what the checks find changes, so that old cache entries
// are not reused.
inline constexpr int kModelCheckRevision = 2;

struct ModelCheckOptions {
  std::string cache_dir;  // folder of cached results; empty: no cache
  // Triangles per slab of a mesh's intersection search (at most 256 slabs,
  // searched in parallel). The slabs depend on the mesh and this number
  // only, never on the thread count; any value finds the same pairs, and
  // only a capped count (a mesh with more than 10⁴ intersecting pairs) may
  // differ with it.
  std::size_t slab_triangles = 32768;
};

struct ModelCheckStats {
  std::size_t meshes = 0;             // meshes of the model
  std::size_t meshes_from_cache = 0;  // of these, whose result came from the cache
};

// Findings for `scene`; `where.file` is scene.name. Empty when all is well.
std::vector<Finding> check_model(const sim::SceneDesc& scene, const ModelCheckOptions& options = {},
                                 ModelCheckStats* stats = nullptr);

}  // namespace gonio::io
