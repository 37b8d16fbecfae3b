// Charts as SVG or PNG: polar intensity diagrams and x-y line charts
// (linear or logarithmic axes), one or more side by side in a figure.
//
// Rendering is gnuplot's (Debian package gnuplot-nox, installed by
// scripts/setup.sh), run as a separate process: headless, no library state
// in Gonio's process, and a failing or missing gnuplot is an error value,
// never a crash. The program is `gnuplot` on PATH, or $GONIO_GNUPLOT. This
// header and io/outputs/plot.cpp are the only places that know about gnuplot.
#pragma once

#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::io {

enum class ImageFormat { Svg, Png };

// From a file name's extension, ".svg" or ".png" (any case); an error
// naming the file otherwise.
Result<ImageFormat> image_format_for(const std::string& path);

enum class LineStyle { Solid, Dashed, Dotted };

// One curve. Points with a non-finite coordinate are left out (a gap).
struct Series {
  std::string label;      // legend entry; empty for none
  std::vector<double> x;  // polar charts: angle [deg]; line charts: abscissa
  std::vector<double> y;  // polar charts: radius (≥ 0); line charts: ordinate
  LineStyle style = LineStyle::Solid;
  bool markers = false;   // draw a mark at every point as well
};

// A polar diagram in the photometric convention: angle 0 points straight
// down (the nadir), positive angles turn counter-clockwise (to the right),
// negative ones to the left; angle labels read 0…180 on both sides.
struct PolarChart {
  std::string title;
  std::string radius_label;  // unit of the radius, e.g. "cd" or "cd/klm", shown as [cd]
  std::vector<Series> series;
};

struct LineChart {
  std::string title;
  std::string x_label;
  std::string y_label;
  bool log_x = false;  // logarithmic axes ignore points ≤ 0 on that axis
  bool log_y = false;
  std::optional<double> x_min, x_max, y_min, y_max;  // automatic where unset
  bool key_below = false;  // the legend under the chart (never over a curve), else top right
  std::vector<Series> series;
};

using Chart = std::variant<PolarChart, LineChart>;

struct Figure {
  std::string title;          // above all charts; empty for none
  std::vector<Chart> charts;  // side by side, left to right; at least one
  int width_px = 1200;        // PNG pixels; SVG user units
  int height_px = 600;
};

// Renders a figure to image bytes. Errors: gnuplot missing or failing (with
// its message), invalid figure (no charts, x and y of different lengths,
// sizes outside 100…10000).
Result<std::string> render_figure(const Figure& figure, ImageFormat format);

// Renders and writes atomically; the format follows the file's extension.
Status write_figure(const std::string& path, const Figure& figure);

}  // namespace gonio::io
