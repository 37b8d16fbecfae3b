#include "io/outputs/intensity_diagram.h"

#include <cmath>
#include <utility>
#include <vector>

namespace gonio::io {
namespace {

// One plane pair as a single curve through the nadir: the second plane at
// negative angles (γ from 180 down to 0), then the first at positive ones.
Series plane_pair(const photometry::Distribution& expanded, double c_right, double c_left,
                  double scale, std::string label, LineStyle style) {
  Series s;
  s.label = std::move(label);
  s.style = style;
  const auto& gammas = expanded.vertical_deg;
  for (std::size_t k = gammas.size(); k-- > 0;) {
    if (gammas[k] == 0.0) continue;  // the nadir comes once, from the right-hand plane
    s.x.push_back(-gammas[k]);
    s.y.push_back(scale * photometry::interpolate(expanded, c_left, gammas[k]));
  }
  for (double g : gammas) {
    s.x.push_back(g);
    s.y.push_back(scale * photometry::interpolate(expanded, c_right, g));
  }
  return s;
}

Status drawable(const photometry::Distribution& d) {
  if (d.type != photometry::PhotometricType::C) {
    Error e;
    e.message = std::string("intensity diagrams are drawn for Type C photometry; this is Type ") +
                photometry::to_string(d.type);
    return e;
  }
  return photometry::validate(d);
}

// The polar diagram and the same curves on cartesian axes, side by side.
Figure diagram_figure(const std::string& title, std::vector<Series> series, const std::string& unit) {
  PolarChart polar;
  polar.radius_label = unit;
  polar.series = series;
  LineChart line;
  line.x_label = "γ [°]  (C180, C270 left; C0, C90 right)";
  line.y_label = "I [" + unit + "]";
  line.x_min = -180.0;
  line.x_max = 180.0;
  line.y_min = 0.0;
  line.series = std::move(series);
  Figure f;
  f.title = title;
  f.charts = {polar, line};
  f.width_px = 1200;
  f.height_px = 560;
  return f;
}

}  // namespace

Result<Figure> overlay_diagram(const photometry::Distribution& a, const photometry::Distribution& b,
                               const OverlayOptions& options) {
  if (Status s = drawable(a); !s.ok()) return s.error();
  if (Status s = drawable(b); !s.ok()) return s.error();
  if (!(options.scale_b > 0.0) || !std::isfinite(options.scale_b)) {
    Error e;
    e.message = "the scale of B must be a positive number";
    return e;
  }
  const photometry::Distribution ea = photometry::expand_symmetry(a);
  const photometry::Distribution eb = photometry::expand_symmetry(b);
  std::vector<Series> series = {
      plane_pair(ea, 0.0, 180.0, 1.0, options.label_a + " C0–C180", LineStyle::Solid),
      plane_pair(ea, 90.0, 270.0, 1.0, options.label_a + " C90–C270", LineStyle::Dashed),
      plane_pair(eb, 0.0, 180.0, options.scale_b, options.label_b + " C0–C180", LineStyle::Dotted),
      plane_pair(eb, 90.0, 270.0, options.scale_b, options.label_b + " C90–C270", LineStyle::Dotted)};
  series[3].markers = true;

  return diagram_figure(options.title, std::move(series), "cd");
}

Result<Figure> intensity_diagram(const photometry::Distribution& d, const DiagramOptions& options) {
  if (Status s = drawable(d); !s.ok()) return s.error();
  const bool relative = std::isfinite(options.per_klm_of_lm);
  if (relative && !(options.per_klm_of_lm > 0.0)) {
    Error e;
    e.message = "cd/klm needs a positive flux";
    return e;
  }
  const double scale = relative ? 1000.0 / options.per_klm_of_lm : 1.0;
  const std::string unit = relative ? "cd/klm" : "cd";
  const photometry::Distribution expanded = photometry::expand_symmetry(d);

  const Series c0 = plane_pair(expanded, 0.0, 180.0, scale, "C0–C180", LineStyle::Solid);
  const Series c90 = plane_pair(expanded, 90.0, 270.0, scale, "C90–C270", LineStyle::Dashed);

  return diagram_figure(options.title, {c0, c90}, unit);
}

}  // namespace gonio::io
