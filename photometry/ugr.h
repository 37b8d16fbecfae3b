// The UGR table of a luminaire: CIE 117:1995's tabular method with the
// standard conditions of CIE 190:2010.
//
// Room and installation (what is computed, stated because every choice moves
// the figures):
// - A rectangular room X × Y (the 19 standard sizes, in multiples of H); the
//   luminaires hang in a regular square array of spacing S = 0.25 H at H above
//   the observer's eye (H = 2 m; UGR does not depend on H, see below), the
//   array covering the ceiling with the outer luminaires S/2 from the walls.
// - The observer sits at the middle of one of the walls of length X, eyes at
//   the height of the floor plane of the calculation, looking horizontally
//   along Y (x is across the line of sight, y along it).
// - Crosswise: the luminaire's C0–C180 axis runs along x, across the line of
//   sight (the observer looks at the luminaires' long sides); endwise: C0 runs
//   along y, the line of sight.
// - Every luminaire in front of the observer counts (they are all above the
//   eye): UGR = 8 log10(0.25 / L_b · Σ L² ω / p²) with L = I / A_p the average
//   luminance of the projected luminous area A_p (photometry/luminance.h)
//   toward the eye, ω = A_p / r², and p Guth's position index in the closed
//   form CIE 117 gives (α, β in degrees).
// - Background luminance L_b = E_i / π, E_i the indirect illuminance of the
//   walls: the flux of every luminaire split into upward (onto the ceiling),
//   downward onto the floor plane at eye height directly (the exact overlap
//   integral of a uniform array, as photometry/direct_ratios.h) and onto the
//   walls; then the inter-reflections of the three surfaces (ceiling, walls,
//   floor at eye height with the reflectance of the set's working plane),
//   exact view factors of the box; E_i = (wall flux − direct wall flux) / wall area.
// - Flux: the intensities as the file gives them — the rated lamp flux for
//   relative photometry, the luminaire as measured for absolute photometry.
//   L² ω ∝ F and L_b ∝ F, so another flux F′ adds 8 log10(F′ / F) to every
//   value (CIE 190's correction); H cancels in the same way.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "photometry/distribution.h"

namespace gonio::photometry {

// The five reflectance sets (ceiling, walls, floor / working plane) [1].
inline constexpr std::array<std::array<double, 3>, 5> kUgrReflectances = {{
    {0.7, 0.5, 0.2}, {0.7, 0.3, 0.2}, {0.5, 0.5, 0.2}, {0.5, 0.3, 0.2}, {0.3, 0.3, 0.2}}};

struct UgrRoom {
  double x_h = 0.0;  // room dimension across the line of sight [H]
  double y_h = 0.0;  // along the line of sight [H]
  std::array<double, 5> crosswise{};  // UGR per reflectance set; NaN where undefined
  std::array<double, 5> endwise{};
};

struct UgrTable {
  bool defined = false;
  std::string why_undefined;  // e.g. "point opening: no luminous area"
  double spacing_h = 0.25;    // [H]
  double flux_lm = kNaN;      // luminaire flux the table holds for [lm]
  std::vector<UgrRoom> rooms; // the 19 rooms in CIE 190's order
};

// The 19 room sizes (X, Y) [H] in CIE 190's order: X 2H with Y 2, 3, 4, 6,
// 8, 12 H; X 4H with the same; X 8H with Y 4, 6, 8, 12 H; X 12H with Y 4, 6, 8 H.
std::vector<std::array<double, 2>> ugr_room_sizes();

// UGR of one room and reflectance set (ceiling, walls, floor) [1], viewed
// endwise or crosswise, at spacing `spacing_h` [H]. NaN when no light
// reaches the observer. Requires validate(d).ok() and a luminous area.
double ugr(const Distribution& d, double x_h, double y_h, const std::array<double, 3>& reflectances,
           bool endwise, double spacing_h = 0.25);

// The whole table; undefined (with the reason) without a luminous area or
// when no light reaches the eye in any room. Requires validate(d).ok().
UgrTable ugr_table(const Distribution& d);

}  // namespace gonio::photometry
