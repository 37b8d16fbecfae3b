#include "sim/bsdfs/abg.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "sim/bsdfs/abg_integral.h"
#include "sim/bsdfs/table_cache.h"
#include "sim/samplers/sampling.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kIntervals = 512;
constexpr double kMaxRadius = 2.0;

// ∫_a^b ρ k(ρ) dρ by composite Simpson (8 panels).
double simpson(const AbgTable& t, double a, double b) {
  const int n = 8;
  const double h = (b - a) / n;
  double s = a * t.kernel(a) + b * t.kernel(b);
  for (int i = 1; i < n; ++i) {
    const double x = a + i * h;
    s += (i % 2 ? 4.0 : 2.0) * x * t.kernel(x);
  }
  return s * h / 3.0;
}

std::shared_ptr<const AbgTable> build(double b, double g) {
  auto t = std::make_shared<AbgTable>();
  t->b = b;
  t->g = g;
  // The core is ~B^(1/g) wide: log-spaced bounds from far inside it to 2.
  const double core = g > 0.0 ? std::pow(b, 1.0 / g) : 1.0;
  const double first = std::clamp(1e-3 * core, 1e-12, 1e-3);
  t->r.push_back(0.0);
  for (int i = 0; i < kIntervals; ++i)
    t->r.push_back(first * std::pow(kMaxRadius / first, static_cast<double>(i) / (kIntervals - 1)));
  t->r.back() = kMaxRadius;
  // r k(r) rises to r* = (B/(g − 1))^(1/g) (g > 1) and falls beyond; each
  // interval's bound is its larger end, or r* inside it.
  const double peak = g > 1.0 ? std::pow(b / (g - 1.0), 1.0 / g) : kMaxRadius;
  double total = 0.0, mass = 0.0;
  t->mass.push_back(0.0);
  for (std::size_t i = 0; i + 1 < t->r.size(); ++i) {
    const double lo = t->r[i], hi = t->r[i + 1];
    double m = std::max(lo * t->kernel(lo), hi * t->kernel(hi));
    if (peak > lo && peak < hi) m = std::max(m, peak * t->kernel(peak));
    t->bound.push_back(m);
    total += m * (hi - lo);
    t->cdf.push_back(total);
    mass += simpson(*t, lo, hi);
    t->mass.push_back(mass);
  }
  for (double& c : t->cdf) c /= total;
  t->i0 = abg_i0(b, g);
  // Albedo over |β0|: ∫ K(R(φ)) dφ with R(φ) the distance from β0 to the
  // unit circle along angle φ (from β0's own direction).
  const int steps = 1024;
  for (int k = 0; k <= 64; ++k) {
    const double b0 = k / 64.0;
    double sum = 0.0;
    for (int j = 0; j < steps; ++j) {
      const double phi = (j + 0.5) * 2.0 * kPi / steps;
      const double c = std::cos(phi), s = std::sin(phi);
      const double radius = -b0 * c + std::sqrt(std::max(0.0, 1.0 - b0 * b0 * s * s));
      sum += t->radial_mass(radius);
    }
    t->albedo[static_cast<std::size_t>(k)] = sum * (2.0 * kPi / steps) / t->i0;
  }
  return t;
}

}  // namespace

double AbgTable::kernel(double dist) const { return 1.0 / (b + (g == 0.0 ? 1.0 : std::pow(dist, g))); }

double AbgTable::radial_mass(double radius) const {
  radius = std::clamp(radius, 0.0, kMaxRadius);
  const auto it = std::upper_bound(r.begin(), r.end(), radius);
  const std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - r.begin())) - 1;
  if (i + 1 >= r.size()) return mass.back();
  return mass[i] + simpson(*this, r[i], radius);
}

double AbgTable::albedo_at(double beta0) const {
  const double x = std::clamp(beta0, 0.0, 1.0) * 64.0;
  const int k = std::min(63, static_cast<int>(x));
  const double f = x - k;
  return (1.0 - f) * albedo[static_cast<std::size_t>(k)] + f * albedo[static_cast<std::size_t>(k + 1)];
}

bool abg_parameters_valid(double b, double g) {
  return std::isfinite(b) && b > 0.0 && std::isfinite(g) && g >= 0.0 && g <= 6.0;
}

std::shared_ptr<const AbgTable> abg_table(double b, double g) {
  return cached_table<AbgTable>({b, g}, build);
}

double abg_a_from_tis(double tis, double b, double g) { return tis / abg_table(b, g)->i0; }
double abg_tis_from_a(double a, double b, double g) { return a * abg_table(b, g)->i0; }

double abg_evaluate(const AbgTable& t, bool transmit, const Vec3& wi, const Vec3& wo) {
  if (!(wi.z > 0.0) || (transmit ? !(wo.z < 0.0) : !(wo.z > 0.0))) return 0.0;
  const double dx = wo.x + wi.x, dy = wo.y + wi.y;
  return t.kernel(std::sqrt(dx * dx + dy * dy)) / t.i0 * std::abs(wo.z);
}

double abg_albedo(const AbgTable& t, const Vec3& wi) {
  if (!(wi.z > 0.0)) return 0.0;
  return t.albedo_at(std::sqrt(wi.x * wi.x + wi.y * wi.y));
}

double abg_pdf(const AbgTable& t, bool transmit, const Vec3& wi, const Vec3& wo) {
  const double a = abg_albedo(t, wi);
  return a > 0.0 ? abg_evaluate(t, transmit, wi, wo) / a : 0.0;
}

Vec3 sample_abg(const AbgTable& t, bool transmit, const Vec3& wi, PhotonRandom& rng) {
  const double bx = -wi.x, by = -wi.y;
  for (int tries = 0; tries < 4096; ++tries) {
    const double u = rng.uniform();
    const auto i = static_cast<std::size_t>(std::upper_bound(t.cdf.begin(), t.cdf.end(), u) - t.cdf.begin());
    if (i >= t.bound.size()) continue;
    const double r = t.r[i] + rng.uniform() * (t.r[i + 1] - t.r[i]);
    if (rng.uniform() * t.bound[i] >= r * t.kernel(r)) continue;
    double c, s;
    sample_unit_circle(rng, &c, &s);
    const double x = bx + r * c, y = by + r * s;
    const double q = x * x + y * y;
    if (!(q < 1.0)) continue;
    const double z = std::sqrt(1.0 - q);
    return {x, y, transmit ? -z : z};
  }
  return {};
}

}  // namespace gonio::sim
