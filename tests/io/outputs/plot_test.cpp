#include "io/outputs/plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <regex>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Point {
  double x, y;
};

// The points of the last subpath ("M x,y L x,y …") of the first path drawn
// in plot group `id` of a gnuplot SVG (the key's sample line, if any, comes
// first; the data last).
std::vector<Point> data_path(const std::string& svg, const std::string& id) {
  const std::size_t group = svg.find("<g id=\"" + id + "\"");
  if (group == std::string::npos) return {};
  const std::size_t d = svg.find(" d='", group);
  const std::size_t end = svg.find('\'', d + 4);
  if (d == std::string::npos || end == std::string::npos) return {};
  std::string path = svg.substr(d + 4, end - d - 4);
  path = path.substr(path.rfind('M'));
  std::vector<Point> points;
  const std::regex number_pair(R"(([-0-9.]+),([-0-9.]+))");
  for (auto it = std::sregex_iterator(path.begin(), path.end(), number_pair); it != std::sregex_iterator(); ++it)
    points.push_back({std::stod((*it)[1]), std::stod((*it)[2])});
  return points;
}

Figure one_chart(Chart chart) {
  Figure f;
  f.charts = {std::move(chart)};
  f.width_px = 600;
  f.height_px = 600;
  return f;
}

TEST(Plot, FormatFollowsTheExtension) {
  EXPECT_EQ(image_format_for("a/b.svg").value(), ImageFormat::Svg);
  EXPECT_EQ(image_format_for("B.PNG").value(), ImageFormat::Png);
  const auto bad = image_format_for("plot.pdf");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().where.file, "plot.pdf");
  EXPECT_NE(bad.error().message.find(".svg or .png"), std::string::npos);
  EXPECT_FALSE(image_format_for("noextension").ok());
}

TEST(Plot, PolarAnglesStartAtTheNadirAndTurnToTheRight) {
  // One curve: 0° at radius 10, the centre, then 90° at radius 10.
  PolarChart chart;
  chart.series.push_back({"", {0.0, 0.0, 90.0}, {10.0, 0.0, 10.0}, LineStyle::Solid, false});
  const Result<std::string> svg = render_figure(one_chart(chart), ImageFormat::Svg);
  ASSERT_TRUE(svg.ok()) << svg.error().message;
  const std::vector<Point> p = data_path(svg.value(), "gnuplot_plot_1a");
  ASSERT_EQ(p.size(), 3u) << svg.value();
  const Point down = p[0], centre = p[1], right = p[2];
  // SVG y grows downwards.
  EXPECT_NEAR(down.x, centre.x, 0.02);
  EXPECT_GT(down.y, centre.y + 50.0);
  EXPECT_NEAR(right.y, centre.y, 0.02);
  EXPECT_GT(right.x, centre.x + 50.0);
  EXPECT_NEAR(down.y - centre.y, right.x - centre.x, 0.05);  // same radius, same scale
}

TEST(Plot, PolarLabelsReadFromZeroToOneEightyOnBothSides) {
  PolarChart chart;
  chart.radius_label = "cd";
  chart.series.push_back({"C0–C180", {-90.0, 0.0, 90.0}, {1.0, 2.0, 1.0}, LineStyle::Solid, false});
  const Result<std::string> svg = render_figure(one_chart(chart), ImageFormat::Svg);
  ASSERT_TRUE(svg.ok()) << svg.error().message;
  for (const char* label : {">0°<", ">30°<", ">90°<", ">150°<", ">180°<", ">[cd]<", ">C0–C180<"})
    EXPECT_NE(svg.value().find(label), std::string::npos) << label;
  EXPECT_EQ(svg.value().find(">330°<"), std::string::npos);
}

TEST(Plot, LogLogLineChartsSkipPointsThatCannotBeShown) {
  LineChart chart;
  chart.title = "RMS error against photons";
  chart.x_label = "photons";
  chart.y_label = "RMS error";
  chart.log_x = chart.log_y = true;
  // Error falling as 1/sqrt(N), with a zero and a NaN that log axes cannot show.
  Series s{"raw", {}, {}, LineStyle::Solid, true};
  for (double n = 1e3; n <= 1e8; n *= 10) {
    s.x.push_back(n);
    s.y.push_back(1.0 / std::sqrt(n));
  }
  s.x.push_back(0.0);
  s.y.push_back(1.0);
  s.x.push_back(1e9);
  s.y.push_back(std::numeric_limits<double>::quiet_NaN());
  chart.series.push_back(s);
  const Result<std::string> svg = render_figure(one_chart(chart), ImageFormat::Svg);
  ASSERT_TRUE(svg.ok()) << svg.error().message;
  const std::vector<Point> p = data_path(svg.value(), "gnuplot_plot_1a");
  ASSERT_EQ(p.size(), 6u);
  // On log-log axes a power law is a straight line with equal steps.
  for (std::size_t k = 1; k + 1 < p.size(); ++k) {
    EXPECT_NEAR(p[k + 1].x - p[k].x, p[1].x - p[0].x, 0.05);
    EXPECT_NEAR(p[k + 1].y - p[k].y, p[1].y - p[0].y, 0.05);
  }
  EXPECT_NE(svg.value().find(">RMS error against photons<"), std::string::npos);
}

// The first point of the first path in plot group `id`: the key's sample
// line where the series has a legend entry.
Point key_sample(const std::string& svg, const std::string& id) {
  const std::size_t group = svg.find("<g id=\"" + id + "\"");
  const std::size_t d = svg.find(" d='M", group);
  if (group == std::string::npos || d == std::string::npos) return {kNaN, kNaN};
  const std::regex number_pair(R"(([-0-9.]+),([-0-9.]+))");
  std::smatch m;
  const std::string rest = svg.substr(d + 5, 64);
  if (!std::regex_search(rest, m, number_pair)) return {kNaN, kNaN};
  return {std::stod(m[1]), std::stod(m[2])};
}

TEST(Plot, LegendBelowTheChartCoversNoCurve) {
  LineChart chart;
  Series s{"diagonal", {0.0, 1.0}, {0.0, 1.0}, LineStyle::Solid, false};
  chart.series.push_back(s);
  for (const bool below : {false, true}) {
    chart.key_below = below;
    const Result<std::string> svg = render_figure(one_chart(chart), ImageFormat::Svg);
    ASSERT_TRUE(svg.ok()) << svg.error().message;
    const std::vector<Point> data = data_path(svg.value(), "gnuplot_plot_1a");
    ASSERT_EQ(data.size(), 2u);
    const double lowest = std::max(data[0].y, data[1].y);  // SVG y grows downwards
    const Point key = key_sample(svg.value(), "gnuplot_plot_1a");
    ASSERT_TRUE(std::isfinite(key.y));
    if (below)
      EXPECT_GT(key.y, lowest) << "the legend must sit under the plot area";
    else
      EXPECT_LT(key.y, lowest) << "top right: inside the plot area";
  }
}

TEST(Plot, PngHasTheRequestedSize) {
  LineChart chart;
  chart.series.push_back({"a", {0, 1, 2}, {0, 1, 4}, LineStyle::Dashed, false});
  Figure f = one_chart(chart);
  f.width_px = 640;
  f.height_px = 360;
  const Result<std::string> png = render_figure(f, ImageFormat::Png);
  ASSERT_TRUE(png.ok()) << png.error().message;
  const std::string& b = png.value();
  ASSERT_GT(b.size(), 24u);
  EXPECT_EQ(b.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(b.substr(12, 4), "IHDR");
  const auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned>(static_cast<unsigned char>(b[at])) << 24) |
           (static_cast<unsigned>(static_cast<unsigned char>(b[at + 1])) << 16) |
           (static_cast<unsigned>(static_cast<unsigned char>(b[at + 2])) << 8) |
           static_cast<unsigned>(static_cast<unsigned char>(b[at + 3]));
  };
  EXPECT_EQ(be32(16), 640u);
  EXPECT_EQ(be32(20), 360u);
}

TEST(Plot, SeveralChartsSideBySideAndAwkwardText) {
  Figure f;
  f.title = "It's \"quoted\"\nand {braces} ^ _ \\ $x";
  PolarChart polar;
  polar.series.push_back({"O'Brien's curve", {0, 45, 90}, {1, 2, 3}, LineStyle::Dotted, false});
  LineChart empty;  // no series at all
  empty.title = "nothing yet";
  f.charts = {polar, empty};
  const Result<std::string> svg = render_figure(f, ImageFormat::Svg);
  ASSERT_TRUE(svg.ok()) << svg.error().message;
  EXPECT_NE(svg.value().find("nothing yet"), std::string::npos);
  EXPECT_NE(svg.value().find("Brien"), std::string::npos);
  EXPECT_NE(svg.value().find("{braces} ^ _"), std::string::npos);
}

TEST(Plot, BadFiguresAreErrors) {
  EXPECT_FALSE(render_figure(Figure{}, ImageFormat::Svg).ok());
  LineChart chart;
  chart.series.push_back({"lopsided", {1, 2, 3}, {1, 2}, LineStyle::Solid, false});
  const auto lopsided = render_figure(one_chart(chart), ImageFormat::Svg);
  ASSERT_FALSE(lopsided.ok());
  EXPECT_NE(lopsided.error().message.find("lopsided"), std::string::npos);
  Figure tiny = one_chart(LineChart{});
  tiny.width_px = 10;
  EXPECT_FALSE(render_figure(tiny, ImageFormat::Svg).ok());
}

TEST(Plot, WritesAtomicallyAndReportsAMissingGnuplot) {
  test::TempDir dir;
  const Figure f = one_chart(LineChart{});
  const std::string path = (dir / "chart.svg").string();
  ASSERT_TRUE(write_figure(path, f).ok());
  EXPECT_NE(test::read_file(path).find("<svg"), std::string::npos);
  const Status missing_dir = write_figure((dir / "no" / "such" / "dir.svg").string(), f);
  EXPECT_FALSE(missing_dir.ok());

  const char* old = std::getenv("GONIO_GNUPLOT");
  const std::string saved = old ? old : "";
  ::setenv("GONIO_GNUPLOT", (dir / "not-a-gnuplot").c_str(), 1);
  const Status s = write_figure((dir / "other.png").string(), f);
  if (old)
    ::setenv("GONIO_GNUPLOT", saved.c_str(), 1);
  else
    ::unsetenv("GONIO_GNUPLOT");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("gnuplot-nox"), std::string::npos) << s.error().message;
  EXPECT_FALSE(std::filesystem::exists(dir / "other.png"));

  // A gnuplot that fails: its message is passed on, nothing is written.
  const std::string fake = (dir / "failing-gnuplot").string();
  test::write_file(fake, "#!/bin/sh\necho 'line 3: something broke' >&2\nexit 1\n");
  std::filesystem::permissions(fake, std::filesystem::perms::owner_all);
  ::setenv("GONIO_GNUPLOT", fake.c_str(), 1);
  const Status failed = write_figure((dir / "failed.svg").string(), f);
  if (old)
    ::setenv("GONIO_GNUPLOT", saved.c_str(), 1);
  else
    ::unsetenv("GONIO_GNUPLOT");
  ASSERT_FALSE(failed.ok());
  EXPECT_NE(failed.error().message.find("something broke"), std::string::npos) << failed.error().message;
  EXPECT_FALSE(std::filesystem::exists(dir / "failed.svg"));
}

}  // namespace
}  // namespace gonio::io
