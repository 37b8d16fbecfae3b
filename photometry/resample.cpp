#include "photometry/resample.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "photometry/angles.h"
#include "photometry/frame.h"

namespace gonio::photometry {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr double kMaxIntensities = 1e7;  // 80 MB of doubles

std::string deg(double a) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", a);
  return buf;
}

Error fail(std::string message) { return Error{{}, std::move(message)}; }

// Whole number of steps in `range`, or -1 if `step` does not divide it.
long whole_steps(double range, double step) {
  const double n = range / step;
  const double r = std::round(n);
  if (!(std::abs(n - r) <= 1e-9 * std::max(1.0, r))) return -1;
  return static_cast<long>(r);
}

Symmetry default_symmetry(const Distribution& d) {
  if (d.type == PhotometricType::C) return d.symmetry;
  return d.symmetry == Symmetry::Lateral ? Symmetry::C0_C180 : Symmetry::None;
}

struct Range {
  double from, to;
};

Range c_range(Symmetry s) {
  switch (s) {
    case Symmetry::Quadrant:
      return {0.0, 90.0};
    case Symmetry::C0_C180:
      return {0.0, 180.0};
    case Symmetry::C90_C270:
      return {90.0, 270.0};
    case Symmetry::Rotational:
    case Symmetry::None:
    case Symmetry::Lateral:
      break;
  }
  return {0.0, 360.0};
}

// γ range of the measured directions, snapped outwards to whole steps.
Range gamma_range(const Distribution& d, double step) {
  double lo = 0.0, hi = 90.0;  // Type B: the LM-63 grid lies in the lower hemisphere
  if (d.type == PhotometricType::C) {
    lo = d.vertical_deg.front();
    hi = d.vertical_deg.back();
  } else if (d.type == PhotometricType::A) {
    lo = d.vertical_deg.front() + 90.0;
    hi = d.vertical_deg.back() + 90.0;
  }
  const double eps = 1e-9;
  lo = std::floor(lo / step + eps) * step;
  hi = std::ceil(hi / step - eps) * step;
  return {std::max(0.0, lo), std::min(180.0, hi)};
}

}  // namespace

Result<Distribution> to_type_c(const Distribution& d, const TypeCGrid& grid) {
  GONIO_CHECK_MSG(validate(d).ok(), "to_type_c needs a valid distribution");
  const double cs = grid.c_step_deg, gs = grid.gamma_step_deg;
  if (!(std::isfinite(cs) && cs > 0.0))
    return fail("the C-plane step must be a positive number of degrees, found " + deg(cs));
  if (!(std::isfinite(gs) && gs > 0.0))
    return fail("the gamma step must be a positive number of degrees, found " + deg(gs));
  const Symmetry sym = grid.symmetry.value_or(default_symmetry(d));
  if (sym == Symmetry::Lateral)
    return fail("lateral symmetry applies to Types A and B, not Type C");

  if (whole_steps(90.0, gs) <= 0)
    return fail("the gamma step " + deg(gs) + " deg does not divide 90 deg into whole steps");
  const Range cr = c_range(sym);
  // (A rotational output averages planes 0, step, … around the whole circle.)
  const long steps = whole_steps(cr.to - cr.from, cs);
  if (steps <= 0)
    return fail("the C-plane step " + deg(cs) + " deg does not divide the C range " + deg(cr.from) +
                ".." + deg(cr.to) + " deg into whole steps");
  const long nc = sym == Symmetry::Rotational ? 1 : steps + 1;
  const Range gr = grid.whole_sphere ? Range{0.0, 180.0} : gamma_range(d, gs);
  const long ng = std::lround((gr.to - gr.from) / gs) + 1;
  // Intensities sampled: the rotational mean samples a whole circle per γ.
  const double sampled =
      static_cast<double>(ng) * static_cast<double>(sym == Symmetry::Rotational ? steps : nc);
  if (sampled > kMaxIntensities)
    return fail("a " + deg(cs) + " x " + deg(gs) +
                " deg grid would hold more than 10^7 intensities");

  const Distribution e = expand_symmetry(d);
  auto sample_grid = [&](const std::vector<double>& c, const std::vector<double>& g) {
    if (d.type == PhotometricType::C) return interpolate_grid(e, c, g);
    std::vector<double> values(c.size() * g.size());
    for (std::size_t i = 0; i < c.size(); ++i)
      for (std::size_t j = 0; j < g.size(); ++j)
        values[i * g.size() + j] =
            intensity_toward(e, direction_from_c_gamma(c[i] * kDeg, g[j] * kDeg));
    return values;
  };

  Distribution out = d;
  out.type = PhotometricType::C;
  out.symmetry = sym;
  out.vertical_deg.resize(static_cast<std::size_t>(ng));
  for (long j = 0; j < ng; ++j) out.vertical_deg[static_cast<std::size_t>(j)] = gr.from + j * gs;
  out.vertical_deg.back() = gr.to;
  out.horizontal_deg.resize(static_cast<std::size_t>(nc));
  for (long i = 0; i < nc; ++i) out.horizontal_deg[static_cast<std::size_t>(i)] = cr.from + i * cs;
  if (sym != Symmetry::Rotational)
    out.horizontal_deg.back() = cr.to;
  else
    out.horizontal_deg = {0.0};
  out.candela.assign(out.horizontal_deg.size() * out.vertical_deg.size(), 0.0);

  if (sym == Symmetry::Rotational) {
    // The mean over C (trapezoid on a circle: every plane weighs the same).
    std::vector<double> circle(static_cast<std::size_t>(steps));
    for (long i = 0; i < steps; ++i) circle[static_cast<std::size_t>(i)] = 360.0 * i / steps;
    const std::vector<double> values = sample_grid(circle, out.vertical_deg);
    for (std::size_t v = 0; v < out.vertical_count(); ++v) {
      double sum = 0.0;
      for (std::size_t i = 0; i < circle.size(); ++i) sum += values[i * out.vertical_count() + v];
      out.at(0, v) = sum / static_cast<double>(steps);
    }
  } else {
    out.candela = sample_grid(out.horizontal_deg, out.vertical_deg);
  }
  return out;
}

}  // namespace gonio::photometry
