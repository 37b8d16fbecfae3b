#include "photometry/beam.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "photometry/angles.h"
#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_c;
using test::sample_direction;
constexpr double kDeg = std::numbers::pi / 180.0;

// Full width of cosⁿγ at `fraction` of its peak: 2 acos(fraction^(1/n)).
double lobe_width(double n, double fraction) {
  return 2 * std::acos(std::pow(fraction, 1 / n)) / kDeg;
}

TEST(Beam, CosineLobesMatchTheirAnalyticWidths) {
  for (double n : {1.0, 2.0, 5.0, 10.0, 20.0, 50.0}) {
    for (double step : {2.5, 0.5}) {
      const Distribution d = sample_direction(PhotometricType::C, Symmetry::Rotational, {0},
                                              angles(0, 180, step), cos_lobe(1000, n));
      const BeamSpread beam = beam_angle(d, 0), field = field_angle(d, 90);
      SCOPED_TRACE("n " + std::to_string(n) + " step " + std::to_string(step));
      // Linear interpolation between samples: the error falls as step².
      const double tol = 0.06 * step * step;
      EXPECT_NEAR(beam.angle_deg, lobe_width(n, 0.5), tol);
      EXPECT_NEAR(field.angle_deg, lobe_width(n, 0.1), tol);
      EXPECT_NEAR(beam.lower_edge_deg, -beam.upper_edge_deg, 1e-9);
      EXPECT_EQ(beam.axis_deg, 0.0);
      EXPECT_DOUBLE_EQ(beam.max_cd, 1000.0);
      EXPECT_DOUBLE_EQ(beam.threshold_cd, 500.0);
      EXPECT_FALSE(beam.lower_open || beam.upper_open);
    }
  }
  // Lambertian: 120° and 2 acos 0.1 = 168.5°.
  const Distribution lambert = sample_c(Symmetry::Rotational, {0}, angles(0, 90, 1),
                                        [](double, double g) { return std::cos(g * kDeg); });
  EXPECT_NEAR(beam_angle(lambert, 0).angle_deg, 120.0, 0.01);
  EXPECT_NEAR(field_angle(lambert, 0).angle_deg, 168.52, 0.01);
}

TEST(Beam, TiltedAndAsymmetricBeams) {
  // A lobe tilted 20° towards C0, three times wider along C90 than C0.
  auto f = [](const Vec3& v) {
    const Vec3 axis{std::sin(20 * kDeg), 0, -std::cos(20 * kDeg)};
    const Vec3 side{std::cos(20 * kDeg), 0, std::sin(20 * kDeg)};
    const double along = dot(v, axis);
    if (along <= 0) return 0.0;
    const double tx = dot(v, side) / along, ty = v.y / along;  // tangent-plane coordinates
    return 1000.0 * std::exp(-(tx * tx) / (2 * 0.1 * 0.1) - (ty * ty) / (2 * 0.3 * 0.3));
  };
  const Distribution d = sample_direction(PhotometricType::C, Symmetry::C0_C180, angles(0, 180, 1),
                                          angles(0, 180, 0.5), f);
  const BeamSpread c0 = beam_angle(d, 0);
  EXPECT_NEAR(c0.axis_deg, 20.0, 1e-9);
  // Half width where exp(-t²/2σ²) = 1/2: t = σ √(2 ln 2), an angle atan(t).
  const double half = std::atan(0.1 * std::sqrt(2 * std::log(2.0))) / kDeg;
  EXPECT_NEAR(c0.lower_edge_deg, 20 - half, 0.02);
  EXPECT_NEAR(c0.upper_edge_deg, 20 + half, 0.02);
  // Across the tilted beam the C90-C270 plane does not pass through the axis;
  // it measures the beam where it cuts it, with its own (lower) maximum.
  const BeamSpread c90 = beam_angle(d, 90);
  EXPECT_NEAR(c90.axis_deg, 0.0, 1e-9);
  EXPECT_LT(c90.max_cd, 0.9 * c0.max_cd);
  EXPECT_GT(c90.angle_deg, 2 * c0.angle_deg);
  // Symmetric and expanded forms agree.
  EXPECT_DOUBLE_EQ(beam_angle(expand_symmetry(d), 90).angle_deg, c90.angle_deg);
}

TEST(Beam, LobesAndDips) {
  // Batwing: peaks at ±30° and a dip at the nadir.
  auto batwing = [](double dip) {
    return sample_c(Symmetry::Rotational, {0}, angles(0, 90, 0.5), [=](double, double g) {
      return dip + (1000 - dip) * std::exp(-std::pow((g - 30) / 8, 2));
    });
  };
  // The dip (40 % of the peak) splits the 50 % beam: only the lobe with the
  // maximum counts (the one at θ = +30°, on the C0 side).
  const BeamSpread split = beam_angle(batwing(400), 0);
  EXPECT_NEAR(split.axis_deg, 30.0, 1e-9);
  EXPECT_GT(split.lower_edge_deg, 0.0);
  EXPECT_LT(split.angle_deg, 40.0);
  // A dip at 60 % does not: the beam spans both wings.
  const BeamSpread whole = beam_angle(batwing(600), 0);
  EXPECT_LT(whole.lower_edge_deg, -30.0);
  EXPECT_NEAR(whole.lower_edge_deg, -whole.upper_edge_deg, 1e-9);
  // A side lobe beyond the edge does not widen the beam.
  const Distribution side =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 1), [](double, double g) {
        return 1000 * std::exp(-std::pow(g / 10, 2)) + 800 * std::exp(-std::pow((g - 60) / 5, 2));
      });
  EXPECT_NEAR(beam_angle(side, 0).angle_deg, 2 * 10 * std::sqrt(std::log(2.0)), 0.05);
}

TEST(Beam, NoBeamOpenBeamsAndUplights) {
  const Distribution iso =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 5), [](double, double) { return 50.0; });
  EXPECT_TRUE(std::isnan(beam_angle(iso, 0).angle_deg));
  const Distribution dark =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 5), [](double, double) { return 0.0; });
  EXPECT_TRUE(std::isnan(beam_angle(dark, 0).angle_deg));
  // Measured to 90° only and still at 70 % there: the beam ends with the data.
  const Distribution wide = sample_c(Symmetry::Rotational, {0}, angles(0, 90, 5),
                                     [](double, double g) { return 1000 - 3.0 * g; });
  const BeamSpread open = beam_angle(wide, 0);
  EXPECT_TRUE(open.lower_open && open.upper_open);
  EXPECT_DOUBLE_EQ(open.angle_deg, 180.0);
  // An uplight: the beam wraps around the zenith (θ = ±180°).
  const Distribution up =
      sample_direction(PhotometricType::C, Symmetry::Rotational, {0}, angles(0, 180, 0.5),
                       [](const Vec3& v) { return v.z > 0 ? 500 * std::pow(v.z, 8) : 0.0; });
  const BeamSpread u = beam_angle(up, 0);
  EXPECT_NEAR(std::abs(u.axis_deg), 180.0, 1e-9);
  EXPECT_NEAR(u.angle_deg, lobe_width(8, 0.5), 0.01);
  // Only the upper hemisphere measured (γ 90..180): same beam.
  const Distribution up_only =
      sample_direction(PhotometricType::C, Symmetry::Rotational, {0}, angles(90, 180, 0.5),
                       [](const Vec3& v) { return v.z > 0 ? 500 * std::pow(v.z, 8) : 0.0; });
  EXPECT_NEAR(beam_angle(up_only, 0).angle_deg, u.angle_deg, 1e-9);
}

TEST(Beam, TypeBFloodlightInBothPlanes) {
  // A floodlight lobe on Type B's photometric zero, narrower along V (the
  // C0-C180 plane) than along H (C90-C270).
  auto flood = [](const Vec3& v) {
    const double along = -v.z;
    if (along <= 0) return 0.0;
    const double tx = v.x / along, ty = v.y / along;
    return 5e4 * std::exp(-(tx * tx) / (2 * 0.05 * 0.05) - (ty * ty) / (2 * 0.15 * 0.15));
  };
  const Distribution b = sample_direction(PhotometricType::B, Symmetry::Lateral, angles(0, 90, 0.5),
                                          angles(-90, 90, 0.5), flood);
  const double half_v = std::atan(0.05 * std::sqrt(2 * std::log(2.0))) / kDeg;
  const double half_h = std::atan(0.15 * std::sqrt(2 * std::log(2.0))) / kDeg;
  EXPECT_NEAR(beam_angle(b, 0).angle_deg, 2 * half_v, 0.1);
  EXPECT_NEAR(beam_angle(b, 90).angle_deg, 2 * half_h, 0.1);
}

}  // namespace
}  // namespace gonio::photometry
