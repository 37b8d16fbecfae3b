// The BUG rating of an outdoor luminaire (IES TM-15-11, Luminaire
// Classification System for Outdoor Luminaires, with its Addendum A):
// backlight, uplight and glare ratings 0…5 from the luminaire lumens in the
// LCS's secondary solid angles.
//
// Zones (Type C angles from the nadir; "front" is the half-space of the
// C0…C180 planes centred on C90 — the street side of LM-63 Type C roadway
// files — and "back" the C180…C360 half, centred on C270):
//   FL, BL 0–30°; FM, BM 30–60°; FH, BH 60–80°; FVH, BVH 80–90°;
//   UL 90–100°, UH 100–180° (all round).
// Lumens are the luminaire's (the rated lamps for relative photometry, as
// measured for absolute photometry): the zones' totals over γ are the exact
// zonal flux of photometry/flux.h, the front/back split of each from a 1° ×
// 0.25° midpoint quadrature. A zone holding less than 1e-9 of the total is
// taken as dark (quadrature rounding, not light).
//
// Ratings: the lowest rating whose every threshold holds (lumens ≤ limit), 5
// when none does. TM-15-11 Addendum A, tables of maximum zonal lumens:
//   B0…B4: BH 110, 500, 1000, 2500, 5000; BM 220, 1000, 2500, 5000, 8500;
//          BL 110, 500, 1000, 2500, 5000.
//   U0…U4: UH 0, 10, 50, 500, 1000; UL 0, 10, 50, 500, 1000.
//   G0…G4: FVH 10, 100, 225, 350, 350; BVH 10, 100, 225, 350, 350;
//          FH 660, 1800, 5000, 7500, 12000; BH 110, 500, 1000, 2500, 5000.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "photometry/distribution.h"

namespace gonio::photometry {

struct BugZones {
  double fl = 0, fm = 0, fh = 0, fvh = 0;  // front zones [lm]
  double bl = 0, bm = 0, bh = 0, bvh = 0;  // back zones [lm]
  double ul = 0, uh = 0;                   // uplight [lm]
};

struct BugRating {
  int b = 0, u = 0, g = 0;  // 0…5
  BugZones zones_lm;
};

// Ratings from zone lumens alone (the tables above).
BugRating rate_bug(const BugZones& zones_lm);

// Zone lumens and ratings of `d`. Requires validate(d).ok().
BugRating bug_rating(const Distribution& d);

// "B1-U0-G1".
std::string to_string(const BugRating& r);

}  // namespace gonio::photometry
