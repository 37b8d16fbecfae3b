#include "photometry/direct_ratios.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_c;
using test::sample_direction;
constexpr double kPi = std::numbers::pi;

// View factor between two directly opposed parallel rectangles X·c by Y·c at
// distance c (the classical closed form, e.g. Howell's catalogue, case C-11).
double facing_rectangles(double x, double y) {
  const double a = 1 + x * x, b = 1 + y * y;
  return 2 / (kPi * x * y) *
         (0.5 * std::log(a * b / (a + b - 1)) + x * std::sqrt(b) * std::atan(x / std::sqrt(b)) +
          y * std::sqrt(a) * std::atan(y / std::sqrt(a)) - x * std::atan(x) - y * std::atan(y));
}

TEST(DirectRatios, LambertianEqualsTheViewFactorOfFacingSquares) {
  const Distribution d = sample_direction(PhotometricType::C, Symmetry::Rotational, {0},
                                          angles(0, 180, 1), cos_lobe(1000, 1));
  const std::array<double, 10> dr = direct_ratios(d);
  for (std::size_t i = 0; i < dr.size(); ++i) {
    const double k = kDirectRatioRoomIndices[i];
    EXPECT_NEAR(dr[i], facing_rectangles(2 * k, 2 * k), 2e-5) << "k " << k;
  }
  EXPECT_NEAR(direct_ratio(d, 0.6), dr[0], 1e-15);
}

// Isotropic downward light, computed from the working plane's side: the
// relative offset of a random luminaire and a random point of the working
// plane has density (1 − |x|/a)(1 − |y|/a)/a² on [−a, a]², and each point
// receives I h / r³ per unit area; over the flux 2π I (h = 1).
double isotropic_from_the_floor(double k) {
  const double a = 2 * k;
  const int n = 1200;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double x = -a + 2 * a * (i + 0.5) / n;
    for (int j = 0; j < n; ++j) {
      const double y = -a + 2 * a * (j + 0.5) / n;
      const double r2 = x * x + y * y + 1;
      sum += (1 - std::abs(x) / a) * (1 - std::abs(y) / a) / (r2 * std::sqrt(r2));
    }
  }
  return sum * (2 * a / n) * (2 * a / n) / (2 * kPi);
}

TEST(DirectRatios, IsotropicDownlightMatchesAnIndependentIntegral) {
  const Distribution d =
      sample_c(Symmetry::Rotational, {0}, angles(0, 90, 5), [](double, double) { return 50.0; });
  for (double k : {0.6, 1.5, 5.0})
    EXPECT_NEAR(direct_ratio(d, k), isotropic_from_the_floor(k), 5e-4)
        << k;  // the reference errs most
}

TEST(DirectRatios, BoundsAndLimits) {
  // Half the flux upward: ratios grow with k towards the downward fraction
  // (0.5) and never exceed it; an uplight sends nothing down; a dark
  // distribution has ratios of 0.
  const Distribution half =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 2.5), [](double, double g) {
        return g < 90 ? 100 * std::cos(g * kPi / 180) : 100 * -std::cos(g * kPi / 180);
      });
  const std::array<double, 10> dr = direct_ratios(half);
  for (std::size_t i = 1; i < dr.size(); ++i) EXPECT_GT(dr[i], dr[i - 1]);
  EXPECT_LT(dr.back(), 0.5);
  EXPECT_NEAR(direct_ratio(half, 500), 0.5, 2e-3);
  const Distribution up =
      sample_c(Symmetry::Rotational, {0}, angles(90, 180, 5), [](double, double) { return 5.0; });
  for (double r : direct_ratios(up)) EXPECT_EQ(r, 0.0);
  const Distribution dark =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 5), [](double, double) { return 0.0; });
  for (double r : direct_ratios(dark)) EXPECT_EQ(r, 0.0);
  // A narrow beam lands almost entirely on the working plane even at k = 0.6.
  const Distribution spot = sample_direction(PhotometricType::C, Symmetry::Rotational, {0},
                                             angles(0, 180, 0.5), cos_lobe(1e4, 2000));
  EXPECT_GT(direct_ratios(spot)[0], 0.97);
}

TEST(DirectRatios, TypeBFloodlightEqualsItsTypeCForm) {
  const Distribution b = sample_direction(PhotometricType::B, Symmetry::Lateral, angles(0, 90, 1),
                                          angles(-90, 90, 1), cos_lobe(1000, 4));
  const Distribution c = sample_direction(PhotometricType::C, Symmetry::Rotational, {0},
                                          angles(0, 180, 1), cos_lobe(1000, 4));
  const std::array<double, 10> rb = direct_ratios(b), rc = direct_ratios(c);
  for (std::size_t i = 0; i < 10; ++i) EXPECT_NEAR(rb[i], rc[i], 1e-3);
}

}  // namespace
}  // namespace gonio::photometry
