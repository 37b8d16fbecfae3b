// PNG files through OpenImageIO: the only file of Gonio that includes it
// (OpenImageIO costs ~0.3 s at process start, so only the gonio executable
// and one small test link this target, gonio::io_image).
#pragma once

#include <string>

#include "io/cube_cross.h"
#include "photometry/diagnostics.h"

namespace gonio::io {

// Writes an 8-bit RGBA PNG, atomically (encoded in memory, then
// io::write_file_atomic): a viewer watching the path sees the old picture or
// the new one, never half of one.
Status write_png(const std::string& path, const Rgba8Image& image);

// Reads a PNG as 8-bit RGBA (for tests and tools).
Result<Rgba8Image> read_png(const std::string& path);

}  // namespace gonio::io
