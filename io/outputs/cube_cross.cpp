#include "io/outputs/cube_cross.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "sim/detectors/cube_map.h"

#include "photometry/diagnostics.h"

namespace gonio::io {
namespace {

// sRGB encoding of linear values in [0, 1] quantised to 16 bits: a table,
// because a pow per texel was most of the cost of drawing the cross. The
// quantisation changes no 8-bit output by more than the rounding (an 8-bit
// step is at least 20 table steps, at black).
constexpr int kTableSize = 65536;

const std::array<std::uint8_t, kTableSize>& srgb_table() {
  static const std::array<std::uint8_t, kTableSize> table = [] {
    std::array<std::uint8_t, kTableSize> t{};
    for (int i = 0; i < kTableSize; ++i) {
      const double v = static_cast<double>(i) / (kTableSize - 1);
      const double encoded = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
      t[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(std::lround(255.0 * encoded));
    }
    return t;
  }();
  return table;
}

std::uint8_t srgb8(double linear) {
  const double v = std::clamp(linear, 0.0, 1.0);
  return srgb_table()[static_cast<std::size_t>(std::lround(v * (kTableSize - 1)))];
}

}  // namespace

CrossSlot cross_slot(int face) {
  // +X, −X, +Y, −Y, +Z, −Z
  static constexpr CrossSlot kSlots[6] = {{2, 1}, {0, 1}, {1, 0}, {1, 2}, {3, 1}, {1, 1}};
  GONIO_CHECK(face >= 0 && face < 6);
  return kSlots[face];
}

double soft_shoulder(double x, double knee) {
  GONIO_CHECK(knee > 0.0 && knee < 1.0);
  if (!(x > knee)) return x;
  const double room = 1.0 - knee;
  return knee + room * -std::expm1(-(x - knee) / room);
}

double flux_quantile_cd(const sim::CubeMapGrid& grid, std::span<const double> intensity_cd, double quantile) {
  GONIO_CHECK(quantile > 0.0 && quantile <= 1.0);
  GONIO_CHECK(intensity_cd.size() == grid.texel_count());
  struct Texel {
    double intensity, flux;
  };
  std::vector<Texel> texels;
  texels.reserve(intensity_cd.size());
  double total = 0.0;
  for (std::size_t t = 0; t < intensity_cd.size(); ++t) {
    const double v = intensity_cd[t];
    if (!std::isfinite(v) || !(v > 0.0)) continue;
    const double flux = v * grid.texel_solid_angle(t);
    texels.push_back({v, flux});
    total += flux;
  }
  if (!(total > 0.0)) return 0.0;
  // The first texel in order of intensity at which the running flux reaches
  // the target, by weighted quickselect: each round places the middle
  // element of the open range [lo, hi) and keeps the side holding the answer,
  // so the work is linear (a preview's white point is computed every
  // iteration; a full sort of 6 × 256² texels took ~30 ms).
  const double target = quantile * total;
  const auto by_intensity = [](const Texel& a, const Texel& b) { return a.intensity < b.intensity; };
  double below = 0.0;  // flux of the texels known to come before lo
  std::size_t lo = 0, hi = texels.size();
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    std::nth_element(texels.begin() + static_cast<std::ptrdiff_t>(lo),
                     texels.begin() + static_cast<std::ptrdiff_t>(mid),
                     texels.begin() + static_cast<std::ptrdiff_t>(hi), by_intensity);
    double left = 0.0;
    for (std::size_t i = lo; i < mid; ++i) left += texels[i].flux;
    if (below + left >= target) {
      hi = mid;
    } else if (below + left + texels[mid].flux >= target) {
      return texels[mid].intensity;
    } else {
      below += left + texels[mid].flux;
      lo = mid + 1;
    }
  }
  // Rounding kept the running sum under the target: the brightest texel.
  return std::max_element(texels.begin(), texels.end(), by_intensity)->intensity;
}

Image8 cube_cross_preview(const sim::CubeMapGrid& grid, std::span<const double> intensity_cd) {
  double white = flux_quantile_cd(grid, intensity_cd, kPreviewQuantile);
  if (!(white > 0.0)) white = 0.0;  // cube_cross_image then takes the maximum
  return cube_cross_image(grid.face_size(), intensity_cd, white, kPreviewKnee);
}

Image8 cube_cross_image(int face_size, std::span<const double> intensity_cd, double white_cd) {
  return cube_cross_image(face_size, intensity_cd, white_cd, 0.0);
}

Image8 cube_cross_image(int face_size, std::span<const double> intensity_cd, double white_cd, double knee) {
  GONIO_CHECK(face_size >= 1 && face_size <= 16384);
  const std::size_t n = static_cast<std::size_t>(face_size);
  GONIO_CHECK(intensity_cd.size() == 6 * n * n);
  if (!(white_cd > 0.0)) {
    white_cd = 0.0;
    for (double v : intensity_cd)
      if (std::isfinite(v)) white_cd = std::max(white_cd, v);
  }
  const double scale = white_cd > 0.0 ? 1.0 / white_cd : 0.0;
  Image8 image;
  image.width = 4 * face_size;
  image.height = 3 * face_size;
  image.channels = 2;
  image.pixels.assign(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 2, 0);
  for (int face = 0; face < 6; ++face) {
    const CrossSlot slot = cross_slot(face);
    for (std::size_t y = 0; y < n; ++y) {
      const std::size_t row = static_cast<std::size_t>(slot.row) * n + y;
      std::uint8_t* out = image.pixels.data() +
                          (row * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(slot.column) * n) * 2;
      for (std::size_t x = 0; x < n; ++x) {
        const double v = intensity_cd[(static_cast<std::size_t>(face) * n + y) * n + x];
        const double lin = v * scale;
        const std::uint8_t g = std::isfinite(v) ? srgb8(knee > 0.0 ? soft_shoulder(lin, knee) : lin) : 0;
        out[2 * x] = g;
        out[2 * x + 1] = 255;
      }
    }
  }
  return image;
}

}  // namespace gonio::io
