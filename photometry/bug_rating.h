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
// when none does. The limits are bug_limits_lm() below (TM-15-11 Addendum A,
// tables of maximum zonal lumens). Which of them an outside copy confirms,
// and where, is stated in tests/photometry/bug_rating_test.cpp
// (BugRating.ThresholdsAsPublished) and in docs/methods.md's BUG paragraph: the
// uplight limits U0…U3 and the G0 limit of FVH/BVH are confirmed; a real
// luminaire's published rating (a Type V pole-top whose BH of 704 lm still
// rates G1) shows that the glare table differs for quadrilateral-symmetric
// luminaires; the rest, including the glare table's FVH/BVH limits for G3
// and G4 (350, 350 here; equal, so no luminaire is G4 by FVH or BVH alone),
// could not be checked against a published copy.
//
// Glare table. The Addendum rates glare of asymmetric luminaires (IES Types
// I–IV) with BH held to the backlight limits, and of quadrilateral-symmetric
// ones (Types V and VS, which have no street side: "back" is just the other
// half) with BH held to FH's limits. bug_rating() takes a luminaire as
// quadrilateral-symmetric when its downward (0–90°) lumens in each of the
// eight 45° octants of C (from C0) lie within ±10 % of the octants' mean
// (the Type VS test of TM-15-20 Annex A, Note 4; a rotationally symmetric
// Type V meets it too); rate_bug() is told which table applies.
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

// TM-15-11 Addendum A: the maximum zonal lumens [lm] of ratings 0…4; above
// the rating-4 limit the rating is 5. BH counts in the backlight and in the
// glare table with the same limits.
struct BugLimits {
  using Row = std::array<double, 5>;
  // Backlight B0…B4.
  Row bh{110, 500, 1000, 2500, 5000};
  Row bm{220, 1000, 2500, 5000, 8500};
  Row bl{110, 500, 1000, 2500, 5000};
  // Uplight U0…U4.
  Row uh{0, 10, 50, 500, 1000};
  Row ul{0, 10, 50, 500, 1000};
  // Glare G0…G4.
  Row fvh{10, 100, 225, 350, 350};
  Row bvh{10, 100, 225, 350, 350};
  Row fh{660, 1800, 5000, 7500, 12000};
  Row bh_glare{110, 500, 1000, 2500, 5000};
  // Glare G0…G4 of BH for quadrilateral-symmetric luminaires (Types V, VS):
  // FH's limits.
  Row bh_glare_symmetric{660, 1800, 5000, 7500, 12000};
};

// Which glare table: IES Types I–IV, or Types V and VS.
enum class BugGlareTable { Asymmetric, QuadrilateralSymmetric };

// The one table rate_bug() uses.
const BugLimits& bug_limits_lm();

struct BugRating {
  int b = 0, u = 0, g = 0;  // 0…5
  BugZones zones_lm;
  BugGlareTable glare_table = BugGlareTable::Asymmetric;
  // Downward (0–90°) lumens in the octants C 0–45°, 45–90°, …, 315–360°
  // (bug_rating() only; zero from rate_bug()).
  std::array<double, 8> octants_down_lm{};
};

// Ratings from zone lumens alone (the tables above), with the glare table
// of `table`.
BugRating rate_bug(const BugZones& zones_lm, BugGlareTable table = BugGlareTable::Asymmetric);

// The octant test above: every octant within ±10 % of their mean (and some
// light downward).
bool quadrilateral_symmetric(const std::array<double, 8>& octants_down_lm);

// Zone lumens, octants, glare table and ratings of `d`. Requires
// validate(d).ok().
BugRating bug_rating(const Distribution& d);

// "B1-U0-G1".
std::string to_string(const BugRating& r);

// "Types I-IV (asymmetric)" or "Types V and VS (quadrilateral symmetric)":
// the glare table a rating used, as info and the datasheet print it.
std::string to_string(BugGlareTable table);

}  // namespace gonio::photometry
