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
// faceted one converges to it as N and M grow.
//
// Curved facets: kind = "curved", with `radius_theta` and/or `radius_azimuth`
// (signed, in the file's length unit; absent: flat that way):
//   - along the profile, each facet's meridian is the circular arc of radius
//     |radius_theta| through its two end rows' points (ρ, z), the chord's
//     flat facet bent: R > 0 concave seen from the lit side (the side the
//     normals face: the arc's centre lies on it), R < 0 convex; the band is
//     that arc turned about the axis (a toroidal band) or, faceted around
//     too, cut by the sector;
//   - around the axis, at every point of the meridian (the arc, the chord or
//     the exact profile) the sector's chord between its two meridians is
//     bent into the circular arc of radius |radius_azimuth| through the
//     chord's ends, in the plane of the chord and the flat facet's normal
//     there, with the same sign rule (a cylinder-like patch across the
//     sector).
// A radius smaller than half a facet's chord is an error. Tessellated from
// the output's needs (sub-rows every δ/4 of the arc's turn along the
// profile, sub-columns every δ around, and the chordal deflection), every
// vertex on the curved facet with its exact normal (the cross product of the
// surface's partial derivatives, taken by central differences of the exact
// parametrisation). A curved facet of radius → ∞ is the flat one.
#pragma once

#include <cmath>
#include <vector>

#include "design/revolved.h"
#include "io/model/cad_model.h"
#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"
#include "photometry/vec3.h"

namespace gonio::design {

struct Facets {
  int theta = 0;    // facets along the profile; 0: smooth
  int azimuth = 0;  // facets around the axis; 0: smooth
  bool curved = false;                 // kind = "curved"
  double radius_theta = INFINITY;      // [m], signed; ∞: flat along the profile
  double radius_azimuth = INFINITY;    // [m], signed; ∞: flat around
  int line = 0;                        // the facets table's line
  int radius_theta_line = 0;           // radius_theta's line (0: not given)
  int radius_azimuth_line = 0;         // radius_azimuth's line (0: not given)
};

// The exact surface of a faceted reflector as patches: one per facet
// (band i of `bands` along the profile, sector j of `sectors` around), each
// parametrised by u ∈ [0, 1] along the profile and v ∈ [0, 1] around
// (increasing azimuth). Where smooth along the profile there is one band,
// the whole profile; where smooth around, `sectors` = 4 quarter turns.
class FacetSurface {
 public:
  // Errors: a radius smaller than half a facet's chord, at the radius's
  // line (where.line, the entry that is wrong; no file: the caller's).
  static Result<FacetSurface> make(const ProfileCurve& curve, const Facets& facets);
  int bands() const { return bands_; }
  int sectors() const { return sectors_; }
  // Point [m] and unit normal (facing the lit side) of patch (i, j) at (u, v).
  void eval(int i, int j, double u, double v, Vec3& p, Vec3& n) const;
  // The arc's (or chord's, or profile's) point and derivative in the
  // meridian half plane of band i at u [m].
  void meridian(int i, double u, double& rho, double& z, double& drho, double& dz) const;
  double side() const { return side_; }

 private:
  const ProfileCurve* curve_ = nullptr;
  Facets facets_;
  int bands_ = 1, sectors_ = 4;
  double side_ = 1.0;
  std::vector<double> row_t_, row_rho_, row_z_;  // the facets' end rows (theta > 0)
  // Per band along the profile where curved: the chord's middle, its unit
  // direction, the unit direction from the arc's centre to the middle, and
  // the arc's half angle asin(c/2|R|).
  std::vector<double> mr_, mz_, tr_, tz_, dr_, dz_, alpha_;
};

// The `facets` table of a reflector (`unit_m`: metres per the file's length
// unit, for the radii). Errors name `path` and the line.
Result<Facets> read_facets(const io::TomlNode& facets, const std::string& path, const std::string& what,
                           double unit_m = 1.0);

// The faceted surface (normals facing the axis's side as revolve's).
// Errors (no place): more than `max_triangles`.
Result<io::CadSurface> revolve_faceted(const ProfileCurve& curve, const Facets& facets, const io::CadTessellation& tess,
                                       std::size_t max_triangles, double* size_m = nullptr,
                                       double* chordal_m = nullptr);

}  // namespace gonio::design
