// Luminous flux of a distribution by solid-angle integration of its candela
// grid: total flux, flux in any zone of vertical angle, downward and upward.
//
// The quadrature (one model of I for every function here):
//
// - Along each plane (γ for Type C, V for Types A and B) I is modelled by a
//   piecewise-cubic Hermite curve through the stored values and integrated
//   exactly against the solid-angle weight (sin γ, cos V, or 1 for Type B,
//   whose weight cos H lies across the planes). Node slopes are the
//   three-point (parabolic) estimates for non-uniform spacing, limited as in
//   Fritsch–Carlson/Hyman: zero at local extrema and flat runs, at most three
//   times either neighbouring secant slope. The curve therefore never leaves
//   the range of its two end values on any interval: no overshoot, never
//   negative for non-negative data, and on under-resolved peaks or hard
//   cut-offs it gives what the piecewise-linear model gives (the integral of
//   a one-sample spike is within a few per cent of the trapezoid's). Where a
//   smooth flank runs into a dark region (I = 0, e.g. the horizon of a
//   Lambertian downlight) the flank keeps its own one-sided slope, so such
//   kinks cost nothing.
// - Across planes: Type C uses the trapezoid rule in C over the planes of
//   expand_symmetry() (the exact integral of the linear interpolation between
//   planes that interpolate() uses; for the periodic C direction it converges
//   faster than any power of the step for smooth data). Types A and B use the
//   Hermite rule across H as well (weight 1 for Type A, cos H for Type B).
// - Symmetric files are integrated as their expansion: a quadrant file and its
//   expanded full version give the same flux to rounding.
// - Unmeasured directions (outside the stored angle ranges) emit nothing.
//
// Accuracy against closed forms (Type C, γ over 0…180°, I = I₀ cosⁿγ on the
// lower hemisphere, 0 above; relative error of Φ = 2πI₀/(n + 1)):
//
//      γ step     n = 1     n = 2     n = 5     n = 10    n = 20
//      5°        4e-6      8e-6      2.4e-5    7.4e-5    2.2e-4
//      2.5°      2.4e-7    4.4e-7    1.6e-6    5.2e-6    1.8e-5
//      1.25°     1.5e-8    2.5e-8    1.0e-7    3.4e-7    1.2e-6
//
// i.e. fourth order in the step for smooth data (the piecewise-linear model
// errs by 0.16 % for n = 10 and 0.32 % for n = 20 at 2.5°). Isotropic data is
// exact. The same lobes sampled as Type B on 5° × 5° (H, V) grids err by
// less than 2e-6. tests/photometry/flux_test.cpp holds these figures to
// account.
//
// Cost: O(stored intensities) — each stored plane is integrated once, however
// many planes its symmetry expands to — plus O(planes · log planes) for the
// symmetry bookkeeping; the expanded grid is never built. About 5 ns per
// stored intensity (benchmarks/flux_benchmark.cpp).
#pragma once

#include "photometry/distribution.h"

namespace gonio::photometry {

// Total luminous flux [lm]: the integral of I over the sphere. For relative
// photometry this is the flux of the luminaire fitted with its rated lamps
// (the candela are stored that way); for absolute photometry, the measured
// flux. Requires validate(d).ok().
double total_flux_lm(const Distribution& d);

// Flux [lm] emitted into the zone of directions whose angle from the nadir
// lies in [gamma_from_deg, gamma_to_deg] (clamped to 0…180°; an empty zone
// gives 0). Type C and Type A (γ = V + 90°) integrate the same model as
// total_flux_lm() over the zone exactly, so adjacent zones add up to the
// whole to rounding. Type B zones do not follow its grid lines: their share
// of the total comes from a 0.5° × 0.5° Type C resampling and is scaled to
// total_flux_lm(), so they add up to the total as well.
// Requires validate(d).ok().
double zonal_flux_lm(const Distribution& d, double gamma_from_deg, double gamma_to_deg);

// Flux below the horizontal (γ 0…90°) and above it (γ 90…180°) [lm].
double downward_flux_lm(const Distribution& d);
double upward_flux_lm(const Distribution& d);

// Many zones of one distribution: the preparation (for Type B, the
// resampling) is done once. zone_lm(a, b) == zonal_flux_lm(d, a, b) and
// total_lm() == total_flux_lm(d). Holds a copy of what it needs, so `d` may
// go away. Requires validate(d).ok().
class ZonalFlux {
 public:
  explicit ZonalFlux(const Distribution& d);
  double total_lm() const { return total_lm_; }
  double zone_lm(double gamma_from_deg, double gamma_to_deg) const;

 private:
  Distribution grid_;   // d, or for Type B its Type C resampling
  double total_lm_;     // total_flux_lm(d)
  double scale_ = 1.0;  // total_lm_ over the flux of grid_ (Type B)
};

}  // namespace gonio::photometry
