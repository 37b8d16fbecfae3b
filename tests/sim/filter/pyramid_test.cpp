#include "sim/filter/pyramid.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

namespace gonio::sim {
namespace {

constexpr double kFaceSolidAngle = 4.0 * std::numbers::pi / 6.0;

TEST(CubePyramid, LevelsFollowTheHalvingsOfTheFaceSize) {
  EXPECT_EQ(CubePyramid::max_levels(256), 9);
  EXPECT_EQ(CubePyramid::max_levels(128), 8);
  EXPECT_EQ(CubePyramid::max_levels(1), 1);
  EXPECT_EQ(CubePyramid::max_levels(100), 3);  // 100, 50, 25
  EXPECT_EQ(CubePyramid::max_levels(7), 1);
  EXPECT_EQ(CubePyramid(64, 99).levels(), 7);
  EXPECT_EQ(CubePyramid(64, 0).levels(), 1);
  const CubePyramid p(100, 5);
  EXPECT_EQ(p.levels(), 3);
  EXPECT_EQ(p.face_size(2), 25);
  EXPECT_EQ(p.texel_count(1), 6u * 50 * 50);
}

TEST(CubePyramid, SolidAnglesAreTheExactCoarseTexels) {
  const int n = 64;
  const CubePyramid p(n, 99);
  for (int k = 0; k < p.levels(); ++k) {
    const int m = p.face_size(k);
    const std::span<const double> omega = p.face_solid_angle_sr(k);
    double sum = 0.0;
    for (int y = 0; y < m; ++y) {
      for (int x = 0; x < m; ++x) {
        const double step = 2.0 / m;
        const double exact = CubeMapGrid::solid_angle(-1 + x * step, -1 + y * step,
                                                      -1 + (x + 1) * step, -1 + (y + 1) * step);
        EXPECT_NEAR(omega[static_cast<std::size_t>(y * m + x)], exact, 1e-13 * exact + 1e-16);
        sum += omega[static_cast<std::size_t>(y * m + x)];
      }
    }
    EXPECT_NEAR(sum, kFaceSolidAngle, 1e-12) << "level " << k;
  }
}

TEST(CubePyramid, PullSumsFluxAndPhotonsOfTheFourTexelsBelow) {
  const int n = 32;
  FarField field(n);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 2.0);
  std::uniform_int_distribution<int> k(0, 9);
  for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, u(rng), static_cast<std::uint64_t>(k(rng)));
  CubePyramid p(n, 99);
  p.pull(field);
  ASSERT_EQ(p.levels(), 6);
  EXPECT_EQ(p.flux_lm(0).data(), field.flux_lm().data());  // level 0 is the field
  for (int level = 1; level < p.levels(); ++level) {
    const std::size_t m = static_cast<std::size_t>(p.face_size(level)), fine = 2 * m;
    const auto flux = p.flux_lm(level), below_flux = p.flux_lm(level - 1);
    const auto photons = p.photons(level), below_photons = p.photons(level - 1);
    for (std::size_t face = 0; face < 6; ++face) {
      for (std::size_t y = 0; y < m; ++y) {
        for (std::size_t x = 0; x < m; ++x) {
          const std::size_t t = (face * m + y) * m + x;
          const std::size_t c = (face * fine + 2 * y) * fine + 2 * x;
          EXPECT_EQ(photons[t], below_photons[c] + below_photons[c + 1] + below_photons[c + fine] +
                                    below_photons[c + fine + 1]);
          EXPECT_NEAR(flux[t], below_flux[c] + below_flux[c + 1] + below_flux[c + fine] + below_flux[c + fine + 1],
                      1e-12);
        }
      }
    }
    double total = 0.0;
    std::uint64_t count = 0;
    for (std::size_t t = 0; t < p.texel_count(level); ++t) {
      total += flux[t];
      count += photons[t];
    }
    EXPECT_NEAR(total, field.total_flux_lm(), 1e-9);
    EXPECT_EQ(count, field.total_photons());
  }
}

TEST(CubePyramid, IntensityOfAnIsotropicFieldIsTheSameOnEveryLevel) {
  // Flux in proportion to solid angle is a constant intensity; because the
  // pyramid sums solid angle like flux, no level sees the cube's uneven
  // texel sizes as a pattern.
  const int n = 64;
  FarField field(n);
  const double intensity = 795.77;
  for (std::size_t t = 0; t < field.texel_count(); ++t)
    field.add(t, intensity * field.grid().texel_solid_angle(t));
  CubePyramid p(n, 99);
  p.pull(field);
  for (int level = 0; level < p.levels(); ++level)
    for (std::size_t t = 0; t < p.texel_count(level); ++t)
      ASSERT_NEAR(p.flux_lm(level)[t] / p.solid_angle_sr(level, t), intensity, 1e-9) << level;
}

TEST(CubePyramid, GivenSolidAnglesAreSummedToo) {
  std::vector<double> equal(16 * 16, 1.0);
  const CubePyramid p(16, 99, equal);
  EXPECT_EQ(p.levels(), 5);
  for (int level = 0; level < p.levels(); ++level)
    EXPECT_EQ(p.face_solid_angle_sr(level)[0], static_cast<double>(1 << (2 * level)));
}

}  // namespace
}  // namespace gonio::sim
