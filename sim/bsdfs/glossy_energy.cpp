#include "sim/bsdfs/glossy_energy.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include <tbb/parallel_for.h>

#include "sim/bsdfs/material.h"
#include "sim/bsdfs/table_cache.h"
#include "sim/samplers/sampling.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

double GlossyEnergy::at(double mu) const {
  const double x = std::clamp(mu, 0.0, 1.0) * kEnergyBins;
  const int k = std::min(kEnergyBins - 1, static_cast<int>(x));
  const double f = x - k;
  return (1.0 - f) * e[static_cast<std::size_t>(k)] + f * e[static_cast<std::size_t>(k + 1)];
}

double glossy_single_albedo(double mx, double my, double f0, const Vec3& wi, int n) {
  if (!(wi.z > 0.0)) return 0.0;
  // f cos θo dωo = F D G2 (wi·h) / (wi·n) dωh, and Walter's slopes (P, Q)
  // are Gaussian with density D(h) cos θh dωh: the integrand per slope is
  // F G2 (wi·h) / ((wi·n)(h·n)), over (u, v) ∈ [0, 1]² mapped to
  // r = √(−ln u), angle 2πv.
  const double lambda_i = beckmann_lambda(mx, my, wi);
  if (!std::isfinite(lambda_i)) return 0.0;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double u = (i + 0.5) / n;
    const double r = std::sqrt(-std::log(u));
    for (int j = 0; j < n; ++j) {
      double s, c;
      sincos_turn((j + 0.5) / n, &s, &c);
      const Vec3 hu{mx * r * c, my * r * s, 1.0};
      const double inv = 1.0 / length(hu);
      const Vec3 h = hu * inv;
      const double ih = dot(wi, h);
      if (!(ih > 0.0)) continue;
      const Vec3 wo = 2.0 * ih * h - wi;
      if (!(wo.z > 0.0)) continue;
      const double g2 = 1.0 / (1.0 + lambda_i + beckmann_lambda(mx, my, wo));
      sum += schlick_fresnel(f0, ih) * g2 * ih / (wi.z * h.z);
    }
  }
  return sum / (static_cast<double>(n) * n);
}

namespace {

// ∫_a^b μ E(μ) dμ over one bin of the piecewise-linear table.
double bin_moment(const GlossyEnergy& t, int k) {
  const double a = static_cast<double>(k) / kEnergyBins, b = static_cast<double>(k + 1) / kEnergyBins;
  const double e0 = t.e[static_cast<std::size_t>(k)];
  const double s = (t.e[static_cast<std::size_t>(k + 1)] - e0) * kEnergyBins;
  return e0 * (b * b - a * a) / 2.0 + s * ((b * b * b - a * a * a) / 3.0 - a * (b * b - a * a) / 2.0);
}

// e_avg and cdf from the nodes e.
void finish_table(GlossyEnergy* t) {
  double e_avg = 0.0, c = 0.0;
  for (int k = 0; k < kEnergyBins; ++k) {
    const double lo = static_cast<double>(k) / kEnergyBins, hi = static_cast<double>(k + 1) / kEnergyBins;
    const double m = bin_moment(*t, k);
    e_avg += 2.0 * m;
    c += (hi * hi - lo * lo) / 2.0 - m;
    t->cdf[static_cast<std::size_t>(k)] = c;
  }
  t->e_avg = std::min(1.0, e_avg);
  if (c > 0.0)
    for (double& v : t->cdf) v /= c;
}

}  // namespace

std::shared_ptr<const GlossyEnergy> build_glossy_energy(double mx, double my) {
  auto t = std::make_shared<GlossyEnergy>();
  t->mx = mx;
  t->my = my;
  // Beckmann is symmetric under x → −x and y → −y: azimuths in [0, π/2]
  // cover all; an isotropic lobe needs one.
  const int azimuths = mx == my ? 1 : 8;
  // The bins in parallel (each its own sum: the same table for any thread
  // count). A 128² quadrature per bin: ~0.25 s for one table on one loaded
  // core, which the first preview of `gonio watch` waited for (issue 43).
  tbb::parallel_for(0, kEnergyBins + 1, [&](int k) {
    const double mu = k == 0 ? 1e-4 : static_cast<double>(k) / kEnergyBins;
    const double s = std::sqrt(1.0 - mu * mu);
    double e = 0.0;
    for (int a = 0; a < azimuths; ++a) {
      const double phi = (a + 0.5) / azimuths * (kPi / 2.0);
      e += glossy_single_albedo(mx, my, 1.0, Vec3{s * std::cos(phi), s * std::sin(phi), mu});
    }
    t->e[static_cast<std::size_t>(k)] = std::clamp(e / azimuths, 0.0, 1.0);
  });
  finish_table(t.get());
  return t;
}

std::shared_ptr<const GlossyEnergy> glossy_energy_from_nodes(double mx, double my,
                                                            const std::array<double, kEnergyBins + 1>& e) {
  if (!(std::isfinite(mx) && mx > 0.0 && std::isfinite(my) && my > 0.0)) return nullptr;
  for (double v : e)
    if (!(v >= 0.0 && v <= 1.0)) return nullptr;
  auto t = std::make_shared<GlossyEnergy>();
  t->mx = mx;
  t->my = my;
  t->e = e;
  finish_table(t.get());
  return t;
}

std::shared_ptr<const GlossyEnergy> offer_glossy_energy(std::shared_ptr<const GlossyEnergy> table) {
  const std::pair<double, double> key{table->mx, table->my};
  return cached_table<GlossyEnergy>(key, [&](double, double) { return std::move(table); });
}

std::shared_ptr<const GlossyEnergy> glossy_energy(double mx, double my) {
  return cached_table<GlossyEnergy>({mx, my}, build_glossy_energy);
}

double multiple_scattering_factor(double f0, double e_avg) {
  const double f_avg = f0 + (1.0 - f0) / 21.0;
  const double d = 1.0 - f_avg * (1.0 - e_avg);
  return d > 0.0 ? f_avg * f_avg * e_avg / d : 0.0;
}

double glossy_ms_evaluate(const GlossyEnergy& t, double kappa, const Vec3& wi, const Vec3& wo) {
  if (!(wi.z > 0.0) || !(wo.z > 0.0) || !(t.e_avg < 1.0)) return 0.0;
  return kappa * (1.0 - t.at(wi.z)) * (1.0 - t.at(wo.z)) * wo.z / (kPi * (1.0 - t.e_avg));
}

double glossy_ms_pdf(const GlossyEnergy& t, const Vec3& wo) {
  if (!(wo.z > 0.0) || !(t.e_avg < 1.0)) return 0.0;
  return (1.0 - t.at(wo.z)) * wo.z / (kPi * (1.0 - t.e_avg));
}

Vec3 sample_glossy_ms(const GlossyEnergy& t, PhotonRandom& rng) {
  const double u = rng.uniform();
  int k = 0;
  while (k < kEnergyBins - 1 && u >= t.cdf[static_cast<std::size_t>(k)]) ++k;
  const double lo = static_cast<double>(k) / kEnergyBins, hi = static_cast<double>(k + 1) / kEnergyBins;
  const double top = 1.0 - std::min(t.e[static_cast<std::size_t>(k)], t.e[static_cast<std::size_t>(k + 1)]);
  double mu = hi;
  for (int tries = 0; tries < 64; ++tries) {
    mu = std::sqrt(lo * lo + rng.uniform() * (hi * hi - lo * lo));
    if (rng.uniform() * top < 1.0 - t.at(mu)) break;
  }
  double c, s;
  sample_unit_circle(rng, &c, &s);
  const double r = std::sqrt(std::max(0.0, 1.0 - mu * mu));
  return {r * c, r * s, mu};
}

}  // namespace gonio::sim
