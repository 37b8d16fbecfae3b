#include "sim/detectors/chi_square.h"

#include <cmath>
#include <limits>

#include "photometry/diagnostics.h"

namespace gonio::sim {
namespace {

constexpr int kMaxIterations = 1'000'000;
constexpr double kEps = 1e-15;

// log(e^{−x} x^a / Γ(a)), the common factor of both expansions.
double log_prefactor(double a, double x) { return a * std::log(x) - x - std::lgamma(a); }

// Lower regularised gamma P(a, x) by its power series; converges fast for x < a + 1.
double lower_by_series(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < kMaxIterations; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::abs(term) < std::abs(sum) * kEps) break;
  }
  return sum * std::exp(log_prefactor(a, x));
}

// Upper regularised gamma Q(a, x) by its continued fraction (modified Lentz);
// converges fast for x ≥ a + 1.
double upper_by_continued_fraction(double a, double x) {
  constexpr double tiny = std::numeric_limits<double>::min() / kEps;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < kMaxIterations; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kEps) break;
  }
  return std::exp(log_prefactor(a, x)) * h;
}

}  // namespace

double chi_square_upper_tail(double x, double dof) {
  GONIO_CHECK(dof > 0.0 && std::isfinite(dof) && !std::isnan(x));
  if (x <= 0.0) return 1.0;
  if (std::isinf(x)) return 0.0;
  const double a = 0.5 * dof, half_x = 0.5 * x;
  if (half_x < a + 1.0) return 1.0 - lower_by_series(a, half_x);
  return upper_by_continued_fraction(a, half_x);
}

}  // namespace gonio::sim
