// What gonio asks the helper gonio-cad to write as STEP (io/model/cad.h's
// export_step; io/model/step.h's write_step_file): named surfaces of
// revolution about the Z axis, each given by points of its meridian profile
// (ρ, z) that the helper approximates by a B-spline curve within a stated
// tolerance and turns about the axis. Plain data and its text form (the
// request file the helper reads), so that only the helper links
// OpenCASCADE.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::io {

struct StepRevolvedPart {
  std::string name;              // the part's product name (XCAF name)
  std::vector<double> rho, z;    // the profile's points in order [mm], ρ ≥ 0
  // Empty: one open profile, a face of revolution (a reflector). Else a
  // solid (a lens, design/lens.h): the points are several curves end to
  // end, each starting at these indices (the first 0; a curve's last point
  // is the next one's first), from the axis back to the axis; the segment
  // along the axis closes the meridian, which is turned into a solid.
  std::vector<std::size_t> curves;
  // > 0: an extruded part (a trough) instead: the points are (x, z) of the
  // XZ plane (x of either sign), extruded along +Y by this length [mm] from
  // y = −extrude_mm/2; 0: turned about the Z axis.
  double extrude_mm = 0.0;
  // Not empty: a cover (design/cover.h) made of OpenCASCADE's primitives
  // instead, no points: "box" (a = x, b = y), "disc" (a = diameter) or
  // "dome" (a = the base's diameter, b = the signed sag), its face toward
  // the luminaire at z [mm], a solid of thickness t below it (a dome: inward
  // of its outer sphere) or, t = 0, one face.
  std::string cover{};
  double cover_a = 0.0, cover_b = 0.0, cover_t = 0.0, cover_z = 0.0;  // [mm]
  // Not empty: planar faces instead, no points (a trough's end caps, a
  // reflector's flat facets): polygons of these corner counts (≥ 3), their
  // corners (x, y, z) [mm] one after another in `corners`, each polygon a
  // plane face, all sewn into one shell.
  std::vector<std::size_t> faces{};
  std::vector<double> corners{};  // x, y, z per corner
  // Not empty: B-spline patches (a reflector's curved facets, or facets one
  // way only), sewn with the planar faces above into the same shell, no
  // points: grids of nu × nv points on the exact surface, (nu, nv) ≥ 2 per
  // patch here, the points (x, y, z) [mm] in `patch_points`, nv per row, nu
  // rows; each patch a B-spline surface within the tolerance of its points.
  std::vector<std::size_t> patches{};  // nu, nv per patch
  std::vector<double> patch_points{};  // x, y, z per point
  // Not empty: a CAD file (STEP or IGES, an absolute path) whose free shapes
  // the helper reads and places by `place` (a 3 × 4 matrix, rows, [mm]:
  // rotation times a uniform scale, then the translation), each a part
  // "NAME/<its name>"; no points (a design's fixed part, design/fixed_part.h).
  // `place` without `file`: the part made from its points (a lens's solid)
  // placed so.
  std::string file{};
  std::vector<double> place{};  // 12 numbers
};

struct StepExport {
  std::string product;           // the assembly's name, above the parts
  double tolerance_mm = 1e-3;    // the B-spline's largest distance from the points
  std::vector<StepRevolvedPart> parts;
};

// The request as text: a header line, then per part its name on one line,
// for an extruded part a line "extrude L", for planar faces a line "faces N"
// and a line per face (its corner count, then x y z per corner), for
// patches a line "patches N" and a line per patch (nu nv, then x y z per
// point), for a placed file a line "file PATH" and a line "place" with 12
// numbers, and its
// points one per line (names lose their line breaks).
std::string serialize_step_export(const StepExport& request);

// Reads the text back; `name` names it in messages. Errors: a malformed or
// truncated request, text after its last part, points not finite, ρ < 0,
// fewer than 2 points.
Result<StepExport> parse_step_export(std::string_view text, const std::string& name);

}  // namespace gonio::io
