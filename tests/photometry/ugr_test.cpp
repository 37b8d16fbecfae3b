#include "photometry/ugr.h"

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

// A 600 × 600 mm Lambertian panel of 3000 lm.
Distribution panel(Symmetry symmetry = Symmetry::Rotational) {
  std::vector<double> c = symmetry == Symmetry::Rotational ? std::vector<double>{0}
                                                           : angles(0, 360, 15);
  Distribution d = sample_direction(PhotometricType::C, symmetry, c, angles(0, 180, 2.5),
                                    cos_lobe(3000 / kPi, 1));
  d.opening.shape = OpeningShape::Circular;
  d.opening.length_m = d.opening.width_m = 0.6;
  return d;
}

TEST(Ugr, RoomSizesInCie190Order) {
  const auto rooms = ugr_room_sizes();
  ASSERT_EQ(rooms.size(), 19u);
  EXPECT_EQ(rooms[0][0], 2.0);
  EXPECT_EQ(rooms[0][1], 2.0);
  EXPECT_EQ(rooms[5][1], 12.0);
  EXPECT_EQ(rooms[6][0], 4.0);
  EXPECT_EQ(rooms[12][0], 8.0);
  EXPECT_EQ(rooms[12][1], 4.0);
  EXPECT_EQ(rooms[18][0], 12.0);
  EXPECT_EQ(rooms[18][1], 8.0);
}

// A rotationally symmetric luminaire with a round opening looks the same
// from every side: crosswise = endwise in every room.
TEST(Ugr, RotationalSymmetryCrosswiseEqualsEndwise) {
  const UgrTable t = ugr_table(panel());
  ASSERT_TRUE(t.defined) << t.why_undefined;
  ASSERT_EQ(t.rooms.size(), 19u);
  for (const UgrRoom& r : t.rooms)
    for (int k = 0; k < 5; ++k) {
      ASSERT_TRUE(std::isfinite(r.crosswise[k]));
      EXPECT_NEAR(r.crosswise[k], r.endwise[k], 1e-9) << r.x_h << "H x " << r.y_h << "H";
    }
}

// L² ω and L_b both scale with the flux: UGR moves by 8 log10 of the ratio.
TEST(Ugr, FluxChangeAddsEightLogRatio) {
  const Distribution a = panel();
  Distribution b = a;
  for (double& v : b.candela) v *= 2.5;
  const UgrTable ta = ugr_table(a), tb = ugr_table(b);
  for (std::size_t i = 0; i < ta.rooms.size(); ++i)
    for (int k = 0; k < 5; ++k)
      EXPECT_NEAR(tb.rooms[i].crosswise[k] - ta.rooms[i].crosswise[k], 8 * std::log10(2.5), 1e-9);
}

// A larger luminous area at the same intensities lowers the luminance:
// L² ω = I² / (A_p r²), so four times the area takes 8 log10 4 off.
TEST(Ugr, FourTimesTheAreaTakesEightLogFourOff) {
  const Distribution a = panel();
  Distribution b = a;
  b.opening.length_m = b.opening.width_m = 1.2;
  const double da = ugr(a, 4, 8, kUgrReflectances[0], false);
  const double db = ugr(b, 4, 8, kUgrReflectances[0], false);
  EXPECT_NEAR(da - db, 8 * std::log10(4.0), 1e-9);
}

// Lighter surfaces raise the background luminance and lower UGR; a room
// seen deeper holds more luminaires in view.
TEST(Ugr, OrderingsOfTheStandardTable) {
  const UgrTable t = ugr_table(panel());
  for (const UgrRoom& r : t.rooms) {
    EXPECT_LT(r.crosswise[0], r.crosswise[1]);  // walls 50 % < 30 %
    EXPECT_LT(r.crosswise[0], r.crosswise[2]);  // ceiling 70 % < 50 %
    EXPECT_LT(r.crosswise[3], r.crosswise[4]);  // 50/30 < 30/30
  }
  // 4H × 8H against 4H × 2H (rooms[10] and rooms[6]).
  EXPECT_GT(t.rooms[10].crosswise[0], t.rooms[6].crosswise[0]);
  // A plausible magnitude for a bare 3000 lm panel of 0.28 m²: 15…25.
  EXPECT_GT(t.rooms[10].crosswise[0], 15.0);
  EXPECT_LT(t.rooms[10].crosswise[0], 25.0);
}

// A linear luminaire, bright across its axis (C90) and dark along it (C0),
// glares more when seen crosswise than endwise.
TEST(Ugr, LinearLuminaireGlaresMoreCrosswise) {
  Distribution d = sample_c(Symmetry::Quadrant, angles(0, 90, 15), angles(0, 180, 2.5),
                            [](double c, double g) {
                              if (g >= 90) return 0.0;
                              const double s = std::sin(c * kPi / 180);
                              const double n = 1 + 6 * (1 - s * s);  // narrow in C0, wide in C90
                              return 1000 * std::pow(std::cos(g * kPi / 180), n);
                            });
  d.opening.shape = OpeningShape::Rectangular;
  d.opening.length_m = 1.2;
  d.opening.width_m = 0.1;
  const UgrTable t = ugr_table(d);
  ASSERT_TRUE(t.defined);
  EXPECT_GT(t.rooms[10].crosswise[0], t.rooms[10].endwise[0] + 1.0);
}

// The table shares work across its rooms (each luminaire position's glare
// term once per orientation, one pass over the hemisphere for every room's
// direct floor flux); ugr() computes one room on its own. They agree on an
// asymmetric luminaire with some uplight, every room, side and reflectance set.
TEST(Ugr, TableEqualsEachRoomComputedAlone) {
  Distribution d = sample_c(Symmetry::None, angles(0, 360, 10), angles(0, 180, 5), [](double c, double g) {
    const double cr = std::cos(c * kPi / 180), gr = g * kPi / 180;
    return g < 90 ? 800 * std::pow(std::cos(gr), 3) * (1 + 0.4 * cr + 0.2 * cr * cr) : 30 * -std::cos(gr);
  });
  d.opening.shape = OpeningShape::Rectangular;
  d.opening.length_m = 0.9;
  d.opening.width_m = 0.3;
  const UgrTable t = ugr_table(d);
  ASSERT_TRUE(t.defined) << t.why_undefined;
  for (const UgrRoom& r : t.rooms)
    for (std::size_t k = 0; k < kUgrReflectances.size(); ++k) {
      EXPECT_NEAR(r.crosswise[k], ugr(d, r.x_h, r.y_h, kUgrReflectances[k], false), 1e-12)
          << r.x_h << "H x " << r.y_h << "H";
      EXPECT_NEAR(r.endwise[k], ugr(d, r.x_h, r.y_h, kUgrReflectances[k], true), 1e-12)
          << r.x_h << "H x " << r.y_h << "H";
    }
  // Off the table's grid (walls not on the spacing) the same figure moves
  // smoothly with the spacing.
  const double at_025 = ugr(d, 4, 8, kUgrReflectances[0], false, 0.25);
  EXPECT_NEAR(ugr(d, 4, 8, kUgrReflectances[0], false, 0.26), at_025, 0.5);
}

TEST(Ugr, UplightIsUndefinedWithAReason) {
  Distribution d = sample_c(Symmetry::Rotational, {0}, angles(0, 180, 5),
                            [](double, double g) { return g > 90 ? 100.0 : 0.0; });
  d.opening.shape = OpeningShape::Rectangular;
  d.opening.length_m = d.opening.width_m = 0.6;
  const UgrTable t = ugr_table(d);
  EXPECT_FALSE(t.defined);
  EXPECT_TRUE(t.rooms.empty());
  EXPECT_NE(t.why_undefined.find("eye"), std::string::npos);
}

TEST(Ugr, PointOpeningIsUndefinedWithAReason) {
  Distribution d = panel();
  d.opening = {};
  const UgrTable t = ugr_table(d);
  EXPECT_FALSE(t.defined);
  EXPECT_NE(t.why_undefined.find("luminous area"), std::string::npos);
}

}  // namespace
}  // namespace gonio::photometry
