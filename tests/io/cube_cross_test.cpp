#include "io/cube_cross.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "sim/cube_map.h"

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
