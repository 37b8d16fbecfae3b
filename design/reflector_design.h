// Direct design of a reflector of revolution for a point source and a
// rotationally symmetric target (`gonio design reflector`, docs/design.md).
//
// Angles: θ is the emitter's γ (from the nadir, −Z) of a ray leaving the
// source at the origin; φ the γ of the reflected ray, signed in the meridian
// half-plane of the reflector point: φ > 0 on the point's own side of the
// axis, φ < 0 across it.
//
// 1. The emitter's intensity I_s(θ) and the target's T(φ) are averaged over C.
// 2. Light the reflector does not catch leaves directly: D(φ) = I_s(φ) for
//    φ < θ_from. The reflector must add R(φ) = s·T(φ) − D(φ), where s scales
//    the target to the flux that leaves (direct + reflectance × the cone's; or s = 1 with
//    `absolute`, where the target's candela are meant as they are). A target
//    below the direct light somewhere (R < 0, by more than 1 % of the
//    reflected flux in all) cannot be made by adding light: an error says where.
// 3. The energy-conserving map: |φ(θ)| = G⁻¹(1 − F(θ)), F the emitter's
//    cumulative flux over the cone [θ_from, θ_to], G the cumulative of R
//    from φ = 0: the cone's inner edge goes to the target's outer edge.
//    Uncrossed: φ ≥ 0, φ decreasing in θ (reflected rays diverge as from a
//    virtual image, like a hyperbola's); crossed: φ ≤ 0, φ increasing in θ
//    (reflected rays cross the axis and each other, like an ellipse's).
// 4. The profile: d(ln r)/dθ = cot((φ − θ)/2), integrated with RK4 from
//    r(θ_to) = distance toward θ_from on a fine grid. Where φ − θ changes sign
//    the profile would pass through the source or run to infinity: an error
//    (uncrossed maps only; a crossed map has φ − θ < 0 throughout).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "design/flux_map.h"
#include "design/revolved.h"
#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::design {

enum class ReflectorMap { Uncrossed, Crossed };

struct ReflectorDesignOptions {
  double from_deg = 45.0;   // the emitter cone the reflector catches: θ from…
  double to_deg = 180.0;    // …to [deg]
  ReflectorMap map = ReflectorMap::Uncrossed;
  double distance_m = 0.02;  // r(θ_to) [m]
  int nodes = 61;            // the polar table's points (the design file's variables)
  int steps = 20000;         // RK4 steps over the cone
  bool absolute = false;     // the target's candela as they are, not scaled to the flux that leaves
  double reflectance = 1.0;  // of the mirror: the reflected flux is reflectance × the cone's
  // Where the target asks less than the direct light, the reflector adds
  // nothing there instead of an error: the feedback's corrected targets
  // (feedback_target), where an extended emitter's direct light spreads
  // beyond the point source's.
  bool allow_deficit = false;
};

struct ReflectorDesign : FluxMapFigures {  // direct light: θ < θ_from
  PolarProfile profile;                // the table: `nodes` points over the cone [rad, m]
  std::vector<double> theta, phi, r;   // the fine solution: steps + 1 points [rad, rad, m]
};

// Designs the profile; errors say why no reflector of this kind can give
// the target (without a file or line: the caller names its inputs).
Result<ReflectorDesign> design_reflector(const photometry::Distribution& emitter,
                                         const photometry::Distribution& target,
                                         const ReflectorDesignOptions& options);

// The design file of a designed reflector (design/design_file.h), lengths in
// millimetres: [materials.reflector] a specular mirror of `reflectance`, one
// emitter at the origin with the profile `emitter_file` (a path relative to
// the design file), and [[reflectors]] `name` with the polar table, each r a
// variable bounded to [0.8 r, 1.25 r] for an optimiser to refine.
// `emitter_key`: "profile" (a photometric file) or "ray_file" (a TM-25 ray file).
io::TomlNode reflector_design_document(const ReflectorDesign& design, const std::string& emitter_file,
                                       double reflectance, const std::string& name,
                                       const std::string& emitter_key = "profile");

// The mean over C of a distribution's intensity at γ [cd].
double rotational_intensity(const photometry::Distribution& expanded, double gamma_deg);

// A rotationally symmetric Type C distribution with these intensities on γ
// (increasing, 0…180) [deg, cd]: targets made from formulas.
photometry::Distribution rotational_distribution(const std::vector<double>& gamma_deg,
                                                 const std::vector<double>& candela);

// The exact case: the intensity a linear map φ = kθ + c (signed, as above)
// makes of the emitter's light caught over [from, to] (I_t(|φ|) =
// I_s(θ)·sin θ/(|k|·|sin φ|)) plus the direct light below `from`, on a γ grid
// of `step_deg`; and the reflector r(θ) = r₀·|sin(((k − 1)θ + c)/2)|^(2/(k − 1))
// with r(to) = distance.
photometry::Distribution linear_map_target(const photometry::Distribution& emitter, double k, double c_rad,
                                           double from_deg, double to_deg, double step_deg = 0.05);
double linear_map_r(double k, double c_rad, double theta, double to_rad, double distance_m);

// Extended emitters (docs/design.md "Extended emitters: feedback").
//
// A die of width × height [m] centred on the origin in the XY plane (facing
// along the emitter's axis), every point of it emitting the emitter's
// intensity distribution averaged over C (a uniform die of that
// distribution): `count` rays of equal flux, 7 floats each as
// io::make_luminous_ray_set takes them (x y z [mm], kx ky kz, flux [lm]).
// γ stratified over the C-averaged distribution's cumulative flux (ray i at
// the quantile (i + ½)/count), C by the golden ratio, positions from a
// fixed-seed generator: the same rays every time.
std::vector<float> die_rays(const photometry::Distribution& emitter, double width_m, double height_m,
                            std::size_t count);

// The next design target of the feedback: the multiplicative correction
// T_{n+1}(γ) = T_n(γ) · T̄(γ_j)/(s·P(γ_j)), the ratio taken on the traced
// grid's nodes γ_j (T̄ the target averaged over node j's γ band as the trace
// bins it, P the traced intensity averaged over C, s = the target's flux over
// the traced one's) and interpolated linearly between them, clamped to
// [1/2, 2], 1 where either is zero; then scaled to T_n's flux. `design_target`
// is T_n (what the last design was made for), `target` the user's T, `traced`
// the last design traced. A rotationally symmetric distribution on the
// γ grid of `step_deg`.
//
// `share` (optional, γ [deg] → [0, 1]): how much of the target at γ is the
// part's own light; the ratio there is taken to that power, T̄/(sP) →
// (T̄/(sP))^share, so that where the target is the direct light the part
// cannot move (a step where the part's rim cuts it, blurred by an extended
// source) the design target is left as it is (design_share). Without it, 1.
photometry::Distribution feedback_target(const photometry::Distribution& design_target,
                                         const photometry::Distribution& target,
                                         const photometry::Distribution& traced, double step_deg = 0.01,
                                         const std::function<double(double)>& share = {});

// The feedback's correction in cumulative-flux space (--correction
// cumulative): each share u of the flux, which the target puts at γ_T(u)
// and the trace at γ_P(u) (the quantiles of their C-averaged cumulative
// fluxes, the trace's scaled to the target's), is moved in the design's
// target from γ_n(u) to γ_n(u) + γ_T(u) − γ_P(u) (kept increasing in u); the
// corrected target is that cumulative's intensity on the γ grid of
// `step_deg`, at T_n's flux. A trace equal to the target leaves T_n as it is;
// a trace whose light lies δ further out moves T_n's light δ inward.
photometry::Distribution feedback_target_cumulative(const photometry::Distribution& design_target,
                                                    const photometry::Distribution& target,
                                                    const photometry::Distribution& traced, double step_deg = 0.01);

// The share of the part's own light in the target at γ [deg]: 1 − D/(s·T)
// clamped to [0, 1], D the emitter's intensity averaged over C where it
// leaves directly (outside [from, to]: γ < from, and γ > to where
// `direct_above_to`), s the design's target scale; 0 where the target is dark.
double design_share(const photometry::Distribution& emitter_expanded, const photometry::Distribution& target_expanded,
                    double gamma_deg, double from_deg, double to_deg, bool direct_above_to, double target_scale);

// 1 where the target (averaged over C) has no step within `band_deg` of γ,
// 0 where it has one: a change of more than `jump` times `peak_cd` between
// two γ 1° apart. An extended source blurs a step over a few degrees, and a
// correction there asks the map for light on the step's wrong side, where
// the profile is most sensitive to it (docs/design.md, "Targets with steps").
double away_from_steps(const photometry::Distribution& target_expanded, double peak_cd, double gamma_deg,
                       double band_deg = 3.0, double jump = 0.1);

// The factor that brings `traced`'s flux where `target` has light (the γ
// where the target averaged over C is above 10⁻⁶ of its peak) to the
// target's flux there: a trace scaled by it is compared for the shape of its
// beam, its stray light (a lens's Fresnel reflections, which no design can
// send into the beam) not taken off the beam as flux normalisation does.
// 1 where either has no light there.
double in_target_scale(const photometry::Distribution& target, const photometry::Distribution& traced);

// Largest |r_b/r_a − 1| between two profiles of the same θ nodes (∞ when they differ in size).
double profile_change(const PolarProfile& a, const PolarProfile& b);

}  // namespace gonio::design
