#include "design/tolerance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "io/support/text.h"
#include "photometry/compare.h"
#include "photometry/format.h"
#include "photometry/bug_rating.h"
#include "photometry/summary.h"
#include "photometry/ugr.h"

namespace gonio::design {
namespace {

// splitmix64: the hypercube's shuffles and jitter.
struct SplitMix {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
};

}  // namespace

const std::array<FigureInfo, kFigureCount>& figure_info() {
  static const std::array<FigureInfo, kFigureCount> info{{
      {"peak_cd", "cd", "peak intensity"},
      {"peak_c", "deg", "peak C"},
      {"peak_gamma", "deg", "peak γ"},
      {"beam_c0", "deg", "beam angle C0-C180"},
      {"beam_c90", "deg", "beam angle C90-C270"},
      {"field_c0", "deg", "field angle C0-C180"},
      {"field_c90", "deg", "field angle C90-C270"},
      {"flux", "lm", "flux"},
      {"lor", "1", "LOR"},
      {"rms", "% of peak", "RMS difference from the nominal"},
      {"ugr", "1", "UGR 4H×8H 70/50/20 crosswise"},
      {"bug_b", "1", "BUG backlight B"},
      {"bug_u", "1", "BUG uplight U"},
      {"bug_g", "1", "BUG glare G"},
      {"cct", "K", "CCT"},
      {"duv_max", "1", "Δu′v′ max over angle"},
      {"axis_c0", "deg", "beam axis tilt towards C0"},
      {"axis_c90", "deg", "beam axis tilt towards C90"},
      {"dugr", "1", "CIE 232 ΔUGR (largest over the views)"},
      {"ugr_cie232", "1", "UGR 4H×8H with CIE 232's ΔUGR"},
  }};
  return info;
}

std::optional<std::size_t> figure_by_key(const std::string& key) {
  for (std::size_t i = 0; i < kFigureCount; ++i)
    if (key == figure_info()[i].key) return i;
  return std::nullopt;
}

Result<FigureValues> figures_of(const photometry::Distribution& d, const photometry::Distribution& nominal,
                                double c_step_deg, double gamma_step_deg) {
  const photometry::Summary s = photometry::summarize(d);
  FigureValues f{};
  f[kPeakCd] = s.max_intensity_cd;
  f[kPeakC] = s.max_c_deg;
  f[kPeakGamma] = s.max_gamma_deg;
  f[kBeamC0] = s.beam_c0_c180.angle_deg;
  f[kBeamC90] = s.beam_c90_c270.angle_deg;
  f[kFieldC0] = s.field_c0_c180.angle_deg;
  f[kFieldC90] = s.field_c90_c270.angle_deg;
  f[kFlux] = s.flux_lm;
  f[kLor] = s.lor;
  photometry::CompareOptions o;
  o.c_step_deg = c_step_deg;
  o.gamma_step_deg = gamma_step_deg;
  Result<photometry::Comparison> c = photometry::compare(nominal, d, o);
  if (!c.ok()) return c.error();
  f[kRms] = 100.0 * c->rms_relative;
  // The project's UGR table and BUG rating (photometry/ugr.h, bug_rating.h).
  f[kUgr] = f[kBugB] = f[kBugU] = f[kBugG] = std::numeric_limits<double>::quiet_NaN();
  if (photometry::validate(d).ok()) {
    const photometry::UgrTable ugr = photometry::ugr_table(d);
    if (ugr.defined)
      for (const photometry::UgrRoom& room : ugr.rooms)
        if (room.x_h == 4.0 && room.y_h == 8.0) f[kUgr] = room.crosswise[0];
    const photometry::BugRating bug = photometry::bug_rating(d);
    f[kBugB] = bug.b;
    f[kBugU] = bug.u;
    f[kBugG] = bug.g;
  }
  f[kCct] = f[kDuvMax] = std::numeric_limits<double>::quiet_NaN();  // the caller's, from a spectral run
  f[kDugr] = f[kUgrCie232] = std::numeric_limits<double>::quiet_NaN();  // the caller's, from luminance images
  const std::array<double, 2> axis = beam_axis_deg(d);
  f[kAxisC0] = axis[0];
  f[kAxisC90] = axis[1];
  return f;
}

std::array<double, 2> beam_axis_deg(const photometry::Distribution& d) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const std::size_t nh = d.horizontal_count(), nv = d.vertical_count();
  if (d.type != photometry::PhotometricType::C || d.symmetry != photometry::Symmetry::None || nh == 0 || nv < 2 ||
      d.candela.size() != nh * nv)
    return {kNaN, kNaN};
  double peak = 0.0;
  for (double v : d.candela) peak = std::max(peak, v);
  if (!(peak > 0.0)) return {kNaN, kNaN};
  constexpr double kRad = std::numbers::pi / 180.0;
  double mx = 0.0, my = 0.0, mz = 0.0;
  for (std::size_t h = 0; h < nh; ++h) {
    // The C range around plane h: halfway to its neighbours (cyclic).
    const double c = d.horizontal_deg[h];
    const double prev = h == 0 ? d.horizontal_deg[nh - 1] - 360.0 : d.horizontal_deg[h - 1];
    const double next = h + 1 == nh ? d.horizontal_deg[0] + 360.0 : d.horizontal_deg[h + 1];
    const double dc = 0.5 * (next - prev) * kRad;
    for (std::size_t v = 0; v < nv; ++v) {
      const double i = d.at(h, v);
      if (!(i >= 0.5 * peak)) continue;
      const double g = d.vertical_deg[v];
      const double lo = v == 0 ? g : 0.5 * (g + d.vertical_deg[v - 1]);
      const double hi = v + 1 == nv ? g : 0.5 * (g + d.vertical_deg[v + 1]);
      const double w = i * dc * (std::cos(lo * kRad) - std::cos(hi * kRad));
      mx += w * std::sin(g * kRad) * std::cos(c * kRad);
      my += w * std::sin(g * kRad) * std::sin(c * kRad);
      mz -= w * std::cos(g * kRad);
    }
  }
  return {std::atan2(mx, -mz) / kRad, std::atan2(my, -mz) / kRad};
}

std::vector<std::vector<double>> latin_hypercube(std::size_t trials, std::size_t dims, std::uint64_t seed) {
  std::vector<std::vector<double>> u(trials, std::vector<double>(dims, 0.0));
  SplitMix rng{seed * 0x2545F4914F6CDD1DULL + 1};
  std::vector<std::size_t> strata(trials);
  for (std::size_t d = 0; d < dims; ++d) {
    std::iota(strata.begin(), strata.end(), std::size_t{0});
    for (std::size_t i = trials; i > 1; --i) std::swap(strata[i - 1], strata[rng.next() % i]);  // Fisher–Yates
    for (std::size_t t = 0; t < trials; ++t)
      u[t][d] = (static_cast<double>(strata[t]) + rng.uniform()) / static_cast<double>(trials);
  }
  return u;
}

std::string SpecLimit::text() const {
  std::string s = std::string(figure_info()[figure].key) + "=";
  if (std::isfinite(lo)) s += format_number(lo);
  s += "..";
  if (std::isfinite(hi)) s += format_number(hi);
  return s;
}

std::string PercentileChoice::text() const {
  return std::string(figure_info()[figure].key) + " " + format_number(percent);
}

std::string PercentileChoice::stem() const {
  return "p" + format_number(percent) + "_" + figure_info()[figure].key;
}

Result<std::vector<PercentileChoice>> parse_percentiles(const std::string& text) {
  std::vector<PercentileChoice> choices;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    start = comma + 1;
    PercentileChoice c;
    std::string number = item;
    if (const std::size_t colon = item.find(':'); colon != std::string::npos) {
      const std::optional<std::size_t> figure = figure_by_key(item.substr(0, colon));
      if (!figure) {
        std::string keys;
        for (const FigureInfo& i : figure_info()) keys += (keys.empty() ? "" : ", ") + std::string(i.key);
        return make_error("--percentile " + io::shown(item) + ": unknown figure (" + keys + ")");
      }
      c.figure = *figure;
      number = item.substr(colon + 1);
    }
    const std::optional<double> v = io::parse_number(number);
    if (!v || !(*v >= 0.0 && *v <= 100.0))
      return make_error("--percentile " + io::shown(item) + ": write P or FIGURE:P with P from 0 to 100");
    c.percent = *v;
    choices.push_back(c);
    if (comma == text.size()) break;
  }
  return choices;
}

std::optional<std::size_t> nearest_rank(const std::vector<double>& values, double percent) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (std::isfinite(values[i])) order.push_back(i);
  if (order.empty()) return std::nullopt;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  const double n = static_cast<double>(order.size());
  const auto rank = static_cast<std::size_t>(std::max(1.0, std::ceil(percent * n / 100.0)));
  return order[std::min(rank, order.size()) - 1];
}

Result<std::vector<SpecLimit>> parse_spec(const std::string& text) {
  std::vector<SpecLimit> limits;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    start = comma + 1;
    std::string keys;
    for (const FigureInfo& i : figure_info()) keys += (keys.empty() ? "" : ", ") + std::string(i.key);
    // FIGURE<=HI and FIGURE>=LO: one-sided limits.
    if (const std::size_t rel = std::min(item.find("<="), item.find(">=")); rel != std::string::npos) {
      const std::optional<std::size_t> figure = figure_by_key(item.substr(0, rel));
      if (!figure) return make_error("--spec " + io::shown(item) + ": unknown figure (" + keys + ")");
      const std::string number = item.substr(rel + 2);
      const std::optional<double> v = io::parse_number(number);
      if (!v || !std::isfinite(*v)) return make_error("--spec " + io::shown(item) + ": " + io::shown(number) + " is not a number");
      SpecLimit l;
      l.figure = *figure;
      (item[rel] == '<' ? l.hi : l.lo) = *v;
      limits.push_back(l);
      if (comma == text.size()) break;
      continue;
    }
    const std::size_t eq = item.find('='), dots = item.find("..");
    if (eq == std::string::npos || dots == std::string::npos || dots < eq)
      return make_error("--spec " + io::shown(item) + ": write FIGURE=LO..HI (either end may be left out)");
    const std::optional<std::size_t> figure = figure_by_key(item.substr(0, eq));
    if (!figure) return make_error("--spec " + io::shown(item) + ": unknown figure (" + keys + ")");
    SpecLimit l;
    l.figure = *figure;
    const std::string lo = item.substr(eq + 1, dots - eq - 1), hi = item.substr(dots + 2);
    if (!lo.empty()) {
      const std::optional<double> v = io::parse_number(lo);
      if (!v) return make_error("--spec " + io::shown(item) + ": " + io::shown(lo) + " is not a number");
      l.lo = *v;
    }
    if (!hi.empty()) {
      const std::optional<double> v = io::parse_number(hi);
      if (!v) return make_error("--spec " + io::shown(item) + ": " + io::shown(hi) + " is not a number");
      l.hi = *v;
    }
    if (lo.empty() && hi.empty()) return make_error("--spec " + io::shown(item) + ": give at least one limit");
    if (!(l.lo <= l.hi)) return make_error("--spec " + io::shown(item) + ": the low limit is above the high one");
    limits.push_back(l);
    if (comma == text.size()) break;
  }
  return limits;
}

double allowed_scale(double nominal, double change_low, double change_high, const SpecLimit& limit) {
  if (!limit.holds(nominal)) return 0.0;
  double k = std::numeric_limits<double>::infinity();
  for (double c : {change_low, change_high}) {
    if (!std::isfinite(c)) continue;
    if (c > 0.0 && std::isfinite(limit.hi)) k = std::min(k, (limit.hi - nominal) / c);
    if (c < 0.0 && std::isfinite(limit.lo)) k = std::min(k, (nominal - limit.lo) / -c);
  }
  return k;
}

FigureValues noise_floor(const FigureValues& nominal, const std::vector<FigureValues>& independent) {
  FigureValues noise{};
  const double n = static_cast<double>(independent.size() + 1);
  for (std::size_t f = 0; f < kFigureCount; ++f) {
    if (independent.empty()) {
      noise[f] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    if (f == kRms) {
      double sum = 0.0;
      for (const FigureValues& v : independent) sum += v[f];
      noise[f] = sum / static_cast<double>(independent.size());
      continue;
    }
    double mean = nominal[f];
    for (const FigureValues& v : independent) mean += v[f];
    mean /= n;
    double ss = (nominal[f] - mean) * (nominal[f] - mean);
    for (const FigureValues& v : independent) ss += (v[f] - mean) * (v[f] - mean);
    noise[f] = std::sqrt(ss / (n - 1.0));
  }
  return noise;
}

bool below_noise(double change, double noise) {
  return std::isfinite(noise) && std::abs(change) < kNoiseFactor * noise;
}

Histogram histogram(const std::vector<double>& values, std::size_t bins) {
  Histogram h;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double v : values)
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (!std::isfinite(lo) || bins == 0) return h;
  if (hi == lo) {
    lo -= 0.5;
    hi += 0.5;
  }
  for (std::size_t i = 0; i <= bins; ++i) h.edges.push_back(lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(bins));
  h.counts.assign(bins, 0);
  for (double v : values)
    if (std::isfinite(v))
      ++h.counts[std::min(bins - 1, static_cast<std::size_t>((v - lo) / (hi - lo) * static_cast<double>(bins)))];
  return h;
}

double SensitivityRow::largest() const {
  double m = 0.0;
  for (double c : {change_low, change_high})
    if (std::isfinite(c)) m = std::max(m, std::abs(c));
  return m;
}

io::Figure tornado_figure(const std::string& title, const std::string& unit, const std::vector<SensitivityRow>& rows,
                          double noise) {
  io::LineChart chart;
  chart.title = title;
  chart.x_label = "change at the low (o) and high (x) limit [" + unit + "]";
  chart.y_label = "tolerance (largest at the top)";
  chart.key_below = true;
  const double n = static_cast<double>(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double y = n - static_cast<double>(i);
    io::Series s;
    s.label = rows[i].label;
    s.x = {rows[i].change_low, 0.0, rows[i].change_high};
    s.y = {y, y, y};
    s.markers = true;
    chart.series.push_back(std::move(s));
  }
  if (std::isfinite(noise) && noise > 0.0)
    for (double sign : {-1.0, 1.0}) {
      io::Series s;
      s.label = sign < 0 ? "noise floor (±" + format_number(kNoiseFactor) + "σ)" : "";
      s.x = {sign * kNoiseFactor * noise, sign * kNoiseFactor * noise};
      s.y = {0.0, n + 1.0};
      s.style = io::LineStyle::Dashed;
      chart.series.push_back(std::move(s));
    }
  chart.y_min = 0.0;
  chart.y_max = n + 1.0;
  io::Figure figure;
  figure.charts.push_back(std::move(chart));
  figure.width_px = 900;
  figure.height_px = 300 + 30 * static_cast<int>(rows.size());
  return figure;
}

}  // namespace gonio::design
