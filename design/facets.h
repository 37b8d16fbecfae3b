// Faceted reflectors of revolution (design files, design/design_file.h):
//
//   [[reflectors]]
//   ...                                # any profile
//   facets = { theta = 12, azimuth = 24, kind = "flat" }
//
// `theta` = N flat facets along the profile (N + 1 rows at equal steps of
// the profile's parameter: θ for a polar table, ρ for a conic, t for a
// B-spline), `azimuth` = M around the axis (equal steps of azimuth); either
// may be 0 (absent): smooth that way, tessellated as the smooth reflector.
// Every facet's corners lie on the exact surface:
//   - both: a plane through its four corners (two parallel chords of
//     neighbouring rows, so the four are coplanar), one normal;
//   - theta alone: a cone band through the rows' circles, its exact normal;
//   - azimuth alone: the ruled surface between two meridians (through the
//     chord at every row), its exact normal side·(dz, −dρ·cos(Δψ/2)) in the
//     sector's mid-plane.
// So a smooth design can be compared with its faceted version, and the
// faceted one converges to it as N and M grow. Only kind = "flat" so far.
#pragma once

#include "design/revolved.h"
#include "io/model/cad_model.h"
#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"

namespace gonio::design {

struct Facets {
  int theta = 0;    // facets along the profile; 0: smooth
  int azimuth = 0;  // facets around the axis; 0: smooth
};

// The `facets` table of a reflector. Errors name `path` and the line.
Result<Facets> read_facets(const io::TomlNode& facets, const std::string& path, const std::string& what);

// The faceted surface (normals facing the axis's side as revolve's).
// Errors (no place): more than `max_triangles`.
Result<io::CadSurface> revolve_faceted(const ProfileCurve& curve, const Facets& facets, const io::CadTessellation& tess,
                                       std::size_t max_triangles, double* size_m = nullptr,
                                       double* chordal_m = nullptr);

}  // namespace gonio::design
