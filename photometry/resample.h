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
// Each value is interpolate() of the expanded input at that direction (bilinear in the input's own
// grid angles), so a Type C input on a grid that contains the output's angles comes back unchanged,
// and directions the input never measured are 0.
//
// Flux is kept to within the interpolation error of the input grid and the
// quadrature error of both grids (see tests/photometry/resample_test.cpp); it
// is not renormalised. Everything else (lamps, keywords, opening, declared
// values) is copied from `d`.
//
// Errors (never a crash): steps that are not finite and positive or do not
// divide their ranges, and grids of more than 10⁷ intensities.
// Requires validate(d).ok().
Result<Distribution> to_type_c(const Distribution& d, const TypeCGrid& grid = {});

}  // namespace gonio::photometry
