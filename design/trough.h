// Extruded trough reflectors of a design file (design/design_file.h) for
// linear luminaires:
//
//   [[troughs]]
//   name = "trough"
//   material = "mirror"
//   profile = "conic"                  # the reflectors' profiles (conic, polar,
//   radius = 20                        #   bspline) with their keys, in the XZ
//   conic = -1                         #   cross-section: ρ is |x|
//   vertex = 10
//   aperture = [0, 30]
//   length = 600                       # along Y, centred on the origin
//   symmetric = true                   # the profile and its mirror image x → −x
//                                      #   (false: the side x ≥ 0 alone)
//   caps = "white"                     # flat end caps at y = ±length/2 of this
//                                      #   material (absent: open ends)
//
// The profile is the reflectors' (design/revolved.h) with ρ read as |x|:
// (x, z) = (±ρ(t), z(t)), extruded along Y. Tessellated on the exact surface
// with exact normals (n_x, 0, n_z): rows across the profile by the
// reflectors' rule (revolved.h's profile_rows), and along Y one span — the
// surface is straight along Y, so more columns would change nothing. The
// caps close the region between the two halves (between the profile and
// x = 0 for a one-sided trough), as strips between consecutive rows, normals
// into the trough.
#pragma once

#include <optional>
#include <string>

#include "design/revolved.h"
#include "io/model/cad_model.h"
#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"

namespace gonio::design {

struct Trough {
  std::string name;
  std::string material;
  std::string caps;        // the caps' material; empty: open ends
  int caps_line = 0;
  Profile profile;         // ρ is |x| [m]
  double length = 0.0;     // along Y [m]
  bool symmetric = true;
  int line = 0;
};

// A [[troughs]] table (variables resolved; lengths × unit_m). Errors name
// `path` and the line: unknown keys, a length not > 0, the profile's own.
Result<Trough> read_trough(const io::TomlNode& t, const std::string& path, double unit_m);

struct TroughMesh {
  io::CadSurface reflector;
  std::optional<io::CadSurface> caps;
  double size_m = 0.0;     // bounding-box diagonal
  double chordal_m = 0.0;  // the chordal deflection used
};

// The trough tessellated to `tess` (CadTessellation's deflections; the
// relative chordal deflection of its bounding-box diagonal). Errors (no
// place: the caller names it): more than `max_triangles`.
Result<TroughMesh> tessellate_trough(const Trough& trough, const io::CadTessellation& tess, std::size_t max_triangles);

// The smallest distance from the point p [m] to the trough's surface (its
// caps left out).
double distance_to_trough(const Trough& trough, const Vec3& p);

}  // namespace gonio::design
