#include "io/outputs/colour_chart.h"

#include <gtest/gtest.h>

#include <cmath>
#include <variant>

namespace gonio::io {
namespace {

TEST(ColourChart, TwoChartsOneCurvePerPlaneAndErrorsForBadCurves) {
  ColourCurve c0{0.0, {0.0, 90.0, 180.0}, {2700.0, std::nan(""), 3000.0}, {0.001, std::nan(""), 0.004}};
  ColourCurve c90 = c0;
  c90.c_deg = 90.0;
  auto f = colour_over_angle_chart({c0, c90}, "lamp", 0.004);
  ASSERT_TRUE(f.ok()) << f.error().message;
  ASSERT_EQ(f->charts.size(), 2u);
  const auto& cct = std::get<LineChart>(f->charts[0]);
  ASSERT_EQ(cct.series.size(), 2u);
  EXPECT_EQ(cct.series[1].label, "C90");
  EXPECT_EQ(cct.y_label, "CCT [K]");
  EXPECT_NE(std::get<LineChart>(f->charts[1]).title.find("max 0.004"), std::string::npos);
  EXPECT_FALSE(colour_over_angle_chart({}, "lamp", 0.0).ok());
  c0.cct_k.pop_back();
  const auto bad = colour_over_angle_chart({c0}, "lamp", 0.0);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "colour curve C0: gamma, CCT and delta u'v' lists differ in length");
}

}  // namespace
}  // namespace gonio::io
