// An 8-bit image in memory: what the PNG writer (io/outputs/image.h) writes and the
// cube-map pictures (io/outputs/cube_cross.h) draw. Plain data, no dependencies.
#pragma once

#include <cstdint>
#include <vector>

namespace gonio::io {

// Pixels row by row from the top, `channels` bytes each: 1 grey, 2 grey and
// alpha (straight, not premultiplied), 3 RGB, 4 RGBA.
struct Image8 {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<std::uint8_t> pixels;  // width · height · channels
};

}  // namespace gonio::io
