#include "photometry/resample.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "photometry/angles.h"
#include "photometry/format.h"
#include "photometry/frame.h"
#include "photometry/hermite.h"

namespace gonio::photometry {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr double kMaxIntensities = 1e7;  // 80 MB of doubles

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


// Spacings of an axis [deg] and the weights monotone_hermite_slopes() wants.
struct AxisSteps {
  std::vector<double> h, inv_h, left_weight;
  explicit AxisSteps(const std::vector<double>& x) : left_weight(x.size(), 0.0) {
    for (std::size_t k = 0; k + 1 < x.size(); ++k) {
      h.push_back(x[k + 1] - x[k]);
      inv_h.push_back(1.0 / h.back());
    }
    for (std::size_t k = 1; k + 1 < x.size(); ++k) left_weight[k] = h[k] / (h[k - 1] + h[k]);
  }
};

// The monotone model never leaves the range of a segment's end values; this
// removes what rounding adds (a −1e-50 cd where both ends are 0).
double within(double x, double a, double b) { return std::clamp(x, std::min(a, b), std::max(a, b)); }

// Index k of the segment [x[k], x[k+1]] that holds a (x.front() <= a <= x.back()).
std::size_t segment_of(const std::vector<double>& x, double a) {
  const auto it = std::upper_bound(x.begin(), x.end(), a);
  const std::size_t k = it == x.begin() ? 0 : static_cast<std::size_t>(it - x.begin()) - 1;
  return std::min(k, x.size() - 2);
}

// The intensity model of an expanded Type A or B distribution that
// total_flux_lm() integrates (photometry/hermite.h): the monotone Hermite
// curve along V in every plane, and through the planes along H. Where the
// bilinear model of interpolate() overestimates a peaked beam by a term in
// h² f'' (0.4 % for a cos²⁰ floodlight on a 2.5° grid), this one carries the
// source's flux to its quadrature error.
class HermiteModel {
 public:
  explicit HermiteModel(const Distribution& e)
      : e_(e), h_steps_(e.horizontal_deg), v_steps_(e.vertical_deg) {
    const std::size_t nh = e.horizontal_count(), nv = e.vertical_count();
    usable_ = nh >= 2 && nv >= 2;
    if (!usable_) return;
    left_v_.resize(nh * nv);
    right_v_.resize(nh * nv);
    std::vector<double> s(nv);
    for (std::size_t p = 0; p < nh; ++p)
      monotone_hermite_slopes(nv, v_steps_.h.data(), v_steps_.inv_h.data(),
                              v_steps_.left_weight.data(), e.candela.data() + p * nv, s.data(),
                              left_v_.data() + p * nv, right_v_.data() + p * nv);
  }

  // Smallest spacing of either axis [deg] (the scale of the model's detail).
  double finest_step_deg() const {
    double m = 180.0;
    for (double h : h_steps_.h) m = std::min(m, h);
    for (double h : v_steps_.h) m = std::min(m, h);
    return m;
  }

  // Intensity [cd] at grid angles [deg]; 0 outside the stored ranges.
  double at(double h_deg, double v_deg) const {
    const std::vector<double>& hs = e_.horizontal_deg;
    const std::vector<double>& vs = e_.vertical_deg;
    if (!usable_ || !(h_deg >= hs.front() && h_deg <= hs.back()) ||
        !(v_deg >= vs.front() && v_deg <= vs.back()))
      return 0.0;
    const std::size_t nv = vs.size();
    const std::size_t k = segment_of(vs, v_deg);
    const double t = (v_deg - vs[k]) * v_steps_.inv_h[k];
    // The H slopes at the ends of segment p need planes p − 2 … p + 3.
    const std::size_t p = segment_of(hs, h_deg);
    const std::size_t lo = p >= 2 ? p - 2 : 0, hi = std::min(hs.size() - 1, p + 3);
    const std::size_t m = hi - lo + 1;
    std::array<double, 6> row{}, s{}, left{}, right{};
    for (std::size_t q = lo; q <= hi; ++q) {
      const double* f = e_.candela.data() + q * nv;
      row[q - lo] = within(hermite_value(v_steps_.h[k], f[k], f[k + 1], right_v_[q * nv + k],
                                         left_v_[q * nv + k + 1], t),
                           f[k], f[k + 1]);
    }
    monotone_hermite_slopes(m, h_steps_.h.data() + lo, h_steps_.inv_h.data() + lo,
                            h_steps_.left_weight.data() + lo, row.data(), s.data(), left.data(),
                            right.data());
    const std::size_t j = p - lo;
    return within(hermite_value(h_steps_.h[p], row[j], row[j + 1], right[j], left[j + 1],
                                (h_deg - hs[p]) * h_steps_.inv_h[p]),
                  row[j], row[j + 1]);
  }

 private:
  const Distribution& e_;
  AxisSteps h_steps_, v_steps_;
  bool usable_ = false;
  std::vector<double> left_v_, right_v_;  // V slopes of every plane, as candela
};

// Type A or B resampled at the Type C grid c × g [deg] (out[i * g.size() + j]):
// each value is the mean of the source model over its C-cell
// [c − c_step/2, c + c_step/2] at that γ, by two-point Gauss–Legendre rules on
// sub-cells no wider than half the source's finest step. Averaging over C
// keeps narrow beams that fall between C-planes, and the trapezoid rule over
// C that total_flux_lm() applies to cell means of a periodic function is the
// exact integral over C; along γ the model is sampled at the grid angle.
std::vector<double> cell_means(const Distribution& expanded, const std::vector<double>& c,
                               const std::vector<double>& g, double c_step_deg) {
  const HermiteModel model(expanded);
  const double fine = model.finest_step_deg();
  constexpr double kGauss = 0.57735026918962576;  // 1/√3
  std::vector<double> out(c.size() * g.size(), 0.0);
  for (std::size_t j = 0; j < g.size(); ++j) {
    const double gamma = g[j] * kDeg;
    // Arc length of the cell across the planes, in source steps.
    const double arc_deg = c_step_deg * std::sin(gamma);
    const int parts = std::max(1, static_cast<int>(std::ceil(2.0 * arc_deg / fine - 1e-9)));
    const double part = c_step_deg / parts;
    for (std::size_t i = 0; i < c.size(); ++i) {
      double sum = 0.0;
      for (int q = 0; q < parts; ++q) {
        const double mid = c[i] - 0.5 * c_step_deg + (q + 0.5) * part;
        for (double x : {-kGauss, kGauss}) {
          const GridAngles a = grid_from_direction(
              expanded.type, direction_from_c_gamma((mid + 0.5 * part * x) * kDeg, gamma));
          sum += model.at(a.horizontal_deg, a.vertical_deg);
        }
      }
      out[i * g.size() + j] = sum / (2.0 * parts);
    }
  }
  return out;
}

}  // namespace

Result<Distribution> to_type_c(const Distribution& d, const TypeCGrid& grid) {
  GONIO_CHECK_MSG(validate(d).ok(), "to_type_c needs a valid distribution");
  const double cs = grid.c_step_deg, gs = grid.gamma_step_deg;
  if (!(std::isfinite(cs) && cs > 0.0))
    return make_error("the C-plane step must be a positive number of degrees, found " +
                      format_number(cs));
  if (!(std::isfinite(gs) && gs > 0.0))
    return make_error("the gamma step must be a positive number of degrees, found " +
                      format_number(gs));
  const Symmetry sym = grid.symmetry.value_or(default_symmetry(d));
  if (sym == Symmetry::Lateral)
    return make_error("lateral symmetry applies to Types A and B, not Type C");

  if (whole_steps(90.0, gs) <= 0)
    return make_error("the gamma step " + format_number(gs) +
                      " deg does not divide 90 deg into whole steps");
  const Range cr = c_range(sym);
  // (A rotational output averages planes 0, step, … around the whole circle.)
  const long steps = whole_steps(cr.to - cr.from, cs);
  if (steps <= 0)
    return make_error("the C-plane step " + format_number(cs) +
                      " deg does not divide the C range " + format_number(cr.from) + ".." +
                      format_number(cr.to) + " deg into whole steps");
  const long nc = sym == Symmetry::Rotational ? 1 : steps + 1;
  const Range gr = grid.whole_sphere ? Range{0.0, 180.0} : gamma_range(d, gs);
  const long ng = std::lround((gr.to - gr.from) / gs) + 1;
  // Intensities sampled: the rotational mean samples a whole circle per γ.
  const double sampled =
      static_cast<double>(ng) * static_cast<double>(sym == Symmetry::Rotational ? steps : nc);
  if (sampled > kMaxIntensities)
    return make_error("a " + format_number(cs) + " x " + format_number(gs) +
                      " deg grid would hold more than 10^7 intensities");

  const Distribution e = expand_symmetry(d);
  auto sample_grid = [&](const std::vector<double>& c, const std::vector<double>& g) {
    if (d.type == PhotometricType::C) return interpolate_grid(e, c, g);
    return cell_means(e, c, g, cs);
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
