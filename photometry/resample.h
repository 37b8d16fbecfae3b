// Resampling a distribution of any photometric type onto a regular Type C
// grid: how Type A and B data become EULUMDAT-ready (LDT is Type C only),
// and how two distributions are brought to one grid for comparison.
#pragma once

#include <optional>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::photometry {

struct TypeCGrid {
  // Spacing of the C-planes [deg]; must divide the C range of the output
  // symmetry (360°, 180° or 90°) into whole steps.
  double c_step_deg = 5.0;
  // Spacing of the γ angles [deg]; must divide 90° into whole steps, so that
  // the horizontal is a grid angle and downward and upward flux stay apart.
  double gamma_step_deg = 2.5;
  // The planes to produce. Unset: Type C input keeps its symmetry; Types A
  // and B map lateral symmetry (a mirror about the C0–C180 plane, see
  // photometry/angles.h) to Symmetry::C0_C180 and none to Symmetry::None.
  // Asking for more symmetry than the data has keeps only the stored range
  // of C (Symmetry::Rotational keeps the mean over C at each γ).
  std::optional<Symmetry> symmetry;
  // Cover γ 0…180° whatever the data measured (unmeasured directions are 0),
  // so that grids of different distributions coincide.
  bool whole_sphere = false;
};

// The distribution `d` sampled on `grid`: planes C = 0, step, … over the
// symmetry's range (0…360° inclusive for Symmetry::None, 0…90° for
// quadrant, 0…180° for C0–C180, 90…270° for C90–C270, the single plane 0° for
// rotational), and γ over the smallest whole-step range that holds every
// measured direction (Type B: 0…90°; Type A: V + 90° snapped outwards;
// Type C: its γ range snapped outwards), or 0…180° with `whole_sphere`.
// Type C input: each value is interpolate() of the expanded input at that
// direction (bilinear in the input's own grid angles), so a Type C input on a
// grid that contains the output's angles comes back unchanged.
// Types A and B: each value is the mean over its C-cell [C − step/2,
// C + step/2] at that γ of the model total_flux_lm() integrates (the
// monotone Hermite curves of photometry/hermite.h through the H and V grid),
// not a bilinear point sample: the trapezoid rule over C of cell means is the
// exact integral over C, and the Hermite model carries the source's flux
// where a bilinear one gains h² I″/12 per cell (0.41 % for a cos²⁰ floodlight
// on a 2.5° grid). Flux is kept to 0.05 % (tests/photometry/resample_test.cpp:
// floodlights of Types A and B, aimed and not, on grids of 2.5°×0.5° to
// 15°×5°), and I₀ cos γ in Type B comes out as I₀ cos γ to 1e-5 I₀.
// Directions the input never measured are 0.
//
// Flux is not renormalised. Everything else (lamps, keywords, opening,
// declared values) is copied from `d`.
//
// Errors (never a crash): steps that are not finite and positive or do not
// divide their ranges, and grids of more than 10⁷ intensities.
// Requires validate(d).ok().
Result<Distribution> to_type_c(const Distribution& d, const TypeCGrid& grid = {});

}  // namespace gonio::photometry
