#include "io/outputs/image.h"

#include <dlfcn.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "io/support/file_io.h"
#include "io/support/process.h"
#include "io/outputs/png_module.h"

#ifndef GONIO_PNG_MODULE_BUILD_PATH
#define GONIO_PNG_MODULE_BUILD_PATH ""
#endif

namespace gonio::io {
namespace {

// The module's entry points, or why it could not be loaded.
struct PngModule {
  decltype(&gonio_png_encode) encode = nullptr;
  decltype(&gonio_png_decode) decode = nullptr;
  std::string error;  // empty when loaded
};

std::vector<std::string> module_candidates() {
  return beside_executable(kPngModuleName, GONIO_PNG_MODULE_BUILD_PATH);
}

PngModule load_module(const std::vector<std::string>& candidates) {
  PngModule m;
  std::string tried;
  for (const std::string& path : candidates) {
    tried += (tried.empty() ? "" : ", ") + path;
    if (access(path.c_str(), R_OK) != 0) continue;
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      m.error = "cannot load the PNG module " + path + ": " + (why ? why : "unknown error");
      return m;
    }
    // The handle stays open for the life of the process.
    auto version = reinterpret_cast<decltype(&gonio_png_module_version)>(
        dlsym(handle, "gonio_png_module_version"));
    m.encode = reinterpret_cast<decltype(&gonio_png_encode)>(dlsym(handle, "gonio_png_encode"));
    m.decode = reinterpret_cast<decltype(&gonio_png_decode)>(dlsym(handle, "gonio_png_decode"));
    if (!version || !m.encode || !m.decode || version() != kPngModuleVersion) {
      m.encode = nullptr;
      m.decode = nullptr;
      m.error = "the PNG module " + path + " is not the one this gonio was built with";
    }
    return m;
  }
  m.error = std::string("the PNG module ") + kPngModuleName +
            " (OpenImageIO) is missing; looked for " + tried;
  return m;
}

// Loaded once, at the first PNG written or read (thread-safe static).
const PngModule& png_module() {
  static const PngModule module = load_module(module_candidates());
  return module;
}

}  // namespace

Status load_png_module(const std::vector<std::string>& candidates) {
  const PngModule m = load_module(candidates);
  if (!m.encode) return make_error("", m.error);
  return Ok{};
}

Status write_png(const std::string& path, const Image8& image) {
  if (image.width <= 0 || image.height <= 0 || image.channels < 1 || image.channels > 4 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) *
                                 static_cast<std::size_t>(image.height) *
                                 static_cast<std::size_t>(image.channels))
    return make_error(path, "internal: malformed image");
  const PngModule& m = png_module();
  if (!m.encode) return make_error(path, m.error);
  std::vector<unsigned char> bytes;
  std::string error;
  if (!m.encode(&image, &bytes, &error)) return make_error(path, error);
  return write_file_atomic(
      path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

Result<Image8> read_png(const std::string& path) {
  const PngModule& m = png_module();
  if (!m.decode) return make_error(path, m.error);
  Image8 image;
  std::string error;
  if (!m.decode(path.c_str(), &image, &error)) return make_error(path, error);
  return image;
}

}  // namespace gonio::io
