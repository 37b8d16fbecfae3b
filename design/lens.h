// Lenses of revolution in design files (`[[lenses]]`, docs/design.md,
// "Lenses"): a closed solid about the Z axis whose meridian is the inner
// surface (facing the source) from the axis out to its rim, the side from
// that rim to the outer surface's rim, and the outer surface back to the
// axis. Light is meant to travel toward −Z (the nadir): the inner surface
// lies above the outer one.
//
//   [[lenses]]
//   name = "lens"
//   material = "pmma"                 # a dielectric ([materials.pmma] dielectric = 1,
//                                     #   ior = 1.491, or preset = "clear PMMA")
//   vertex = -5                       # z of the inner surface's vertex
//   thickness = 4                     # the centre thickness: the outer vertex is at vertex − thickness
//   aperture = 10                     # ρ of the rims of conic surfaces
//   inner = { profile = "conic", radius = -30, conic = 0, aspheric = [0] }
//   outer = { profile = "conic", radius = 15, conic = -0.5 }
//   side = { profile = "bspline", degree = 2, points = [[14, -12]] }   # optional
//
// Surfaces (design/revolved.h's profiles): `conic`, z = vertex − sag(ρ) over
// ρ 0…aperture (sag positive toward −Z, the direction of travel: R > 0 has
// its centre below the vertex); `bspline`, control points (ρ, z) relative to
// the surface's vertex, the first [0, 0] (the vertex itself); `polar`, r(θ)
// about the origin (the source) from θ = 0 (the nadir), e.g. a sphere
// centred on the source. The side: a straight segment from rim to rim by
// default (a cylinder where both rims have one ρ, none where they meet); or a
// B-spline whose end control points are the two rims and whose `points` are
// the ones between, absolute (ρ, z): a TIR collimator's side (a quadratic
// B-spline is a parabola's arc).
//
// The mesh: each of the three surfaces revolved with its exact normals,
// facing out of the solid, all three with one azimuth count and their rims
// sharing their vertices' positions, so that the solid is closed.
// Errors name the line: unknown keys, a surface that does not start on the
// axis, a lens thinner than zero (its meridian crosses itself, or winds the
// wrong way: the outer surface above the inner one), an emitter on a
// surface or inside the glass.
#pragma once

#include <string>
#include <vector>

#include "design/revolved.h"
#include "io/model/cad_model.h"
#include "io/model/parts_file.h"
#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"
#include "sim/affine.h"

namespace gonio::design {

// A lens of revolution as the file gives it (lengths in metres): its
// meridian as three profiles, each traversed in its own parameter's
// direction: inner from the axis to its rim, side from the inner rim to the
// outer rim, outer from the axis to its rim.
struct Lens {
  std::string name;
  std::string material;
  Profile inner, outer, side;
  bool has_side = true;  // false: the rims meet (a knife edge)
  int line = 0;
  // Placed (keys `position`, `rotate_deg`, as a fixed part's): the lens as
  // defined about the Z axis, turned about the origin (about X, then Y, then
  // Z, the design's axes), then moved by `position` [m]; none: on the axis.
  Vec3 position{0.0, 0.0, 0.0};
  Vec3 rotate_deg{0.0, 0.0, 0.0};
};

// The placement of `lens` (identity where it has none).
sim::Affine lens_transform(const Lens& lens);

// Reads one [[lenses]] table of a resolved document; `unit_m` metres per
// the file's length unit. Errors name `path` and the line.
Result<Lens> read_lens(const io::TomlNode& table, const std::string& path, double unit_m);

// The lens's meridian as a closed polygon (ρ, z) [m], clockwise: `samples`
// points per curve (inner, side, outer reversed); the axis closes it.
std::vector<std::pair<double, double>> lens_meridian(const Lens& lens, std::size_t samples = 1024);

// The lens as a CAD part of one closed surface (inner, side and outer, or
// two without a side, with their own vertices and normals, the rims'
// positions shared) tessellated to `t`, normals outward. Errors: as revolve's.
Result<io::CadPart> lens_part(const Lens& lens, const io::CadTessellation& t, std::size_t max_triangles);

// An emitter placed at `position_m` on a surface (within `chordal_m`) or
// inside the glass: an error message naming it, else empty.
std::string lens_emitter_problem(const Lens& lens, const Vec3& position_m, double chordal_m);

// The lens's meridian for STEP: its curves (inner, side, outer) sampled at
// `samples` equal steps of their parameters [mm], each from the axis or the
// inner rim in the order above.
struct LensCurves {
  std::vector<std::vector<double>> rho, z;  // per curve
};
LensCurves lens_curves_mm(const Lens& lens, int samples);

}  // namespace gonio::design
