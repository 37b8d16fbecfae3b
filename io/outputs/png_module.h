// The interface between io/outputs/image.cpp and the PNG codec module gonio_png.so
// (io/outputs/png_module.cpp, the only OpenImageIO file). Internal to io: callers use
// io/outputs/image.h. Both sides are built together, so C++ types may cross; the
// version guards against a stale module beside a newer executable.
#pragma once

#include <string>
#include <vector>

#include "io/outputs/image8.h"

namespace gonio::io {

inline constexpr int kPngModuleVersion = 1;
// The module's file name; io/outputs/image.cpp looks for it next to the executable,
// then in ../lib/gonio/ beside it, then where the build put it.
inline constexpr const char* kPngModuleName = "gonio_png.so";

}  // namespace gonio::io

extern "C" {
// kPngModuleVersion of the module.
int gonio_png_module_version();
// Encodes `image` (already checked: 1–4 channels, sizes consistent) as an
// 8-bit PNG into `bytes`; false and `error` set on failure.
bool gonio_png_encode(const gonio::io::Image8* image, std::vector<unsigned char>* bytes,
                      std::string* error);
// Decodes the image at `path` into `image` with its own channels (1–4, at
// most 2²⁸ pixels); false and `error` set on failure.
bool gonio_png_decode(const char* path, gonio::io::Image8* image, std::string* error);
}
