#include "photometry/luminance.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "photometry/intensity_sampler.h"

namespace gonio::photometry {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

double known(double v) { return std::isfinite(v) && v > 0.0 ? v : 0.0; }

}  // namespace

double bottom_area_m2(const LuminousOpening& o) {
  using S = OpeningShape;
  const double l = o.length_m, w = o.width_m;
  switch (o.shape) {
    case S::Point:
    case S::VerticalCircle:
    case S::VerticalEllipse:
      return 0.0;
    case S::Rectangular:
    case S::RectangularWithSides:
      return l * w;
    case S::Circular:
    case S::VerticalCylinder:
    case S::Sphere: {
      const double dia = std::max(l, w);
      return kPi / 4 * dia * dia;
    }
    case S::Ellipse:
    case S::VerticalEllipticalCylinder:
    case S::Ellipsoid:
      return kPi / 4 * l * w;
    case S::HorizontalCylinderAlongLength:
    case S::HorizontalEllipticalCylinderAlongLength:
    case S::HorizontalCylinderAlongWidth:
    case S::HorizontalEllipticalCylinderAlongWidth:
      return l * w;
  }
  return 0.0;
}

double projected_area_m2(const LuminousOpening& o, double c_deg, double gamma_deg) {
  using S = OpeningShape;
  const double c = c_deg * kDeg, g = gamma_deg * kDeg;
  // Direction toward the viewer in the photometric frame.
  const double dx = std::sin(g) * std::cos(c), dy = std::sin(g) * std::sin(c), dz = -std::cos(g);
  const double l = o.length_m, w = o.width_m, h = o.height_m;
  const double down = std::max(0.0, -dz);
  switch (o.shape) {
    case S::Point:
      return 0.0;
    case S::Rectangular:
    case S::Circular:
    case S::Ellipse:
    case S::RectangularWithSides: {
      double a = bottom_area_m2(o) * down;
      const bool round = o.shape == S::Circular || o.shape == S::Ellipse;
      const double* sh = o.side_height_m;
      const bool per_side = std::isfinite(sh[0]) || std::isfinite(sh[1]) ||
                            std::isfinite(sh[2]) || std::isfinite(sh[3]);
      if (per_side) {
        // EULUMDAT: a side of height h_C faces each of C0, C90, C180, C270.
        const double across_x = round ? std::max(l, w) : w;  // the C0/C180 faces' breadth
        const double across_y = round ? std::max(l, w) : l;  // the C90/C270 faces' breadth
        a += std::max(0.0, dx) * across_x * known(sh[0]) + std::max(0.0, -dx) * across_x * known(sh[2]) +
             std::max(0.0, dy) * across_y * known(sh[1]) + std::max(0.0, -dy) * across_y * known(sh[3]);
      } else if (o.shape == S::RectangularWithSides) {
        a += std::abs(dx) * w * h + std::abs(dy) * l * h;
      }
      return a;
    }
    case S::VerticalCylinder: {
      const double dia = std::max(l, w);
      const double* sh = o.side_height_m;
      double a = kPi / 4 * dia * dia * std::abs(dz);
      if (std::isfinite(sh[0]) || std::isfinite(sh[1]) || std::isfinite(sh[2]) || std::isfinite(sh[3])) {
        // EULUMDAT round opening with side heights: bottom only from below;
        // the side is a cylinder's, D h sin γ, with the height of the side
        // the viewer faces (h_C0 or h_C180 across C0–C180, h_C90 or h_C270
        // across C90–C270, blended by cos² C and sin² C between them).
        a = kPi / 4 * dia * dia * down;
        const double horiz = std::hypot(dx, dy);
        if (horiz > 0.0) {
          const double cx = dx / horiz, cy = dy / horiz;
          const double h_x = cx >= 0.0 ? known(sh[0]) : known(sh[2]);
          const double h_y = cy >= 0.0 ? known(sh[1]) : known(sh[3]);
          a += dia * horiz * (cx * cx * h_x + cy * cy * h_y);
        }
        return a;
      }
      return a + dia * h * std::hypot(dx, dy);
    }
    case S::VerticalEllipticalCylinder:
      return kPi / 4 * l * w * std::abs(dz) + h * std::sqrt(l * l * dy * dy + w * w * dx * dx);
    case S::Sphere: {
      const double dia = std::max({l, w, h});
      return kPi / 4 * dia * dia;
    }
    case S::Ellipsoid: {
      const double a = l / 2, b = w / 2, cc = h / 2;
      return kPi * std::sqrt(b * b * cc * cc * dx * dx + a * a * cc * cc * dy * dy +
                             a * a * b * b * dz * dz);
    }
    case S::HorizontalCylinderAlongLength:
    case S::HorizontalEllipticalCylinderAlongLength: {
      // Axis along x, length l; cross-section w (y) × h (z).
      const double hh = o.shape == S::HorizontalCylinderAlongLength && h <= 0.0 ? w : h;
      return l * std::sqrt(w * w * dz * dz + hh * hh * dy * dy) + kPi / 4 * w * hh * std::abs(dx);
    }
    case S::HorizontalCylinderAlongWidth:
    case S::HorizontalEllipticalCylinderAlongWidth: {
      const double hh = o.shape == S::HorizontalCylinderAlongWidth && h <= 0.0 ? l : h;
      return w * std::sqrt(l * l * dz * dz + hh * hh * dx * dx) + kPi / 4 * l * hh * std::abs(dy);
    }
    case S::VerticalCircle: {
      const double dia = std::max(w, h);
      return kPi / 4 * dia * dia * std::max(0.0, dx);
    }
    case S::VerticalEllipse:
      return kPi / 4 * w * h * std::max(0.0, dx);
  }
  return 0.0;
}

LuminanceTable luminance_table(const Distribution& d) {
  LuminanceTable t;
  for (int g = 45; g <= 85; g += 5) t.gamma_deg.push_back(g);
  t.c_deg = {0.0, 90.0};
  if (d.opening.shape == OpeningShape::Point) {
    t.why_undefined = "point opening: the file gives no luminous area";
    return t;
  }
  const IntensitySampler sampler(d);
  const double bottom = bottom_area_m2(d.opening);
  double max_l = 0.0;
  for (double c : t.c_deg) {
    std::vector<double> row, ldt;
    for (double g : t.gamma_deg) {
      const double i = sampler.cd(c, g);
      const double a = projected_area_m2(d.opening, c, g);
      const double l = a > 0.0 ? i / a : kNaN;
      if (std::isfinite(l)) max_l = std::max(max_l, l);
      row.push_back(l);
      ldt.push_back(bottom > 0.0 ? i / (bottom * std::cos(g * kDeg)) : kNaN);
    }
    t.cd_m2.push_back(std::move(row));
    t.ldt_cd_m2.push_back(std::move(ldt));
  }
  t.defined = true;
  t.max_cd_m2 = max_l;
  return t;
}

}  // namespace gonio::photometry
