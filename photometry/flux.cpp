#include "photometry/flux.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "photometry/hermite.h"
#include "photometry/resample.h"

namespace gonio::photometry {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Solid-angle weight along an axis.
enum class Weight { One, Sin, Cos };

double weight(Weight w, double x) {
  switch (w) {
    case Weight::Sin:
      return std::sin(x);
    case Weight::Cos:
      return std::cos(x);
    case Weight::One:
      break;
  }
  return 1.0;
}

// 8-point Gauss–Legendre rule on [0, 1]: exact for polynomials of degree 15,
// so a cubic times sin or cos over a segment as long as 180° is integrated
// to about 1e-12 relative.
constexpr std::array<double, 8> kGaussX = {
    0.5 - 0.5 * 0.9602898564975363, 0.5 - 0.5 * 0.7966664774136267, 0.5 - 0.5 * 0.5255324099163290,
    0.5 - 0.5 * 0.1834346424956498, 0.5 + 0.5 * 0.1834346424956498, 0.5 + 0.5 * 0.5255324099163290,
    0.5 + 0.5 * 0.7966664774136267, 0.5 + 0.5 * 0.9602898564975363};
constexpr std::array<double, 8> kGaussW = {0.5 * 0.1012285362903763, 0.5 * 0.2223810344533745,
                                           0.5 * 0.3137066458778873, 0.5 * 0.3626837833783620,
                                           0.5 * 0.3626837833783620, 0.5 * 0.3137066458778873,
                                           0.5 * 0.2223810344533745, 0.5 * 0.1012285362903763};

// Integrals over [lo, hi] ⊆ [a, b] of the cubic Hermite basis functions of the
// segment [a, b] (in t = (x − a)/(b − a)) times the weight:
// {h00, h01, h10, h11} for value at a, value at b, slope at a, slope at b.
using Moments = std::array<double, 4>;

Moments moments(double a, double b, double lo, double hi, Weight w) {
  Moments m = {0.0, 0.0, 0.0, 0.0};
  const double h = b - a, len = hi - lo;
  for (std::size_t i = 0; i < kGaussX.size(); ++i) {
    const double x = lo + len * kGaussX[i];
    const double t = (x - a) / h, t2 = t * t, t3 = t2 * t;
    const double ww = weight(w, x) * kGaussW[i] * len;
    m[0] += (2.0 * t3 - 3.0 * t2 + 1.0) * ww;
    m[1] += (-2.0 * t3 + 3.0 * t2) * ww;
    m[2] += (t3 - 2.0 * t2 + t) * ww;
    m[3] += (t3 - t2) * ww;
  }
  return m;
}

// One axis of a grid (angles in radians) with the weight of its solid-angle
// element, and the monotone Hermite rule of flux.h along it. Holds scratch
// space: one object per thread.
class Axis {
 public:
  Axis(const std::vector<double>& angles_deg, Weight w) : w_(w) {
    x_.reserve(angles_deg.size());
    for (double a : angles_deg) x_.push_back(a * kDeg);
    const std::size_t n = x_.size();
    for (std::size_t k = 0; k + 1 < n; ++k) {
      h_.push_back(x_[k + 1] - x_[k]);
      inv_h_.push_back(1.0 / h_.back());
      m_.push_back(moments(x_[k], x_[k + 1], x_[k], x_[k + 1], w));
    }
    // Weights of the three-point slope at interior nodes.
    left_.assign(n, 0.0);
    for (std::size_t k = 1; k + 1 < n; ++k) left_[k] = h_[k] / (h_[k - 1] + h_[k]);
    s_.resize(n);
    dl_.resize(n);
    dr_.resize(n);
  }

  std::size_t size() const { return x_.size(); }
  double front() const { return x_.front(); }
  double back() const { return x_.back(); }

  // ∫ over the whole axis of the model of f (size() values) times the weight.
  double integrate(const double* f) {
    if (x_.size() < 2) return 0.0;
    slopes(f);
    double sum = 0.0;
    for (std::size_t k = 0; k + 1 < x_.size(); ++k) sum += segment(f, k, m_[k]);
    return sum;
  }

  // The same over [lo, hi] [rad] only (clamped to the axis).
  double integrate(const double* f, double lo, double hi) {
    lo = std::max(lo, x_.front());
    hi = std::min(hi, x_.back());
    if (x_.size() < 2 || !(hi > lo)) return 0.0;
    slopes(f);
    double sum = 0.0;
    for (std::size_t k = 0; k + 1 < x_.size(); ++k) {
      const double a = x_[k], b = x_[k + 1];
      if (b <= lo || a >= hi) continue;
      if (a >= lo && b <= hi)
        sum += segment(f, k, m_[k]);
      else
        sum += segment(f, k, moments(a, b, std::max(a, lo), std::min(b, hi), w_));
    }
    return sum;
  }

 private:
  double segment(const double* f, std::size_t k, const Moments& m) const {
    return f[k] * m[0] + f[k + 1] * m[1] + h_[k] * (dr_[k] * m[2] + dl_[k + 1] * m[3]);
  }

  // Secant slopes s_ and the node slopes used by the segment left of each
  // node (dl_) and right of it (dr_); equal except at the edge of a dark run.
  void slopes(const double* f) {
    monotone_hermite_slopes(x_.size(), h_.data(), inv_h_.data(), left_.data(), f, s_.data(),
                            dl_.data(), dr_.data());
  }

  Weight w_;
  std::vector<double> x_, h_, inv_h_, left_;
  std::vector<Moments> m_;
  std::vector<double> s_, dl_, dr_;
};

// Integral over C of per-plane values g (one per expanded plane) by the
// trapezoid rule over the expanded planes [rad].
double trapezoid_c(const std::vector<ExpandedPlane>& planes, const std::vector<double>& g) {
  double sum = 0.0;
  for (std::size_t p = 0; p + 1 < planes.size(); ++p)
    sum += 0.5 * (g[p] + g[p + 1]) * (planes[p + 1].angle_deg - planes[p].angle_deg) * kDeg;
  return sum;
}

// Per expanded plane: the vertical integral of its intensities, computed once
// per stored row (blended seam planes get their own row).
template <class RowIntegral>
std::vector<double> plane_integrals(const Distribution& d, const std::vector<ExpandedPlane>& planes,
                                    RowIntegral&& integrate_row) {
  const std::size_t nv = d.vertical_count();
  std::vector<double> row_value(d.horizontal_count(), 0.0);
  std::vector<char> done(d.horizontal_count(), 0);
  std::vector<double> blend(nv);
  std::vector<double> g(planes.size());
  for (std::size_t p = 0; p < planes.size(); ++p) {
    const ExpandedPlane& pl = planes[p];
    if (pl.t != 0.0) {
      const double* a = d.candela.data() + pl.row * nv;
      const double* b = d.candela.data() + pl.row_b * nv;
      for (std::size_t v = 0; v < nv; ++v) blend[v] = a[v] * (1.0 - pl.t) + b[v] * pl.t;
      g[p] = integrate_row(blend.data());
      continue;
    }
    if (!done[pl.row]) {
      row_value[pl.row] = integrate_row(d.candela.data() + pl.row * nv);
      done[pl.row] = 1;
    }
    g[p] = row_value[pl.row];
  }
  return g;
}

// Flux of a Type C distribution with γ restricted to [lo, hi] [rad].
double flux_c(const Distribution& d, double lo, double hi) {
  const std::vector<ExpandedPlane> planes = expanded_planes(d);
  Axis gamma(d.vertical_deg, Weight::Sin);
  const bool whole = lo <= gamma.front() && hi >= gamma.back();
  const auto g = plane_integrals(d, planes, [&](const double* row) {
    return whole ? gamma.integrate(row) : gamma.integrate(row, lo, hi);
  });
  return trapezoid_c(planes, g);
}

// Flux of a Type A or B distribution; for Type A, V restricted to [lo, hi] [rad].
double flux_ab(const Distribution& d, double lo, double hi) {
  const std::vector<ExpandedPlane> planes = expanded_planes(d);
  const bool type_a = d.type == PhotometricType::A;
  Axis vertical(d.vertical_deg, type_a ? Weight::Cos : Weight::One);
  const auto g = plane_integrals(
      d, planes, [&](const double* row) { return vertical.integrate(row, lo, hi); });
  std::vector<double> h_deg(planes.size());
  for (std::size_t p = 0; p < planes.size(); ++p) h_deg[p] = planes[p].angle_deg;
  Axis horizontal(h_deg, type_a ? Weight::One : Weight::Cos);
  return horizontal.integrate(g.data());
}

}  // namespace

double total_flux_lm(const Distribution& d) {
  GONIO_CHECK_MSG(validate(d).ok(), "total_flux_lm needs a valid distribution");
  const double inf = std::numeric_limits<double>::infinity();
  return d.type == PhotometricType::C ? flux_c(d, -inf, inf) : flux_ab(d, -inf, inf);
}

ZonalFlux::ZonalFlux(const Distribution& d) : total_lm_(total_flux_lm(d)) {
  if (d.type != PhotometricType::B) {
    grid_ = d;
    return;
  }
  TypeCGrid fine;
  fine.c_step_deg = 0.5;
  fine.gamma_step_deg = 0.5;
  Result<Distribution> c = to_type_c(d, fine);
  GONIO_CHECK(c.ok());
  grid_ = std::move(c).value();
  const double whole = total_flux_lm(grid_);
  scale_ = whole != 0.0 ? total_lm_ / whole : 0.0;
}

double ZonalFlux::zone_lm(double gamma_from_deg, double gamma_to_deg) const {
  const double from = std::clamp(gamma_from_deg, 0.0, 180.0),
               to = std::clamp(gamma_to_deg, 0.0, 180.0);
  if (!(to > from)) return 0.0;
  if (grid_.type == PhotometricType::A)
    return flux_ab(grid_, (from - 90.0) * kDeg, (to - 90.0) * kDeg);
  return scale_ * flux_c(grid_, from * kDeg, to * kDeg);
}

double zonal_flux_lm(const Distribution& d, double gamma_from_deg, double gamma_to_deg) {
  GONIO_CHECK_MSG(validate(d).ok(), "zonal_flux_lm needs a valid distribution");
  if (d.type != PhotometricType::B) {
    const double from = std::clamp(gamma_from_deg, 0.0, 180.0),
                 to = std::clamp(gamma_to_deg, 0.0, 180.0);
    if (!(to > from)) return 0.0;
    return d.type == PhotometricType::C ? flux_c(d, from * kDeg, to * kDeg)
                                        : flux_ab(d, (from - 90.0) * kDeg, (to - 90.0) * kDeg);
  }
  return ZonalFlux(d).zone_lm(gamma_from_deg, gamma_to_deg);
}

double downward_flux_lm(const Distribution& d) { return zonal_flux_lm(d, 0.0, 90.0); }
double upward_flux_lm(const Distribution& d) { return zonal_flux_lm(d, 90.0, 180.0); }

}  // namespace gonio::photometry
