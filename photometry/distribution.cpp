#include "photometry/distribution.h"

#include <algorithm>
#include <tuple>
#include <utility>

#include "photometry/format.h"

namespace gonio::photometry {
namespace {

constexpr double kAngleTol = 1e-9;  // [deg] angles closer than this are one angle

bool strictly_increasing_finite(const std::vector<double>& v) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) return false;
    if (i > 0 && !(v[i] > v[i - 1])) return false;
  }
  return true;
}

bool near(double a, double b) { return std::abs(a - b) <= kAngleTol; }

Status validate_horizontal_c(const Distribution& d) {
  const auto& h = d.horizontal_deg;
  const double first = h.front(), last = h.back();
  const auto range = [&](double lo, double hi, const char* what) -> Status {
    if (!near(first, lo) || !near(last, hi))
      return make_error(std::string("symmetry ") + what + " needs horizontal angles from " +
                        format_number(lo) + " to " + format_number(hi) + ", found " +
                        format_number(first) + " to " + format_number(last));
    return Ok{};
  };
  switch (d.symmetry) {
    case Symmetry::Rotational:
      if (h.size() != 1)
        return make_error("a rotationally symmetric distribution has exactly one C-plane, found " +
                          std::to_string(h.size()));
      if (first < -kAngleTol || first > 360.0 + kAngleTol)
        return make_error("C-plane angle " + format_number(first) + " outside 0..360");
      return Ok{};
    case Symmetry::Quadrant: return range(0.0, 90.0, "quadrant");
    case Symmetry::C0_C180: return range(0.0, 180.0, "C0-C180");
    case Symmetry::C90_C270: return range(90.0, 270.0, "C90-C270");
    case Symmetry::None:
      if (h.size() < 2) return make_error("a distribution without symmetry needs at least two C-planes");
      if (first < -kAngleTol || last > 360.0 + kAngleTol)
        return make_error("C-plane angles must lie in 0..360, found " + format_number(first) + " to " +
                          format_number(last));
      return Ok{};
    case Symmetry::Lateral:
      return make_error("lateral symmetry applies to Types A and B, not Type C");
  }
  return Ok{};
}

Status validate_horizontal_ab(const Distribution& d) {
  const auto& h = d.horizontal_deg;
  if (d.symmetry == Symmetry::Lateral) {
    if (!near(h.front(), 0.0))
      return make_error("lateral symmetry needs horizontal angles starting at 0, found " +
                        format_number(h.front()));
  } else if (d.symmetry != Symmetry::None) {
    return make_error(std::string("symmetry ") + to_string(d.symmetry) + " applies to Type C only");
  }
  if (h.front() < -90.0 - kAngleTol || h.back() > 90.0 + kAngleTol)
    return make_error("horizontal angles of Types A and B must lie in -90..90, found " +
                      format_number(h.front()) + " to " + format_number(h.back()));
  return Ok{};
}

// Trapezoidal mean over the full circle of row values at one vertical index,
// on an expanded Type C grid whose planes run from 0 to 360.
double circular_mean(const Distribution& e, std::size_t v) {
  const auto& c = e.horizontal_deg;
  double sum = 0.0;
  for (std::size_t h = 0; h + 1 < c.size(); ++h)
    sum += 0.5 * (e.at(h, v) + e.at(h + 1, v)) * (c[h + 1] - c[h]);
  return sum / 360.0;
}

// Index i with a[i] <= x <= a[i+1] (a has >= 2 entries, x within range) and
// the fraction of the way from a[i] to a[i+1].
std::pair<std::size_t, double> bracket(const std::vector<double>& a, double x) {
  auto it = std::upper_bound(a.begin(), a.end(), x);
  std::size_t i = it == a.begin() ? 0 : static_cast<std::size_t>(it - a.begin()) - 1;
  i = std::min(i, a.size() - 2);
  const double t = (x - a[i]) / (a[i + 1] - a[i]);
  return {i, std::clamp(t, 0.0, 1.0)};
}


}  // namespace

const char* to_string(PhotometricType type) {
  switch (type) {
    case PhotometricType::C: return "C";
    case PhotometricType::B: return "B";
    case PhotometricType::A: return "A";
  }
  return "?";
}

const char* to_string(Symmetry symmetry) {
  switch (symmetry) {
    case Symmetry::None: return "none";
    case Symmetry::Rotational: return "rotational";
    case Symmetry::C0_C180: return "C0-C180";
    case Symmetry::C90_C270: return "C90-C270";
    case Symmetry::Quadrant: return "quadrant";
    case Symmetry::Lateral: return "lateral";
  }
  return "?";
}

const char* to_string(OpeningShape shape) {
  switch (shape) {
    case OpeningShape::Point: return "point";
    case OpeningShape::Rectangular: return "rectangular";
    case OpeningShape::RectangularWithSides: return "rectangular with luminous sides";
    case OpeningShape::Circular: return "circular";
    case OpeningShape::Ellipse: return "ellipse";
    case OpeningShape::VerticalCylinder: return "vertical cylinder";
    case OpeningShape::VerticalEllipticalCylinder: return "vertical elliptical cylinder";
    case OpeningShape::Sphere: return "sphere";
    case OpeningShape::Ellipsoid: return "ellipsoid";
    case OpeningShape::HorizontalCylinderAlongLength: return "horizontal cylinder along length";
    case OpeningShape::HorizontalEllipticalCylinderAlongLength:
      return "horizontal elliptical cylinder along length";
    case OpeningShape::HorizontalCylinderAlongWidth: return "horizontal cylinder along width";
    case OpeningShape::HorizontalEllipticalCylinderAlongWidth:
      return "horizontal elliptical cylinder along width";
    case OpeningShape::VerticalCircle: return "vertical circle";
    case OpeningShape::VerticalEllipse: return "vertical ellipse";
  }
  return "?";
}

const char* to_string(FileGenerationType type) {
  switch (type) {
    case FileGenerationType::Undefined: return "undefined";
    case FileGenerationType::ComputerSimulation: return "computer simulation";
    case FileGenerationType::UnaccreditedLab: return "test at an unaccredited lab";
    case FileGenerationType::UnaccreditedLabScaled:
      return "test at an unaccredited lab, lumen scaled";
    case FileGenerationType::UnaccreditedLabInterpolated:
      return "test at an unaccredited lab, interpolated angle set";
    case FileGenerationType::UnaccreditedLabInterpolatedScaled:
      return "test at an unaccredited lab, interpolated angle set, lumen scaled";
    case FileGenerationType::AccreditedLab: return "test at an accredited lab";
    case FileGenerationType::AccreditedLabScaled: return "test at an accredited lab, lumen scaled";
    case FileGenerationType::AccreditedLabInterpolated:
      return "test at an accredited lab, interpolated angle set";
    case FileGenerationType::AccreditedLabInterpolatedScaled:
      return "test at an accredited lab, interpolated angle set, lumen scaled";
  }
  return "?";
}

double Distribution::rated_lamp_flux_lm() const {
  if (absolute || lamps.empty()) return kNaN;
  double sum = 0.0;
  for (const LampSet& l : lamps) sum += l.flux_lm;
  return sum;
}

const Keyword* Distribution::find_keyword(std::string_view key) const {
  for (const Keyword& k : keywords)
    if (k.key == key) return &k;
  return nullptr;
}

void Distribution::set_keyword(std::string_view key, std::string value) {
  for (Keyword& k : keywords) {
    if (k.key == key) {
      k.value = std::move(value);
      return;
    }
  }
  keywords.push_back({std::string(key), std::move(value)});
}

Status validate(const Distribution& d) {
  if (d.vertical_deg.empty()) return make_error("no vertical angles");
  if (d.horizontal_deg.empty()) return make_error("no horizontal angles");
  if (!strictly_increasing_finite(d.vertical_deg))
    return make_error("vertical angles must be finite and strictly increasing");
  if (!strictly_increasing_finite(d.horizontal_deg))
    return make_error("horizontal angles must be finite and strictly increasing");

  if (d.type == PhotometricType::C) {
    if (d.vertical_deg.front() < -kAngleTol || d.vertical_deg.back() > 180.0 + kAngleTol)
      return make_error("Type C vertical angles must lie in 0..180, found " +
                        format_number(d.vertical_deg.front()) + " to " +
                        format_number(d.vertical_deg.back()));
    if (Status s = validate_horizontal_c(d); !s.ok()) return s;
  } else {
    if (d.vertical_deg.front() < -90.0 - kAngleTol || d.vertical_deg.back() > 90.0 + kAngleTol)
      return make_error("vertical angles of Types A and B must lie in -90..90, found " +
                        format_number(d.vertical_deg.front()) + " to " +
                        format_number(d.vertical_deg.back()));
    if (Status s = validate_horizontal_ab(d); !s.ok()) return s;
  }

  const std::size_t expected = d.vertical_deg.size() * d.horizontal_deg.size();
  if (d.candela.size() != expected)
    return make_error("expected " + std::to_string(expected) + " intensities, found " +
                      std::to_string(d.candela.size()));
  for (double v : d.candela)
    if (!std::isfinite(v)) return make_error("intensities must be finite");

  for (const LampSet& l : d.lamps) {
    if (l.count <= 0) return make_error("a lamp set needs a positive lamp count");
    if (!d.absolute && !(std::isfinite(l.flux_lm) && l.flux_lm > 0.0))
      return make_error("relative photometry needs a positive rated lamp flux");
  }
  return Ok{};
}

std::vector<ExpandedPlane> expanded_planes(const Distribution& d) {
  // The full precondition costs a pass over the data; callers have checked
  // it. Sizes are what memory safety rests on.
  GONIO_CHECK_MSG(!d.horizontal_deg.empty() && !d.vertical_deg.empty() &&
                      d.candela.size() == d.horizontal_deg.size() * d.vertical_deg.size(),
                  "expanded_planes needs a valid distribution");
  // (angle, source row) pairs, stored planes first so that they win ties.
  std::vector<std::pair<double, std::size_t>> planes;
  if (d.type != PhotometricType::C) {
    for (std::size_t h = 0; h < d.horizontal_deg.size(); ++h) {
      planes.emplace_back(d.horizontal_deg[h], h);
      if (d.symmetry == Symmetry::Lateral && d.horizontal_deg[h] > kAngleTol)
        planes.emplace_back(-d.horizontal_deg[h], h);
    }
  } else if (d.symmetry == Symmetry::Rotational) {
    return {{0.0, 0, 0, 0.0}, {360.0, 0, 0, 0.0}};
  } else {
    std::vector<double (*)(double)> images = {[](double c) { return c; }};
    if (d.symmetry == Symmetry::C0_C180 || d.symmetry == Symmetry::Quadrant)
      images.push_back([](double c) { return 360.0 - c; });
    if (d.symmetry == Symmetry::C90_C270 || d.symmetry == Symmetry::Quadrant)
      images.push_back([](double c) { return 180.0 - c; });
    if (d.symmetry == Symmetry::Quadrant) images.push_back([](double c) { return 180.0 + c; });
    for (auto image : images) {
      for (std::size_t h = 0; h < d.horizontal_deg.size(); ++h) {
        double c = std::fmod(image(d.horizontal_deg[h]), 360.0);
        if (c < 0.0) c += 360.0;
        if (c > 360.0 - kAngleTol) c = 0.0;
        planes.emplace_back(c, h);
      }
    }
  }

  // Sort by angle; of each run of near-equal angles keep the one listed
  // first (a stored plane before its mirror images).
  std::vector<std::size_t> order(planes.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return planes[a].first < planes[b].first; });
  std::vector<ExpandedPlane> out;
  out.reserve(order.size() + 2);
  for (std::size_t i = 0; i < order.size();) {
    std::size_t best = order[i], j = i + 1;
    while (j < order.size() && near(planes[order[j]].first, planes[order[j - 1]].first)) {
      best = std::min(best, order[j]);
      ++j;
    }
    out.push_back({planes[best].first, planes[best].second, planes[best].second, 0.0});
    i = j;
  }

  if (d.type == PhotometricType::C) {
    // Close the circle: a plane at 0 (blended across the seam if the data
    // has none) and its copy at 360.
    if (out.front().angle_deg > kAngleTol) {
      const double lo = out.back().angle_deg - 360.0, hi = out.front().angle_deg;
      const double t = (0.0 - lo) / (hi - lo);
      out.insert(out.begin(), {0.0, out.back().row, out.front().row, t});
    }
    ExpandedPlane closing = out.front();
    closing.angle_deg = 360.0;
    out.push_back(closing);
  }
  return out;
}

Distribution expand_symmetry(const Distribution& d) {
  GONIO_CHECK_MSG(validate(d).ok(), "expand_symmetry needs a valid distribution");
  const std::vector<ExpandedPlane> planes = expanded_planes(d);
  Distribution e = d;
  e.symmetry = Symmetry::None;
  const std::size_t nv = d.vertical_deg.size();
  e.horizontal_deg.resize(planes.size());
  e.candela.resize(planes.size() * nv);
  for (std::size_t p = 0; p < planes.size(); ++p) {
    const ExpandedPlane& plane = planes[p];
    e.horizontal_deg[p] = plane.angle_deg;
    const double* a = d.candela.data() + plane.row * nv;
    const double* b = d.candela.data() + plane.row_b * nv;
    double* out = e.candela.data() + p * nv;
    for (std::size_t v = 0; v < nv; ++v)
      out[v] = plane.t == 0.0 ? a[v] : a[v] * (1.0 - plane.t) + b[v] * plane.t;
  }
  return e;
}

double interpolate(const Distribution& e, double horizontal_deg, double vertical_deg) {
  GONIO_CHECK(e.symmetry == Symmetry::None);
  const auto& vert = e.vertical_deg;
  const auto& hor = e.horizontal_deg;
  const std::size_t nv = vert.size();
  if (!(vertical_deg >= vert.front() - kAngleTol && vertical_deg <= vert.back() + kAngleTol))
    return 0.0;
  vertical_deg = std::clamp(vertical_deg, vert.front(), vert.back());

  double h = horizontal_deg;
  if (e.type == PhotometricType::C) {
    if (near(vertical_deg, 0.0) || near(vertical_deg, 180.0)) {
      const std::size_t v = near(vertical_deg, 0.0) ? 0 : nv - 1;
      if (near(vert[v], vertical_deg)) return circular_mean(e, v);
    }
    h = std::fmod(h, 360.0);
    if (h < 0.0) h += 360.0;
  } else if (!(h >= hor.front() - kAngleTol && h <= hor.back() + kAngleTol)) {
    return 0.0;
  }
  h = std::clamp(h, hor.front(), hor.back());

  // Interpolate along the vertical axis in the two bracketing planes, then
  // between the planes.
  auto column = [&](std::size_t row) {
    const double* r = e.candela.data() + row * nv;
    if (nv == 1) return r[0];
    auto [i, t] = bracket(vert, vertical_deg);
    return r[i] * (1.0 - t) + r[i + 1] * t;
  };
  if (hor.size() == 1) return column(0);
  auto [j, s] = bracket(hor, h);
  return column(j) * (1.0 - s) + column(j + 1) * s;
}

std::vector<double> interpolate_grid(const Distribution& e, const std::vector<double>& horizontal_deg,
                                     const std::vector<double>& vertical_deg) {
  GONIO_CHECK(e.symmetry == Symmetry::None);
  const auto& vert = e.vertical_deg;
  const auto& hor = e.horizontal_deg;
  const std::size_t nv = vert.size();

  // Per vertical angle: outside (0), a pole of Type C (one value), or a
  // bracket in the stored angles.
  enum class Kind { Outside, Pole, Inside };
  struct Line {
    Kind kind = Kind::Outside;
    std::size_t i = 0;
    double t = 0.0;
    double pole = 0.0;
  };
  std::vector<Line> rows(vertical_deg.size());
  for (std::size_t j = 0; j < vertical_deg.size(); ++j) {
    double v = vertical_deg[j];
    Line& line = rows[j];
    if (!(v >= vert.front() - kAngleTol && v <= vert.back() + kAngleTol)) continue;
    v = std::clamp(v, vert.front(), vert.back());
    if (e.type == PhotometricType::C && (near(v, 0.0) || near(v, 180.0))) {
      const std::size_t k = near(v, 0.0) ? 0 : nv - 1;
      if (near(vert[k], v)) {
        line.kind = Kind::Pole;
        line.pole = circular_mean(e, k);
        continue;
      }
    }
    line.kind = Kind::Inside;
    if (nv > 1) std::tie(line.i, line.t) = bracket(vert, v);
  }
  std::vector<Line> cols(horizontal_deg.size());
  for (std::size_t i = 0; i < horizontal_deg.size(); ++i) {
    double h = horizontal_deg[i];
    Line& line = cols[i];
    if (e.type == PhotometricType::C) {
      h = std::fmod(h, 360.0);
      if (h < 0.0) h += 360.0;
    } else if (!(h >= hor.front() - kAngleTol && h <= hor.back() + kAngleTol)) {
      continue;
    }
    line.kind = Kind::Inside;
    if (hor.size() > 1) std::tie(line.i, line.t) = bracket(hor, std::clamp(h, hor.front(), hor.back()));
  }

  std::vector<double> out(horizontal_deg.size() * vertical_deg.size(), 0.0);
  for (std::size_t i = 0; i < cols.size(); ++i) {
    if (cols[i].kind == Kind::Outside) continue;
    const std::size_t j0 = cols[i].i, j1 = hor.size() > 1 ? j0 + 1 : j0;
    const double s = cols[i].t;
    const double* r0 = e.candela.data() + j0 * nv;
    const double* r1 = e.candela.data() + j1 * nv;
    double* o = out.data() + i * vertical_deg.size();
    for (std::size_t j = 0; j < rows.size(); ++j) {
      const Line& row = rows[j];
      if (row.kind == Kind::Pole) {
        o[j] = row.pole;
      } else if (row.kind == Kind::Inside) {
        const std::size_t k0 = row.i, k1 = nv > 1 ? k0 + 1 : k0;
        const double a = r0[k0] * (1.0 - row.t) + r0[k1] * row.t;
        const double b = r1[k0] * (1.0 - row.t) + r1[k1] * row.t;
        o[j] = hor.size() > 1 ? a * (1.0 - s) + b * s : a;
      }
    }
  }
  return out;
}

}  // namespace gonio::photometry
