// Volume scattering: the Henyey–Greenstein phase function and the sheet
// model (sim/bsdfs/slab.h) against closed forms — the unscattered beam
// through a Fresnel slab, single scattering in a thin slab, Chandrasekhar's
// H-function law for light leaving a thick conservative slab — energy
// conservation, and the datasheet fit against the values it was given.
#include "sim/bsdfs/volume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "sim/bsdfs/slab.h"
#include "sim/bsdfs/material.h"
#include "sim/samplers/sampling.h"
#include "tests/sim/bsdfs/lobe_checks.h"

namespace gonio::sim {
namespace {

using test::kDeg;
using test::kPi;

TEST(HenyeyGreenstein, NormalisedWithMeanCosineGAndSampledByItsDensity) {
  for (double g : {-0.5, 0.0, 0.3, 0.8, 0.95}) {
    // ∫ p dω and ∫ cos Θ p dω in μ = cos Θ (p depends on μ alone), fine
    // enough for the forward peak of g = 0.95.
    double norm = 0.0, mean = 0.0;
    const int steps = 400000;
    for (int k = 0; k < steps; ++k) {
      const double mu = -1.0 + (k + 0.5) * 2.0 / steps;
      norm += 2.0 * kPi * henyey_greenstein(g, mu) * 2.0 / steps;
      mean += 2.0 * kPi * mu * henyey_greenstein(g, mu) * 2.0 / steps;
    }
    EXPECT_NEAR(norm, 1.0, 1e-6) << g;
    EXPECT_NEAR(mean, g, 1e-6) << g;
    // Sampled directions: cos Θ in 40 bins of equal probability by the
    // closed-form CDF F(μ) = (1 − g²)/(2g) (1/√(1 + g² − 2gμ) − 1/(1 + g)),
    // and the azimuth about the direction of travel in 24 bins.
    const auto cdf = [g](double mu) {
      if (std::abs(g) < 1e-6) return 0.5 * (mu + 1.0);
      return (1.0 - g * g) / (2.0 * g) * (1.0 / std::sqrt(1.0 + g * g - 2.0 * g * mu) - 1.0 / (1.0 + g));
    };
    const Vec3 travel = normalize(Vec3{0.3, -0.5, 0.8});
    const Basis b = basis_from_normal(travel);
    const int n = 200000, nb = 40, na = 24;
    std::vector<double> bins(nb, 0.0), az(na, 0.0);
    for (int k = 0; k < n; ++k) {
      PhotonRandom rng(77, static_cast<std::uint64_t>(k));
      const Vec3 d = sample_henyey_greenstein(travel, g, rng);
      ASSERT_NEAR(length(d), 1.0, 1e-12);
      const Vec3 l = b.to_local(d);
      bins[static_cast<std::size_t>(std::clamp(static_cast<int>(cdf(l.z) * nb), 0, nb - 1))] += 1.0;
      double p = std::atan2(l.y, l.x);
      if (p < 0) p += 2 * kPi;
      az[static_cast<std::size_t>(std::clamp(static_cast<int>(p / (2 * kPi) * na), 0, na - 1))] += 1.0;
    }
    double chi = 0.0, chi_az = 0.0;
    for (double o : bins) chi += (o - n / double(nb)) * (o - n / double(nb)) / (n / double(nb));
    for (double o : az) chi_az += (o - n / double(na)) * (o - n / double(na)) / (n / double(na));
    EXPECT_GT(chi_square_upper_tail(chi, nb - 1), 1e-4) << g << ": chi2 " << chi;
    EXPECT_GT(chi_square_upper_tail(chi_az, na - 1), 1e-4) << g << ": azimuth chi2 " << chi_az;
  }
}

// The closed-form CDF of cos Θ under Henyey–Greenstein:
// F(μ) = (1 − g²)/(2g) (1/√(1 + g² − 2gμ) − 1/(1 + g)).
double henyey_greenstein_cdf(double g, double mu) {
  if (std::abs(g) < 1e-6) return 0.5 * (mu + 1.0);
  return (1.0 - g * g) / (2.0 * g) * (1.0 / std::sqrt(1.0 + g * g - 2.0 * g * mu) - 1.0 / (1.0 + g));
}

TEST(HenyeyGreenstein, OneDivisionInverseIsTheLibraryInverse) {
  // The tracer's cos Θ (one division) and sample_henyey_greenstein_cos (two)
  // are one inverse CDF written two ways: equal to rounding, and both
  // invert the closed-form CDF.
  for (double g : {-0.999, -0.8, -0.3, 0.0, 1e-7, 2e-6, 0.3, 0.8, 0.95, 0.999}) {
    for (int k = 0; k <= 1000; ++k) {
      const double u = k / 1000.0;
      const double a = henyey_greenstein_cos_of_ratio(g, u, 1.0), b = sample_henyey_greenstein_cos(g, u);
      // The same u as a ratio x/w (the tracer's rescaled uniform).
      ASSERT_NEAR(henyey_greenstein_cos_of_ratio(g, 1473.0 * u, 1473.0), a, 1e-12 + 1e-15 / std::max(std::abs(g), 1e-6));
      // (Both lose digits to cancellation as g → 0: ~10⁻¹⁶/g.)
      ASSERT_NEAR(a, b, 1e-12 + 1e-15 / std::max(std::abs(g), 1e-6)) << g << " " << u;
      ASSERT_GE(a, -1.0);
      ASSERT_LE(a, 1.0);
      // (|g| < 10⁻⁶ is drawn as uniform, cos Θ = 1 − 2u: F = 1 − u.)
      ASSERT_NEAR(henyey_greenstein_cdf(g, a), std::abs(g) < 1e-6 ? 1.0 - u : u, 1e-9) << g << " " << u;
    }
  }
}

// n volume events of scatter_or_absorb along `travel`: the share absorbed,
// and of the scattered ones cos Θ in 40 bins of equal probability by the
// closed-form CDF (chi-square), the largest distance of their empirical CDF
// from it (Kolmogorov–Smirnov), their mean cos Θ and the azimuth about
// `travel` in 24 bins (chi-square), and the two together in 8 × 8 cells
// (chi-square: independent).
struct EventStats {
  double absorbed = 0.0, chi_cos = 0.0, ks = 0.0, mean_cos = 0.0, chi_azimuth = 0.0, worst_length = 0.0;
  double chi_joint = 0.0;  // 8 × 8 cells of equal probability in (F(cos Θ), azimuth): independence
  int scattered = 0;
};
EventStats volume_events(const Vec3& travel, double mu_s, double mu_a, double g, int n, std::uint64_t seed) {
  const Basis b = basis_from_normal(travel);
  const int nb = 40, na = 24;
  std::vector<double> bins(nb, 0.0), az(na, 0.0), joint(64, 0.0), cdf_values;
  EventStats e;
  double sum = 0.0;
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(seed, static_cast<std::uint64_t>(k));
    Vec3 d;
    if (!scatter_or_absorb(travel, mu_s, mu_a, g, rng, &d)) {
      e.absorbed += 1.0;
      continue;
    }
    ++e.scattered;
    e.worst_length = std::max(e.worst_length, std::abs(length(d) - 1.0));
    const Vec3 l = b.to_local(d);
    const double f = henyey_greenstein_cdf(g, std::clamp(l.z, -1.0, 1.0));
    cdf_values.push_back(f);
    sum += l.z;
    bins[static_cast<std::size_t>(std::clamp(static_cast<int>(f * nb), 0, nb - 1))] += 1.0;
    double p = std::atan2(l.y, l.x);
    if (p < 0) p += 2 * kPi;
    az[static_cast<std::size_t>(std::clamp(static_cast<int>(p / (2 * kPi) * na), 0, na - 1))] += 1.0;
    joint[static_cast<std::size_t>(std::clamp(static_cast<int>(f * 8), 0, 7) * 8 +
                                   std::clamp(static_cast<int>(p / (2 * kPi) * 8), 0, 7))] += 1.0;
  }
  const double m = e.scattered;
  for (double o : joint) e.chi_joint += (o - m / 64) * (o - m / 64) / (m / 64);
  for (double o : bins) e.chi_cos += (o - m / nb) * (o - m / nb) / (m / nb);
  for (double o : az) e.chi_azimuth += (o - m / na) * (o - m / na) / (m / na);
  std::sort(cdf_values.begin(), cdf_values.end());
  for (std::size_t i = 0; i < cdf_values.size(); ++i)
    e.ks = std::max({e.ks, std::abs(cdf_values[i] - i / m), std::abs(cdf_values[i] - (i + 1) / m)});
  e.mean_cos = sum / m;
  e.absorbed /= n;
  return e;
}

TEST(HenyeyGreenstein, OneDrawEventHasTheDensityTheMeanCosineAndAUniformAzimuth) {
  // The tracer's volume event (one draw: absorption, cos Θ and azimuth)
  // against the closed forms, for forward, backward, isotropic and very
  // peaked phase functions and directions of travel along and against the
  // poles of the basis (Duff et al.'s basis changes branch at z = 0).
  const int n = 200000;
  std::uint64_t seed = 90;
  for (double g : {0.0, 0.8, -0.8, 0.95, 0.999}) {
    for (const Vec3& travel : {normalize(Vec3{0.3, -0.5, 0.8}), Vec3{0, 0, -1}, Vec3{1, 0, 0}, normalize(Vec3{0.2, 0.1, -0.97})}) {
      const EventStats e = volume_events(travel, 1000.0, 0.0, g, n, ++seed);
      // Var cos Θ = (1 + 2g²)/3 − g² = (1 − g²)/3 (the second Legendre
      // moment of Henyey–Greenstein is g²).
      const double sigma = std::sqrt((1.0 - g * g) / 3.0 / n);
      std::printf("  g %6.3f travel (%5.2f %5.2f %5.2f): mean cos %.5f (sigma %.1e), chi2 cos %.1f, KS %.5f, chi2 azimuth %.1f, joint %.1f\n",
                  g, travel.x, travel.y, travel.z, e.mean_cos, sigma, e.chi_cos, e.ks, e.chi_azimuth, e.chi_joint);
      EXPECT_EQ(e.absorbed, 0.0);
      EXPECT_NEAR(e.mean_cos, g, 5.0 * sigma) << g;
      EXPECT_GT(chi_square_upper_tail(e.chi_cos, 39), 1e-4) << g << ": chi2 " << e.chi_cos;
      EXPECT_LT(e.ks, 2.23 / std::sqrt(n)) << g;  // p = 10⁻⁴, as the chi-squares
      EXPECT_GT(chi_square_upper_tail(e.chi_azimuth, 23), 1e-4) << g << ": azimuth chi2 " << e.chi_azimuth;
      EXPECT_GT(chi_square_upper_tail(e.chi_joint, 63), 1e-4) << g << ": joint chi2 " << e.chi_joint;
      EXPECT_LT(e.worst_length, 1e-15) << g;
    }
  }
}

TEST(HenyeyGreenstein, OneDrawEventAbsorbsWithChanceMuAOverMuTIndependentlyOfTheDirection) {
  // Half absorbed: the scattered half must still be Henyey–Greenstein (the
  // uniform that decided is rescaled, not reused as it is); the opal PMMA
  // preset's μs 1473/m, μa 2.9/m: absorbed with chance 0.001965.
  const int n = 200000;
  const Vec3 travel = normalize(Vec3{-0.4, 0.7, 0.2});
  for (double g : {0.0, 0.8, 0.999}) {
    const EventStats e = volume_events(travel, 1.0, 1.0, g, n, 5);
    EXPECT_NEAR(e.absorbed, 0.5, 5.0 * std::sqrt(0.25 / n)) << g;
    EXPECT_NEAR(e.mean_cos, g, 5.0 * std::sqrt((1.0 - g * g) / 3.0 / e.scattered)) << g;
    EXPECT_GT(chi_square_upper_tail(e.chi_cos, 39), 1e-4) << g << ": chi2 " << e.chi_cos;
    EXPECT_LT(e.ks, 2.23 / std::sqrt(e.scattered)) << g;
    EXPECT_GT(chi_square_upper_tail(e.chi_azimuth, 23), 1e-4) << g << ": azimuth chi2 " << e.chi_azimuth;
    EXPECT_GT(chi_square_upper_tail(e.chi_joint, 63), 1e-4) << g << ": joint chi2 " << e.chi_joint;
  }
  const double p = 2.9 / (1473.0 + 2.9);
  const EventStats opal = volume_events(travel, 1473.0, 2.9, 0.8, 1000000, 6);
  std::printf("  opal PMMA: absorbed %.6f of the events (mu_a/mu_t %.6f)\n", opal.absorbed, p);
  EXPECT_NEAR(opal.absorbed, p, 5.0 * std::sqrt(p * (1 - p) / 1000000));
}

TEST(HenyeyGreenstein, OneDrawEventStaysUnitOverTheLongestWalk) {
  // 100,000 events in a row (the tracer's kMaxVolumeEvents): one Newton step
  // a event keeps the direction unit to rounding; no drift.
  Vec3 d = normalize(Vec3{0.3, -0.5, 0.8});
  PhotonRandom rng(3, 4);
  double worst = 0.0;
  for (int k = 0; k < 100000; ++k) {
    Vec3 next;
    ASSERT_TRUE(scatter_or_absorb(d, 1.0, 0.0, 0.9, rng, &next));
    d = next;
    worst = std::max(worst, std::abs(length(d) - 1.0));
  }
  EXPECT_LT(worst, 1e-15);
  // A direction off unit length by 10⁻⁸ (a float-rounded normal, say)
  // comes back unit to rounding: the Newton step squares the error.
  PhotonRandom r2(3, 5);
  Vec3 next;
  ASSERT_TRUE(scatter_or_absorb(normalize(Vec3{0.3, -0.5, 0.8}) * (1.0 + 1e-8), 1.0, 0.0, 0.9, r2, &next));
  EXPECT_LT(std::abs(length(next) - 1.0), 1e-15);
}

TEST(FreePath, ZigguratIsTheExponentialDistribution) {
  // 10⁶ draws of standard_exponential against F(x) = 1 − e^−x: 64 bins of
  // equal probability (chi-square), Kolmogorov–Smirnov, the mean and the
  // variance (1 and 1), and the tail beyond the ziggurat's base r = 7.697
  // and beyond 12 (e^−7.697 = 4.54·10⁻⁴, e^−12 = 6.1·10⁻⁶ of the draws).
  const int n = 1000000, nb = 64;
  std::vector<double> x;
  x.reserve(n);
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(11, static_cast<std::uint64_t>(k));
    x.push_back(standard_exponential(rng));
    ASSERT_GE(x.back(), 0.0);
  }
  std::vector<double> bins(nb, 0.0);
  double sum = 0.0, sum2 = 0.0, beyond_r = 0.0, beyond_12 = 0.0;
  for (double v : x) {
    const double f = 1.0 - std::exp(-v);
    bins[static_cast<std::size_t>(std::clamp(static_cast<int>(f * nb), 0, nb - 1))] += 1.0;
    sum += v;
    sum2 += v * v;
    beyond_r += v > 7.69711747013104972 ? 1.0 : 0.0;
    beyond_12 += v > 12.0 ? 1.0 : 0.0;
  }
  double chi = 0.0;
  for (double o : bins) chi += (o - n / double(nb)) * (o - n / double(nb)) / (n / double(nb));
  std::sort(x.begin(), x.end());
  double ks = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double f = 1.0 - std::exp(-x[i]);
    ks = std::max({ks, std::abs(f - double(i) / n), std::abs(f - double(i + 1) / n)});
  }
  const double mean = sum / n, variance = sum2 / n - mean * mean;
  std::printf("  ziggurat: mean %.5f variance %.5f chi2 %.1f (63 dof) KS*sqrt(n) %.3f beyond r %.0f (%.0f) beyond 12 %.0f (%.1f)\n",
              mean, variance, chi, ks * std::sqrt(double(n)), beyond_r, n * std::exp(-7.69711747013104972), beyond_12,
              n * std::exp(-12.0));
  EXPECT_GT(chi_square_upper_tail(chi, nb - 1), 1e-4) << chi;
  EXPECT_LT(ks, 2.23 / std::sqrt(double(n)));
  EXPECT_NEAR(mean, 1.0, 5.0 / std::sqrt(double(n)));
  EXPECT_NEAR(variance, 1.0, 5.0 * std::sqrt(8.0 / n));  // Var of s² = (μ₄ − σ⁴)/n = 8/n
  const double pr = std::exp(-7.69711747013104972);
  EXPECT_NEAR(beyond_r, n * pr, 5.0 * std::sqrt(n * pr));
  EXPECT_NEAR(beyond_12, n * std::exp(-12.0), 5.0 * std::sqrt(n * std::exp(-12.0)) + 1.0);
  // The wedges in detail: the layers' edges lie where the density changes
  // fastest relative to the bins above; 400 bins of width 0.02 on [0, 8)
  // against their exact probabilities.
  std::vector<double> fine(400, 0.0);
  for (double v : x)
    if (v < 8.0) fine[static_cast<std::size_t>(v / 0.02)] += 1.0;
  double chi_fine = 0.0;
  for (int b = 0; b < 400; ++b) {
    const double e = n * (std::exp(-0.02 * b) - std::exp(-0.02 * (b + 1)));
    chi_fine += (fine[static_cast<std::size_t>(b)] - e) * (fine[static_cast<std::size_t>(b)] - e) / e;
  }
  EXPECT_GT(chi_square_upper_tail(chi_fine, 399), 1e-4) << chi_fine;
}

TEST(FreePath, LowDiscrepancyDrawsInvertOneUniform) {
  // Under the Sobol' sampler the free path is −ln u of one coordinate (a
  // fixed count of draws keeps the sequence's dimensions aligned).
  for (std::uint64_t photon = 0; photon < 64; ++photon) {
    PhotonRandom a(5, photon, SamplerKind::Sobol), b(5, photon, SamplerKind::Sobol);
    ASSERT_TRUE(a.low_discrepancy());
    EXPECT_EQ(standard_exponential(a), -std::log(b.uniform_open0()));
    EXPECT_EQ(a.dimensions(), 1);
  }
}

TEST(Slab, UnscatteredBeamFollowsTheFresnelSlabFormula) {
  // T = (1 − R)² τ / (1 − R² τ²), τ = exp(−μt d) (VALIDATION.md's absorbing
  // slab, with μt = μs + μa), R the normal-incidence Fresnel reflectance.
  SlabMedium m;
  m.scattering_per_m = 200.0;
  m.absorption_per_m = 50.0;
  m.thickness_m = 0.002;
  m.ior = 1.5;
  const SlabOptics o = slab_optics(m, 0.0, 400000, 3);
  const double r = 0.04, tau = std::exp(-250.0 * 0.002);
  const double expected = (1 - r) * (1 - r) * tau / (1 - r * r * tau * tau);
  EXPECT_NEAR(o.unscattered, expected, 5.0 * std::sqrt(expected / 400000));
}

TEST(Slab, ThinSlabIsSingleScattering) {
  // Index-matched (n = 1), optical depth τ = 0.02, no absorption: the light
  // scattered once into exit cosine μ > 0 is, per dμ,
  //   F(μ) = 2π p(μ) μ (e^{−τ/μ} − e^{−τ}) / (μ − 1),
  // and double scattering adds O(τ²) = 4·10⁻⁴ of the beam.
  SlabMedium m;
  m.scattering_per_m = 10.0;
  m.thickness_m = 0.002;
  m.ior = 1.0;
  m.g = 0.6;
  const double tau = 0.02;
  const SlabOptics o = slab_optics(m, 0.0, 2000000, 5);
  EXPECT_NEAR(o.unscattered, std::exp(-tau), 5.0 * std::sqrt(std::exp(-tau) * (1 - std::exp(-tau)) / 2e6));
  // Scattered and transmitted, in total: ∫_0^1 F dμ.
  double single = 0.0;
  const int steps = 20000;
  for (int k = 0; k < steps; ++k) {
    const double mu = (k + 0.5) / steps;
    single += 2 * kPi * henyey_greenstein(0.6, mu) * mu * (std::exp(-tau / mu) - std::exp(-tau)) / (mu - 1.0) / steps;
  }
  const double scattered = o.transmittance - o.unscattered;
  std::printf("  thin slab: scattered and transmitted %.6f, single scattering %.6f\n", scattered, single);
  EXPECT_NEAR(scattered, single, 0.03 * single);
  EXPECT_NEAR(o.transmittance + o.reflectance, 1.0, 1e-12);  // nothing absorbed, nothing lost
}

// Chandrasekhar's H-function for conservative isotropic scattering,
// H(μ) = 1 / (1 − (μ/2) ∫_0^1 H(μ')/(μ + μ') dμ'), iterated on a Gauss grid.
double chandrasekhar_h(double mu) {
  static std::vector<double> x, w, h;
  if (h.empty()) {
    const int n = 64;
    for (int i = 0; i < n; ++i) {  // midpoint in μ' = s²: dense near 0
      const double s = (i + 0.5) / n;
      x.push_back(s * s);
      w.push_back(2.0 * s / n);
    }
    h.assign(x.size(), 1.0);
    for (int it = 0; it < 5000; ++it) {
      std::vector<double> next(h.size());
      for (std::size_t i = 0; i < x.size(); ++i) {
        double sum = 0.0;
        for (std::size_t j = 0; j < x.size(); ++j) sum += w[j] * h[j] / (x[i] + x[j]);
        next[i] = 1.0 / (1.0 - 0.5 * x[i] * sum);
      }
      h = next;
    }
  }
  double sum = 0.0;
  for (std::size_t j = 0; j < x.size(); ++j) sum += w[j] * h[j] / (mu + x[j]);
  return 1.0 / (1.0 - 0.5 * mu * sum);
}

TEST(Slab, ThickConservativeSlabFollowsChandrasekharsLaw) {
  // Light leaving a thick, non-absorbing, isotropically scattering slab
  // (index-matched) has the Milne problem's radiance law L(μ)/L(1) =
  // H(μ)/H(1); Chandrasekhar (Radiative Transfer, 1950, Table XIII) gives
  // H(1) = 2.9078, so L(0)/L(1) = 0.3439. Intensity ∝ μ H(μ).
  EXPECT_NEAR(chandrasekhar_h(1.0), 2.9078, 2e-3);
  EXPECT_NEAR(chandrasekhar_h(0.0), 1.0, 1e-12);
  SlabMedium m;
  m.scattering_per_m = 10000.0;  // τ = 20
  m.thickness_m = 0.002;
  m.ior = 1.0;
  m.g = 0.0;
  const SlabOptics o = slab_optics(m, 0.0, 1000000, 9);
  EXPECT_NEAR(o.transmittance + o.reflectance, 1.0, 1e-12);
  // The transmitted flux in six zones of 12.5° from the normal (0–75°),
  // each as a share of all six, against ∫ μ H(μ) dω over the zone
  // (2.5°-bins: intensity × solid angle; noise ~0.5 % per zone).
  double measured[6] = {}, expected[6] = {}, m_sum = 0.0, e_sum = 0.0;
  for (int k = 0; k < 30; ++k) {
    const double a = k * 2.5 * kDeg, b = (k + 1) * 2.5 * kDeg;
    const double omega = 2.0 * kPi * (std::cos(a) - std::cos(b));
    measured[k / 5] += o.relative_intensity[static_cast<std::size_t>(k)] * omega;
    for (int j = 0; j < 50; ++j) {
      const double t = a + (j + 0.5) * (b - a) / 50;
      expected[k / 5] += std::cos(t) * chandrasekhar_h(std::cos(t)) * 2.0 * kPi * std::sin(t) * (b - a) / 50;
    }
  }
  for (int z = 0; z < 6; ++z) {
    m_sum += measured[z];
    e_sum += expected[z];
  }
  double worst = 0.0;
  for (int z = 0; z < 6; ++z) {
    std::printf("    %4.1f-%4.1f deg: %.4f of the flux, mu H(mu) gives %.4f\n", 12.5 * z, 12.5 * (z + 1),
                measured[z] / m_sum, expected[z] / e_sum);
    worst = std::max(worst, std::abs(measured[z] / m_sum - expected[z] / e_sum) / (expected[z] / e_sum));
  }
  std::printf("  thick slab: worst relative difference %.4f; half-value angle %.2f deg\n", worst, o.half_value_deg);
  EXPECT_LT(worst, 0.02);
}

TEST(Slab, SheetBsdfHoldsTheSheetModelsReflectanceAndTransmittance) {
  // Two Monte Carlos of one medium — the tabulated sheet (3-D directions,
  // binned) and the sheet model (1-D): the table's albedos at normal and at
  // 60° incidence must be the sheet model's R and T, and its transmission
  // must peak in the straight-through patch for a forward-scattering sheet.
  SlabMedium m;
  m.scattering_per_m = 800.0;
  m.absorption_per_m = 20.0;
  m.g = 0.9;
  m.ior = 1.49;
  m.thickness_m = 0.002;
  const TabulatedBsdf t = sheet_bsdf(m, 40000, 4);
  for (double theta : {0.0, 60.0}) {
    const SlabOptics o = slab_optics(m, theta, 100000, 6);
    const Vec3 wi = test::incident(theta, 30.0);
    double r = 0.0, tr = 0.0;
    t.albedo(true, wi, &r, &tr);
    std::printf("  sheet table at %2.0f deg: R %.4f T %.4f; sheet model R %.4f T %.4f\n", theta, r, tr, o.reflectance,
                o.transmittance);
    EXPECT_NEAR(r, o.reflectance, 0.01) << theta;
    EXPECT_NEAR(tr, o.transmittance, 0.01) << theta;
  }
  const Vec3 wi = test::incident(30.0, 30.0);
  const double through = t.evaluate(true, wi, Vec3{-wi.x, -wi.y, -wi.z});
  const double sideways = t.evaluate(true, wi, Vec3{wi.x, wi.y, -wi.z});
  EXPECT_GT(through, 3.0 * sideways);
}

TEST(Slab, FitReturnsTheDatasheetValuesItWasGiven) {
  // Round trip: a medium's optics, fitted, give a medium with the same
  // optics (transmittance and haze; transmittance and half-value angle).
  SlabMedium truth;
  truth.scattering_per_m = 3000.0;
  truth.absorption_per_m = 20.0;
  truth.g = 0.8;
  truth.thickness_m = 0.002;
  const SlabOptics o = slab_optics(truth, 0.0, 20000, 2);
  VolumeDatasheet sheet;
  sheet.transmittance = o.transmittance;
  sheet.half_value_deg = o.half_value_deg;
  sheet.thickness_m = truth.thickness_m;
  Result<SlabMedium> fit = fit_volume(sheet, 20000, 2);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  std::printf("  fit: mus %.1f (%.1f) /m, mua %.2f (%.2f) /m\n", fit->scattering_per_m, truth.scattering_per_m,
              fit->absorption_per_m, truth.absorption_per_m);
  const SlabOptics back = slab_optics(*fit, 0.0, 20000, 2);
  EXPECT_NEAR(back.transmittance, o.transmittance, 2e-3);
  EXPECT_NEAR(back.half_value_deg, o.half_value_deg, 1.0);
  // A weak diffuser by its haze.
  SlabMedium weak = truth;
  weak.scattering_per_m = 300.0;
  weak.absorption_per_m = 5.0;
  const SlabOptics w = slab_optics(weak, 0.0, 20000, 2);
  VolumeDatasheet hazy;
  hazy.transmittance = w.transmittance;
  hazy.haze = w.haze;
  hazy.thickness_m = weak.thickness_m;
  fit = fit_volume(hazy, 20000, 2);
  ASSERT_TRUE(fit.ok()) << fit.error().message;
  EXPECT_NEAR(fit->scattering_per_m, 300.0, 15.0);
  EXPECT_NEAR(fit->absorption_per_m, 5.0, 3.0);
  // Out of reach: a transmittance above what two Fresnel faces let through.
  hazy.transmittance = 0.97;
  EXPECT_FALSE(fit_volume(hazy, 2000, 2).ok());
  hazy.haze = -1.0;
  EXPECT_FALSE(fit_volume(hazy, 2000, 2).ok());  // neither haze nor angle
}

}  // namespace
}  // namespace gonio::sim
