// Direct ratios: the share of a luminaire's flux that reaches the working
// plane of a room directly, before any reflection, at the ten room indices
// EULUMDAT files quote (k = 0.6, 0.8, 1, 1.25, 1.5, 2, 2.5, 3, 4, 5).
//
// Model (stated here because it is ours, see below):
// - A square room of side a; the luminaires hang in a plane at height h above
//   the working plane. Room index k = a·b / (h (a + b)) = a / (2h).
// - Many identical luminaires spread evenly over the luminaire plane (the
//   limit of a fine regular array), upright, C0 parallel to a wall.
// - A direction (C, γ) below the horizontal lands on the working plane from
//   the fraction P = (1 − u|cos C|)₊ (1 − u|sin C|)₊ of luminaire positions,
//   u = tan γ / (2k): the overlap of the working plane with its copy shifted
//   by h tan γ along C.
// - The direct ratio is DR(k) = ∫ I P dΩ / Φ over the lower hemisphere,
//   relative to the luminaire's total flux Φ (as EULUMDAT files quote it: an
//   uplight has direct ratios near 0). It grows with k towards the downward
//   flux fraction; for a Lambertian luminaire it equals the view factor
//   between two facing squares of side a at distance h.
//
// Provenance: EULUMDAT's direct ratios come from the utilisation-factor
// method of CIE 52-1982, which tabulates coefficients of the cumulative flux
// in four cones. Those tables could not be consulted for this project, so
// this is not a copy of that method but the direct flux it approximates,
// integrated over the intensity distribution. On the four real luminaires of
// the test corpus (three downlights and an uplight, qlumedit/*.ldt) it
// reproduces the declared values to within 0.012 at every k; whether it
// matches CIE 52's tables more closely than that is not verified.
#pragma once

#include <array>

#include "photometry/distribution.h"

namespace gonio::photometry {

inline constexpr std::array<double, 10> kDirectRatioRoomIndices = {0.6, 0.8, 1.0, 1.25, 1.5,
                                                                   2.0, 2.5, 3.0, 4.0,  5.0};

// DR at each of kDirectRatioRoomIndices [1], integrated on a 1° (C) × 0.25° (γ)
// midpoint grid of interpolate()'s model (within 1e-5 of the closed form for
// a Lambertian luminaire).
// All zero for a dark distribution. Requires validate(d).ok().
std::array<double, 10> direct_ratios(const Distribution& d);

// DR at any room index k > 0 [1].
double direct_ratio(const Distribution& d, double room_index);

}  // namespace gonio::photometry
