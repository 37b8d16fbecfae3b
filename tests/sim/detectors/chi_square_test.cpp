#include "sim/detectors/chi_square.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gonio::sim {
namespace {

// For even degrees of freedom 2m the tail has the closed form
// e^{−x/2} Σ_{i<m} (x/2)^i / i!.
double even_dof_tail(double x, int m) {
  double term = 1.0, sum = 0.0;
  for (int i = 0; i < m; ++i) {
    if (i > 0) term *= 0.5 * x / i;
    sum += term;
  }
  return std::exp(-0.5 * x) * sum;
}

TEST(ChiSquare, EvenDegreesOfFreedomMatchTheClosedForm) {
  for (int m : {1, 2, 5, 10, 50, 200}) {
    for (double x : {0.01, 0.5, 1.0, 2.0 * m - 3.0, 2.0 * m, 2.0 * m + 7.0, 3.0 * m + 40.0}) {
      if (x <= 0.0) continue;
      const double expected = even_dof_tail(x, m);
      EXPECT_NEAR(chi_square_upper_tail(x, 2.0 * m), expected, 1e-12 + 1e-10 * expected)
          << "dof " << 2 * m << " x " << x;
    }
  }
}

TEST(ChiSquare, OneDegreeOfFreedomIsTheNormalTail) {
  for (double x : {0.001, 0.3, 1.0, 3.841458820694124, 10.0, 40.0}) {
    const double expected = std::erfc(std::sqrt(0.5 * x));
    EXPECT_NEAR(chi_square_upper_tail(x, 1.0), expected, 1e-12 + 1e-10 * expected) << x;
  }
  EXPECT_NEAR(chi_square_upper_tail(3.841458820694124, 1.0), 0.05, 1e-12);
}

TEST(ChiSquare, ManyDegreesOfFreedomApproachTheNormalApproximation) {
  // Wilson–Hilferty: (X/k)^{1/3} is nearly normal with mean 1 − 2/(9k) and
  // variance 2/(9k); its error falls like 1/k.
  for (double k : {1e3, 1e5}) {
    for (double z : {-2.0, 0.0, 1.0, 3.0}) {
      const double s = std::sqrt(2.0 / (9.0 * k));
      const double x = k * std::pow(1.0 - 2.0 / (9.0 * k) + z * s, 3.0);
      EXPECT_NEAR(chi_square_upper_tail(x, k), 0.5 * std::erfc(z / std::sqrt(2.0)), 2e-4)
          << "dof " << k << " z " << z;
    }
  }
}

TEST(ChiSquare, Limits) {
  EXPECT_EQ(chi_square_upper_tail(0.0, 3.0), 1.0);
  EXPECT_EQ(chi_square_upper_tail(-1.0, 3.0), 1.0);
  EXPECT_EQ(chi_square_upper_tail(INFINITY, 3.0), 0.0);
  double previous = 1.0;
  for (double x = 0.5; x < 100.0; x += 0.5) {
    const double q = chi_square_upper_tail(x, 7.0);
    EXPECT_LE(q, previous);
    previous = q;
  }
}

}  // namespace
}  // namespace gonio::sim
