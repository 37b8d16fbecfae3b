#include "sim/detectors/far_field_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(ExpectedTexelFlux, ConstantIntensityGivesFluxInProportionToSolidAngle) {
  const CubeMapGrid grid(16);
  const std::vector<double> flux = expected_texel_flux(grid, [](const Vec3&) { return 2.0; }, 3);
  double total = 0.0;
  for (std::size_t t = 0; t < flux.size(); ++t) {
    EXPECT_NEAR(flux[t], 2.0 * grid.texel_solid_angle(t), 1e-14);
    total += flux[t];
  }
  EXPECT_NEAR(total, 8.0 * kPi, 1e-12);
}

TEST(ExpectedTexelFlux, LambertianLobeIntegratesToPiTimesPeak) {
  // I = I0 cos γ on the lower hemisphere: Φ = π I0 (VALIDATION.md).
  const CubeMapGrid grid(32);
  const double i0 = 3183.1;
  const auto lambert = [&](const Vec3& d) { return d.y < 0.0 ? -d.y * i0 : 0.0; };
  double total = 0.0;
  for (double f : expected_texel_flux(grid, lambert, 4)) total += f;
  EXPECT_NEAR(total / (kPi * i0), 1.0, 1e-4);
}

TEST(FarFieldSampler, ProbabilitiesAreTheNormalisedWeights) {
  const std::vector<double> w = {0.0, 1.0, 5.0, 0.5, 3.5, 0.0, 2.0, 8.0};
  const FarFieldSampler sampler(w);
  for (std::size_t i = 0; i < w.size(); ++i) EXPECT_DOUBLE_EQ(sampler.probability(i), w[i] / 20.0);
  for (double u = 0.0; u < 1.0; u += 1e-3) EXPECT_NE(w[sampler.sample(u)], 0.0);
}

TEST(FarFieldSampler, PhotonsFillTexelsInProportionToExpectedFlux) {
  const CubeMapGrid grid(4);
  const auto lobe = [](const Vec3& d) { return 1.0 + 0.8 * d.x + 0.1 * d.z * d.z; };
  const std::vector<double> expected = expected_texel_flux(grid, lobe, 4);
  const FarFieldSampler sampler(expected);
  FarField field(4);
  std::mt19937_64 rng(5);
  const std::uint64_t photons = 400'000;
  sampler.add_photons(field, photons, 0.25, rng);
  EXPECT_EQ(field.total_photons(), photons);
  EXPECT_DOUBLE_EQ(field.total_flux_lm(), 0.25 * photons);
  for (std::size_t t = 0; t < field.texel_count(); ++t) {
    const double mean = photons * sampler.probability(t);
    EXPECT_NEAR(static_cast<double>(field.photons(t)), mean, 5.0 * std::sqrt(mean)) << t;
  }
}

}  // namespace
}  // namespace gonio::sim
