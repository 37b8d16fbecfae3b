#include "photometry/summary.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "photometry/angles.h"
#include "photometry/flux.h"
#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_c;
using test::sample_direction;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

Distribution lambertian(double i0) {
  return sample_direction(PhotometricType::C, Symmetry::Quadrant, angles(0, 90, 15),
                          angles(0, 180, 2.5), cos_lobe(i0, 1));
}

TEST(CieFluxCode, ClosedForms) {
  // Lambertian downlight: flux within θ of the nadir ∝ sin²θ, so
  // N1..N3 = 43.75, 75, 93.75; all of it downward.
  Distribution d = lambertian(1000);
  d.lamps[0].flux_lm = 1.25 * kPi * 1000;  // LOR 0.8
  const CieFluxCode c = cie_flux_code(d);
  EXPECT_NEAR(c.n1, 43.75, 1e-3);
  EXPECT_NEAR(c.n2, 75.0, 1e-3);
  EXPECT_NEAR(c.n3, 93.75, 1e-3);
  EXPECT_NEAR(c.n4, 100.0, 1e-9);
  EXPECT_NEAR(c.n5, 80.0, 1e-3);
  EXPECT_EQ(to_string(c), "44 75 94 100 80");
  // Isotropic: the cones hold 1/4, 1/2, 3/4 of the lower hemisphere, which
  // holds half the flux. Absolute photometry has no LOR.
  Distribution iso =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 5), [](double, double) { return 1.0; });
  iso.absolute = true;
  const CieFluxCode i = cie_flux_code(iso);
  EXPECT_NEAR(i.n1, 25.0, 1e-9);
  EXPECT_NEAR(i.n2, 50.0, 1e-9);
  EXPECT_NEAR(i.n3, 75.0, 1e-9);
  EXPECT_NEAR(i.n4, 50.0, 1e-9);
  EXPECT_TRUE(std::isnan(i.n5));
  EXPECT_EQ(to_string(i), "25 50 75 50 -");
  // cosⁿ: 100 (1 − cos^{n+1} of the cone angle).
  const Distribution narrow = sample_direction(PhotometricType::C, Symmetry::Rotational, {0},
                                               angles(0, 180, 1), cos_lobe(1000, 9));
  EXPECT_NEAR(cie_flux_code(narrow).n1, 100 * (1 - std::pow(0.75, 10)), 1e-3);
  EXPECT_NEAR(cie_flux_code(narrow).n3, 100 * (1 - std::pow(0.25, 10)), 1e-3);
  // A pure uplight has no downward flux to share out.
  const Distribution up =
      sample_c(Symmetry::Rotational, {0}, angles(90, 180, 5), [](double, double) { return 3.0; });
  EXPECT_TRUE(std::isnan(cie_flux_code(up).n1));
  EXPECT_NEAR(cie_flux_code(up).n4, 0.0, 1e-12);
}

TEST(Summary, DerivedValuesOfALambertianDownlight) {
  Distribution d = lambertian(1000);
  d.lamps = {LampSet{2, "LED", 2000.0, "", "", 15.0}};
  d.input_watts = 30.0;
  const Summary s = summarize(d);
  const double phi = kPi * 1000;
  EXPECT_NEAR(s.flux_lm, phi, 1e-5 * phi);
  EXPECT_DOUBLE_EQ(s.rated_lamp_flux_lm, 2000.0);
  EXPECT_TRUE(s.lor_defined);
  EXPECT_NEAR(s.lor, phi / 2000.0, 1e-5);
  EXPECT_NEAR(s.dff, 1.0, 1e-12);
  EXPECT_NEAR(s.upward_flux_lm, 0.0, 1e-9);
  ASSERT_EQ(s.zones.size(), 6u);
  // Zone 0–θ of a Lambertian: π I₀ sin²θ.
  EXPECT_NEAR(s.zones[0].flux_lm, phi * 0.25, 1e-4 * phi);
  EXPECT_NEAR(s.zones[2].flux_lm, phi * 0.75, 1e-4 * phi);
  EXPECT_DOUBLE_EQ(s.zones[5].flux_lm, s.zones[3].flux_lm + s.zones[4].flux_lm);
  double tens = 0;
  for (const Zone& z : s.zones_10deg) tens += z.flux_lm;
  EXPECT_NEAR(tens, s.flux_lm, 1e-12 * phi);
  EXPECT_DOUBLE_EQ(s.max_intensity_cd, 1000.0);
  EXPECT_DOUBLE_EQ(s.max_gamma_deg, 0.0);
  EXPECT_NEAR(s.beam_c0_c180.angle_deg, 120.0, 0.05);
  EXPECT_NEAR(s.field_c90_c270.angle_deg, 168.52, 0.05);
  EXPECT_DOUBLE_EQ(s.input_power_w, 30.0);
  EXPECT_DOUBLE_EQ(s.efficacy_lm_per_w, s.flux_lm / 30.0);
  EXPECT_EQ(to_string(s.cie_flux_code), "44 75 94 100 157");
  // Without input watts the lamp sets' wattage counts; absolute photometry
  // has no LOR.
  d.input_watts = kNaN;
  d.absolute = true;
  d.lamps[0].flux_lm = kNaN;
  const Summary a = summarize(d);
  EXPECT_FALSE(a.lor_defined);
  EXPECT_TRUE(std::isnan(a.lor));
  EXPECT_DOUBLE_EQ(a.input_power_w, 15.0);
  EXPECT_NEAR(a.flux_lm, s.flux_lm, 1e-12);
}

TEST(Summary, SymmetricAndExpandedFilesAgree) {
  auto f = [](double c, double g) {
    return g < 90
               ? 500 * std::pow(std::cos(g * kDeg), 3) * (1 + 0.5 * std::pow(std::cos(c * kDeg), 2))
               : 20.0;
  };
  const Distribution q = sample_c(Symmetry::Quadrant, angles(0, 90, 10), angles(0, 180, 5), f);
  const Summary a = summarize(q), b = summarize(expand_symmetry(q));
  EXPECT_NEAR(a.flux_lm, b.flux_lm, 1e-12 * a.flux_lm);
  EXPECT_NEAR(a.dff, b.dff, 1e-12);
  for (std::size_t i = 0; i < a.zones.size(); ++i)
    EXPECT_NEAR(a.zones[i].flux_lm, b.zones[i].flux_lm, 1e-9);
  EXPECT_EQ(a.max_intensity_cd, b.max_intensity_cd);
  EXPECT_DOUBLE_EQ(a.beam_c0_c180.angle_deg, b.beam_c0_c180.angle_deg);
  EXPECT_DOUBLE_EQ(a.field_c90_c270.angle_deg, b.field_c90_c270.angle_deg);
  EXPECT_EQ(to_string(a.cie_flux_code), to_string(b.cie_flux_code));
  // Wider along C0 (cos²C term): the C0-C180 beam is wider than C90-C270's.
  EXPECT_GT(a.beam_c0_c180.angle_deg, a.beam_c90_c270.angle_deg);
}

TEST(Summary, TypeBFloodlight) {
  // A lobe on Type B's photometric zero, peak 2000 cd.
  const Distribution b = sample_direction(PhotometricType::B, Symmetry::Lateral, angles(0, 90, 1),
                                          angles(-90, 90, 1), cos_lobe(2000, 30));
  const Summary s = summarize(b);
  EXPECT_NEAR(s.flux_lm, 2 * kPi * 2000 / 31, 1e-4 * s.flux_lm);
  EXPECT_NEAR(s.dff, 1.0, 1e-9);
  EXPECT_DOUBLE_EQ(s.max_intensity_cd, 2000.0);
  EXPECT_DOUBLE_EQ(s.max_horizontal_deg, 0.0);
  EXPECT_DOUBLE_EQ(s.max_vertical_deg, 0.0);
  EXPECT_NEAR(s.max_gamma_deg, 0.0, 1e-9);
  const double width = 2 * std::acos(std::pow(0.5, 1.0 / 30)) / kDeg;
  EXPECT_NEAR(s.beam_c0_c180.angle_deg, width, 0.1);
  EXPECT_NEAR(s.beam_c90_c270.angle_deg, width, 0.1);
  EXPECT_NEAR(s.cie_flux_code.n1, 100 * (1 - std::pow(0.75, 31)), 0.05);
}

}  // namespace
}  // namespace gonio::photometry
