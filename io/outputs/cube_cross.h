// The unfolded cube map as a picture: the six faces in a horizontal cross,
//
//            +Y
//       −X   −Z   +X   +Z
//            −Y
//
// (4N × 3N texels), every face as stored in the cube map (sim/detectors/cube_map.h,
// OpenEXR's layout: x right, y down), none rotated: with this arrangement
// every shared edge of the cross joins texels that are neighbours on the
// sphere. In Gonio's default photometric frame (nadir −Y) the downward
// light is the bottom face and the view from below the luminaire is the
// centre face's lower neighbour.
//
// Tone mapping: intensity / white, then a tone curve, sRGB encoded, grey
// with alpha; texels outside the cross are transparent.
//
// Previews (cube_cross_preview) expose robustly: one bright texel (a bare
// lamp seen through an opening, a focused reflection) must not leave the
// rest of the picture black, as a white point at the maximum would. The
// white point is the flux-weighted quantile: the intensity below which the
// texels carrying 99 % of the flux lie (tiny bright spots carry little flux
// and are left out; a beam that carries most of the flux sets it). Up to
// kPreviewKnee of white the curve is linear; above it a soft shoulder
// y = k + (1 − k)(1 − exp(−(x − k)/(1 − k))) approaches 1 with the same
// slope at the knee, so brighter texels still get brighter, never clip hard.
#pragma once

#include <span>

#include "io/outputs/image8.h"
#include "sim/detectors/cube_map.h"

namespace gonio::io {

// Where face `face` (0..5: +X, −X, +Y, −Y, +Z, −Z) sits in the cross, in
// face units: column 0..3, row 0..2.
struct CrossSlot {
  int column;
  int row;
};
CrossSlot cross_slot(int face);

// The tone-mapped cross of a cube map of `face_size` texels per edge with
// one value per texel in cube-map order (6 · face_size² values [cd]), as a
// grey-and-alpha image. `white_cd` ≤ 0 picks the largest value as white.
// Non-finite values are drawn black.
Image8 cube_cross_image(int face_size, std::span<const double> intensity_cd,
                            double white_cd = 0.0);

// The same with the soft shoulder from `knee` (in (0, 1); 0: plain clipping).
Image8 cube_cross_image(int face_size, std::span<const double> intensity_cd, double white_cd, double knee);

inline constexpr double kPreviewQuantile = 0.99;  // of the flux, for the white point
inline constexpr double kPreviewKnee = 0.75;      // linear up to this fraction of white

// The intensity [cd] below which the texels holding `quantile` of the map's
// flux (intensity × texel solid angle) lie; non-finite and negative values
// are ignored. 0 for a dark map. Requires quantile in (0, 1].
double flux_quantile_cd(const sim::CubeMapGrid& grid, std::span<const double> intensity_cd, double quantile);

// The soft-shoulder tone curve above for x = intensity / white ≥ 0: x below
// the knee, then towards 1 (never above). Requires knee in (0, 1).
double soft_shoulder(double x, double knee);

// The preview picture: white = flux_quantile_cd(kPreviewQuantile) (the
// maximum if that is 0), curve soft_shoulder(kPreviewKnee).
Image8 cube_cross_preview(const sim::CubeMapGrid& grid, std::span<const double> intensity_cd);

}  // namespace gonio::io
