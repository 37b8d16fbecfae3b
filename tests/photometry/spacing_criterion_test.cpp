#include "photometry/spacing_criterion.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_c;
using test::sample_direction;

// With I(γ) cos³γ = f(γ) symmetric, SC = 2 tan γ½ where f(γ½) = f(0) / 2, and
// the diagonal S = √2 tan γ¼ where f(γ¼) = f(0) / 4.
TEST(SpacingCriterion, LambertianClosedForm) {
  const Distribution d = sample_direction(PhotometricType::C, Symmetry::Quadrant, angles(0, 90, 15),
                                          angles(0, 180, 1), cos_lobe(1000, 1));
  const SpacingCriterion sc = spacing_criterion(d);
  const double half = 2 * std::tan(std::acos(std::pow(0.5, 0.25)));  // cos⁴γ = 1/2: 1.2872
  ASSERT_TRUE(sc.c0_c180.ratio);
  ASSERT_TRUE(sc.c90_c270.ratio);
  ASSERT_TRUE(sc.diagonal.ratio);
  EXPECT_NEAR(*sc.c0_c180.ratio, half, 2e-3);
  EXPECT_NEAR(*sc.c90_c270.ratio, half, 2e-3);
  EXPECT_NEAR(*sc.diagonal.ratio, std::sqrt(2.0), 2e-3);  // cos⁴γ = 1/4 at 45°
}

TEST(SpacingCriterion, IsotropicClosedForm) {
  const Distribution d =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 1), [](double, double) { return 100.0; });
  const SpacingCriterion sc = spacing_criterion(d);
  ASSERT_TRUE(sc.c0_c180.ratio);
  EXPECT_NEAR(*sc.c0_c180.ratio, 2 * std::tan(std::acos(std::cbrt(0.5))), 2e-3);   // 1.5328
  EXPECT_NEAR(*sc.diagonal.ratio, std::sqrt(2.0) * std::tan(std::acos(std::cbrt(0.25))), 2e-3);
}

// A luminaire narrower along C90 than along C0 has the smaller SC there.
TEST(SpacingCriterion, FollowsThePlanes) {
  const Distribution d = sample_c(Symmetry::Quadrant, angles(0, 90, 5), angles(0, 180, 1),
                                  [](double c, double g) {
                                    if (g >= 90) return 0.0;
                                    const double n = 1 + 4 * std::pow(std::sin(c * 3.14159265 / 180), 2);
                                    return 1000 * std::pow(std::cos(g * 3.14159265 / 180), n);
                                  });
  const SpacingCriterion sc = spacing_criterion(d);
  ASSERT_TRUE(sc.c0_c180.ratio && sc.c90_c270.ratio);
  EXPECT_GT(*sc.c0_c180.ratio, *sc.c90_c270.ratio + 0.3);
}

TEST(SpacingCriterion, UplightHasNoneWithAReason) {
  const Distribution d = sample_c(Symmetry::Rotational, {0}, angles(0, 180, 5),
                                  [](double, double g) { return g > 95 ? 100.0 : 0.0; });
  const SpacingCriterion sc = spacing_criterion(d);
  EXPECT_FALSE(sc.c0_c180.ratio);
  EXPECT_FALSE(sc.diagonal.ratio);
  EXPECT_NE(sc.c0_c180.why_undefined.find("straight down"), std::string::npos);
}

}  // namespace
}  // namespace gonio::photometry
