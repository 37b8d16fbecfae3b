// The three photometric coordinate systems of IES LM-63 (Types A, B and C)
// as mappings between a direction of the luminaire's local photometric frame
// and the grid angles (horizontal H, vertical V) a file stores.
//
// Local frame (photometry/frame.h): x = C0, y = C90, z = zenith; nadir is −z.
// The conventions follow the key definitions of ANSI/IESNA LM-63-2002 §3:
//
//   photometric zero        the nadir: (H 0°, V 0°) for Types B and C,
//                           (H 0°, V −90°) for Type A;
//   photometric horizontal  the horizontal direction +x: (H 0°, V 90°) for
//                           Types B and C, (H 0°, V 0°) for Type A;
//   photometric planes      Types A and C: vertical half-planes that share the
//                           vertical axis; Type B: planes that share a
//                           horizontal axis (here the y axis, C90–C270);
//   horizontal angles       counter-clockwise seen from above for Type C,
//                           clockwise for Types A and B (+H turns from +x
//                           towards −y, the C270 side).
//
// Type C (interiors, roads): γ from the nadir, C about the vertical axis:
//   d(C, γ) = (sin γ cos C, sin γ sin C, −cos γ),    dΩ = sin γ dγ dC.
// Type A (automotive): the polar axis is vertical, V is the elevation above
// the horizontal plane, H turns about the vertical axis:
//   d(H, V) = (cos V cos H, −cos V sin H, sin V),    dΩ = cos V dV dH,
// so Type A is Type C re-labelled: γ = V + 90°, C = −H (mod 360°).
// Type B (floodlights): the polar axis is horizontal (y). V turns the plane
// through that axis from the nadir (V 0°) towards +x (V 90°); H is the
// latitude in that plane towards the axis, so H = ±90° are the poles ∓y:
//   d(H, V) = (cos H sin V, −sin H, −cos H cos V),   dΩ = cos H dH dV,
// equivalently sin H = −sin γ sin C and tan V = tan γ cos C. A floodlight
// measured in Type B has its beam axis at (0°, 0°), LM-63's photometric
// zero; where it is aimed in a scene is the frame's business
// (PhotometricFrame), not the file's. The LM-63 grid (H and V in −90…90°)
// covers the lower hemisphere z ≤ 0; Type A's covers x ≥ 0.
//
// Every horizontal mirror H → −H (lateral symmetry) is the mirror y → −y,
// i.e. about the C0–C180 plane, for Types A and B alike.
#pragma once

#include "photometry/distribution.h"
#include "photometry/vec3.h"

namespace gonio::photometry {

// Type A or Type B angles of a direction [rad].
struct HV {
  double h_rad;  // horizontal angle H [rad]
  double v_rad;  // vertical angle V [rad]
};

// Local unit direction at Type A angles [rad].
Vec3 direction_from_type_a(double h_rad, double v_rad);
// Type A angles of a local direction (need not be unit, must be non-zero):
// H in (−π, π], V in [−π/2, π/2]; H = 0 at the poles (V = ±π/2).
HV type_a_from_direction(const Vec3& local);

// Local unit direction at Type B angles [rad].
Vec3 direction_from_type_b(double h_rad, double v_rad);
// Type B angles of a local direction (need not be unit, must be non-zero):
// H in [−π/2, π/2], V in (−π, π]; V = 0 at the poles (H = ±π/2).
HV type_b_from_direction(const Vec3& local);

// The grid angles a distribution of `type` stores, in degrees:
// Type C: (C, γ); Types A and B: (H, V).
struct GridAngles {
  double horizontal_deg;  // C or H [deg]
  double vertical_deg;    // γ or V [deg]
};

// Local unit direction at grid angles [deg] of the given type.
Vec3 direction_from_grid(PhotometricType type, double horizontal_deg, double vertical_deg);
// Grid angles [deg] of a local direction (need not be unit, must be
// non-zero). Type C: C in [0, 360), γ in [0, 180]; Type A: H in (−180, 180],
// V in [−90, 90]; Type B: H in [−90, 90], V in (−180, 180].
GridAngles grid_from_direction(PhotometricType type, const Vec3& local);

// Solid angle per unit of grid angles, dΩ / (dH dV) [sr/rad²], at grid angles
// [rad]: sin γ for Type C, cos V for Type A, cos H for Type B.
double solid_angle_jacobian(PhotometricType type, double horizontal_rad, double vertical_rad);

// Intensity [cd] of a distribution returned by expand_symmetry() toward a
// local direction (need not be unit, must be non-zero): interpolate() at the
// direction's grid angles, so 0 where the grid holds no data.
double intensity_toward(const Distribution& expanded, const Vec3& local);

}  // namespace gonio::photometry
