// PNG files through OpenImageIO: the only file of Gonio that includes it
// (OpenImageIO costs ~0.3 s at process start, so only the gonio executable
// and one small test link this target, gonio::io_image).
#pragma once

#include <string>

#include "io/image8.h"
#include "photometry/diagnostics.h"

namespace gonio::io {

// Writes an 8-bit PNG (1 to 4 channels), atomically (encoded in memory,
// then io::write_file_atomic): a viewer watching the path sees the old
// picture or the new one, never half of one.
Status write_png(const std::string& path, const Image8& image);

// Reads a PNG (any image OpenImageIO reads) as 8 bits per channel, with the
// file's channels (for tests and tools).
Result<Image8> read_png(const std::string& path);

}  // namespace gonio::io
