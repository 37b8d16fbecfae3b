// The unfolded cube map as a picture: the six faces in a horizontal cross,
//
//            +Y
//       −X   −Z   +X   +Z
//            −Y
//
// (4N × 3N texels), every face as stored in the cube map (sim/cube_map.h,
// OpenEXR's layout: x right, y down), none rotated: with this arrangement
// every shared edge of the cross joins texels that are neighbours on the
// sphere. In Gonio's default photometric frame (nadir −Y) the downward
// light is the bottom face and the view from below the luminaire is the
// centre face's lower neighbour.
//
// Tone mapping for previews: intensity / white, clipped to [0, 1], sRGB
// encoded, grey with alpha; texels outside the cross are transparent.
#pragma once

#include <span>

#include "io/image8.h"

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

}  // namespace gonio::io
