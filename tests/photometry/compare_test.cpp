#include "photometry/compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "photometry/resample.h"
#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_c;
using test::sample_direction;
constexpr double kDeg = std::numbers::pi / 180.0;

Distribution asymmetric() {
  return sample_c(Symmetry::None, angles(0, 360, 5), angles(0, 180, 2.5), [](double c, double g) {
    return g < 90 ? 800 * std::pow(std::cos(g * kDeg), 4) * (1 + 0.4 * std::cos(c * kDeg)) + 5
                  : 5.0;
  });
}

Distribution scaled(Distribution d, double s) {
  for (double& v : d.candela) v *= s;
  return d;
}

TEST(Compare, ADistributionWithItselfDiffersByNothing) {
  const Distribution a = asymmetric();
  const Result<Comparison> r = compare(a, a);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->rms_relative, 0.0);
  EXPECT_EQ(r->max_relative, 0.0);
  EXPECT_DOUBLE_EQ(r->flux_ratio, 1.0);
  EXPECT_EQ(r->beam_difference_c0_c180_deg, 0.0);
  EXPECT_EQ(r->field_difference_c90_c270_deg, 0.0);
  // The nadir of this data differs between planes; its pole value is their
  // mean (interpolate()), so the peak is the next ring, γ = 2.5°, in C0.
  EXPECT_DOUBLE_EQ(r->reference_cd, 800 * std::pow(std::cos(2.5 * kDeg), 4) * 1.4 + 5);
}

TEST(Compare, AScaledCopyReportsTheScale) {
  const Distribution a = asymmetric();
  for (double s : {0.5, 1.3}) {
    const Result<Comparison> r = compare(a, scaled(a, s));
    ASSERT_TRUE(r.ok());
    EXPECT_NEAR(r->max_relative, std::abs(s - 1), 1e-12);
    EXPECT_NEAR(r->flux_ratio, s, 1e-12);
    EXPECT_GT(r->rms_relative, 0.0);
    EXPECT_LT(r->rms_relative, r->max_relative);
    EXPECT_NEAR(r->beam_difference_c0_c180_deg, 0.0, 1e-9);  // beam angles do not scale
    // Normalised to equal flux, nothing is left.
    CompareOptions o;
    o.normalize_flux = true;
    const Result<Comparison> n = compare(a, scaled(a, s), o);
    ASSERT_TRUE(n.ok());
    EXPECT_NEAR(n->scale, 1 / s, 1e-12);
    EXPECT_NEAR(n->max_relative, 0.0, 1e-12);
    EXPECT_NEAR(n->rms_relative, 0.0, 1e-12);
  }
  // A uniform offset δ everywhere: RMS = max = δ / I_ref (the weights are
  // normalised over the sphere).
  const Distribution iso =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 5), [](double, double) { return 100.0; });
  const Result<Comparison> r = compare(iso, scaled(iso, 1.1));
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(r->rms_relative, 0.1, 1e-12);
  EXPECT_NEAR(r->max_relative, 0.1, 1e-12);
}

TEST(Compare, RmsIsWeightedBySolidAngle) {
  // B differs from A only in the polar cap γ < 30° (a solid angle of
  // 2π(1 − cos 30°)): RMS² ≈ δ² × cap / 4π, however densely the cap is
  // sampled.
  const Distribution a =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 1), [](double, double) { return 100.0; });
  const Distribution b = sample_c(Symmetry::Rotational, {0}, angles(0, 180, 1),
                                  [](double, double g) { return g < 30 ? 120.0 : 100.0; });
  CompareOptions o;
  o.gamma_step_deg = 0.5;
  o.c_step_deg = 2;
  const Result<Comparison> r = compare(a, b, o);
  ASSERT_TRUE(r.ok());
  const double cap = 2 * std::numbers::pi * (1 - std::cos(30 * kDeg));
  EXPECT_NEAR(r->rms_relative, 0.2 * std::sqrt(cap / (4 * std::numbers::pi)), 2e-3);
  EXPECT_NEAR(r->max_relative, 0.2, 1e-12);
  EXPECT_LT(r->max_at_gamma_deg, 30.0);
}

TEST(Compare, DifferentTypesAndGridsOfOneFunction) {
  // A Type B floodlight and a Type C sampling of the same lobe: close, and
  // closer on finer source grids. (Steps that hold the common grid's 2.5° γ
  // angles: between them the Type C side is interpolated linearly and errs by
  // h²/8 · I'', which would hide the B side's convergence.)
  double previous = 1;
  for (double step : {5.0, 2.5, 1.25}) {
    const Distribution c = sample_direction(PhotometricType::C, Symmetry::Rotational, {0},
                                            angles(0, 180, step), cos_lobe(1000, 8));
    const Distribution b =
        sample_direction(PhotometricType::B, Symmetry::Lateral, angles(0, 90, step),
                         angles(-90, 90, step), cos_lobe(1000, 8));
    const Result<Comparison> r = compare(c, b);
    ASSERT_TRUE(r.ok());
    EXPECT_LT(r->rms_relative, 0.01);
    EXPECT_LT(std::abs(r->flux_ratio - 1), 1e-4);
    EXPECT_LT(r->max_relative, previous) << step;
    previous = r->max_relative;
  }
}

// Mistakes it catches: symmetry not expanded (a quadrant file and its full
// copy on the same angles would read as different), a vertical list or a
// type not compared, a tolerance so loose that 0.1° apart reads the same.
TEST(Compare, SameAnglesOverTheWholeSphere) {
  const Distribution full = asymmetric();
  EXPECT_TRUE(same_angles(full, full));
  const auto lobe = [](double c, double g) { return g < 90 ? 100 + c * 0.0 + g : 1.0; };
  const Distribution quadrant = sample_c(Symmetry::Quadrant, angles(0, 90, 5), angles(0, 180, 2.5), lobe);
  const Distribution whole = sample_c(Symmetry::None, angles(0, 360, 5), angles(0, 180, 2.5), lobe);
  EXPECT_TRUE(same_angles(quadrant, whole));
  const Distribution finer = sample_c(Symmetry::None, angles(0, 360, 5), angles(0, 180, 1.25), lobe);
  EXPECT_FALSE(same_angles(whole, finer));
  Distribution shifted = whole;
  shifted.vertical_deg[1] += 0.1;
  EXPECT_FALSE(same_angles(whole, shifted));
  const Distribution coarser_c = sample_c(Symmetry::None, angles(0, 360, 10), angles(0, 180, 2.5), lobe);
  EXPECT_FALSE(same_angles(whole, coarser_c));
  Distribution type_b = whole;
  type_b.type = PhotometricType::B;
  EXPECT_FALSE(same_angles(whole, type_b));
}

TEST(Compare, BadOptionsAreErrors) {
  const Distribution a = asymmetric();
  CompareOptions o;
  o.c_step_deg = 7;
  EXPECT_FALSE(compare(a, a, o).ok());
  o.c_step_deg = 5;
  o.gamma_step_deg = -1;
  EXPECT_FALSE(compare(a, a, o).ok());
}

}  // namespace
}  // namespace gonio::photometry
