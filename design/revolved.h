// Surfaces of revolution about the Z axis from a meridian profile, and their
// tessellation with exact-surface normals (design files, design/design_file.h).
//
// A profile is a curve (ρ(t), z(t)) in the half plane ρ ≥ 0, in metres:
//   - conic: z(ρ) = vertex − sag(ρ), sag = cρ²/(1 + √(1 − (1+κ)c²ρ²)) + Σ a₂ᵢρ²ⁱ
//     (i ≥ 2), t = ρ over [ρ_inner, ρ_outer];
//   - polar: r(θ) about the origin, θ from the nadir (−Z): (ρ, z) = r·(sin θ,
//     −cos θ), t = θ; ln r is a cubic spline through the table (clamped, end
//     slopes from the three nearest nodes), so the curve and its normal are
//     smooth between the nodes;
//   - bspline: a clamped B-spline through control points (ρ, z), t over [0, 1]
//     (a profile that crosses itself or has a cusp is an error).
//
// Tessellation from the output's needs (the rule of CAD parts,
// io::CadTessellation, made finer along the profile): a new row wherever the
// tangent has turned by δ/4 (δ the angular deflection) or the chord would
// leave the curve by more than the chordal deflection; around the axis the
// azimuth step is at most δ and the chord of the widest circle within the
// chordal deflection. Every vertex lies on the exact surface and carries the
// exact normal. Why δ/4 along the profile: on a designed reflector traced
// against its exact target on a 1° grid (δ = 0.8°; docs/design.md) rows every
// δ left 0.12 % RMS of the peak, δ/4 0.009 %, while a 4× finer azimuth
// changed nothing (0.10 %).
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "io/model/cad_model.h"
#include "photometry/diagnostics.h"

namespace gonio::design {

struct ConicProfile {
  double radius = 0.0;            // R at the vertex [m]; c = 1/R (0: a flat sag, aspherics only)
  double conic = 0.0;             // κ
  std::vector<double> aspheric;   // a4, a6, … [m^(1−2i)]
  double vertex = 0.0;            // z of the vertex [m]
  double inner = 0.0, outer = 0.0;  // ρ range [m]
};

struct PolarProfile {
  std::vector<double> theta;      // [rad], increasing, in [0, π]
  std::vector<double> r;          // [m], > 0
};

// A clamped B-spline through control points (ρ, z) of the meridian half
// plane, uniform knots, t over [0, 1]; degree 1…5, at least degree + 1
// points, every ρ ≥ 0 (the curve stays in its control points' hull).
struct BSplineProfile {
  int degree = 3;
  std::vector<double> rho, z;     // [m]
};

using Profile = std::variant<ConicProfile, PolarProfile, BSplineProfile>;

// The profile as a curve: point, derivative and normal at t.
class ProfileCurve {
 public:
  // Errors (without a place: the caller names the file and line): a conic
  // undefined over its aperture, a table out of order.
  // A profile whose points are not finite or beyond 10⁶ m is an error too.
  static Result<ProfileCurve> make(const Profile& profile);

  double t0() const { return t0_; }
  double t1() const { return t1_; }
  // (ρ, z) [m] and d(ρ, z)/dt.
  void eval(double t, double& rho, double& z, double& drho, double& dz) const;
  // A degree-1 B-spline: straight spans whose tangent jumps at the knots.
  bool piecewise_linear() const;

 private:
  static Result<ProfileCurve> make_unchecked(const Profile& profile);
  Profile profile_;
  double t0_ = 0.0, t1_ = 0.0;
  std::vector<double> slope_;  // polar: d ln r/dθ at the nodes
};

// r(θ) of a polar table between its nodes (the spline above) and d ln r/dθ.
double polar_r(const PolarProfile& p, double theta, double* dlnr = nullptr);

// The profile sampled at 4096 equal steps of t, with the tangent's angle
// atan2(dz, dρ) unwrapped along it; the rows the tessellation keeps (indices
// into the samples: a new row wherever the tangent has turned by δ/4 or the
// chord leaves the curve by more than `chordal_m`; first and last always);
// (a piecewise-linear profile's rows straddle every knot where its tangent
// turns, so that each span's facets carry that span's own normal: rows
// between the knots, with the normal of whichever span a row fell in,
// biased every shading normal by up to a span's turn — a 200-point polyline
// CPC traced 9 % over its closed form on the axis, docs/design.md);
// and the side (+1 or −1) for which side · (dz, −dρ)/|·| faces the origin
// over the profile as a whole. revolve() and the troughs (design/trough.h)
// share them.
struct ProfileSample {
  double t = 0.0, rho = 0.0, z = 0.0, drho = 0.0, dz = 0.0, angle = 0.0;
  bool corner = false;  // a knot where the tangent turns lies between the previous sample and this one
};
std::vector<ProfileSample> sample_profile(const ProfileCurve& curve);
std::vector<std::size_t> profile_rows(const std::vector<ProfileSample>& fine, double delta_rad, double chordal_m);
double normal_side(const std::vector<ProfileSample>& fine);
// The size of a surface of revolution whose profile reaches ρ_max and spans
// z_min … z_max (its bounding box's diagonal, √(8ρ_max² + Δz²), as a CAD
// part's) and the chordal deflection `tess` gives it [m]: tess.chordal_m,
// or its relative deflection of the size, at least chordal_min_m.
struct RevolvedExtent {
  double size = 0.0, chordal = 0.0;
};
RevolvedExtent revolved_extent(double rho_max, double z_min, double z_max, const io::CadTessellation& tess);
// Steps around the axis: at most δ, and the chord of the widest circle
// (radius rho_max) within the chordal deflection; at least 8.
std::size_t azimuth_segments(double rho_max, double delta_rad, double chordal_m);

// The surface of revolution of `curve`, tessellated to `t` (CadTessellation's
// angular and chordal deflections; its size for the relative chordal
// deflection is the surface's bounding-box diagonal), normals facing the
// Z axis's side of the profile where `normals_toward_origin`, and the
// triangles wound counter-clockwise seen from the side the normals face.
// Errors: more than `max_triangles` (a deflection too fine for the part).
// `extra`: a lens's surfaces (design/lens.h) share one azimuth count, so that
// their rims meet vertex for vertex, and each faces out of the solid.
struct RevolveOptions {
  int normal_side = 0;       // 0: toward the origin; ±1: normal = ±(dz, −dρ)/|·| along t
  std::size_t segments = 0;  // 0: from the deflections; else exactly this many around the axis
};
Result<io::CadSurface> revolve(const ProfileCurve& curve, const io::CadTessellation& t, std::size_t max_triangles,
                               double* size_m = nullptr, double* chordal_m = nullptr,
                               const RevolveOptions& extra = {});

// Whether the segments ab and cd cross (properly: touching ends do not).
bool segments_cross(double ax, double ay, double bx, double by, double cx, double cy, double dx, double dy);

// The smallest distance from the point (ρ, z) to the profile [m].
double distance_to_profile(const ProfileCurve& curve, double rho, double z);

}  // namespace gonio::design
