#include "photometry/bug_rating.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_c;
using test::sample_direction;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

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
  // BL 1250 > 1000 → B3; no uplight → U0; FVH 151 ≤ 225 but BH 1099 > 1000 → G3.
  EXPECT_EQ(to_string(r), "B3-U0-G3");
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
