// Luminous area and average luminance of a luminaire: the projected area of
// the file's luminous opening seen from a direction, and the luminance table
// data sheets quote (γ 45…85° in the C0 and C90 planes).
//
// Projected area (the opening as a convex luminous body; dimensions from
// photometry::LuminousOpening, x = C0–C180 = length, y = C90–C270 = width,
// z = height — LM-63's axes; an EULUMDAT file's length lies along C90–C270
// and its reader puts it into `width_m`, io/photometric/ldt.h). Seen from
// the direction d(C, γ) of the photometric frame:
// - flat openings facing down (rectangle, disc, ellipse): A·cos γ below the
//   horizontal, 0 above;
// - a box (RectangularWithSides): the bottom plus the sides that face the
//   viewer, A_b cos γ + sin γ (|cos C| w h + |sin C| l h): the faces toward
//   C0 and C180 are as broad as the width (the C90–C270 extent), those
//   toward C90 and C270 as the length. EULUMDAT's four side heights (C0, C90,
//   C180, C270) are used per side where the file has them: h_C0 for the face
//   toward C0 (C in (270°, 90°)), h_C180 otherwise, h_C90 for C in (0°, 180°),
//   h_C270 otherwise (CIE 117's A_bottom cos γ + A_side(C) sin γ);
// - an EULUMDAT round opening with side heights: the disc plus a cylinder's
//   side D h sin γ, h the facing side's height (blended by cos² C, sin² C);
// - cylinders, spheres and ellipsoids: the exact projected area of the solid
//   (e.g. a vertical cylinder πD²/4 |cos γ| + D h sin γ);
// - vertical discs and ellipses (LM-63-2019) face C0: A·max(0, d·x);
// - a point opening has no area: luminance is undefined.
//
// Luminance L(C, γ) = I(C, γ) / A_p(C, γ) [cd/m²] (the average luminance of the
// projected opening). `ldt_cd_m2` is the EULUMDAT reading that uses the
// bottom face alone, I / (A_b cos γ), which is what a file without side
// heights gives either way.
#pragma once

#include <string>
#include <vector>

#include "photometry/distribution.h"

namespace gonio::photometry {

// Projected area [m²] of the luminous opening seen from the direction
// (c_deg, gamma_deg) of the photometric frame. 0 for a point opening.
double projected_area_m2(const LuminousOpening& opening, double c_deg, double gamma_deg);

// Area of the opening's downward-facing face [m²] (0 for point, vertical
// discs and spheres have their horizontal cross-section).
double bottom_area_m2(const LuminousOpening& opening);

struct LuminanceTable {
  bool defined = false;
  std::string why_undefined;         // e.g. "point opening (no luminous area)"
  std::vector<double> gamma_deg;     // 45, 50, …, 85 [deg]
  std::vector<double> c_deg;         // 0, 90 [deg]
  // [c][gamma] average luminance over the projected opening [cd/m²].
  std::vector<std::vector<double>> cd_m2;
  // [c][gamma] the bottom face alone, I / (A_b cos γ) [cd/m²]; NaN where
  // the opening has no bottom face.
  std::vector<std::vector<double>> ldt_cd_m2;
  double max_cd_m2 = kNaN;           // largest value of cd_m2 [cd/m²]
};

// The table for `d` (intensities as the file gives them: rated lamps, or as
// measured for absolute photometry). Requires validate(d).ok().
LuminanceTable luminance_table(const Distribution& d);

}  // namespace gonio::photometry
