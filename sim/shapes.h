// Mesh builders: the shapes luminaires are made of, as plain triangle meshes
// (sim::Mesh), and the measures tests and emitters need (area, volume).
//
// Conventions shared by every builder:
// - Metres. Shapes are built around the origin with +Y (glTF's up) as their
//   axis; place them with transform().
// - Triangles wind counter-clockwise seen from the front side. Closed shapes
//   face outwards; each open shape says which side is its front.
// - Closed shapes are watertight by index: every edge is shared by exactly
//   two triangles with opposite directions, except where a lathe profile has
//   a crease and shading normals are on (there vertices are duplicated so
//   each side keeps its own normal; welding positions closes the mesh again).
// - Smooth shapes carry unit shading normals (front side) and, for surfaces
//   of revolution, unit tangents around the axis (the direction of an
//   anisotropic lobe's `glossy_mx`). Flat shapes (box, slab) carry none.
// - Bad arguments (non-positive sizes, too few segments, negative radii) are
//   programming errors and stop through GONIO_CHECK.
#pragma once

#include <span>

#include "sim/affine.h"
#include "sim/scene.h"

namespace gonio::sim {

// One point of a lathe profile in the half-plane r ≥ 0 of the XY plane.
struct ProfilePoint {
  double r_m;  // distance from the Y axis [m], ≥ 0
  double y_m;  // height along the Y axis [m]
};

struct LatheOptions {
  int segments = 64;               // facets around the axis, ≥ 3
  bool closed_profile = false;     // the last profile point joins the first
  bool shading_normals = true;     // smooth normals (and tangents); off: flat facets
  double crease_angle_deg = 30.0;  // profile corners turning more than this stay sharp
};

// Surface of revolution of a profile about the Y axis (a right-handed turn
// about +Y). The front side is on the right of the direction of travel in
// the (r, y) half-plane, i.e. its normal is (dy, −dr): a profile walked from
// the south pole up to the north pole faces outwards. Points on the axis
// (r = 0) become single pole vertices; consecutive points must differ.
Mesh lathe(std::span<const ProfilePoint> profile, const LatheOptions& options = {});

// Flat disc of radius `radius_m` in the plane y = 0, centred on the axis,
// facing +Y (a regular polygon of `segments` sides).
Mesh disc(double radius_m, int segments = 64);

// Closed sphere centred at the origin: `rings` latitude bands from pole to
// pole, `segments` around the Y axis; vertices lie exactly on the sphere and
// carry exact normals.
Mesh sphere(double radius_m, int segments = 64, int rings = 32);

// Closed axis-aligned box centred at the origin, 12 triangles.
Mesh box(double size_x_m, double size_y_m, double size_z_m);

// A rectangular slab: a box of `thickness_m` along Y, centred at the origin,
// its large faces at y = ±thickness/2.
Mesh slab(double size_x_m, double size_z_m, double thickness_m);

// Ideal paraboloid reflector with its focus at the origin, opening towards
// −Y: y = f − ρ²/(4f) for ρ from `hole_radius_m` (0: no hole, the vertex at
// (0, f, 0) is closed) to `aperture_radius_m`. `rings` bands along ρ,
// `segments` around the axis; vertices lie on the ideal surface with exact
// normals. The front (reflecting) side faces the focus.
Mesh paraboloid(double focal_length_m, double aperture_radius_m, double hole_radius_m,
                int rings = 64, int segments = 128);

// transform(Mesh&, const Affine&): sim/scene.h.

// Swaps front and back: reverses the winding and negates shading normals.
void flip(Mesh& mesh);

// Area of one triangle [m²] and its unit normal on the front side.
double triangle_area_m2(const Mesh& mesh, std::size_t triangle);
Vec3 triangle_normal(const Mesh& mesh, std::size_t triangle);

// Total area of all triangles [m²].
double surface_area_m2(const Mesh& mesh);

// Signed volume [m³] enclosed by a closed mesh (divergence theorem),
// positive when the front side faces outwards. Meaningless for open meshes.
double enclosed_volume_m3(const Mesh& mesh);

}  // namespace gonio::sim
