#include "photometry/validation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "photometry/flux.h"
#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_c;
using test::sample_direction;
constexpr double kPi = std::numbers::pi;

// A clean relative-photometry downlight: LOR 0.8, declared values that match.
Distribution clean() {
  Distribution d = sample_direction(PhotometricType::C, Symmetry::Quadrant, angles(0, 90, 15),
                                    angles(0, 180, 2.5), cos_lobe(1000, 2));
  const double flux = 2 * kPi * 1000 / 3;
  d.lamps[0].flux_lm = flux / 0.8;
  d.lamps[0].power_w = 20;
  d.input_watts = 22;
  d.declared_lor_percent = 80;
  d.declared_dff_percent = 100;
  return d;
}

std::vector<std::string> codes(const std::vector<Finding>& f) {
  std::vector<std::string> out;
  for (const Finding& x : f) out.push_back(x.code);
  return out;
}

// The findings of `d` are exactly `expected` (by code), each with a message.
void expect_codes(const Distribution& d, std::vector<std::string> expected) {
  const std::vector<Finding> f = check(d);
  std::vector<std::string> got = codes(f);
  std::sort(got.begin(), got.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(got, expected);
  for (const Finding& x : f) {
    EXPECT_FALSE(x.message.empty()) << x.code;
    EXPECT_TRUE(x.where.file.empty());
  }
}

const Finding* find(const std::vector<Finding>& f, const std::string& code) {
  for (const Finding& x : f)
    if (x.code == code) return &x;
  return nullptr;
}

TEST(Validation, CleanModelsGiveNoFindings) {
  expect_codes(clean(), {});
  expect_codes(expand_symmetry(clean()), {});
  Distribution abs = clean();
  abs.absolute = true;
  abs.lamps[0].flux_lm = kNaN;
  expect_codes(abs, {});
  Distribution b = sample_direction(PhotometricType::B, Symmetry::Lateral, angles(0, 90, 5),
                                    angles(-90, 90, 5), cos_lobe(4000, 10));
  b.absolute = true;
  expect_codes(b, {});
  Distribution a =
      sample_direction(PhotometricType::A, Symmetry::None, angles(-90, 90, 5), angles(-90, 90, 5),
                       [](const Vec3& v) { return v.x > 0 ? 100 * v.x : 0.0; });
  expect_codes(a, {});
}

TEST(Validation, StructuralErrors) {
  Distribution d = clean();
  d.vertical_deg.clear();
  d.candela.clear();
  expect_codes(d, {"no-angles"});

  d = clean();
  d.vertical_deg[3] = kNaN;
  expect_codes(d, {"angle-not-finite"});

  d = clean();
  std::swap(d.vertical_deg[4], d.vertical_deg[5]);
  expect_codes(d, {"vertical-angles-order"});
  EXPECT_NE(check(d)[0].message.find("follows"), std::string::npos);

  d = clean();
  d.horizontal_deg[2] = d.horizontal_deg[1];
  expect_codes(d, {"horizontal-angles-order"});

  d = clean();
  d.vertical_deg.back() = 190;
  expect_codes(d, {"vertical-angle-range"});

  d = sample_c(Symmetry::None, {0, 90, 180, 270, 370}, angles(0, 90, 45),
               [](double, double) { return 1.0; });
  expect_codes(d, {"horizontal-angle-range"});

  d = clean();
  d.horizontal_deg = angles(0, 120, 20);  // still 7 planes
  expect_codes(d, {"symmetry-range"});
  EXPECT_NE(check(d)[0].message.find("0 to 90"), std::string::npos);
  d = clean();
  d.symmetry = Symmetry::Lateral;
  expect_codes(d, {"symmetry-range"});
  d = sample_direction(PhotometricType::B, Symmetry::Quadrant, angles(0, 90, 30),
                       angles(-90, 90, 30), cos_lobe(1, 1));
  expect_codes(d, {"symmetry-range"});

  d = clean();
  d.candela.pop_back();
  expect_codes(d, {"candela-count"});

  d = clean();
  d.candela[7] = std::numeric_limits<double>::infinity();
  d.candela[9] = kNaN;
  const std::vector<Finding> f = check(d);
  expect_codes(d, {"non-finite-intensity"});
  EXPECT_NE(f[0].message.find("2 intensities"), std::string::npos);

  d = clean();
  d.lamps[0].count = 0;
  expect_codes(d, {"lamp-count"});
  d = clean();
  d.lamps[0].flux_lm = -5;
  expect_codes(d, {"lamp-flux"});
  for (const Finding& x : check(d)) EXPECT_EQ(x.severity, Severity::Error);
}

TEST(Validation, DataErrors) {
  Distribution d = clean();
  d.candela[20] = -3;
  expect_codes(d, {"negative-intensity"});
  EXPECT_NE(check(d)[0].message.find("-3 cd"), std::string::npos);
  d = clean();
  std::fill(d.candela.begin(), d.candela.end(), 0.0);
  expect_codes(d, {"all-zero"});
  EXPECT_EQ(worst(check(d)), Severity::Error);
}

TEST(Validation, SymmetryConsistency) {
  // Nadir and zenith values that differ between C-planes, and C0 != C360.
  auto f = [](double c, double g) { return 100 + (g == 0 || g == 180 ? c / 10 : 0.0); };
  Distribution d = sample_c(Symmetry::None, angles(0, 360, 30), angles(0, 180, 10), f);
  d.absolute = true;
  expect_codes(d, {"nadir-mismatch", "zenith-mismatch", "seam-mismatch"});
  EXPECT_EQ(worst(check(d)), Severity::Warning);
  // Within the tolerance (0.1 % of the peak) nothing is reported.
  auto g = [](double c, double gg) { return 100 + (gg == 0 ? c / 1e4 : 0.0); };
  Distribution quiet = sample_c(Symmetry::None, angles(0, 330, 30), angles(0, 180, 10), g);
  quiet.absolute = true;
  expect_codes(quiet, {});
  // Type B values at the pole H = 90 depend on V although it is one direction.
  Distribution b = sample_direction(PhotometricType::B, Symmetry::Lateral, angles(0, 90, 30),
                                    angles(-90, 90, 30), [](const Vec3&) { return 10.0; });
  b.absolute = true;
  b.at(3, 2) = 12.0;
  expect_codes(b, {"pole-mismatch"});
  Distribution a = sample_direction(PhotometricType::A, Symmetry::None, angles(-90, 90, 30),
                                    angles(-90, 90, 30), [](const Vec3&) { return 10.0; });
  a.absolute = true;
  a.at(2, 0) = 11.0;  // V = -90, the nadir, for one H
  expect_codes(a, {"pole-mismatch"});
}

TEST(Validation, DeclaredAndIntegratedValues) {
  Distribution d = clean();
  d.lamps[0].flux_lm = total_flux_lm(d) / 1.2;  // LOR 120 %
  d.declared_lor_percent = 120;
  expect_codes(d, {"lor-implausible"});
  EXPECT_NE(check(d)[0].message.find("120 %"), std::string::npos);

  d = clean();
  d.declared_lor_percent = 75;  // integrates to 80 %
  expect_codes(d, {"lor-mismatch"});
  d.declared_lor_percent = 79;  // within 3 %
  expect_codes(d, {});
  d.declared_lor_percent = 0;  // an unfilled field
  expect_codes(d, {"lor-mismatch"});

  d = clean();
  d.declared_dff_percent = 90;
  expect_codes(d, {"dff-mismatch"});
  d.declared_dff_percent = 98.5;
  expect_codes(d, {});

  d = clean();
  d.input_watts = 1.0;  // 2 kLm from 1 W
  expect_codes(d, {"efficacy-implausible"});
  d.input_watts = kNaN;  // falls back on the lamp wattage, 20 W: fine
  expect_codes(d, {});

  d = clean();
  d.lamps.clear();
  expect_codes(d, {"no-lamp-data"});
}

TEST(Validation, AbsurdMagnitudesAndThinGrids) {
  Distribution d = clean();
  for (double& v : d.candela) v *= 1e7;  // peak 1e10 cd, 2e10 lm
  d.lamps[0].flux_lm *= 1e7;
  expect_codes(d, {"absurd-intensity", "absurd-flux", "efficacy-implausible"});
  d = clean();
  for (double& v : d.candela) v *= 1e-10;
  d.lamps[0].flux_lm *= 1e-10;
  expect_codes(d, {"absurd-intensity"});

  Distribution ring = sample_c(Symmetry::Rotational, {0}, {45}, [](double, double) { return 5.0; });
  ring.absolute = true;
  expect_codes(ring, {"no-solid-angle", "vertical-range-nonstandard"});
  Distribution plane = sample_direction(PhotometricType::B, Symmetry::None, {0},
                                        angles(-90, 90, 10), cos_lobe(10, 1));
  plane.absolute = true;
  expect_codes(plane, {"no-solid-angle"});
  Distribution odd =
      sample_c(Symmetry::Rotational, {0}, angles(0, 85, 5), [](double, double) { return 5.0; });
  odd.absolute = true;
  expect_codes(odd, {"vertical-range-nonstandard"});
}

TEST(Validation, CustomTolerances) {
  Distribution d = clean();
  d.declared_lor_percent = 79;
  CheckOptions strict;
  strict.declared_lor_tolerance = 0.001;
  EXPECT_EQ(codes(check(d, strict)), std::vector<std::string>{"lor-mismatch"});
  EXPECT_NE(find(check(d, strict), "lor-mismatch")->message.find("79 %"), std::string::npos);
}

}  // namespace
}  // namespace gonio::photometry
