#include "photometry/bug_rating.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <string>
#include <utility>

#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_c;
using test::sample_direction;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// TM-15-11 Addendum A's maximum zonal lumens, ratings 0…4, as found outside
// Gonio. The search (issue 23; pages, code, docs and issues corpora, and the
// repositories fetched under /work/.mirror) found no copy of the Addendum's
// tables themselves; these statements of them were found:
//  [MLO]  IDA–IES Model Lighting Ordinance (2011), User's Guide to Table C,
//         reproduced in the Dobbins JLUS Light Pollution Study, p. 270
//         (viewer.joomag.com/dobbins-jlus-imp-public-draft-light-pollution-
//         study/0336510001522942340?page=270): "Zone 0 allows no light above
//         90 degrees", "Zone 2 allows only 50 lumens in the UH and UL zones,
//         100 lumens total", "Zone 3 allows only 500 lumens i[n the UH and UL
//         zones]" (the stored copy ends there); MLO Table C-2 gives LZ0…LZ4
//         the ratings U0…U4, so these are the U0, U2 and U3 limits.
//  [ASH]  I. Ashdown, "Photometric Imprecision Can Limit BUG Rating
//         Utility", LEUKOS (abstract, paperexplained.cn/articles/paper/detail/
//         90dfd2910448d0f745a37c5deb4c1b9fc2e565ed): "IES TM-15-11 requires
//         that a luminaire with an uplight rating of U0 emits zero lumens into
//         the upper hemisphere, while a U1 uplight rating or a G0 glare rating
//         for high viewing angles requires fewer than 10 lumens."
//  [SELUX] A real luminaire whose LCS zone lumens and BUG rating are both
//         published: Selux Aya pole-top AYAP-SR-1-HO-30-BL-UNV (Type V
//         "Symmetric Round" optic, 5074 lm, UL Verification Services test
//         16033338.03), as transcribed from the manufacturer's IES Road Report
//         and spec sheet into ulcspec/ULC, examples/selux-aya-pole-sr-ho-
//         3000k.ulc (outdoor_classification: lcs_zonal_lumens and bug_rating;
//         read at commits 09da7ac and 08987bb, the same numbers): FL = BL =
//         362.8, FM = BM = 1447.2, FH = BH = 703.8, FVH = BVH = 23.1, UL = UH
//         = 0 lm; B2-U0-G1. It confirms intervals, not values: each lit zone
//         lies at or under its rating's limit, and B2 and G1 each need some
//         zone over the limit one rating lower (B1: BH 703.8 > 500 or BM
//         1447.2 > 1000; G0: FVH 23.1 > 10 or FH 703.8 > 660; Gonio's rows
//         meet both). And it shows the Addendum's second glare table: with
//         BH held to the backlight limits (G1 ≤ 500) this Type V luminaire
//         would be G2, so for Types V and VS the G1 limit of BH is at least
//         703.8 lm.
// Every other limit below is Gonio's value, typed from memory of the
// Addendum by an earlier session and NOT confirmed by any outside copy; it is
// pinned here so that a change has to come with its source. So is the Type
// V/VS row of BH's glare limits: FH's row, as the Addendum's separate table
// for quadrilateral-symmetric luminaires is remembered ([SELUX] bounds only
// its G1 limit from below). One is suspect: FVH/BVH G3 = G4 = 350 makes G4
// unreachable by those zones (every other row rises strictly), and public
// TypeScript code found by the search (two files) carries the row
// 10/100/225/500/750 (and applies it to the wrong zones, so it is no
// authority either). holg/eulumdat-rs's glare table
// (FH/BH 10/180/600/2000/4000, FVH/BVH 10/10/50/200/400) agrees with none of
// this and is not used.
struct PublishedRow {
  const char* zone;
  std::array<double, 5> limits_lm;
  const char* confirmed;  // which limits an outside copy states, and where
};
const PublishedRow kBacklight[] = {
    {"BH", {110, 500, 1000, 2500, 5000}, "703.8 <= B2 [SELUX]; values none"},
    {"BM", {220, 1000, 2500, 5000, 8500}, "1447.2 <= B2 [SELUX]; values none"},
    {"BL", {110, 500, 1000, 2500, 5000}, "362.8 <= B2 [SELUX]; values none"},
};
const PublishedRow kUplight[] = {
    {"UH", {0, 10, 50, 500, 1000}, "U0 [MLO][ASH], U1 [ASH], U2 [MLO], U3 [MLO]; U4 none"},
    {"UL", {0, 10, 50, 500, 1000}, "U0 [MLO][ASH], U1 [ASH], U2 [MLO], U3 [MLO]; U4 none"},
};
const PublishedRow kGlare[] = {
    {"FVH", {10, 100, 225, 350, 350}, "G0 [ASH]; 23.1 <= G1 [SELUX]; G1…G4 none (G3, G4 suspect)"},
    {"BVH", {10, 100, 225, 350, 350}, "G0 [ASH]; 23.1 <= G1 [SELUX]; G1…G4 none (G3, G4 suspect)"},
    {"FH", {660, 1800, 5000, 7500, 12000}, "703.8 <= G1 [SELUX]; values none"},
    {"BH", {110, 500, 1000, 2500, 5000}, "none (Types I-IV)"},
    {"BH (Types V, VS)", {660, 1800, 5000, 7500, 12000}, "G1 >= 703.8 [SELUX]; values none"},
};

// The rating a single lit zone earns from a row: the lowest whose limit holds.
int rating_for(const std::array<double, 5>& limits_lm, double lm) {
  for (int r = 0; r < 5; ++r)
    if (lm <= limits_lm[r]) return r;
  return 5;
}

// All 50 limits, as values and as behaviour: Gonio's table equals the rows
// above, and rate_bug puts each limit inside its rating and the least lumen
// more outside it (so a change of any one limit, up or down, fails here).
TEST(BugRating, ThresholdsAsPublished) {
  const BugLimits& l = bug_limits_lm();
  EXPECT_EQ(l.bh, kBacklight[0].limits_lm);
  EXPECT_EQ(l.bm, kBacklight[1].limits_lm);
  EXPECT_EQ(l.bl, kBacklight[2].limits_lm);
  EXPECT_EQ(l.uh, kUplight[0].limits_lm);
  EXPECT_EQ(l.ul, kUplight[1].limits_lm);
  EXPECT_EQ(l.fvh, kGlare[0].limits_lm);
  EXPECT_EQ(l.bvh, kGlare[1].limits_lm);
  EXPECT_EQ(l.fh, kGlare[2].limits_lm);
  EXPECT_EQ(l.bh_glare, kGlare[3].limits_lm);
  EXPECT_EQ(l.bh_glare_symmetric, kGlare[4].limits_lm);

  using Setter = void (*)(BugZones&, double);
  struct Case {
    const PublishedRow& row;
    Setter set;
    int BugRating::* rating;
    BugGlareTable table = BugGlareTable::Asymmetric;
  };
  constexpr auto kSym = BugGlareTable::QuadrilateralSymmetric;
  const Case cases[] = {
      {kBacklight[0], [](BugZones& z, double v) { z.bh = v; }, &BugRating::b},
      {kBacklight[1], [](BugZones& z, double v) { z.bm = v; }, &BugRating::b},
      {kBacklight[2], [](BugZones& z, double v) { z.bl = v; }, &BugRating::b},
      {kUplight[0], [](BugZones& z, double v) { z.uh = v; }, &BugRating::u},
      {kUplight[1], [](BugZones& z, double v) { z.ul = v; }, &BugRating::u},
      {kGlare[0], [](BugZones& z, double v) { z.fvh = v; }, &BugRating::g},
      {kGlare[1], [](BugZones& z, double v) { z.bvh = v; }, &BugRating::g},
      {kGlare[2], [](BugZones& z, double v) { z.fh = v; }, &BugRating::g},
      {kGlare[3], [](BugZones& z, double v) { z.bh = v; }, &BugRating::g},
      {kGlare[4], [](BugZones& z, double v) { z.bh = v; }, &BugRating::g, kSym},
      // The backlight and uplight tables are the same for both glare tables.
      {kBacklight[0], [](BugZones& z, double v) { z.bh = v; }, &BugRating::b, kSym},
      {kUplight[1], [](BugZones& z, double v) { z.ul = v; }, &BugRating::u, kSym},
  };
  int edges = 0;
  for (const Case& c : cases) {
    for (int r = 0; r < 5; ++r) {
      const double limit = c.row.limits_lm[r];
      const double above = limit + std::max(1e-6, 1e-9 * limit);
      BugZones at, over;
      c.set(at, limit);
      c.set(over, above);
      SCOPED_TRACE(std::string(c.row.zone) + " rating " + std::to_string(r) +
                   " (confirmed: " + c.row.confirmed + ")");
      EXPECT_EQ(rate_bug(at, c.table).*c.rating, rating_for(c.row.limits_lm, limit));
      EXPECT_LE(rate_bug(at, c.table).*c.rating, r);
      EXPECT_EQ(rate_bug(over, c.table).*c.rating, rating_for(c.row.limits_lm, above));
      EXPECT_GT(rate_bug(over, c.table).*c.rating, r);
      ++edges;
    }
  }
  EXPECT_EQ(edges, 60);  // the 45 of Types I-IV, BH's 5 of Types V/VS, 10 repeated under V/VS
}

// The outside statements themselves, as sentences a reader can check.
TEST(BugRating, UplightAndHighAngleGlareAsStatedOutside) {
  BugZones z;
  // [ASH] "U0 emits zero lumens into the upper hemisphere"; [MLO] "Zone 0
  // allows no light above 90 degrees".
  EXPECT_EQ(rate_bug(z).u, 0);
  z.ul = 0.01;
  EXPECT_EQ(rate_bug(z).u, 1);
  z = {};
  z.uh = 0.01;
  EXPECT_EQ(rate_bug(z).u, 1);
  // [ASH] "a U1 uplight rating or a G0 glare rating for high viewing angles
  // requires fewer than 10 lumens".
  z = {};
  z.ul = 9.9;
  z.uh = 9.9;
  EXPECT_EQ(rate_bug(z).u, 1);
  z.ul = 10.1;
  EXPECT_EQ(rate_bug(z).u, 2);
  z = {};
  z.fvh = 9.9;
  z.bvh = 9.9;
  EXPECT_EQ(rate_bug(z).g, 0);
  z.bvh = 10.1;
  EXPECT_EQ(rate_bug(z).g, 1);
  // [MLO] "Zone 2 allows only 50 lumens in the UH and UL zones, 100 lumens
  // total" (LZ2 takes U2).
  z = {};
  z.ul = 50;
  z.uh = 50;
  EXPECT_EQ(rate_bug(z).u, 2);
  z.uh = 50.5;
  EXPECT_EQ(rate_bug(z).u, 3);
  // [MLO] "Zone 3 allows only 500 lumens i[n the UH and UL zones]" (LZ3: U3).
  z = {};
  z.ul = 500;
  z.uh = 500;
  EXPECT_EQ(rate_bug(z).u, 3);
  z.ul = 500.5;
  EXPECT_EQ(rate_bug(z).u, 4);
}

// [SELUX]'s published zone lumens, the published rating (B2-U0-G1), and which
// glare table gives it.
constexpr BugZones kSeluxAyaZones{.fl = 362.8,
                                  .fm = 1447.2,
                                  .fh = 703.8,
                                  .fvh = 23.1,
                                  .bl = 362.8,
                                  .bm = 1447.2,
                                  .bh = 703.8,
                                  .bvh = 23.1,
                                  .ul = 0,
                                  .uh = 0};

TEST(BugRating, PublishedRatingOfARealLuminaire) {
  const BugRating r = rate_bug(kSeluxAyaZones, BugGlareTable::QuadrilateralSymmetric);
  EXPECT_EQ(to_string(r), "B2-U0-G1");
  // Held to the Types I-IV table, BH's 703.8 lm (> 500) would make it G2: the
  // rating Gonio gave before the Type V/VS table, which the published G1
  // refutes. Backlight and uplight do not depend on the table.
  const BugRating asym = rate_bug(kSeluxAyaZones, BugGlareTable::Asymmetric);
  EXPECT_EQ(asym.b, 2);
  EXPECT_EQ(asym.u, 0);
  EXPECT_EQ(asym.g, 2);
}

// The same luminaire as a photometric file would carry it: rotationally
// symmetric (its optic is "Symmetric Round", its IES file symmetric about the
// nadir), with the intensity constant within each LCS γ zone so that the
// zones hold the published lumens (the IES file itself is not public; its
// peak of 1522 cd at 57.5° is smoothed into the 30–60° zone's 1258 cd).
// bug_rating() finds the zone lumens, the octants all equal, the Type V/VS
// glare table, and the published rating.
TEST(BugRating, PublishedRatingFromASymmetricDistribution) {
  const BugZones& p = kSeluxAyaZones;
  const auto zone_cd = [](double both_halves_lm, double a, double b) {
    return both_halves_lm / (2 * kPi * (std::cos(a * kDeg) - std::cos(b * kDeg)));
  };
  const double i_low = zone_cd(p.fl + p.bl, 0, 30), i_mid = zone_cd(p.fm + p.bm, 30, 60);
  const double i_high = zone_cd(p.fh + p.bh, 60, 80), i_vhigh = zone_cd(p.fvh + p.bvh, 80, 90);
  const Distribution d = sample_c(Symmetry::Rotational, {0}, angles(0, 180, 0.05), [&](double, double g) {
    // At a zone edge below the horizontal the mean of the two sides, so that
    // the linear interpolation between samples moves (almost) no flux across
    // the edge; none at and above 90° (the published U0).
    const auto at = [&](double x) {
      return x < 30 ? i_low : x < 60 ? i_mid : x < 80 ? i_high : x < 90 ? i_vhigh : 0.0;
    };
    return g >= 90 ? 0.0 : 0.5 * (at(g - 1e-9) + at(g + 1e-9));
  });
  const BugRating r = bug_rating(d);
  const BugZones& z = r.zones_lm;
  for (const auto& [got, want] : std::initializer_list<std::pair<double, double>>{
           {z.fl, p.fl}, {z.fm, p.fm}, {z.fh, p.fh}, {z.fvh, p.fvh}, {z.bl, p.bl}, {z.bm, p.bm}, {z.bh, p.bh}, {z.bvh, p.bvh}})
    EXPECT_NEAR(got, want, 0.5);
  EXPECT_EQ(z.ul, 0.0);
  EXPECT_EQ(z.uh, 0.0);
  for (double o : r.octants_down_lm) EXPECT_NEAR(o, 5073.8 / 8, 1.0);
  EXPECT_EQ(r.glare_table, BugGlareTable::QuadrilateralSymmetric);
  EXPECT_EQ(to_string(r), "B2-U0-G1");
}

// The octant test that picks the glare table: within ±10 % of the octants'
// mean is quadrilateral-symmetric (Types V, VS), beyond it is not.
TEST(BugRating, GlareTableFollowsTheOctants) {
  std::array<double, 8> o;
  o.fill(100);
  EXPECT_TRUE(quadrilateral_symmetric(o));
  o[3] = 110;  // mean 101.25: 8.6 % over
  EXPECT_TRUE(quadrilateral_symmetric(o));
  o[3] = 120;  // mean 102.5: 17 % over
  EXPECT_FALSE(quadrilateral_symmetric(o));
  o.fill(0);
  EXPECT_FALSE(quadrilateral_symmetric(o));  // no light downward

  // A square (Type VS) lobe, ±5 % with C, is symmetric; the same with one
  // quadrant 40 % brighter is not.
  const auto square = [](double bright_quadrant) {
    return sample_c(Symmetry::None, angles(0, 360, 2.5), angles(0, 180, 1), [=](double c, double g) {
      if (g >= 90) return 0.0;
      const double k = c >= 90 && c < 180 ? bright_quadrant : 1.0;
      return k * 800 * (1 + 0.05 * std::cos(4 * c * kDeg)) * std::cos(g * kDeg);
    });
  };
  const BugRating vs = bug_rating(square(1.0));
  EXPECT_EQ(vs.glare_table, BugGlareTable::QuadrilateralSymmetric);
  const BugRating lopsided = bug_rating(square(1.4));
  EXPECT_EQ(lopsided.glare_table, BugGlareTable::Asymmetric);
  double sum = 0;
  for (double v : vs.octants_down_lm) sum += v;
  const BugZones& z = vs.zones_lm;
  EXPECT_NEAR(sum, z.fl + z.fm + z.fh + z.fvh + z.bl + z.bm + z.bh + z.bvh, 1e-9 * sum);
}

// The tables' edges: a limit is still inside its rating, one lumen more is not.
TEST(BugRating, ThresholdsFromZoneLumens) {
  BugZones z;
  EXPECT_EQ(to_string(rate_bug(z)), "B0-U0-G0");
  z.bh = 110;
  z.bm = 220;
  z.bl = 110;
  EXPECT_EQ(rate_bug(z).b, 0);
  z.bm = 221;
  EXPECT_EQ(rate_bug(z).b, 1);
  z.bl = 8000;
  EXPECT_EQ(rate_bug(z).b, 5);
  z = {};
  z.ul = 10;
  EXPECT_EQ(rate_bug(z).u, 1);
  z.uh = 0.001;
  EXPECT_EQ(rate_bug(z).u, 1);
  z.ul = 0;
  z.uh = 0;
  EXPECT_EQ(rate_bug(z).u, 0);
  z.uh = 1000.5;
  EXPECT_EQ(rate_bug(z).u, 5);
  z = {};
  z.fvh = 10;
  z.fh = 660;
  EXPECT_EQ(rate_bug(z).g, 0);
  z.fh = 7000;  // FH alone: G3
  EXPECT_EQ(rate_bug(z).g, 3);
  z.fvh = 351;  // beyond G4's 350
  EXPECT_EQ(rate_bug(z).g, 5);
  z = {};
  z.bh = 2000;  // BH counts in glare too
  EXPECT_EQ(rate_bug(z).g, 3);
  EXPECT_EQ(rate_bug(z).b, 3);
}

// A Lambertian full cut-off downlight of 10 000 lm, built from its zonal
// lumens by hand: the flux within γ of the nadir is Φ sin²γ, half of it in
// front and half behind.
TEST(BugRating, LambertianDownlightByHand) {
  const double flux = 10000;
  const Distribution d = sample_direction(PhotometricType::C, Symmetry::Quadrant, angles(0, 90, 5),
                                          angles(0, 180, 0.5), cos_lobe(flux / kPi, 1));
  const auto share = [&](double a, double b) {
    return 0.5 * flux * (std::pow(std::sin(b * kDeg), 2) - std::pow(std::sin(a * kDeg), 2));
  };
  const BugRating r = bug_rating(d);
  const BugZones& z = r.zones_lm;
  EXPECT_NEAR(z.fl, share(0, 30), 1.0);
  EXPECT_NEAR(z.bl, share(0, 30), 1.0);
  EXPECT_NEAR(z.fm, share(30, 60), 1.0);
  EXPECT_NEAR(z.bh, share(60, 80), 1.0);
  EXPECT_NEAR(z.fvh, share(80, 90), 1.0);
  EXPECT_EQ(z.ul, 0.0);
  EXPECT_EQ(z.uh, 0.0);
  // BL 1250 > 1000 → B3; no uplight → U0. Rotationally symmetric, so the
  // Type V/VS glare table: FVH 151 ≤ 225 and FH = BH = 1099 ≤ 1800 → G2 (the
  // Types I-IV table would hold BH to 1000 for G2 → G3).
  EXPECT_EQ(r.glare_table, BugGlareTable::QuadrilateralSymmetric);
  EXPECT_EQ(to_string(r), "B3-U0-G2");
  EXPECT_EQ(rate_bug(z, BugGlareTable::Asymmetric).g, 3);
}

// Light thrown only toward C90 (the street side) has no backlight.
TEST(BugRating, FrontIsTheC90Side) {
  const Distribution d = sample_c(Symmetry::None, angles(0, 360, 5), angles(0, 180, 1),
                                  [](double c, double g) {
                                    if (g >= 90) return 0.0;
                                    return c > 10 && c < 170 ? 500.0 * std::cos(g * kDeg) : 0.0;
                                  });
  const BugRating r = bug_rating(d);
  EXPECT_EQ(r.zones_lm.bl + r.zones_lm.bm + r.zones_lm.bh + r.zones_lm.bvh, 0.0);
  EXPECT_GT(r.zones_lm.fl, 0.0);
  EXPECT_EQ(r.b, 0);
  EXPECT_EQ(r.glare_table, BugGlareTable::Asymmetric);  // half the octants dark
}

TEST(BugRating, UplightZones) {
  // Isotropic 100 cd: UL holds 2π·100·(cos 90° − cos 100°), UH the rest of the top.
  const Distribution d =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 0.5), [](double, double) { return 100.0; });
  const BugRating r = bug_rating(d);
  EXPECT_NEAR(r.zones_lm.ul, 2 * kPi * 100 * std::cos(80 * kDeg), 0.05);
  EXPECT_NEAR(r.zones_lm.ul + r.zones_lm.uh, 2 * kPi * 100, 0.05);
  EXPECT_EQ(r.u, 4);  // UL 109 lm, UH 519 lm: U3 needs UH ≤ 500, U4 holds (≤ 1000)
}

}  // namespace
}  // namespace gonio::photometry
