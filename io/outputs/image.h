// PNG files through OpenImageIO, which is loaded only when a PNG is first
// written or read: the codec is the module gonio_png.so (io/outputs/png_module.cpp),
// found next to the executable, in ../lib/gonio/ beside it, or where the build
// wrote it. Linked at start, OpenImageIO's ~250 shared libraries cost every
// gonio process ~0.4 s. Without the module every call here returns an error
// naming the places looked in.
#pragma once

#include <string>
#include <vector>

#include "io/outputs/image8.h"
#include "photometry/diagnostics.h"

namespace gonio::io {

// Writes an 8-bit PNG (1 to 4 channels), atomically (encoded in memory,
// then io::write_file_atomic): a viewer watching the path sees the old
// picture or the new one, never half of one.
Status write_png(const std::string& path, const Image8& image);

// Reads a PNG (any image OpenImageIO reads) as 8 bits per channel, with the
// file's channels (for tests and tools).
Result<Image8> read_png(const std::string& path);

// Loads the module from the first of `candidates` that exists, as write_png
// and read_png do with their own list: ok, or the error they would return
// (missing module, a file that is no module, a module of another build).
Status load_png_module(const std::vector<std::string>& candidates);

}  // namespace gonio::io
