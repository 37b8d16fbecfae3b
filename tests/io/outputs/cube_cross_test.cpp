#include "io/outputs/cube_cross.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "sim/detectors/cube_map.h"

namespace gonio::io {
namespace {

// The image pixel of texel (face, x, y) in the cross.
std::pair<int, int> pixel_of(int n, int face, int x, int y) {
  const CrossSlot s = cross_slot(face);
  return {s.column * n + x, s.row * n + y};
}

TEST(CubeCross, EveryEdgeOfTheCrossJoinsNeighboursOnTheSphere) {
  // Two image pixels side by side that belong to different faces must be
  // texels next to each other on the sphere: centres about one texel apart.
  const int n = 16;
  const sim::CubeMapGrid grid(n);
  std::vector<long> texel_at(static_cast<std::size_t>(4 * n * 3 * n), -1);
  for (int face = 0; face < 6; ++face)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const auto [px, py] = pixel_of(n, face, x, y);
        texel_at[static_cast<std::size_t>(py * 4 * n + px)] = static_cast<long>(grid.index(face, x, y));
      }
  const double texel_angle = 2.0 * std::atan(1.0 / n);  // at a face centre
  int joints = 0;
  for (int py = 0; py < 3 * n; ++py) {
    for (int px = 0; px < 4 * n; ++px) {
      const long a = texel_at[static_cast<std::size_t>(py * 4 * n + px)];
      if (a < 0) continue;
      for (auto [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
        if (px + dx >= 4 * n || py + dy >= 3 * n) continue;
        const long b = texel_at[static_cast<std::size_t>((py + dy) * 4 * n + px + dx)];
        if (b < 0 || a / (n * n) == b / (n * n)) continue;
        ++joints;
        const double angle = std::acos(std::clamp(
            dot(grid.texel_direction(static_cast<std::size_t>(a)), grid.texel_direction(static_cast<std::size_t>(b))),
            -1.0, 1.0));
        EXPECT_LT(angle, 0.75 * texel_angle) << "pixel " << px << "," << py;
      }
    }
  }
  EXPECT_EQ(joints, 5 * n);  // five shared edges inside the cross
}

TEST(CubeCross, ToneMapsToSrgbGreyWithTransparentBackground) {
  const int n = 2;
  std::vector<double> v(6 * n * n, 0.0);
  v[sim::CubeMapGrid(n).index(3, 1, 0)] = 10.0;                             // −Y: the white point
  v[sim::CubeMapGrid(n).index(3, 0, 1)] = 5.0;                              // half
  v[sim::CubeMapGrid(n).index(0, 0, 0)] = std::numeric_limits<double>::quiet_NaN();
  const Image8 img = cube_cross_image(n, v);
  ASSERT_EQ(img.width, 8);
  ASSERT_EQ(img.height, 6);
  ASSERT_EQ(img.channels, 2);  // grey, alpha
  auto at = [&](int x, int y, int c) { return img.pixels[static_cast<std::size_t>((y * img.width + x) * 2 + c)]; };
  EXPECT_EQ(at(3, 4, 0), 255);  // −Y sits at column 1, row 2
  EXPECT_EQ(at(2, 5, 0), 188);  // sRGB(0.5) = 0.7354
  EXPECT_EQ(at(4, 2, 0), 0);    // +X (column 2, row 1), the NaN texel
  EXPECT_EQ(at(4, 2, 1), 255);
  EXPECT_EQ(at(0, 0, 1), 0);    // outside the cross
  // An explicit white point.
  EXPECT_EQ(cube_cross_image(n, v, 20.0).pixels[static_cast<std::size_t>((4 * img.width + 3) * 2)], 188);
  // The sRGB curve at every 8-bit step against its closed form.
  for (int i = 0; i <= 1000; ++i) {
    const double linear = i / 1000.0;
    std::vector<double> one(6 * n * n, 0.0);
    one[0] = linear;
    const double encoded = linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
    const Image8 g = cube_cross_image(n, one, 1.0);
    const auto [px, py] = pixel_of(n, 0, 0, 0);
    EXPECT_NEAR(g.pixels[static_cast<std::size_t>((py * g.width + px) * 2)], 255.0 * encoded, 0.5 + 1e-9) << linear;
  }
}

}  // namespace
}  // namespace gonio::io

namespace gonio::io {
namespace {

TEST(CubeCrossPreview, SoftShoulderIsLinearToTheKneeThenSmoothAndBelowOne) {
  const double k = kPreviewKnee;
  EXPECT_EQ(soft_shoulder(0.0, k), 0.0);
  EXPECT_EQ(soft_shoulder(0.5, k), 0.5);
  EXPECT_EQ(soft_shoulder(k, k), k);
  // Slope 1 on both sides of the knee, increasing, approaching 1.
  const double h = 1e-6;
  EXPECT_NEAR((soft_shoulder(k + h, k) - k) / h, 1.0, 1e-5);
  double last = k;
  for (double x = k + 0.01; x < 6.0; x *= 1.1) {  // exp underflows to 1 beyond
    const double y = soft_shoulder(x, k);
    EXPECT_GT(y, last);
    EXPECT_LT(y, 1.0);
    last = y;
  }
  // Closed form: one white above the knee gives k + (1 − k)(1 − e^−1).
  EXPECT_NEAR(soft_shoulder(1.0, k), k + (1 - k) * (1 - std::exp(-1.0)), 1e-15);
}

double srgb(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
}

TEST(CubeCrossPreview, WhitePointIsTheFluxQuantileSoOneBrightTexelLeavesTheRestVisible) {
  const int n = 64;
  const sim::CubeMapGrid grid(n);
  // A uniform 100 cd sphere with one texel of 10⁴ cd (the lamp seen through
  // an opening): 100 times brighter, but well under 1 % of the flux.
  std::vector<double> v(grid.texel_count(), 100.0);
  const std::size_t spot = grid.index(3, 32, 32);
  v[spot] = 1e4;
  double total = 0.0;
  for (std::size_t t = 0; t < v.size(); ++t) total += v[t] * grid.texel_solid_angle(t);
  ASSERT_LT(v[spot] * grid.texel_solid_angle(spot) / total, 0.01);
  EXPECT_EQ(flux_quantile_cd(grid, v, kPreviewQuantile), 100.0);
  EXPECT_EQ(flux_quantile_cd(grid, v, 1.0), 1e4);
  EXPECT_EQ(flux_quantile_cd(grid, std::vector<double>(grid.texel_count(), 0.0), 0.99), 0.0);

  const Image8 preview = cube_cross_preview(grid, v);
  const Image8 linear = cube_cross_image(n, v);
  const auto grey = [&](const Image8& img, int face, int x, int y) {
    const CrossSlot s = cross_slot(face);
    const int px = s.column * n + x, py = s.row * n + y;
    return static_cast<int>(img.pixels[static_cast<std::size_t>((py * img.width + px) * 2)]);
  };
  // The background at white: the shoulder's value at 1; the spot near 1.
  EXPECT_NEAR(grey(preview, 0, 3, 3), 255.0 * srgb(soft_shoulder(1.0, kPreviewKnee)), 0.5);
  EXPECT_EQ(grey(preview, 3, 32, 32), 255);
  // The linear mapping to the maximum leaves the background at 1 % of white.
  EXPECT_NEAR(grey(linear, 0, 3, 3), 255.0 * srgb(0.01), 0.5);
  EXPECT_EQ(grey(linear, 3, 32, 32), 255);
}

TEST(CubeCrossPreview, FluxQuantileIsTheSortedRunningSumsAnswer) {
  // Against the definition, by a full sort: random maps with ties, zeros,
  // negative and non-finite values, for quantiles from tiny to 1.
  const int n = 24;
  const sim::CubeMapGrid grid(n);
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> v(grid.texel_count());
    for (double& x : v) {
      const auto r = rng() % 100;
      x = r < 10 ? 0.0 : r < 12 ? -3.0 : r < 13 ? std::nan("") : r < 40 ? 50.0 : static_cast<double>(rng() % 10000) / 7.0;
    }
    std::vector<std::pair<double, double>> sorted;  // intensity, flux
    double total = 0.0;
    for (std::size_t t = 0; t < v.size(); ++t)
      if (std::isfinite(v[t]) && v[t] > 0.0) {
        sorted.emplace_back(v[t], v[t] * grid.texel_solid_angle(t));
        total += sorted.back().second;
      }
    std::sort(sorted.begin(), sorted.end());
    for (double q : {1e-6, 0.1, 0.5, 0.9, 0.99, 1.0}) {
      double sum = 0.0, expected = sorted.back().first;
      for (const auto& [intensity, flux] : sorted) {
        sum += flux;
        if (sum >= q * total) {
          expected = intensity;
          break;
        }
      }
      // Summation order differs (rounding); the answer may move only where
      // the running sum meets the target within rounding, i.e. to a
      // neighbour in order.
      const double got = flux_quantile_cd(grid, v, q);
      const auto at = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(expected, -1.0));
      const auto lo = at == sorted.begin() ? at : at - 1;
      const auto hi = std::min(sorted.end() - 1, at + 1);
      EXPECT_TRUE(got == expected || got == lo->first || got == hi->first)
          << "trial " << trial << " q " << q << ": " << got << " against " << expected;
    }
  }
}

TEST(CubeCrossPreview, ABeamCarryingTheFluxSetsTheWhitePoint) {
  const int n = 16;
  const sim::CubeMapGrid grid(n);
  std::vector<double> v(grid.texel_count(), 0.0);
  for (int y = 6; y < 10; ++y)
    for (int x = 6; x < 10; ++x) v[grid.index(3, x, y)] = 500.0;  // a beam on −Y
  EXPECT_EQ(flux_quantile_cd(grid, v, kPreviewQuantile), 500.0);
  const Image8 preview = cube_cross_preview(grid, v);
  const CrossSlot s = cross_slot(3);
  EXPECT_NEAR(preview.pixels[static_cast<std::size_t>(((s.row * n + 7) * preview.width + s.column * n + 7) * 2)],
              255.0 * srgb(soft_shoulder(1.0, kPreviewKnee)), 0.5);
}

}  // namespace
}  // namespace gonio::io
