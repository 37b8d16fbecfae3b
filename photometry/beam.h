// Beam and field angles: the angular width of a distribution's beam in one
// vertical plane.
//
// Definition (IES: the angle between the two directions in which the
// intensity is 50 % of the maximum intensity, measured in a plane through the
// beam axis; the field angle likewise at 10 %):
//
// - The plane is a pair of C half-planes, C = c and C = c + 180° (the C0–C180
//   plane for c = 0), a great circle through nadir and zenith. Along it θ is
//   the signed angle from the nadir: θ = γ on the half-plane C = c, θ = −γ on
//   C = c + 180°, so θ = ±180° is the zenith.
// - I(θ) is the distribution along that circle: interpolate() of the expanded
//   distribution, linear in γ between the stored vertical angles (Type C), or
//   sampled every 0.1° along the circle (Types A and B, whose grids do not
//   follow C-planes).
// - The maximum is the largest I(θ) in this plane (the beam in this plane,
//   not the luminaire's overall peak); where it lies is the beam axis (of
//   equal maxima, the one nearest the nadir, then the one with θ > 0).
// - From the axis, walk outwards on both sides: each edge is the first θ at
//   which I(θ) has fallen to fraction × maximum, placed by linear
//   interpolation between samples. Side lobes beyond an edge do not widen the
//   beam; a dip between lobes that stays above the threshold does not split
//   it.
// - A walk that reaches the end of the measured γ range before falling to the
//   threshold stops there (LM-63: unmeasured directions are dark), and the
//   side is marked open: the beam is at least that wide.
// - If I(θ) never falls to the threshold all round the circle (an isotropic
//   source), or the plane is dark, there is no beam: the angle is NaN.
// - angle_deg = upper_edge_deg − lower_edge_deg. Edges are unwrapped about
//   the axis, so a beam around the zenith has, e.g., edges 160° and 200°.
#pragma once

#include "photometry/distribution.h"

namespace gonio::photometry {

struct BeamSpread {
  double fraction = kNaN;        // threshold as a fraction of max_cd (0.5 beam, 0.1 field)
  double max_cd = kNaN;          // largest intensity in the plane [cd]
  double threshold_cd = kNaN;    // fraction × max_cd [cd]
  double axis_deg = kNaN;        // θ of the maximum [deg]
  double lower_edge_deg = kNaN;  // θ of the edge below the axis [deg]
  double upper_edge_deg = kNaN;  // θ of the edge above the axis [deg]
  double angle_deg = kNaN;       // full beam width [deg]; NaN when there is no beam
  bool lower_open = false;       // the lower edge is where the measured range ends
  bool upper_open = false;       // the upper edge is where the measured range ends
};

// The beam spread of `d` at `fraction` of the maximum (in (0, 1]) in the
// plane C = c_deg / C = c_deg + 180°. Requires validate(d).ok().
BeamSpread beam_spread(const Distribution& d, double c_deg, double fraction);

// beam_spread() at 50 % (beam angle) and 10 % (field angle).
inline BeamSpread beam_angle(const Distribution& d, double c_deg) {
  return beam_spread(d, c_deg, 0.5);
}
inline BeamSpread field_angle(const Distribution& d, double c_deg) {
  return beam_spread(d, c_deg, 0.1);
}

}  // namespace gonio::photometry
