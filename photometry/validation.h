// The model-level half of `gonio check`: everything that can be wrong with a
// distribution whatever file it came from. Readers add the format-level
// findings (syntax, fields, line numbers) and fill in `Finding::where`.
//
// Stable codes (tests and scripts match them) and their severities:
//
//   error — the model cannot be used as it is; derived checks are skipped
//     no-angles                 an angle list is empty
//     angle-not-finite          an angle is NaN or infinite
//     vertical-angles-order     vertical angles not strictly increasing
//     horizontal-angles-order   horizontal angles not strictly increasing
//     vertical-angle-range      γ outside 0…180° (Type C) or V outside −90…90°
//     horizontal-angle-range    C outside 0…360° or H outside −90…90°
//     symmetry-range            horizontal range does not fit the symmetry
//                               (e.g. quadrant data not spanning 0…90°)
//     candela-count             intensities ≠ horizontal × vertical angles
//     non-finite-intensity      an intensity is NaN or infinite
//     lamp-count                a lamp set with a count ≤ 0
//     lamp-flux                 relative photometry with a rated lamp flux
//                               that is not a positive number
//     invalid-model             anything else validate() refuses (a safety net:
//                               the codes above cover all its rules today)
//   error — the data is physically impossible or useless
//     negative-intensity        an intensity below 0 cd
//     all-zero                  every intensity is 0: the luminaire emits nothing
//   warning
//     no-lamp-data              relative photometry without lamp sets (no LOR)
//     vertical-range-nonstandard  vertical range LM-63-2002 does not allow
//                               (Type C: first 0° or 90°, last 90° or 180°;
//                               Types A/B: first −90° or 0°, last 90°)
//     no-solid-angle            a single vertical angle (or, for Types A/B, a
//                               single horizontal angle): the grid spans no
//                               solid angle and the flux is 0
//     nadir-mismatch            C-planes disagree at γ = 0° (one direction)
//     zenith-mismatch           C-planes disagree at γ = 180°
//     seam-mismatch             planes C = 0° and C = 360° disagree
//     pole-mismatch             Types A/B: values at a pole of the grid
//                               (Type A V = ±90°, Type B H = ±90°) disagree
//     lor-implausible           relative photometry with a light output ratio
//                               above CheckOptions::max_lor
//     lor-mismatch              declared LOR (EULUMDAT LORL) differs from the
//                               integrated one by more than the tolerance
//     dff-mismatch              declared downward flux fraction differs from
//                               the integrated one by more than the tolerance
//     absurd-intensity          peak intensity above 10⁹ cd or below 10⁻⁶ cd
//     absurd-flux               total flux above 10⁷ lm
//     efficacy-implausible      flux per input watt above 300 lm/W
//
// Each message says what was found and what was expected, with numbers.
#pragma once

#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::photometry {

struct CheckOptions {
  // Spread of the values that must agree (nadir, zenith, seam, poles), as a
  // fraction of the peak intensity.
  double pole_tolerance = 1e-3;
  // Largest plausible light output ratio [1]: 1 plus an allowance for the
  // quadrature error of coarse grids and rounded candela values.
  double max_lor = 1.02;
  // Relative difference between declared and integrated LOR that is reported.
  double declared_lor_tolerance = 0.03;
  // Difference between declared and integrated DFF that is reported
  // [percentage points].
  double declared_dff_tolerance_percent = 2.0;
  double max_intensity_cd = 1e9;         // brighter than a searchlight [cd]
  double min_peak_intensity_cd = 1e-6;   // a peak dimmer than this is a unit error [cd]
  double max_flux_lm = 1e7;              // [lm]
  double max_efficacy_lm_per_w = 300.0;  // white light cannot do much better [lm/W]
};

// Every finding for `d`, structural errors first. Never fails and never
// stops the program, whatever `d` holds; an empty list means nothing to
// report. The findings carry no SourceLoc: callers add the file.
std::vector<Finding> check(const Distribution& d, const CheckOptions& options = {});

}  // namespace gonio::photometry
