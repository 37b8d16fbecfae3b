#include "sim/samplers/sampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;

// Pearson's χ² of counts against expected counts; bins with tiny
// expectations are skipped.
double chi_square(const std::vector<double>& observed, const std::vector<double>& expected) {
  double chi2 = 0.0;
  for (std::size_t i = 0; i < observed.size(); ++i)
    if (expected[i] > 5.0) chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
  return chi2;
}

TEST(Sampling, SmallAngleSinCosMatchesTheLibraryToRounding) {
  // |x| ≤ π/8, where the series is promised to 9·10⁻¹⁶ (plus rounding).
  double worst = 0.0;
  for (int k = -4000; k <= 4000; ++k) {
    const double x = k / 4000.0 * std::numbers::pi / 8.0;
    double s, c;
    sincos_small(x, &s, &c);
    worst = std::max({worst, std::abs(s - std::sin(x)), std::abs(c - std::cos(x))});
  }
  EXPECT_LT(worst, 1.2e-15);
}

TEST(Sampling, BasisIsOrthonormalAndRightHanded) {
  for (const Vec3 n : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, normalize(Vec3{1, 2, 3}),
                       normalize(Vec3{-1, 0.5, -0.01}), Vec3{1, 0, 0}}) {
    const Basis b = basis_from_normal(n);
    EXPECT_NEAR(length(b.t), 1.0, 1e-12);
    EXPECT_NEAR(length(b.b), 1.0, 1e-12);
    EXPECT_NEAR(dot(b.t, b.b), 0.0, 1e-12);
    EXPECT_NEAR(dot(b.t, n), 0.0, 1e-12);
    const Vec3 c = cross(b.t, b.b);
    EXPECT_NEAR(c.x, n.x, 1e-12);
    EXPECT_NEAR(c.y, n.y, 1e-12);
    EXPECT_NEAR(c.z, n.z, 1e-12);
    const Vec3 w = b.to_world(b.to_local({0.3, -0.2, 0.9}));
    EXPECT_NEAR(w.x, 0.3, 1e-12);
  }
  const Basis bt = basis_from_normal_tangent({0, 0, 1}, {2, 0, 0.5});
  EXPECT_NEAR(bt.t.x, 1.0, 1e-12);
  EXPECT_NEAR(bt.b.y, 1.0, 1e-12);
}

TEST(Sampling, CosineHemisphereMatchesItsDensity) {
  // Histogram of cos θ in 20 bins: the probability of [c0, c1] under
  // cos θ/π is c1² − c0².
  const int n = 400000, bins = 20;
  std::vector<double> obs(bins, 0.0), exp(bins);
  std::vector<double> phi_obs(8, 0.0), phi_exp(8, n / 8.0);
  for (int i = 0; i < n; ++i) {
    PhotonRandom r(9, static_cast<std::uint64_t>(i));
    const Vec3 d = sample_cosine_hemisphere(r);
    ASSERT_NEAR(length(d), 1.0, 1e-12);
    ASSERT_GE(d.z, 0.0);
    obs[std::min(bins - 1, static_cast<int>(d.z * bins))] += 1;
    double phi = std::atan2(d.y, d.x);
    if (phi < 0) phi += 2 * kPi;
    phi_obs[std::min(7, static_cast<int>(phi / (2 * kPi) * 8))] += 1;
  }
  for (int b = 0; b < bins; ++b) {
    const double c0 = static_cast<double>(b) / bins, c1 = static_cast<double>(b + 1) / bins;
    exp[b] = n * (c1 * c1 - c0 * c0);
  }
  EXPECT_LT(chi_square(obs, exp), 43.8);      // 19 dof, p = 0.001
  EXPECT_LT(chi_square(phi_obs, phi_exp), 24.3);  // 7 dof
}

TEST(Sampling, UniformSphereMatchesItsDensity) {
  const int n = 400000, bins = 20;
  std::vector<double> obs(bins, 0.0), exp(bins, n / static_cast<double>(bins));
  for (int i = 0; i < n; ++i) {
    PhotonRandom r(10, static_cast<std::uint64_t>(i));
    const Vec3 d = sample_uniform_sphere(r);
    ASSERT_NEAR(length(d), 1.0, 1e-12);
    // Archimedes: z is uniform on [−1, 1].
    obs[std::min(bins - 1, static_cast<int>((d.z + 1.0) / 2.0 * bins))] += 1;
  }
  EXPECT_LT(chi_square(obs, exp), 43.8);
}

TEST(Sampling, DensitiesIntegrateToOne) {
  // Midpoint quadrature over the sphere in (cos θ, φ).
  const int nt = 400, np = 400;
  double cosine = 0.0, uniform = 0.0;
  for (int i = 0; i < nt; ++i) {
    const double z = -1.0 + (i + 0.5) * 2.0 / nt;
    for (int j = 0; j < np; ++j) {
      const double dw = (2.0 / nt) * (2.0 * kPi / np);
      cosine += cosine_hemisphere_pdf(z) * dw;
      uniform += uniform_sphere_pdf() * dw;
    }
  }
  EXPECT_NEAR(cosine, 1.0, 1e-5);
  EXPECT_NEAR(uniform, 1.0, 1e-9);
}

TEST(Sampling, TrianglePointsAreUniform) {
  // The barycentric weight of one corner is > 1/2 on a quarter of the area.
  const int n = 200000;
  int big = 0;
  for (int i = 0; i < n; ++i) {
    PhotonRandom r(11, static_cast<std::uint64_t>(i));
    const Barycentric b = sample_uniform_triangle(r.uniform(), r.uniform());
    ASSERT_NEAR(b.b0 + b.b1 + b.b2, 1.0, 1e-12);
    ASSERT_GE(std::min({b.b0, b.b1, b.b2}), 0.0);
    big += b.b2 > 0.5;
  }
  EXPECT_NEAR(big / static_cast<double>(n), 0.25, 5 * std::sqrt(0.25 * 0.75 / n));
}

}  // namespace
}  // namespace gonio::sim
