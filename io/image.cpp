#include "io/image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <vector>

#include "io/file_io.h"

namespace gonio::io {
namespace {

// One out-of-line constructor: GCC 12 reports false maybe-uninitialized
// warnings for Error temporaries built inline next to OpenImageIO's code.
Error image_error(const std::string& path, const std::string& message) {
  return Error{SourceLoc{path, 0, 0}, message};
}

}  // namespace

Status write_png(const std::string& path, const Rgba8Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4)
    return image_error(path, "internal: malformed image");
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  auto out = OIIO::ImageOutput::create("preview.png", &memory);
  if (!out) return image_error(path, "cannot create a PNG writer: " + OIIO::geterror());
  OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::UINT8);
  // Straight (not premultiplied) alpha, as PNG stores it: no conversion.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  if (!out->open("preview.png", spec) || !out->write_image(OIIO::TypeDesc::UINT8, image.rgba.data()) ||
      !out->close())
    return image_error(path, "cannot encode PNG: " + out->geterror());
  return write_file_atomic(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

Result<Rgba8Image> read_png(const std::string& path) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) return image_error(path, "cannot read image: " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  constexpr long long kMaxPixels = 1LL << 28;
  if (spec.width <= 0 || spec.height <= 0 || static_cast<long long>(spec.width) * spec.height > kMaxPixels)
    return image_error(path, "image size out of range");
  Rgba8Image image;
  image.width = spec.width;
  image.height = spec.height;
  image.rgba.assign(static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) * 4, 255);
  const int channels = std::min(spec.nchannels, 4);
  // Channels read into the first `channels` bytes of each RGBA pixel.
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, image.rgba.data(), 4))
    return image_error(path, "cannot decode image: " + in->geterror());
  in->close();
  return image;
}

}  // namespace gonio::io
