#include "io/outputs/intensity_diagram.h"

#include <gtest/gtest.h>

namespace gonio::io {
namespace {

// Quadrant symmetry, planes 0, 45, 90; I = 100 + C + γ so every value tells
// where it came from.
photometry::Distribution quadrant() {
  photometry::Distribution d;
  d.symmetry = photometry::Symmetry::Quadrant;
  d.horizontal_deg = {0.0, 45.0, 90.0};
  d.vertical_deg = {0.0, 30.0, 60.0, 90.0};
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg) d.candela.push_back(g == 0.0 ? 100.0 : 100.0 + c + g);
  d.absolute = true;
  return d;
}

TEST(IntensityDiagram, PlanesRunThroughTheNadirWithC0AndC90OnTheRight) {
  const Result<Figure> f = intensity_diagram(quadrant(), {"Quadrant", photometry::kNaN});
  ASSERT_TRUE(f.ok()) << f.error().message;
  ASSERT_EQ(f->charts.size(), 2u);
  const PolarChart& polar = std::get<PolarChart>(f->charts[0]);
  EXPECT_EQ(polar.radius_label, "cd");
  ASSERT_EQ(polar.series.size(), 2u);
  const Series& c0 = polar.series[0];
  const Series& c90 = polar.series[1];
  EXPECT_EQ(c0.label, "C0–C180");
  EXPECT_EQ(c90.label, "C90–C270");
  // −90 … 0 … 90: C180 (= C0 by the quadrant mirror) on the left.
  EXPECT_EQ(c0.x, (std::vector<double>{-90, -60, -30, 0, 30, 60, 90}));
  EXPECT_EQ(c0.y, (std::vector<double>{190, 160, 130, 100, 130, 160, 190}));
  // C90 and C270 both hold the C90 plane: 100 + 90 + γ.
  EXPECT_EQ(c90.y, (std::vector<double>{280, 250, 220, 100, 220, 250, 280}));
  const LineChart& line = std::get<LineChart>(f->charts[1]);
  EXPECT_EQ(line.series[0].y, c0.y);
  EXPECT_EQ(line.y_label, "I [cd]");
}

TEST(IntensityDiagram, AsymmetricPlanesKeepTheirSides) {
  photometry::Distribution d;
  d.symmetry = photometry::Symmetry::None;
  d.horizontal_deg = {0, 90, 180, 270, 360};
  d.vertical_deg = {0, 90};
  d.candela = {10, 1, 10, 2, 10, 3, 10, 4, 10, 1};
  d.absolute = true;
  const Result<Figure> f = intensity_diagram(d);
  ASSERT_TRUE(f.ok()) << f.error().message;
  const PolarChart& polar = std::get<PolarChart>(f->charts[0]);
  EXPECT_EQ(polar.series[0].y, (std::vector<double>{3, 10, 1}));  // C180 left, C0 right
  EXPECT_EQ(polar.series[1].y, (std::vector<double>{4, 10, 2}));  // C270 left, C90 right
}

TEST(IntensityDiagram, RelativeScaleIsCandelaPerKilolumen) {
  const Result<Figure> f = intensity_diagram(quadrant(), {"", 2000.0});
  ASSERT_TRUE(f.ok());
  const PolarChart& polar = std::get<PolarChart>(f->charts[0]);
  EXPECT_EQ(polar.radius_label, "cd/klm");
  EXPECT_DOUBLE_EQ(polar.series[0].y[3], 50.0);  // 100 cd per 2 klm
  EXPECT_FALSE(intensity_diagram(quadrant(), {"", -5.0}).ok());
}

TEST(IntensityDiagram, RefusesWhatItCannotDraw) {
  photometry::Distribution b = quadrant();
  b.type = photometry::PhotometricType::B;
  const auto type_b = intensity_diagram(b);
  ASSERT_FALSE(type_b.ok());
  EXPECT_NE(type_b.error().message.find("Type C"), std::string::npos);
  photometry::Distribution broken = quadrant();
  broken.candela.pop_back();
  EXPECT_FALSE(intensity_diagram(broken).ok());
}

}  // namespace
}  // namespace gonio::io
