#include "photometry/angles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "photometry/frame.h"
#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

void expect_near(const Vec3& a, const Vec3& b, double tol = 1e-12) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

const Vec3 kNadir{0, 0, -1};
const Vec3 kZenith{0, 0, 1};
const Vec3 kC0{1, 0, 0};  // LM-63 "photometric horizontal"
const Vec3 kC90{0, 1, 0};
const Vec3 kC270{0, -1, 0};

TEST(Angles, Lm63PhotometricZeroAndHorizontal) {
  // LM-63-2002 §3: photometric zero is the nadir at (H 0, V 0) for Types B and
  // C and at (H 0, V -90) for Type A; photometric horizontal is at (H 0, V 90)
  // for Types B and C and at (H 0, V 0) for Type A.
  expect_near(direction_from_grid(PhotometricType::C, 0, 0), kNadir);
  expect_near(direction_from_grid(PhotometricType::B, 0, 0), kNadir);
  expect_near(direction_from_grid(PhotometricType::A, 0, -90), kNadir);
  expect_near(direction_from_grid(PhotometricType::C, 0, 90), kC0);
  expect_near(direction_from_grid(PhotometricType::B, 0, 90), kC0);
  expect_near(direction_from_grid(PhotometricType::A, 0, 0), kC0);
  expect_near(direction_from_grid(PhotometricType::C, 0, 180), kZenith);
  expect_near(direction_from_grid(PhotometricType::A, 0, 90), kZenith);
}

TEST(Angles, HorizontalAnglesTurnCounterClockwiseForCAndClockwiseForAB) {
  // Seen from above, C0 -> C90 is counter-clockwise (+x -> +y); LM-63 counts
  // Types A and B clockwise, so +H turns from +x towards -y.
  expect_near(direction_from_grid(PhotometricType::C, 90, 90), kC90);
  expect_near(direction_from_grid(PhotometricType::A, 90, 0), kC270);
  expect_near(direction_from_grid(PhotometricType::B, 90, 0), kC270);
  expect_near(direction_from_grid(PhotometricType::B, 90, 37), kC270);  // a pole of Type B
  expect_near(direction_from_grid(PhotometricType::B, -90, -12), kC90);
  // Type B planes share the horizontal y axis: every direction with H = 0
  // lies in the x-z plane (the C0-C180 plane), V turning nadir -> +x.
  for (double v = -90; v <= 90; v += 15) {
    const Vec3 d = direction_from_grid(PhotometricType::B, 0, v);
    EXPECT_NEAR(d.y, 0.0, 1e-15);
    expect_near(d, {std::sin(v * kDeg), 0, -std::cos(v * kDeg)});
  }
  // Type A planes share the vertical axis: H fixes the azimuth.
  for (double v = -80; v <= 80; v += 20) {
    const Vec3 d = direction_from_grid(PhotometricType::A, 30, v);
    EXPECT_NEAR(std::atan2(d.y, d.x), -30 * kDeg, 1e-12);
  }
}

TEST(Angles, TypeAIsTypeCRelabelled) {
  for (double h = -180; h <= 180; h += 22.5)
    for (double v = -90; v <= 90; v += 7.5)
      expect_near(direction_from_grid(PhotometricType::A, h, v),
                  direction_from_grid(PhotometricType::C, -h, v + 90));
}

TEST(Angles, TypeBMatchesTheCieConversionFormulas) {
  // sin H = -sin γ sin C and tan V = tan γ cos C (with the clockwise H of LM-63).
  for (double c = 0; c < 360; c += 15) {
    for (double g = 2.5; g < 90; g += 7.5) {
      const GridAngles b =
          grid_from_direction(PhotometricType::B, direction_from_c_gamma(c * kDeg, g * kDeg));
      EXPECT_NEAR(std::sin(b.horizontal_deg * kDeg), -std::sin(g * kDeg) * std::sin(c * kDeg),
                  1e-12);
      EXPECT_NEAR(std::tan(b.vertical_deg * kDeg), std::tan(g * kDeg) * std::cos(c * kDeg), 1e-9);
    }
  }
}

TEST(Angles, RoundTrips) {
  for (double h = -89; h <= 89; h += 8) {
    for (double v = -179; v <= 179; v += 11) {
      const GridAngles b =
          grid_from_direction(PhotometricType::B, direction_from_grid(PhotometricType::B, h, v));
      EXPECT_NEAR(b.horizontal_deg, h, 1e-10);
      EXPECT_NEAR(b.vertical_deg, v, 1e-10);
    }
  }
  for (double h = -179; h <= 179; h += 11) {
    for (double v = -89; v <= 89; v += 8) {
      const GridAngles a =
          grid_from_direction(PhotometricType::A, direction_from_grid(PhotometricType::A, h, v));
      EXPECT_NEAR(a.horizontal_deg, h, 1e-10);
      EXPECT_NEAR(a.vertical_deg, v, 1e-10);
    }
  }
  for (double c = 0; c < 360; c += 13) {
    for (double g = 1; g < 180; g += 9) {
      const GridAngles k =
          grid_from_direction(PhotometricType::C, direction_from_grid(PhotometricType::C, c, g));
      EXPECT_NEAR(k.horizontal_deg, c, 1e-10);
      EXPECT_NEAR(k.vertical_deg, g, 1e-10);
    }
  }
  // Poles map to a fixed second angle, and scaled directions give the same angles.
  EXPECT_EQ(grid_from_direction(PhotometricType::B, {0, 2, 0}).vertical_deg, 0.0);
  EXPECT_NEAR(grid_from_direction(PhotometricType::B, {0, 2, 0}).horizontal_deg, -90.0, 1e-12);
  EXPECT_EQ(grid_from_direction(PhotometricType::A, {0, 0, -3}).horizontal_deg, 0.0);
  EXPECT_NEAR(grid_from_direction(PhotometricType::A, {0, 0, -3}).vertical_deg, -90.0, 1e-12);
  const GridAngles s = grid_from_direction(PhotometricType::B, {3, -1, -2});
  const GridAngles u = grid_from_direction(PhotometricType::B, normalize(Vec3{3, -1, -2}));
  EXPECT_NEAR(s.horizontal_deg, u.horizontal_deg, 1e-12);
  EXPECT_NEAR(s.vertical_deg, u.vertical_deg, 1e-12);
}

TEST(Angles, LateralMirrorIsTheC0C180Plane) {
  for (PhotometricType t : {PhotometricType::A, PhotometricType::B}) {
    for (double h = 0; h <= 90; h += 10) {
      for (double v = -90; v <= 90; v += 10) {
        const Vec3 p = direction_from_grid(t, h, v), m = direction_from_grid(t, -h, v);
        expect_near(m, {p.x, -p.y, p.z});
      }
    }
  }
}

TEST(Angles, Lm63GridsCoverTheirHemispheres) {
  // H, V in -90..90: Type B covers z <= 0, Type A covers x >= 0.
  for (double h = -90; h <= 90; h += 5) {
    for (double v = -90; v <= 90; v += 5) {
      EXPECT_LE(direction_from_grid(PhotometricType::B, h, v).z, 1e-15);
      EXPECT_GE(direction_from_grid(PhotometricType::A, h, v).x, -1e-15);
    }
  }
}

// |∂d/∂h × ∂d/∂v| by central differences.
double numeric_jacobian(PhotometricType t, double h, double v) {
  const double e = 1e-6;
  auto d = [&](double hh, double vv) { return direction_from_grid(t, hh / kDeg, vv / kDeg); };
  const Vec3 dh = (d(h + e, v) - d(h - e, v)) / (2 * e);
  const Vec3 dv = (d(h, v + e) - d(h, v - e)) / (2 * e);
  return length(cross(dh, dv));
}

TEST(Angles, SolidAngleJacobianMatchesTheMapping) {
  for (PhotometricType t : {PhotometricType::A, PhotometricType::B, PhotometricType::C}) {
    for (double h = -1.4; h <= 1.4; h += 0.2) {
      for (double v = 0.05; v <= 1.5; v += 0.15) {
        const double vv = t == PhotometricType::A ? v - 0.8 : v;  // keep A's V inside (-π/2, π/2)
        EXPECT_NEAR(solid_angle_jacobian(t, h, vv), numeric_jacobian(t, h, vv), 1e-8)
            << to_string(t) << " h " << h << " v " << vv;
      }
    }
  }
  // Integrated over each system's whole domain, the Jacobian gives 4π.
  const int n = 2000;
  double a = 0, b = 0, c = 0;
  for (int i = 0; i < n; ++i) {
    const double u = (i + 0.5) / n;
    a += solid_angle_jacobian(PhotometricType::A, 0, -kPi / 2 + kPi * u) * kPi / n * 2 * kPi;
    b += solid_angle_jacobian(PhotometricType::B, -kPi / 2 + kPi * u, 0) * kPi / n * 2 * kPi;
    c += solid_angle_jacobian(PhotometricType::C, 0, kPi * u) * kPi / n * 2 * kPi;
  }
  EXPECT_NEAR(a, 4 * kPi, 1e-5);
  EXPECT_NEAR(b, 4 * kPi, 1e-5);
  EXPECT_NEAR(c, 4 * kPi, 1e-5);
}

// A smooth, asymmetric intensity of the local direction.
double field(const Vec3& d) {
  return 100.0 + 40.0 * d.x + 25.0 * d.y - 30.0 * d.z + 10.0 * d.x * d.y;
}

Distribution sample(PhotometricType type, std::vector<double> h, std::vector<double> v) {
  Distribution d;
  d.type = type;
  d.symmetry = Symmetry::None;
  d.horizontal_deg = std::move(h);
  d.vertical_deg = std::move(v);
  for (double hh : d.horizontal_deg)
    for (double vv : d.vertical_deg) d.candela.push_back(field(direction_from_grid(type, hh, vv)));
  d.absolute = true;
  d.lamps = {LampSet{}};
  return d;
}

using test::angles;

TEST(Angles, IntensityTowardADirectionReadsTheRightGridCell) {
  const Distribution b =
      expand_symmetry(sample(PhotometricType::B, angles(-90, 90, 1), angles(-90, 90, 1)));
  const Distribution a =
      expand_symmetry(sample(PhotometricType::A, angles(-90, 90, 1), angles(-90, 90, 1)));
  const Distribution c =
      expand_symmetry(sample(PhotometricType::C, angles(0, 360, 1), angles(0, 180, 1)));
  for (double u = -0.9; u <= 0.9; u += 0.3) {
    for (double w = -0.9; w <= 0.9; w += 0.3) {
      const Vec3 down = normalize(Vec3{u, w, -1.0});  // lower hemisphere: inside Type B's grid
      const Vec3 front = normalize(Vec3{1.0, u, w});  // x > 0: inside Type A's grid
      EXPECT_NEAR(intensity_toward(b, down), field(down), 0.02);
      EXPECT_NEAR(intensity_toward(a, front), field(front), 0.02);
      EXPECT_NEAR(intensity_toward(c, down), field(down), 0.02);
      EXPECT_NEAR(intensity_toward(c, -front), field(-front), 0.02);
      // Outside the LM-63 grids nothing is measured, so nothing is emitted.
      EXPECT_EQ(intensity_toward(b, -down), 0.0);
      EXPECT_EQ(intensity_toward(a, -front), 0.0);
    }
  }
}

}  // namespace
}  // namespace gonio::photometry
