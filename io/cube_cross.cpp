#include "io/cube_cross.h"

#include <algorithm>
#include <cmath>

#include "photometry/diagnostics.h"

namespace gonio::io {
namespace {

std::uint8_t srgb8(double linear) {
  const double v = std::clamp(linear, 0.0, 1.0);
  const double encoded = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  return static_cast<std::uint8_t>(std::lround(255.0 * encoded));
}

}  // namespace

CrossSlot cross_slot(int face) {
  // +X, −X, +Y, −Y, +Z, −Z
  static constexpr CrossSlot kSlots[6] = {{2, 1}, {0, 1}, {1, 0}, {1, 2}, {3, 1}, {1, 1}};
  GONIO_CHECK(face >= 0 && face < 6);
  return kSlots[face];
}

Rgba8Image cube_cross_image(int face_size, std::span<const double> intensity_cd, double white_cd) {
  GONIO_CHECK(face_size >= 1 && face_size <= 16384);
  const std::size_t n = static_cast<std::size_t>(face_size);
  GONIO_CHECK(intensity_cd.size() == 6 * n * n);
  if (!(white_cd > 0.0)) {
    white_cd = 0.0;
    for (double v : intensity_cd)
      if (std::isfinite(v)) white_cd = std::max(white_cd, v);
  }
  const double scale = white_cd > 0.0 ? 1.0 / white_cd : 0.0;
  Rgba8Image image;
  image.width = 4 * face_size;
  image.height = 3 * face_size;
  image.rgba.assign(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4, 0);
  for (int face = 0; face < 6; ++face) {
    const CrossSlot slot = cross_slot(face);
    for (std::size_t y = 0; y < n; ++y) {
      const std::size_t row = static_cast<std::size_t>(slot.row) * n + y;
      std::uint8_t* out = image.rgba.data() +
                          (row * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(slot.column) * n) * 4;
      for (std::size_t x = 0; x < n; ++x) {
        const double v = intensity_cd[(static_cast<std::size_t>(face) * n + y) * n + x];
        const std::uint8_t g = std::isfinite(v) ? srgb8(v * scale) : 0;
        out[4 * x + 0] = out[4 * x + 1] = out[4 * x + 2] = g;
        out[4 * x + 3] = 255;
      }
    }
  }
  return image;
}

}  // namespace gonio::io
