#include "photometry/flux.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "photometry/angles.h"
#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_c;
using test::sample_direction;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

double rel(double value, double expected) { return std::abs(value / expected - 1.0); }

Distribution lobe_c(double n, double c_step, double gamma_step, Symmetry sym = Symmetry::None) {
  const double c_to = sym == Symmetry::Quadrant ? 90 : sym == Symmetry::C0_C180 ? 180 : 360;
  return sample_direction(
      PhotometricType::C, sym,
      sym == Symmetry::Rotational ? std::vector<double>{0} : angles(0, c_to, c_step),
      angles(0, 180, gamma_step), cos_lobe(1000.0, n));
}

TEST(Flux, IsotropicIsExact) {
  for (double step : {30.0, 10.0, 5.0, 2.5}) {
    const Distribution d = sample_c(Symmetry::None, angles(0, 360, 15), angles(0, 180, step),
                                    [](double, double) { return 795.77; });
    EXPECT_NEAR(total_flux_lm(d), 4 * kPi * 795.77, 1e-9) << step;
  }
  // 10 000 lm <-> 795.77 cd (VALIDATION.md).
  const Distribution r = sample_c(Symmetry::Rotational, {0}, angles(0, 180, 5),
                                  [](double, double) { return 10000.0 / (4 * kPi); });
  EXPECT_NEAR(total_flux_lm(r), 10000.0, 1e-8);
}

TEST(Flux, LambertianLowerHemisphere) {
  // Φ = π I₀ (10 000 lm <-> 3183.1 cd), whether the file stops at 90° or
  // carries the dark upper hemisphere: the kink at the horizon costs nothing.
  const double i0 = 10000.0 / kPi;
  for (double step : {5.0, 2.5}) {
    const Distribution half = sample_c(Symmetry::Rotational, {0}, angles(0, 90, step),
                                       [&](double, double g) { return i0 * std::cos(g * kDeg); });
    const Distribution full = sample_direction(PhotometricType::C, Symmetry::Rotational, {0},
                                               angles(0, 180, step), cos_lobe(i0, 1));
    EXPECT_LT(rel(total_flux_lm(half), 10000.0), 1e-5) << step;
    EXPECT_LT(rel(total_flux_lm(full), 10000.0), 1e-5) << step;
  }
}

TEST(Flux, CosineLobesMeetTheClosedFormOnTheStandardGrid) {
  // Φ = 2π I₀ / (n + 1) to within 0.1 % on a 5° (C) × 2.5° (γ) grid; the rule
  // does far better (flux.h's table).
  const double bound[] = {1e-6, 1e-6, 3e-6, 1e-5, 3e-5};
  const double ns[] = {1, 2, 5, 10, 20};
  for (int i = 0; i < 5; ++i) {
    const double n = ns[i];
    const double exact = 2 * kPi * 1000.0 / (n + 1);
    const double err = rel(total_flux_lm(lobe_c(n, 5, 2.5)), exact);
    EXPECT_LT(err, 1e-3) << "n " << n;
    EXPECT_LT(err, bound[i]) << "n " << n;
  }
}

TEST(Flux, ErrorFallsWithTheStepAtFourthOrder) {
  for (double n : {2.0, 5.0, 10.0, 20.0}) {
    const double exact = 2 * kPi * 1000.0 / (n + 1);
    const double e10 = rel(total_flux_lm(lobe_c(n, 15, 10)), exact);
    const double e5 = rel(total_flux_lm(lobe_c(n, 15, 5)), exact);
    const double e25 = rel(total_flux_lm(lobe_c(n, 15, 2.5)), exact);
    const double e125 = rel(total_flux_lm(lobe_c(n, 15, 1.25)), exact);
    SCOPED_TRACE("n " + std::to_string(n));
    EXPECT_GT(e10 / e5, 3.0);  // coarse grids: pre-asymptotic
    EXPECT_GT(e5 / e25, 8.0);  // 16 for a clean fourth order
    EXPECT_GT(e25 / e125, 12.0);
    EXPECT_LT(e125, 2e-6);
  }
}

TEST(Flux, NonUniformAngleListsStayAccurate) {
  // Real files refine the grid where the beam changes fast.
  std::vector<double> g = angles(0, 30, 1);
  for (double a : angles(32.5, 60, 2.5)) g.push_back(a);
  for (double a : angles(65, 90, 5)) g.push_back(a);
  for (double a : {105.0, 120.0, 150.0, 180.0}) g.push_back(a);
  for (double n : {1.0, 5.0, 20.0}) {
    const Distribution d =
        sample_direction(PhotometricType::C, Symmetry::Rotational, {0}, g, cos_lobe(1000, n));
    EXPECT_LT(rel(total_flux_lm(d), 2 * kPi * 1000.0 / (n + 1)), 1e-4) << n;
  }
}

TEST(Flux, PartialVerticalRanges) {
  // Uplight only (γ 90..180) and downlight only (γ 0..90).
  for (double n : {1.0, 3.0, 10.0}) {
    const Distribution up =
        sample_c(Symmetry::Quadrant, angles(0, 90, 15), angles(90, 180, 2.5),
                 [&](double, double g) { return 500.0 * std::pow(-std::cos(g * kDeg), n); });
    const Distribution down =
        sample_c(Symmetry::Quadrant, angles(0, 90, 15), angles(0, 90, 2.5),
                 [&](double, double g) { return 500.0 * std::pow(std::cos(g * kDeg), n); });
    const double exact = 2 * kPi * 500.0 / (n + 1);
    EXPECT_LT(rel(total_flux_lm(up), exact), 2e-5) << n;
    EXPECT_LT(rel(total_flux_lm(down), exact), 2e-5) << n;
    EXPECT_NEAR(upward_flux_lm(down), 0.0, 1e-9);
    EXPECT_NEAR(downward_flux_lm(up), 0.0, 1e-9);
  }
}

// An asymmetric lobe with a closed form: I = I₀ cosⁿγ (1 + cos²C) below the
// horizon, Φ = 3π I₀ / (n + 1).
double asym_lobe(double c, double g, double n) {
  return g < 90 ? 1000.0 * std::pow(std::cos(g * kDeg), n) * (1.0 + std::pow(std::cos(c * kDeg), 2))
                : 0.0;
}

TEST(Flux, AsymmetricDistributionAndEverySymmetryAgree) {
  const double n = 4;
  auto f = [&](double c, double g) { return asym_lobe(c, g, n); };
  const double exact = 3 * kPi * 1000.0 / (n + 1);
  const Distribution full = sample_c(Symmetry::None, angles(0, 360, 5), angles(0, 180, 2.5), f);
  const double phi = total_flux_lm(full);
  EXPECT_LT(rel(phi, exact), 1e-5);
  // cos²C is mirror-symmetric about both planes: every stored form of it
  // integrates as its expansion, to rounding.
  const Distribution quadrant =
      sample_c(Symmetry::Quadrant, angles(0, 90, 5), angles(0, 180, 2.5), f);
  const Distribution c0 = sample_c(Symmetry::C0_C180, angles(0, 180, 5), angles(0, 180, 2.5), f);
  const Distribution c90 = sample_c(Symmetry::C90_C270, angles(90, 270, 5), angles(0, 180, 2.5), f);
  for (const Distribution* d : {&quadrant, &c0, &c90}) {
    SCOPED_TRACE(to_string(d->symmetry));
    EXPECT_NEAR(total_flux_lm(*d), phi, 1e-12 * phi);
    EXPECT_NEAR(total_flux_lm(expand_symmetry(*d)), phi, 1e-12 * phi);
    EXPECT_NEAR(zonal_flux_lm(*d, 10, 50), zonal_flux_lm(full, 10, 50), 1e-12 * phi);
  }
  // A rotational file is its 0..360 expansion.
  const Distribution rot = lobe_c(3, 0, 2.5, Symmetry::Rotational);
  EXPECT_NEAR(total_flux_lm(rot), total_flux_lm(expand_symmetry(rot)), 1e-12 * total_flux_lm(rot));
}

TEST(Flux, FullRangeWithoutClosingPlane) {
  // Planes 10..350: the seam plane at 0 is blended; for a C-independent
  // lobe the flux is unaffected.
  const Distribution d = sample_direction(PhotometricType::C, Symmetry::None, angles(10, 350, 20),
                                          angles(0, 180, 2.5), cos_lobe(1000, 2));
  EXPECT_LT(rel(total_flux_lm(d), 2 * kPi * 1000.0 / 3), 1e-6);
}

TEST(Flux, ZonesMatchTheirClosedFormsAndAddUp) {
  const double n = 5;
  const Distribution d = lobe_c(n, 5, 2.5);
  const double total = total_flux_lm(d);
  // Zone [a, b] of the lobe: 2π I₀ (cos^{n+1} a − cos^{n+1} b) / (n + 1),
  // also across grid lines (41.4°, 75.5° are the CIE zone limits).
  auto exact = [&](double a, double b) {
    return 2 * kPi * 1000.0 *
           (std::pow(std::cos(a * kDeg), n + 1) - std::pow(std::cos(b * kDeg), n + 1)) / (n + 1);
  };
  for (auto [a, b] :
       {std::pair{0.0, 30.0}, {0.0, 41.41}, {12.3, 47.9}, {0.0, 60.0}, {60.0, 75.52}, {0.0, 90.0}})
    EXPECT_NEAR(zonal_flux_lm(d, a, b), exact(a, b), 3e-5 * total) << a << ".." << b;
  // Zones that tile the sphere add up to the total.
  double sum = 0;
  const double cuts[] = {0, 7.3, 30, 41.41, 60, 75.52, 90, 133, 180};
  for (int i = 0; i + 1 < 9; ++i) sum += zonal_flux_lm(d, cuts[i], cuts[i + 1]);
  EXPECT_NEAR(sum, total, 1e-12 * total);
  EXPECT_NEAR(downward_flux_lm(d) + upward_flux_lm(d), total, 1e-12 * total);
  // Out-of-range and empty zones.
  EXPECT_NEAR(zonal_flux_lm(d, -20, 200), total, 1e-12 * total);
  EXPECT_EQ(zonal_flux_lm(d, 50, 50), 0.0);
  EXPECT_EQ(zonal_flux_lm(d, 60, 30), 0.0);
  // Isotropic zones are exact: 2π I (cos a − cos b).
  const Distribution iso =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 5), [](double, double) { return 10.0; });
  EXPECT_NEAR(zonal_flux_lm(iso, 41.41, 75.52),
              2 * kPi * 10 * (std::cos(41.41 * kDeg) - std::cos(75.52 * kDeg)), 1e-9);
}

TEST(Flux, TypesAAndBMeetTheClosedForms) {
  // The same cosine lobe, pointing at Type B's photometric zero (the nadir),
  // and for Type A at its photometric horizontal (+x, V = 0).
  const double ns[] = {1, 2, 5, 10, 20};
  for (double n : ns) {
    const double exact = 2 * kPi * 1000.0 / (n + 1);
    const Distribution b =
        sample_direction(PhotometricType::B, Symmetry::None, angles(-90, 90, 2.5),
                         angles(-90, 90, 2.5), cos_lobe(1000, n));
    const Distribution b_lateral =
        sample_direction(PhotometricType::B, Symmetry::Lateral, angles(0, 90, 2.5),
                         angles(-90, 90, 2.5), cos_lobe(1000, n));
    auto forward = [&](const Vec3& v) { return cos_lobe(1000, n)(Vec3{v.z, v.y, -v.x}); };
    const Distribution a = sample_direction(PhotometricType::A, Symmetry::Lateral,
                                            angles(0, 90, 2.5), angles(-90, 90, 2.5), forward);
    SCOPED_TRACE("n " + std::to_string(n));
    EXPECT_LT(rel(total_flux_lm(b), exact), 1e-4);
    EXPECT_NEAR(total_flux_lm(b_lateral), total_flux_lm(b), 1e-12 * exact);
    EXPECT_LT(rel(total_flux_lm(a), exact), 1e-4);
    // Type A's lobe is split by its V = 0 plane, the horizontal.
    EXPECT_NEAR(downward_flux_lm(a), 0.5 * total_flux_lm(a), 1e-9 * exact);
    // Type B's grid lies in the lower hemisphere (one resampling is enough).
    if (n == 5) {
      EXPECT_NEAR(downward_flux_lm(b), total_flux_lm(b), 1e-9 * exact);
    }
  }
}

TEST(Flux, TypeBZonesFollowTheDirectionsNotTheGrid) {
  const double n = 3;
  const Distribution b = sample_direction(PhotometricType::B, Symmetry::Lateral, angles(0, 90, 2.5),
                                          angles(-90, 90, 2.5), cos_lobe(1000, n));
  const double total = total_flux_lm(b);
  auto exact = [&](double a, double z) {
    return 2 * kPi * 1000.0 *
           (std::pow(std::cos(a * kDeg), n + 1) - std::pow(std::cos(z * kDeg), n + 1)) / (n + 1);
  };
  EXPECT_NEAR(zonal_flux_lm(b, 0, 30), exact(0, 30), 2e-3 * total);
  EXPECT_NEAR(zonal_flux_lm(b, 30, 60), exact(30, 60), 2e-3 * total);
  EXPECT_NEAR(zonal_flux_lm(b, 0, 30) + zonal_flux_lm(b, 30, 90) + zonal_flux_lm(b, 90, 180), total,
              1e-9 * total);
}

TEST(Flux, DegenerateAndHostileData) {
  // All dark, one ring of directions (no solid angle), two angles (linear).
  EXPECT_EQ(total_flux_lm(sample_c(Symmetry::None, angles(0, 360, 30), angles(0, 180, 10),
                                   [](double, double) { return 0.0; })),
            0.0);
  EXPECT_EQ(
      total_flux_lm(sample_c(Symmetry::Rotational, {0}, {45}, [](double, double) { return 7.0; })),
      0.0);
  const Distribution two = sample_c(Symmetry::Rotational, {0}, {0, 90},
                                    [](double, double g) { return g == 0 ? 2.0 : 0.0; });
  // I = 2 (1 − γ/(π/2)) on [0, π/2]: 2π ∫ I sin γ dγ = 4π (1 − 2/π).
  EXPECT_NEAR(total_flux_lm(two), 4 * kPi * (1 - 2 / kPi), 1e-10);
}

// Trapezoid in γ of I sin γ: a crude but model-free reference.
double trapezoid(const Distribution& d) {
  const Distribution e = expand_symmetry(d);
  double sum = 0;
  for (std::size_t h = 0; h + 1 < e.horizontal_count(); ++h) {
    const double dc = (e.horizontal_deg[h + 1] - e.horizontal_deg[h]) * kDeg;
    for (std::size_t r : {h, h + 1})
      for (std::size_t v = 0; v + 1 < e.vertical_count(); ++v) {
        const double g0 = e.vertical_deg[v] * kDeg, g1 = e.vertical_deg[v + 1] * kDeg;
        sum += 0.25 * dc * (g1 - g0) * (e.at(r, v) * std::sin(g0) + e.at(r, v + 1) * std::sin(g1));
      }
  }
  return sum;
}

TEST(Flux, NeverGoesBadlyWrongOnSpikesStepsAndNoise) {
  // A one-sample spike, a hard cut-off and random non-negative data: the
  // monotone model stays close to the model-free trapezoid sum and is never
  // negative.
  const Distribution spike = sample_c(Symmetry::Rotational, {0}, angles(0, 180, 5),
                                      [](double, double g) { return g == 40 ? 1000.0 : 0.0; });
  EXPECT_LT(rel(total_flux_lm(spike), trapezoid(spike)), 0.1);
  for (double edge : {20.0, 21.0, 22.5, 24.0}) {
    const Distribution hat = sample_c(Symmetry::Rotational, {0}, angles(0, 180, 2.5),
                                      [&](double, double g) { return g <= edge ? 100.0 : 0.0; });
    EXPECT_LT(rel(total_flux_lm(hat), trapezoid(hat)), 0.02) << edge;
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 50; ++trial) {
    const Distribution noise =
        sample_c(Symmetry::None, angles(0, 360, 30), angles(0, 180, 5), [&](double, double) {
          const double r = u(rng);
          return r < 0.4 ? 0.0 : 1000.0 * u(rng);
        });
    const double phi = total_flux_lm(noise);
    EXPECT_GE(phi, 0.0);
    EXPECT_LT(rel(phi, trapezoid(noise)), 0.15);
  }
}

}  // namespace
}  // namespace gonio::photometry
