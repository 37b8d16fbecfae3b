#include "photometry/luminance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>
#include <vector>

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

// Issue 34, case 7: the vertical elliptical cylinder and the horizontal
// cylinders, seen along the frame's axes (length l along C0–C180, width w
// along C90–C270, height h; LM-63-2019's axes). From the nadir: the
// footprint; from C0 at γ 90°: the face across C0 (a vertical elliptical
// cylinder and one along the width show w·h, one along the length its round
// end π/4·w·h); from C90 at 90°: the face across C90 (l·h, or the round end
// π/4·l·h of one along the width). A shape read with l and w exchanged, or
// C0 and C90 exchanged, fails every horizontal view.
TEST(ProjectedArea, CylindersAlongTheFramesAxes) {
  const double l = 0.6, w = 0.2, h = 0.1;
  struct View {
    double c_deg, gamma_deg, area;
  };
  const auto check = [](const LuminousOpening& o, std::initializer_list<View> views) {
    for (const View& v : views)
      EXPECT_NEAR(projected_area_m2(o, v.c_deg, v.gamma_deg), v.area, 1e-12)
          << to_string(o.shape) << " from C " << v.c_deg << ", gamma " << v.gamma_deg;
  };
  check(opening(OpeningShape::VerticalEllipticalCylinder, l, w, h),
        {{0, 0, kPi / 4 * l * w}, {0, 90, w * h}, {90, 90, l * h}, {180, 90, w * h}, {270, 90, l * h},
         {0, 180, kPi / 4 * l * w}});
  check(opening(OpeningShape::HorizontalEllipticalCylinderAlongLength, l, w, h),
        {{0, 0, l * w}, {0, 90, kPi / 4 * w * h}, {90, 90, l * h}, {180, 90, kPi / 4 * w * h}, {0, 180, l * w}});
  check(opening(OpeningShape::HorizontalEllipticalCylinderAlongWidth, l, w, h),
        {{0, 0, w * l}, {0, 90, w * h}, {90, 90, kPi / 4 * l * h}, {270, 90, kPi / 4 * l * h}, {0, 180, w * l}});
  // Round cylinders (height 0: the cross-section is a circle of the width,
  // or of the length for one along the width).
  check(opening(OpeningShape::HorizontalCylinderAlongLength, l, w),
        {{0, 0, l * w}, {0, 90, kPi / 4 * w * w}, {90, 90, l * w}});
  check(opening(OpeningShape::HorizontalCylinderAlongWidth, l, w),
        {{0, 0, w * l}, {0, 90, w * l}, {90, 90, kPi / 4 * l * l}});
}

// Issue 34, case 8 (the projected-area axes), a check independent of the
// closed forms: every opening shape built as a polyhedron in the
// photometric frame from LM-63-2019's definitions (length along C0–C180 = x,
// width along C90–C270 = y, height z; the C0 vertical disc in the y–z plane),
// its projected area toward d(C, γ) = Σ over faces of max(0, a_f · d), a_f
// the face's outward area vector (Cauchy's projection formula; flat
// openings are one face toward the nadir, a box's top is not luminous).
// Within 0.1 % (the tessellation) at 77 directions; the same shapes with
// length and width exchanged differ by up to 3× and fail.
namespace polyhedron {

using Face = std::vector<Vec3>;

// The area vector of a planar polygon, made to point away from `inside`.
Vec3 outward_area(const Face& f, const Vec3& inside) {
  Vec3 a{0, 0, 0}, mid{0, 0, 0};
  for (std::size_t i = 0; i < f.size(); ++i) {
    a = a + 0.5 * cross(f[i], f[(i + 1) % f.size()]);
    mid = mid + f[i] / static_cast<double>(f.size());
  }
  return dot(a, mid - inside) < 0.0 ? -1.0 * a : a;
}

struct Body {
  std::vector<Face> faces;
  Vec3 inside{0, 0, 0};
  std::vector<Vec3> areas;  // outward area vectors, once the faces are in place
  void close() {
    for (const Face& f : faces) areas.push_back(outward_area(f, inside));
  }
  double projected(const Vec3& d) const {
    double s = 0.0;
    for (const Vec3& a : areas) s += std::max(0.0, dot(a, d));
    return s;
  }
};

constexpr int kN = 720;

// An ellipse of semi-axes a along u and b along v about c.
Face ellipse(const Vec3& c, const Vec3& u, double a, const Vec3& v, double b) {
  Face f;
  for (int i = 0; i < kN; ++i) {
    const double t = 2 * kPi * i / kN;
    f.push_back(c + a * std::cos(t) * u + b * std::sin(t) * v);
  }
  return f;
}

// A cylinder of elliptical section (semi-axes a along u, b along v) along
// `axis` from c − axis·len/2 to c + axis·len/2, with both ends.
void cylinder(Body& body, const Vec3& c, const Vec3& axis, double len, const Vec3& u, double a, const Vec3& v,
              double b) {
  const Face lo = ellipse(c - 0.5 * len * axis, u, a, v, b), hi = ellipse(c + 0.5 * len * axis, u, a, v, b);
  body.faces.push_back(lo);
  body.faces.push_back(hi);
  for (int i = 0; i < kN; ++i) {
    const int j = (i + 1) % kN;
    body.faces.push_back({lo[i], lo[j], hi[j], hi[i]});
  }
  body.inside = c;
}

Body of(const LuminousOpening& o) {
  using S = OpeningShape;
  const double l = o.length_m, w = o.width_m, h = o.height_m;
  const Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  Body b;
  switch (o.shape) {
    case S::Rectangular:
      b.faces = {{{-l / 2, -w / 2, 0}, {l / 2, -w / 2, 0}, {l / 2, w / 2, 0}, {-l / 2, w / 2, 0}}};
      b.inside = {0, 0, 1};  // one face, toward the nadir
      break;
    case S::Circular:
      b.faces = {ellipse({0, 0, 0}, x, std::max(l, w) / 2, y, std::max(l, w) / 2)};
      b.inside = {0, 0, 1};
      break;
    case S::Ellipse:
      b.faces = {ellipse({0, 0, 0}, x, l / 2, y, w / 2)};
      b.inside = {0, 0, 1};
      break;
    case S::RectangularWithSides: {
      const Vec3 p[8] = {{-l / 2, -w / 2, 0}, {l / 2, -w / 2, 0}, {l / 2, w / 2, 0}, {-l / 2, w / 2, 0},
                         {-l / 2, -w / 2, h}, {l / 2, -w / 2, h}, {l / 2, w / 2, h}, {-l / 2, w / 2, h}};
      b.faces = {{p[0], p[1], p[2], p[3]}, {p[0], p[1], p[5], p[4]}, {p[1], p[2], p[6], p[5]},
                 {p[2], p[3], p[7], p[6]}, {p[3], p[0], p[4], p[7]}};  // no top
      b.inside = {0, 0, h / 2};
      break;
    }
    case S::VerticalCylinder:
      cylinder(b, {0, 0, h / 2}, z, h, x, std::max(l, w) / 2, y, std::max(l, w) / 2);
      break;
    case S::VerticalEllipticalCylinder:
      cylinder(b, {0, 0, h / 2}, z, h, x, l / 2, y, w / 2);
      break;
    case S::HorizontalCylinderAlongLength:
    case S::HorizontalEllipticalCylinderAlongLength:
      cylinder(b, {0, 0, 0}, x, l, y, w / 2, z, (h > 0 ? h : w) / 2);
      break;
    case S::HorizontalCylinderAlongWidth:
    case S::HorizontalEllipticalCylinderAlongWidth:
      cylinder(b, {0, 0, 0}, y, w, x, l / 2, z, (h > 0 ? h : l) / 2);
      break;
    case S::Sphere:
    case S::Ellipsoid: {
      const double dia = std::max({l, w, h});
      const Vec3 r = o.shape == S::Sphere ? Vec3{dia / 2, dia / 2, dia / 2} : Vec3{l / 2, w / 2, h / 2};
      const int rings = 120, segments = 240;
      const auto at = [&](int i, int j) {
        const double th = kPi * i / rings, ph = 2 * kPi * j / segments;
        return Vec3{r.x * std::sin(th) * std::cos(ph), r.y * std::sin(th) * std::sin(ph), r.z * std::cos(th)};
      };
      for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
          if (i > 0) b.faces.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
          if (i + 1 < rings) b.faces.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
        }
      break;
    }
    case S::VerticalCircle:
      b.faces = {ellipse({0, 0, 0}, y, std::max(w, h) / 2, z, std::max(w, h) / 2)};
      b.inside = {-1, 0, 0};  // facing C0
      break;
    case S::VerticalEllipse:
      b.faces = {ellipse({0, 0, 0}, y, w / 2, z, h / 2)};
      b.inside = {-1, 0, 0};
      break;
    case S::Point:
      break;
  }
  b.close();
  return b;
}

}  // namespace polyhedron

TEST(ProjectedArea, EveryShapeIsItsPolyhedronsShadowAlongLm63sAxes) {
  using S = OpeningShape;
  const double l = 0.6, w = 0.25, h = 0.1;
  std::vector<std::pair<double, double>> views;  // (C, γ) [deg]
  for (double c = 0; c < 360; c += 30)
    for (double g : {0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0, 75.0})
      if (!(g == 0.0 || g == 180.0) || c == 0) views.push_back({c, g});
  for (double c : {17.0, 101.0, 253.0}) views.push_back({c, 47.0});
  int checked = 0;
  double worst = 0.0, worst_swapped = 0.0;
  for (const S shape : {S::Rectangular, S::RectangularWithSides, S::Circular, S::Ellipse, S::VerticalCylinder,
                        S::VerticalEllipticalCylinder, S::Sphere, S::Ellipsoid, S::HorizontalCylinderAlongLength,
                        S::HorizontalEllipticalCylinderAlongLength, S::HorizontalCylinderAlongWidth,
                        S::HorizontalEllipticalCylinderAlongWidth, S::VerticalCircle, S::VerticalEllipse}) {
    const bool round_ends = shape == S::HorizontalCylinderAlongLength || shape == S::HorizontalCylinderAlongWidth;
    const LuminousOpening o = opening(shape, l, w, round_ends ? 0.0 : h);
    LuminousOpening swapped = o;
    std::swap(swapped.length_m, swapped.width_m);
    const polyhedron::Body body = polyhedron::of(o), other = polyhedron::of(swapped);
    for (const auto& [c, g] : views) {
      const double cr = c * kDeg, gr = g * kDeg;
      const Vec3 d{std::sin(gr) * std::cos(cr), std::sin(gr) * std::sin(cr), -std::cos(gr)};
      const double want = body.projected(d);
      const double ours = projected_area_m2(o, c, g);
      EXPECT_NEAR(ours, want, 1e-3 * std::max(want, 1e-3)) << to_string(shape) << " from C " << c << ", gamma " << g;
      if (want > 1e-3) {
        worst = std::max(worst, std::abs(ours / want - 1.0));
        worst_swapped = std::max(worst_swapped, std::abs(other.projected(d) / want - 1.0));
      }
      ++checked;
    }
  }
  std::printf("projected areas against the polyhedra: largest difference %.2e; with length and width exchanged %.2f\n",
              worst, worst_swapped);
  EXPECT_EQ(checked, static_cast<int>(14 * views.size()));
  EXPECT_GT(worst_swapped, 1.0) << "length and width exchanged must be visible";
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
