#include "photometry/distribution.h"

#include <gtest/gtest.h>

#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
// A Type C distribution whose intensity is a known function of (C, γ).
constexpr auto make_c = test::sample_c;

double asym(double c, double g) { return 100.0 + c + 0.5 * g; }

TEST(Distribution, ValidAndInvalidModels) {
  Distribution d = make_c(Symmetry::None, angles(0, 360, 30), angles(0, 180, 10), asym);
  EXPECT_TRUE(validate(d).ok());

  Distribution unsorted = d;
  std::swap(unsorted.vertical_deg[2], unsorted.vertical_deg[3]);
  EXPECT_FALSE(validate(unsorted).ok());

  Distribution short_data = d;
  short_data.candela.pop_back();
  Status s = validate(short_data);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("intensities"), std::string::npos);

  Distribution nan = d;
  nan.candela[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(validate(nan).ok());

  Distribution wrong_range = make_c(Symmetry::Quadrant, angles(0, 180, 30), angles(0, 90, 10), asym);
  EXPECT_FALSE(validate(wrong_range).ok());

  Distribution lateral_c = d;
  lateral_c.symmetry = Symmetry::Lateral;
  EXPECT_FALSE(validate(lateral_c).ok());

  Distribution no_flux = d;
  no_flux.lamps[0].flux_lm = kNaN;
  EXPECT_FALSE(validate(no_flux).ok());
  no_flux.absolute = true;
  EXPECT_TRUE(validate(no_flux).ok());
}

TEST(Distribution, NegativeIntensitiesAreStructurallyValid) {
  // Negative values are data problems that `gonio check` reports; the model
  // must hold them so that they can be reported.
  Distribution d = make_c(Symmetry::Rotational, {0}, angles(0, 180, 10), asym);
  d.candela[3] = -1.0;
  EXPECT_TRUE(validate(d).ok());
}

TEST(Distribution, ExpansionMirrorsEachSymmetry) {
  struct Case {
    Symmetry sym;
    std::vector<double> planes;
    double (*mirror)(double c);  // where the value at C comes from
  };
  const Case cases[] = {
      {Symmetry::Quadrant, angles(0, 90, 15),
       [](double c) {
         c = std::fmod(c, 180.0);
         return c > 90.0 ? 180.0 - c : c;
       }},
      {Symmetry::C0_C180, angles(0, 180, 15), [](double c) { return c > 180.0 ? 360.0 - c : c; }},
      {Symmetry::C90_C270, angles(90, 270, 15),
       [](double c) {
         if (c < 90.0) return 180.0 - c;
         if (c > 270.0) return 540.0 - c;
         return c;
       }},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(to_string(k.sym));
    Distribution d = make_c(k.sym, k.planes, angles(0, 180, 10), asym);
    ASSERT_TRUE(validate(d).ok());
    Distribution e = expand_symmetry(d);
    EXPECT_EQ(e.symmetry, Symmetry::None);
    ASSERT_TRUE(validate(e).ok());
    EXPECT_DOUBLE_EQ(e.horizontal_deg.front(), 0.0);
    EXPECT_DOUBLE_EQ(e.horizontal_deg.back(), 360.0);
    EXPECT_EQ(e.horizontal_deg.size(), 360 / 15 + 1);
    for (std::size_t h = 0; h < e.horizontal_count(); ++h) {
      const double c = e.horizontal_deg[h];
      for (std::size_t v = 0; v < e.vertical_count(); ++v)
        EXPECT_DOUBLE_EQ(e.at(h, v), asym(k.mirror(c == 360.0 ? 0.0 : c), e.vertical_deg[v]))
            << "C " << c << " gamma " << e.vertical_deg[v];
    }
  }
}

TEST(Distribution, RotationalExpandsToTwoPlanes) {
  Distribution d = make_c(Symmetry::Rotational, {0}, angles(0, 180, 5), asym);
  Distribution e = expand_symmetry(d);
  ASSERT_EQ(e.horizontal_deg, (std::vector<double>{0.0, 360.0}));
  EXPECT_DOUBLE_EQ(interpolate(e, 123.0, 45.0), asym(0, 45));
}

TEST(Distribution, FullRangeWithoutClosingPlaneWrapsAtTheSeam) {
  // Planes 10..350: the seam is bridged between 350 and 370 (= 10).
  Distribution d = make_c(Symmetry::None, angles(10, 350, 20), {0, 90, 180},
                          [](double c, double) { return c; });
  Distribution e = expand_symmetry(d);
  ASSERT_DOUBLE_EQ(e.horizontal_deg.front(), 0.0);
  ASSERT_DOUBLE_EQ(e.horizontal_deg.back(), 360.0);
  // Halfway between 350 (value 350) and 370 (value 10): 180.
  EXPECT_DOUBLE_EQ(interpolate(e, 0.0, 90.0), 180.0);
  EXPECT_DOUBLE_EQ(interpolate(e, 360.0, 90.0), 180.0);
  EXPECT_DOUBLE_EQ(interpolate(e, 355.0, 90.0), 265.0);
}

TEST(Distribution, InterpolationIsBilinearAndContinuousAcrossTheSeam) {
  Distribution d = make_c(Symmetry::None, angles(0, 360, 10), angles(0, 180, 5),
                          [](double c, double g) { return 1000.0 + 2.0 * std::min(c, 360.0 - c) + g; });
  Distribution e = expand_symmetry(d);
  EXPECT_NEAR(interpolate(e, 12.5, 47.5), 1000.0 + 25.0 + 47.5, 1e-9);
  EXPECT_NEAR(interpolate(e, -5.0, 30.0), interpolate(e, 355.0, 30.0), 1e-12);
  EXPECT_NEAR(interpolate(e, 359.999999, 30.0), interpolate(e, 0.0, 30.0), 1e-3);
  EXPECT_NEAR(interpolate(e, 720.0 + 15.0, 30.0), interpolate(e, 15.0, 30.0), 1e-12);
}

TEST(Distribution, PolesHaveOneValue) {
  // Inconsistent nadir values across planes: the pole gets the circular mean.
  Distribution d = make_c(Symmetry::None, {0, 90, 180, 270, 360}, {0, 90, 180},
                          [](double c, double) { return c == 90.0 ? 200.0 : 100.0; });
  Distribution e = expand_symmetry(d);
  for (double c : {0.0, 45.0, 90.0, 200.0}) EXPECT_DOUBLE_EQ(interpolate(e, c, 0.0), 125.0);
  EXPECT_DOUBLE_EQ(interpolate(e, 17.0, 180.0), 125.0);
}

TEST(Distribution, UnmeasuredDirectionsEmitNothing) {
  Distribution d = make_c(Symmetry::Rotational, {0}, angles(0, 90, 5),
                          [](double, double) { return 50.0; });
  Distribution e = expand_symmetry(d);
  EXPECT_DOUBLE_EQ(interpolate(e, 0, 90.0), 50.0);
  EXPECT_DOUBLE_EQ(interpolate(e, 0, 90.5), 0.0);
  EXPECT_DOUBLE_EQ(interpolate(e, 0, 180.0), 0.0);
}

TEST(Distribution, LateralSymmetryMirrorsTypeB) {
  Distribution d;
  d.type = PhotometricType::B;
  d.symmetry = Symmetry::Lateral;
  d.horizontal_deg = {0, 30, 60, 90};
  d.vertical_deg = {-90, 0, 90};
  for (double h : d.horizontal_deg)
    for (double v : d.vertical_deg) d.candela.push_back(10.0 + h + v * 0.1);
  d.absolute = true;
  d.lamps = {LampSet{}};
  ASSERT_TRUE(validate(d).ok());
  Distribution e = expand_symmetry(d);
  ASSERT_EQ(e.horizontal_deg, (std::vector<double>{-90, -60, -30, 0, 30, 60, 90}));
  EXPECT_DOUBLE_EQ(interpolate(e, -45.0, 0.0), interpolate(e, 45.0, 0.0));
  EXPECT_DOUBLE_EQ(interpolate(e, 45.0, 45.0), 10.0 + 45.0 + 4.5);
  EXPECT_DOUBLE_EQ(interpolate(e, 45.0, 95.0), 0.0);
}

TEST(Distribution, ExpandedPlanesDescribeExpandSymmetry) {
  struct Case {
    Symmetry sym;
    std::vector<double> planes;
  };
  const Case cases[] = {
      {Symmetry::None, angles(0, 360, 20)},     {Symmetry::None, angles(10, 350, 20)},
      {Symmetry::Quadrant, angles(0, 90, 15)},  {Symmetry::C0_C180, angles(0, 180, 30)},
      {Symmetry::C90_C270, angles(90, 270, 10)}, {Symmetry::Rotational, {0}},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(to_string(k.sym));
    const Distribution d = make_c(k.sym, k.planes, angles(0, 180, 30), asym);
    const Distribution e = expand_symmetry(d);
    const std::vector<ExpandedPlane> planes = expanded_planes(d);
    ASSERT_EQ(planes.size(), e.horizontal_count());
    for (std::size_t p = 0; p < planes.size(); ++p) {
      EXPECT_EQ(planes[p].angle_deg, e.horizontal_deg[p]);
      for (std::size_t v = 0; v < d.vertical_count(); ++v)
        EXPECT_DOUBLE_EQ(e.at(p, v), (1 - planes[p].t) * d.at(planes[p].row, v) +
                                         planes[p].t * d.at(planes[p].row_b, v));
    }
  }
  // A seam blend appears only where the data has no plane at 0.
  const auto blends = [](const Distribution& d) {
    int n = 0;
    for (const ExpandedPlane& p : expanded_planes(d)) n += p.t != 0.0;
    return n;
  };
  EXPECT_EQ(blends(make_c(Symmetry::None, angles(10, 350, 20), {0, 90}, asym)), 2);
  EXPECT_EQ(blends(make_c(Symmetry::None, angles(0, 340, 20), {0, 90}, asym)), 0);
}

TEST(Distribution, ExpansionOfManyPlanesKeepsEveryAngleOnce) {
  // 0.25 degree quadrant data: 361 stored planes become 1441 (0..360).
  const Distribution d = make_c(Symmetry::Quadrant, angles(0, 90, 0.25), {0, 90, 180}, asym);
  const Distribution e = expand_symmetry(d);
  ASSERT_EQ(e.horizontal_count(), 1441u);
  for (std::size_t h = 1; h < e.horizontal_count(); ++h)
    EXPECT_NEAR(e.horizontal_deg[h] - e.horizontal_deg[h - 1], 0.25, 1e-9);
}

TEST(Distribution, InterpolateGridEqualsInterpolateAtEveryPoint) {
  // Grid lines inside, outside, on the poles, across the seam, and for Types A/B.
  const std::vector<double> hs = {-725, -90, -45.5, -0.0, 0, 3.3, 89.99, 90, 90.01, 179, 359.5, 360, 361, 1e3};
  const std::vector<double> vs = {-100, -90, -12.5, 0, 1e-12, 7.7, 90, 123.4, 180, 180.5};
  Distribution c = make_c(Symmetry::None, {0, 40, 90, 200, 270, 360}, {0, 30, 90, 180},
                          [](double cc, double g) { return 1 + cc + 10 * std::sin(g); });
  Distribution partial = make_c(Symmetry::C0_C180, angles(0, 180, 45), angles(10, 120, 10), asym);
  Distribution rot = make_c(Symmetry::Rotational, {0}, {0, 45, 90}, asym);
  Distribution b;
  b.type = PhotometricType::B;
  b.symmetry = Symmetry::Lateral;
  b.horizontal_deg = {0, 30, 90};
  b.vertical_deg = {-90, -10, 0, 45, 90};
  for (int i = 0; i < 15; ++i) b.candela.push_back(3.0 * i + 1);
  b.absolute = true;
  Distribution a = b;
  a.type = PhotometricType::A;
  a.symmetry = Symmetry::None;
  a.horizontal_deg = {-60, 0, 60};
  for (const Distribution* d : {&c, &partial, &rot, &b, &a}) {
    const Distribution e = expand_symmetry(*d);
    const std::vector<double> grid = interpolate_grid(e, hs, vs);
    ASSERT_EQ(grid.size(), hs.size() * vs.size());
    for (std::size_t i = 0; i < hs.size(); ++i)
      for (std::size_t j = 0; j < vs.size(); ++j)
        EXPECT_NEAR(grid[i * vs.size() + j], interpolate(e, hs[i], vs[j]), 1e-12)
            << to_string(d->type) << " " << hs[i] << " " << vs[j];
  }
}

TEST(Distribution, KeywordsAndLampFlux) {
  Distribution d;
  d.set_keyword("MANUFAC", "Acme");
  d.set_keyword("LUMCAT", "X-1");
  d.set_keyword("MANUFAC", "Acme Lighting");
  ASSERT_NE(d.find_keyword("MANUFAC"), nullptr);
  EXPECT_EQ(d.find_keyword("MANUFAC")->value, "Acme Lighting");
  EXPECT_EQ(d.keywords.size(), 2u);
  EXPECT_EQ(d.find_keyword("TEST"), nullptr);

  d.lamps = {LampSet{2, "LED", 1500.0, "", "", kNaN}, LampSet{1, "LED", 500.0, "", "", kNaN}};
  EXPECT_DOUBLE_EQ(d.rated_lamp_flux_lm(), 2000.0);
  d.absolute = true;
  EXPECT_TRUE(std::isnan(d.rated_lamp_flux_lm()));
}

}  // namespace
}  // namespace gonio::photometry
