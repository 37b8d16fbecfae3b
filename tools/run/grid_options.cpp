#include "tools/run/grid_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "io/photometric/ldt.h"
#include "io/photometric/photometric_file.h"
#include "photometry/format.h"

namespace gonio::app {
namespace {

constexpr double kSlack = 1e-9;  // [deg] angles this close are the same

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool parse_number(std::string_view s, double* out) {
  s = trim(s);
  if (s.empty()) return false;
  if (s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), *out);
  return ec == std::errc() && end == s.data() + s.size() && std::isfinite(*out);
}

// Appends `v`, merging it with an equal last angle.
Status append(std::vector<double>& out, double v, const std::string& option, std::string_view item) {
  if (!out.empty() && std::abs(v - out.back()) <= kSlack) return Ok{};
  if (!out.empty() && v < out.back())
    return make_error(option + ": angles must be in ascending order, but '" + std::string(item) + "' gives " +
                      format_number(v) + " after " + format_number(out.back()));
  out.push_back(v);
  return Ok{};
}

}  // namespace

Result<std::vector<double>> parse_angle_list(std::string_view text, const std::string& option) {
  std::vector<double> out;
  if (trim(text).empty()) return make_error(option + ": empty list (e.g. 0:0.1:5,6:1:90)");
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string_view item = trim(text.substr(start, comma - start));
    start = comma + 1;
    if (item.empty()) return make_error(option + ": an empty item in '" + std::string(text) + "'");
    const std::size_t c1 = item.find(':');
    if (c1 == std::string_view::npos) {
      double v = 0.0;
      if (!parse_number(item, &v)) return make_error(option + ": '" + std::string(item) + "' is not a number");
      if (Status s = append(out, v, option, item); !s.ok()) return s.error();
      continue;
    }
    const std::size_t c2 = item.find(':', c1 + 1);
    double from = 0.0, step = 0.0, to = 0.0;
    if (c2 == std::string_view::npos || item.find(':', c2 + 1) != std::string_view::npos ||
        !parse_number(item.substr(0, c1), &from) || !parse_number(item.substr(c1 + 1, c2 - c1 - 1), &step) ||
        !parse_number(item.substr(c2 + 1), &to))
      return make_error(option + ": '" + std::string(item) + "' is not a range FROM:STEP:TO (e.g. 0:0.1:5)");
    if (!(step > 0.0)) return make_error(option + ": the step of '" + std::string(item) + "' must be positive");
    if (to < from) return make_error(option + ": '" + std::string(item) + "' ends below where it starts");
    const double n = (to - from) / step;
    const double whole = std::round(n);
    if (std::abs(n - whole) > 1e-6 * std::max(1.0, n))
      return make_error(option + ": '" + std::string(item) + "': " + format_number(to - from) +
                        " is not a whole number of " + format_number(step) + "° steps");
    if (whole > static_cast<double>(sim::kMaxGridAngles))
      return make_error(option + ": '" + std::string(item) + "' gives more than " +
                        std::to_string(sim::kMaxGridAngles) + " angles");
    const auto count = static_cast<long>(whole);
    for (long k = 0; k <= count; ++k) {
      // Computed from the ends, not summed, so 0:0.1:5 gives 0.3, not 0.30000000000000004.
      const double v = k == count ? to : std::round((from + static_cast<double>(k) * step) * 1e9) / 1e9;
      if (Status s = append(out, v, option, item); !s.ok()) return s.error();
    }
    if (out.size() > sim::kMaxGridAngles) break;
  }
  if (out.size() > sim::kMaxGridAngles)
    return make_error(option + ": more than " + std::to_string(sim::kMaxGridAngles) + " angles");
  return out;
}

std::vector<double> full_circle_c_angles(std::vector<double> c, photometry::Symmetry symmetry) {
  using photometry::Symmetry;
  const auto wrap = [](double v) {
    v = std::fmod(v, 360.0);
    if (v < 0.0) v += 360.0;
    if (v > 360.0 - kSlack) v = 0.0;
    return std::abs(v) <= kSlack ? 0.0 : v;
  };
  std::vector<double> out;
  for (double v : c) {
    out.push_back(wrap(v));
    if (symmetry == Symmetry::C0_C180 || symmetry == Symmetry::Quadrant) out.push_back(wrap(360.0 - v));
    if (symmetry == Symmetry::C90_C270 || symmetry == Symmetry::Quadrant) out.push_back(wrap(180.0 - v));
    if (symmetry == Symmetry::Quadrant) out.push_back(wrap(180.0 + v));
  }
  std::sort(out.begin(), out.end());
  std::vector<double> unique;
  for (double v : out)
    if (unique.empty() || v - unique.back() > kSlack) unique.push_back(v);
  return unique;
}

Result<sim::CGammaGrid> grid_like_file(const std::string& path, const sim::CGammaGrid& defaults,
                                       std::string* extended) {
  Result<io::PhotometricFile> file = io::read_photometric_file(path);
  if (!file.ok()) {
    // "file:line: message", with the file named even where the reader left it out.
    const std::string where = to_string(file.error());
    return make_error("--grid-like: " + (where.find(path) == std::string::npos ? path + ": " + where : where));
  }
  const photometry::Distribution& d = file.value().distribution;
  if (d.type != photometry::PhotometricType::C)
    return make_error("--grid-like: " + path + " is Type " + photometry::to_string(d.type) +
                      "; simulations write Type C, so only a Type C file's angles can be taken");
  sim::CGammaGrid grid = defaults;
  grid.c_angles_deg.clear();
  grid.gamma_angles_deg.clear();
  std::string added;
  std::vector<double> g = d.vertical_deg;
  if (g.empty()) return make_error("--grid-like: " + path + " has no gamma angles");
  if (g.front() > kSlack) {
    const double gap = g.size() > 1 ? g[1] - g[0] : g.front();
    const int n = std::max(1, static_cast<int>(std::ceil(g.front() / gap - 1e-9)));
    std::vector<double> below;
    for (int k = 0; k < n; ++k) below.push_back(g.front() * k / n);
    added += "gamma 0-" + format_number(g.front()) + " every " + format_number(g.front() / n) + " deg";
    g.insert(g.begin(), below.begin(), below.end());
  }
  if (g.back() < 180.0 - kSlack) {
    const double last = g.back();
    const double gap = g.size() > 1 ? g[g.size() - 1] - g[g.size() - 2] : 180.0 - last;
    const int n = std::max(1, static_cast<int>(std::ceil((180.0 - last) / gap - 1e-9)));
    for (int k = 1; k <= n; ++k) g.push_back(k == n ? 180.0 : last + (180.0 - last) * k / n);
    added += std::string(added.empty() ? "" : ", ") + "gamma " + format_number(last) + "-180 every " +
             format_number((180.0 - last) / n) + " deg";
  }
  grid.gamma_angles_deg = std::move(g);
  if (d.symmetry != photometry::Symmetry::Rotational) {
    grid.c_angles_deg = full_circle_c_angles(d.horizontal_deg, d.symmetry);
  } else {
    added += std::string(added.empty() ? "" : ", ") + "C-planes every " + format_number(defaults.c_step_deg) +
             " deg (the file is rotationally symmetric)";
  }
  if (Status s = sim::validate(grid); !s.ok())
    return make_error("--grid-like: the angles of " + path + " make no grid Gonio can write: " + s.error().message);
  if (extended) *extended = added;
  return grid;
}

Result<sim::CGammaGrid> resolve_grid(const GridOptions& o, std::string* note) {
  sim::CGammaGrid grid;
  grid.c_step_deg = o.c_step;
  grid.gamma_step_deg = o.gamma_step;
  if (note) note->clear();
  if (o.grid_like) {
    if (o.c_angles || o.gamma_angles)
      return make_error("--grid-like and --" + std::string(o.c_angles ? "c-angles" : "gamma-angles") +
                        " exclude each other");
    Result<sim::CGammaGrid> like = grid_like_file(*o.grid_like, grid, note);
    if (!like.ok()) return like.error();
    grid = std::move(like.value());
  }
  if (o.gamma_angles) {
    Result<std::vector<double>> list = parse_angle_list(*o.gamma_angles, "--gamma-angles");
    if (!list.ok()) return list.error();
    grid.gamma_angles_deg = std::move(list.value());
    sim::CGammaGrid check;
    check.gamma_angles_deg = grid.gamma_angles_deg;
    if (Status s = sim::validate(check); !s.ok()) return make_error("--gamma-angles: " + s.error().message);
  }
  if (o.c_angles) {
    Result<std::vector<double>> list = parse_angle_list(*o.c_angles, "--c-angles");
    if (!list.ok()) return list.error();
    if (!list.value().empty() && list.value().back() > 360.0 + kSlack)
      return make_error("--c-angles: " + format_number(list.value().back()) + " is outside 0…360°");
    grid.c_angles_deg = full_circle_c_angles(std::move(list.value()), o.symmetry.value_or(photometry::Symmetry::None));
    sim::CGammaGrid check;
    check.c_angles_deg = grid.c_angles_deg;
    if (Status s = sim::validate(check); !s.ok()) {
      const bool partial = !o.symmetry && !grid.c_angles_deg.empty() && grid.c_angles_deg.back() <= 270.0;
      return make_error("--c-angles: " + s.error().message +
                        (partial ? " (a symmetry's range alone, e.g. 0:15:90, needs --symmetry quadrant, "
                                   "C0-C180 or C90-C270)"
                                 : ""));
    }
  }
  if (Status s = sim::validate(grid); !s.ok()) {
    const char* option = o.grid_like ? "--grid-like" : "--gamma-step/--c-step";
    return make_error(std::string(option) + ": " + s.error().message);
  }
  return grid;
}

Status check_grid_for_ldt(const sim::CGammaGrid& grid, const std::string& c_source, const std::string& gamma_source) {
  if (grid.c_count() > io::kMaxLdtCPlanes)
    return make_error(c_source + ": " + std::to_string(grid.c_count()) + " C-planes, more than the " +
                      std::to_string(io::kMaxLdtCPlanes) +
                      " EULUMDAT holds (--format ldt or gldf); fewer planes, or leave ldt out of --format");
  if (grid.gamma_count() > io::kMaxLdtGammaAngles)
    return make_error(gamma_source + ": " + std::to_string(grid.gamma_count()) + " gamma angles, more than the " +
                      std::to_string(io::kMaxLdtGammaAngles) +
                      " EULUMDAT holds (--format ldt or gldf); fewer angles, or leave ldt out of --format");
  return Ok{};
}

}  // namespace gonio::app
