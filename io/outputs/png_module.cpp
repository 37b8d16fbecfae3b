// The PNG codec module (gonio_png.so): the only file of Gonio that includes
// OpenImageIO. io/outputs/image.cpp loads it with dlopen at the first PNG written or
// read, so that processes that never touch a PNG do not load OpenImageIO's
// ~250 shared libraries (~0.4 s at every start). The interface is
// io/outputs/png_module.h: plain data in, bytes or pixels out, errors as text.
#include "io/outputs/png_module.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <vector>

extern "C" {

int gonio_png_module_version() { return gonio::io::kPngModuleVersion; }

bool gonio_png_encode(const gonio::io::Image8* image, std::vector<unsigned char>* bytes,
                      std::string* error) {
  OIIO::Filesystem::IOVecOutput memory(*bytes);
  auto out = OIIO::ImageOutput::create("preview.png", &memory);
  if (!out) {
    *error = "cannot create a PNG writer: " + OIIO::geterror();
    return false;
  }
  OIIO::ImageSpec spec(image->width, image->height, image->channels, OIIO::TypeDesc::UINT8);
  if (image->channels == 2) spec.alpha_channel = 1;
  // Straight (not premultiplied) alpha, as PNG stores it: no conversion.
  spec.attribute("oiio:UnassociatedAlpha", 1);
  // Fast deflate and no row filters: previews are rewritten every iteration.
  // Level 1 took half the default's time (files 1.7× larger); libpng's
  // adaptive filter choice then took as long as the rest of writing a
  // 6 × 256² preview, filter included (BM_PreviewOutput: 53 → 29 ms).
  spec.attribute("png:compressionLevel", 1);
  spec.attribute("png:filter", 0x08);  // PNG_FILTER_NONE
  if (!out->open("preview.png", spec) ||
      !out->write_image(OIIO::TypeDesc::UINT8, image->pixels.data()) || !out->close()) {
    *error = "cannot encode PNG: " + out->geterror();
    return false;
  }
  return true;
}

bool gonio_png_decode(const char* path, gonio::io::Image8* image, std::string* error) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) {
    *error = "cannot read image: " + OIIO::geterror();
    return false;
  }
  const OIIO::ImageSpec& spec = in->spec();
  constexpr long long kMaxPixels = 1LL << 28;
  if (spec.width <= 0 || spec.height <= 0 ||
      static_cast<long long>(spec.width) * spec.height > kMaxPixels || spec.nchannels < 1 ||
      spec.nchannels > 4) {
    *error = "image size or channel count out of range";
    return false;
  }
  image->width = spec.width;
  image->height = spec.height;
  image->channels = spec.nchannels;
  image->pixels.assign(static_cast<std::size_t>(spec.width) * static_cast<std::size_t>(spec.height) *
                           static_cast<std::size_t>(spec.nchannels),
                       0);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, image->pixels.data())) {
    *error = "cannot decode image: " + in->geterror();
    return false;
  }
  in->close();
  return true;
}

}  // extern "C"
