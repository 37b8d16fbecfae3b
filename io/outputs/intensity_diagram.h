// The intensity diagram of a distribution, as photometric reports and
// light-planning programs draw it: the C0–C180 and C90–C270 planes on a
// polar diagram (nadir down; C0 and C90 to the right, C180 and C270 to the
// left) and the same planes on cartesian axes (γ from −180° to 180°, the
// negative side being C180 and C270).
#pragma once

#include <string>

#include "io/outputs/plot.h"
#include "photometry/distribution.h"

namespace gonio::io {

struct DiagramOptions {
  std::string title;  // above both charts; empty for none
  // Relative scale: intensities in cd per 1000 lm of this flux [lm]. NaN
  // (the default) draws candela.
  double per_klm_of_lm = photometry::kNaN;
};

// Type C only (an error otherwise, or for a distribution that fails
// photometry::validate). Planes missing from the file are interpolated
// (photometry::interpolate after expand_symmetry); γ keeps the file's angles.
Result<Figure> intensity_diagram(const photometry::Distribution& distribution,
                                 const DiagramOptions& options = {});

// Two distributions in one diagram (`gonio compare --plot`): A's C0–C180 and
// C90–C270 curves solid and dashed, B's dotted (C90–C270 with markers), in
// cd on both charts. B's intensities are multiplied by `scale_b` (1, or the
// flux ratio when comparing shapes); labels name the files. Same
// requirements and errors as intensity_diagram() for each input.
struct OverlayOptions {
  std::string title;
  std::string label_a = "A";
  std::string label_b = "B";
  double scale_b = 1.0;  // [1]
};

Result<Figure> overlay_diagram(const photometry::Distribution& a, const photometry::Distribution& b,
                               const OverlayOptions& options = {});

}  // namespace gonio::io
