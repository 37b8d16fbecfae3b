#include "photometry/luminance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_direction;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

LuminousOpening opening(OpeningShape shape, double l, double w, double h = 0.0) {
  LuminousOpening o;
  o.shape = shape;
  o.length_m = l;
  o.width_m = w;
  o.height_m = h;
  return o;
}

TEST(ProjectedArea, ClosedForms) {
  const auto rect = opening(OpeningShape::Rectangular, 1.2, 0.3);
  EXPECT_NEAR(projected_area_m2(rect, 37, 60), 0.36 * 0.5, 1e-12);
  EXPECT_EQ(projected_area_m2(rect, 0, 120), 0.0);  // a downward face is not seen from above
  const auto box = opening(OpeningShape::RectangularWithSides, 1.2, 0.3, 0.1);
  // From C0 at γ 60°: bottom cos 60° + the C0 face (width × height) sin 60°.
  EXPECT_NEAR(projected_area_m2(box, 0, 60), 0.36 * 0.5 + 0.3 * 0.1 * std::sin(60 * kDeg), 1e-12);
  EXPECT_NEAR(projected_area_m2(box, 90, 60), 0.36 * 0.5 + 1.2 * 0.1 * std::sin(60 * kDeg), 1e-12);
  const auto sphere = opening(OpeningShape::Sphere, 0.2, 0.2, 0.2);
  for (double g : {0.0, 45.0, 90.0, 170.0})
    EXPECT_NEAR(projected_area_m2(sphere, 33, g), kPi * 0.01, 1e-12);
  const auto cyl = opening(OpeningShape::VerticalCylinder, 0.2, 0.2, 0.5);
  EXPECT_NEAR(projected_area_m2(cyl, 10, 90), 0.2 * 0.5, 1e-12);
  EXPECT_NEAR(projected_area_m2(cyl, 10, 0), kPi * 0.01, 1e-12);
  // An ellipsoid seen along its axes shows the ellipse of the other two.
  const auto ell = opening(OpeningShape::Ellipsoid, 0.4, 0.2, 0.1);
  EXPECT_NEAR(projected_area_m2(ell, 0, 0), kPi * 0.2 * 0.1, 1e-12);
  EXPECT_NEAR(projected_area_m2(ell, 0, 90), kPi * 0.1 * 0.05, 1e-12);
  EXPECT_EQ(projected_area_m2(opening(OpeningShape::Point, 0, 0), 0, 45), 0.0);
}

TEST(ProjectedArea, EulumdatSideHeightsPerFace) {
  auto o = opening(OpeningShape::RectangularWithSides, 1.0, 0.5, 0.2);
  o.side_height_m[0] = 0.2;  // C0 face
  o.side_height_m[1] = 0.0;
  o.side_height_m[2] = 0.0;
  o.side_height_m[3] = 0.1;  // C270 face
  const double s = std::sin(60 * kDeg);
  EXPECT_NEAR(projected_area_m2(o, 0, 60), 0.5 * 0.5 + 0.5 * 0.2 * s, 1e-12);
  EXPECT_NEAR(projected_area_m2(o, 180, 60), 0.5 * 0.5, 1e-12);
  EXPECT_NEAR(projected_area_m2(o, 270, 60), 0.5 * 0.5 + 1.0 * 0.1 * s, 1e-12);
}

// An EULUMDAT round opening with side heights (a disc of diameter D over a
// cylinder's side, CIE 117's A_bottom cos γ + A_side sin γ with A_side =
// D h): the same side area from every C when the heights are equal (a box
// reading, D h (|cos C| + |sin C|), would be √2 larger at C45), and the
// facing side's height where they differ.
TEST(ProjectedArea, EulumdatRoundOpeningWithSideHeights) {
  auto o = opening(OpeningShape::VerticalCylinder, 0.075, 0.075, 0.083);
  for (double& h : o.side_height_m) h = 0.083;
  const double c60 = 0.5, s60 = std::sin(60 * kDeg), disc = kPi / 4 * 0.075 * 0.075;
  for (double c : {0.0, 30.0, 45.0, 135.0, 300.0})
    EXPECT_NEAR(projected_area_m2(o, c, 60), disc * c60 + 0.075 * 0.083 * s60, 1e-12) << "C " << c;
  o.side_height_m[0] = 0.02;  // toward C0
  o.side_height_m[1] = 0.04;  // toward C90
  EXPECT_NEAR(projected_area_m2(o, 0, 60), disc * c60 + 0.075 * 0.02 * s60, 1e-12);
  EXPECT_NEAR(projected_area_m2(o, 90, 60), disc * c60 + 0.075 * 0.04 * s60, 1e-12);
  EXPECT_NEAR(projected_area_m2(o, 180, 60), disc * c60 + 0.075 * 0.083 * s60, 1e-12);
  EXPECT_NEAR(projected_area_m2(o, 45, 60), disc * c60 + 0.075 * 0.03 * s60, 1e-12);
}

// A flat Lambertian disc has one luminance in every direction: I₀ / A.
TEST(LuminanceTable, LambertianDiscIsUniform) {
  Distribution d = sample_direction(PhotometricType::C, Symmetry::Rotational, {0},
                                    angles(0, 180, 2.5), cos_lobe(1000, 1));
  d.opening = opening(OpeningShape::Circular, 0.2, 0.2);
  const LuminanceTable t = luminance_table(d);
  ASSERT_TRUE(t.defined);
  ASSERT_EQ(t.gamma_deg.size(), 9u);
  EXPECT_EQ(t.gamma_deg.front(), 45.0);
  EXPECT_EQ(t.gamma_deg.back(), 85.0);
  const double l = 1000 / (kPi * 0.01);
  for (std::size_t c = 0; c < t.c_deg.size(); ++c)
    for (std::size_t g = 0; g < t.gamma_deg.size(); ++g) {
      EXPECT_NEAR(t.cd_m2[c][g] / l, 1.0, 1e-9);
      EXPECT_NEAR(t.ldt_cd_m2[c][g] / l, 1.0, 1e-9);
    }
  EXPECT_NEAR(t.max_cd_m2 / l, 1.0, 1e-9);
}

TEST(LuminanceTable, SidesLowerTheLuminanceAtGrazingAngles) {
  Distribution d = sample_direction(PhotometricType::C, Symmetry::Quadrant, angles(0, 90, 15),
                                    angles(0, 180, 5), cos_lobe(1000, 1));
  d.opening = opening(OpeningShape::RectangularWithSides, 0.6, 0.6, 0.05);
  const LuminanceTable t = luminance_table(d);
  ASSERT_TRUE(t.defined);
  // At 85° the side (0.6 × 0.05 sin 85°) is as large as the bottom's
  // projection (0.36 cos 85°): about half the bottom-only reading.
  const double s85 = std::sin(85 * kDeg), c85 = std::cos(85 * kDeg);
  EXPECT_NEAR(t.cd_m2[0].back() / t.ldt_cd_m2[0].back(), 0.36 * c85 / (0.36 * c85 + 0.03 * s85), 1e-9);
  EXPECT_LT(t.cd_m2[0].back(), 0.55 * t.ldt_cd_m2[0].back());
  EXPECT_NEAR(t.cd_m2[0][0],
              1000 * std::cos(45 * kDeg) /
                  (0.36 * std::cos(45 * kDeg) + 0.6 * 0.05 * std::sin(45 * kDeg)),
              1e-6);
}

TEST(LuminanceTable, PointOpeningIsUndefinedWithAReason) {
  const Distribution d = sample_direction(PhotometricType::C, Symmetry::Rotational, {0},
                                          angles(0, 180, 5), cos_lobe(1000, 1));
  const LuminanceTable t = luminance_table(d);
  EXPECT_FALSE(t.defined);
  EXPECT_NE(t.why_undefined.find("point"), std::string::npos);
}

}  // namespace
}  // namespace gonio::photometry
