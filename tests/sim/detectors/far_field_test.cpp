#include "sim/detectors/far_field.h"

#include <gtest/gtest.h>

#include <numbers>

namespace gonio::sim {
namespace {

TEST(FarField, IntensityIsFluxOverExactSolidAngle) {
  FarField f(8);
  // An isotropic source of 1000 lm put into every texel in proportion to its
  // solid angle has 1000 / 4π cd everywhere, whatever the texel's size.
  for (std::size_t t = 0; t < f.texel_count(); ++t)
    f.add(t, 1000.0 * f.grid().texel_solid_angle(t) / (4.0 * std::numbers::pi), 3);
  for (std::size_t t = 0; t < f.texel_count(); ++t)
    EXPECT_NEAR(f.intensity_cd(t), 1000.0 / (4.0 * std::numbers::pi), 1e-9);
  EXPECT_NEAR(f.total_flux_lm(), 1000.0, 1e-9);
  EXPECT_EQ(f.total_photons(), 3 * f.texel_count());
}

TEST(FarField, AddingFarFieldsSumsTexels) {
  FarField a(2), b(2);
  a.add(5, 1.5);
  b.add(5, 2.0, 4);
  b.add(7, 1.0);
  a.add(b);
  EXPECT_DOUBLE_EQ(a.flux_lm(5), 3.5);
  EXPECT_EQ(a.photons(5), 5u);
  EXPECT_EQ(a.photons(7), 1u);
  a.clear();
  EXPECT_EQ(a.total_photons(), 0u);
  EXPECT_EQ(a.total_flux_lm(), 0.0);
}

}  // namespace
}  // namespace gonio::sim
