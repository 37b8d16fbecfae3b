#include "io/model/gltf_lights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace gonio::io {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// ∫ f(θ) 2π sin θ dθ over [0, π] by composite Simpson with n (even) steps.
template <class F>
double solid_angle_integral(F f, int n = 200000) {
  const double h = kPi / n;
  double sum = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double t = i * h;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * f(t) * std::sin(t);
  }
  return 2.0 * kPi * sum * h / 3.0;
}

TEST(GltfLights, IsotropicFluxIsFourPiI) {
  EXPECT_NEAR(isotropic_flux_lm(795.77), 10000.0, 0.1);  // VALIDATION.md: 10 000 lm ↔ 795.77 cd
  EXPECT_DOUBLE_EQ(isotropic_flux_lm(1.0), 4.0 * kPi);
}

TEST(GltfLights, SpotFalloffFollowsTheExtensionsCurve) {
  const double inner = 10 * kDeg, outer = 30 * kDeg;
  EXPECT_DOUBLE_EQ(khr_spot_falloff(0.0, inner, outer), 1.0);
  EXPECT_DOUBLE_EQ(khr_spot_falloff(inner, inner, outer), 1.0);
  EXPECT_NEAR(khr_spot_falloff(outer, inner, outer), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(khr_spot_falloff(60 * kDeg, inner, outer), 0.0);
  // Halfway in cos θ the linear ramp is 1/2, squared 1/4.
  const double mid = std::acos(0.5 * (std::cos(inner) + std::cos(outer)));
  EXPECT_NEAR(khr_spot_falloff(mid, inner, outer), 0.25, 1e-12);
  // Monotone between the cones.
  double last = 1.0;
  for (double t = inner; t <= outer; t += 0.1 * kDeg) {
    const double v = khr_spot_falloff(t, inner, outer);
    EXPECT_LE(v, last + 1e-15);
    last = v;
  }
}

TEST(GltfLights, SpotFluxClosedFormMatchesQuadrature) {
  const double I = 1000.0;
  for (auto [inner_deg, outer_deg] : {std::pair{0.0, 45.0}, std::pair{10.0, 30.0},
                                      std::pair{5.0, 6.0}, std::pair{0.0, 90.0},
                                      std::pair{30.0, 30.0}, std::pair{40.0, 20.0}}) {
    const double inner = inner_deg * kDeg, outer = outer_deg * kDeg;
    const double closed = khr_spot_flux_lm(I, inner, outer);
    const double numeric =
        solid_angle_integral([&](double t) { return I * khr_spot_falloff(t, inner, outer); });
    EXPECT_NEAR(closed, numeric, 2e-5 * closed) << inner_deg << " " << outer_deg;
  }
  // Full hemisphere with a hard edge is 2πI.
  EXPECT_NEAR(khr_spot_flux_lm(I, kPi / 2, kPi / 2), 2 * kPi * I, 1e-9);
}

// The tabulated profile, interpolated as photometry::interpolate does,
// carries the closed-form flux and the shape of the falloff.
TEST(GltfLights, SpotDistributionIsValidAndCarriesTheFlux) {
  const double I = 500.0;
  for (auto [inner_deg, outer_deg] :
       {std::pair{0.0, 45.0}, std::pair{10.0, 30.0}, std::pair{2.0, 4.0}, std::pair{25.0, 25.0}}) {
    const double inner = inner_deg * kDeg, outer = outer_deg * kDeg;
    const photometry::Distribution d = khr_spot_distribution(I, inner, outer);
    ASSERT_TRUE(photometry::validate(d).ok()) << photometry::validate(d).error().message;
    EXPECT_EQ(d.symmetry, photometry::Symmetry::Rotational);
    EXPECT_TRUE(d.absolute);
    const photometry::Distribution e = photometry::expand_symmetry(d);
    EXPECT_DOUBLE_EQ(photometry::interpolate(e, 0.0, 0.0), I);
    EXPECT_DOUBLE_EQ(photometry::interpolate(e, 123.0, 90.0), 0.0);
    const double numeric = solid_angle_integral(
        [&](double t) { return photometry::interpolate(e, 37.0, t / kDeg); });
    const double closed = khr_spot_flux_lm(I, inner, outer);
    EXPECT_NEAR(numeric, closed, 1e-4 * closed) << inner_deg << " " << outer_deg;
    for (double g = 0.0; g < outer_deg; g += 0.37)
      EXPECT_NEAR(photometry::interpolate(e, 0.0, g), I * khr_spot_falloff(g * kDeg, inner, outer),
                  2e-4 * I)
          << g;
  }
}

TEST(GltfLights, LightFramePutsNadirOnMinusZAndC0OnPlusX) {
  // Untransformed node: EXT_lights_ies's (0, 0) is −Z, C0 +X, C90 +Y.
  const photometry::PhotometricFrame f = light_frame({1, 0, 0}, {0, 0, 1});
  const Vec3 nadir = f.to_world(photometry::direction_from_c_gamma(0.0, 0.0));
  EXPECT_NEAR(nadir.z, -1.0, 1e-15);
  const Vec3 c0 = f.to_world(photometry::direction_from_c_gamma(0.0, kPi / 2));
  EXPECT_NEAR(c0.x, 1.0, 1e-15);
  const Vec3 c90 = f.to_world(photometry::direction_from_c_gamma(kPi / 2, kPi / 2));
  EXPECT_NEAR(c90.y, 1.0, 1e-15);
  // Scale and shear are removed: the frame stays orthonormal.
  const photometry::PhotometricFrame g = light_frame({3, 0, 1}, {0, 0, 0.5});
  EXPECT_NEAR(length(g.c0), 1.0, 1e-12);
  EXPECT_NEAR(dot(g.c0, g.up), 0.0, 1e-12);
  EXPECT_NEAR(g.c0.x, 1.0, 1e-12);
  EXPECT_NEAR(g.up.z, 1.0, 1e-12);
}

}  // namespace
}  // namespace gonio::io
