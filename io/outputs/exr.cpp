#include "io/outputs/exr.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfEnvmap.h>
#include <OpenEXR/ImfEnvmapAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <set>
#include <stdexcept>

#include "io/support/file_io.h"

namespace gonio::io {
namespace {

constexpr std::size_t kMaxPixels = std::size_t{1} << 28;
constexpr std::size_t kMaxChannels = 64;
constexpr std::size_t kMaxFileBytes = std::size_t{1} << 32;

// OpenEXR writes through this into memory, so that the file can then be
// written atomically.
class MemoryOStream : public Imf::OStream {
 public:
  MemoryOStream() : Imf::OStream("memory") {}
  void write(const char c[], int n) override {
    const std::size_t end = position_ + static_cast<std::size_t>(n);
    if (end > bytes_.size()) bytes_.resize(end);
    std::memcpy(bytes_.data() + position_, c, static_cast<std::size_t>(n));
    position_ = end;
  }
  uint64_t tellp() override { return position_; }
  void seekp(uint64_t pos) override { position_ = static_cast<std::size_t>(pos); }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
  std::size_t position_ = 0;
};

class MemoryIStream : public Imf::IStream {
 public:
  explicit MemoryIStream(const std::string& bytes) : Imf::IStream("memory"), bytes_(bytes) {}
  bool read(char c[], int n) override {
    if (n < 0 || position_ + static_cast<std::size_t>(n) > bytes_.size())
      throw std::runtime_error("unexpected end of file");
    std::memcpy(c, bytes_.data() + position_, static_cast<std::size_t>(n));
    position_ += static_cast<std::size_t>(n);
    return position_ < bytes_.size();
  }
  uint64_t tellg() override { return position_; }
  void seekg(uint64_t pos) override { position_ = static_cast<std::size_t>(pos); }
  void clear() override {}

 private:
  const std::string& bytes_;
  std::size_t position_ = 0;
};

}  // namespace

const ExrImage::FloatChannel* ExrImage::find_float(const std::string& name) const {
  for (const auto& c : float_channels)
    if (c.name == name) return &c;
  return nullptr;
}

const ExrImage::UintChannel* ExrImage::find_uint(const std::string& name) const {
  for (const auto& c : uint_channels)
    if (c.name == name) return &c;
  return nullptr;
}

const std::string* ExrImage::find_attribute(const std::string& name) const {
  for (const auto& [k, v] : attributes)
    if (k == name) return &v;
  return nullptr;
}

ExrImage cube_image(int face_size) {
  ExrImage image;
  image.width = face_size;
  image.height = 6 * face_size;
  image.envmap = Envmap::Cube;
  return image;
}

Status write_exr(const std::string& path, const ExrImage& image) {
  if (image.width < 1 || image.height < 1) return make_error(path, "image has no pixels");
  const std::size_t pixels = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  if (pixels > kMaxPixels) return make_error(path, "image too large to write");
  if (image.float_channels.empty() && image.uint_channels.empty())
    return make_error(path, "image has no channels");
  if (image.envmap == Envmap::Cube && image.height != 6 * image.width)
    return make_error(path, "a cube map must be N x 6N pixels");
  std::set<std::string> names;
  for (const auto& c : image.float_channels) {
    if (c.values.size() != pixels)
      return make_error(path, "channel '" + c.name + "' has the wrong size");
    if (c.name.empty() || !names.insert(c.name).second)
      return make_error(path, "channel names must be unique and non-empty");
  }
  for (const auto& c : image.uint_channels) {
    if (c.values.size() != pixels)
      return make_error(path, "channel '" + c.name + "' has the wrong size");
    if (c.name.empty() || !names.insert(c.name).second)
      return make_error(path, "channel names must be unique and non-empty");
  }

  MemoryOStream stream;
  try {
    Imf::Header header(image.width, image.height);
    header.compression() = image.compress ? Imf::ZIP_COMPRESSION : Imf::NO_COMPRESSION;
    if (image.envmap == Envmap::Cube) Imf::addEnvmap(header, Imf::ENVMAP_CUBE);
    if (image.envmap == Envmap::LatLong) Imf::addEnvmap(header, Imf::ENVMAP_LATLONG);
    for (const auto& [k, v] : image.attributes) header.insert(k, Imf::StringAttribute(v));
    Imf::FrameBuffer frame;
    const std::size_t row = static_cast<std::size_t>(image.width);
    for (const auto& c : image.float_channels) {
      header.channels().insert(c.name, Imf::Channel(Imf::FLOAT));
      frame.insert(c.name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(c.values.data())),
                                      sizeof(float), sizeof(float) * row));
    }
    for (const auto& c : image.uint_channels) {
      header.channels().insert(c.name, Imf::Channel(Imf::UINT));
      frame.insert(c.name,
                   Imf::Slice(Imf::UINT, reinterpret_cast<char*>(const_cast<std::uint32_t*>(c.values.data())),
                              sizeof(std::uint32_t), sizeof(std::uint32_t) * row));
    }
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(frame);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    return make_error(path, std::string("OpenEXR: ") + e.what());
  }
  return write_file_atomic(path, stream.bytes());
}

Result<ExrImage> read_exr(const std::string& path) {
  Result<std::string> bytes = read_file(path, kMaxFileBytes);
  if (!bytes.ok()) return bytes.error();
  // The magic number first: a clear message for files that are not EXR.
  if (bytes->size() < 4 || static_cast<unsigned char>((*bytes)[0]) != 0x76 ||
      static_cast<unsigned char>((*bytes)[1]) != 0x2f || static_cast<unsigned char>((*bytes)[2]) != 0x31 ||
      static_cast<unsigned char>((*bytes)[3]) != 0x01)
    return make_error(path, "not an OpenEXR file");
  ExrImage image;
  try {
    MemoryIStream stream(*bytes);
    Imf::InputFile file(stream);
    const Imf::Header& header = file.header();
    const Imath::Box2i window = header.dataWindow();
    const long long w = static_cast<long long>(window.max.x) - window.min.x + 1;
    const long long h = static_cast<long long>(window.max.y) - window.min.y + 1;
    if (w < 1 || h < 1 || static_cast<unsigned long long>(w) * static_cast<unsigned long long>(h) > kMaxPixels)
      return make_error(
          path, "image size " + std::to_string(w) + " x " + std::to_string(h) + " out of range");
    image.width = static_cast<int>(w);
    image.height = static_cast<int>(h);
    if (Imf::hasEnvmap(header)) {
      image.envmap = Imf::envmap(header) == Imf::ENVMAP_CUBE ? Envmap::Cube : Envmap::LatLong;
    }
    for (auto it = header.begin(); it != header.end(); ++it) {
      if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
        image.attributes.emplace_back(it.name(), s->value());
    }
    std::size_t channel_count = 0;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) ++channel_count;
    if (channel_count > kMaxChannels) return make_error(path, "too many channels");

    const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    const std::size_t row = static_cast<std::size_t>(w);
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
        return make_error(path, std::string("channel '") + it.name() + "' is subsampled");
      if (it.channel().type == Imf::UINT) {
        image.uint_channels.push_back({it.name(), std::vector<std::uint32_t>(pixels)});
      } else {
        image.float_channels.push_back({it.name(), std::vector<float>(pixels)});
      }
    }
    Imf::FrameBuffer frame;
    // Slices are addressed from the data window's origin.
    for (auto& c : image.float_channels)
      frame.insert(c.name, Imf::Slice::Make(Imf::FLOAT, c.values.data(), window, sizeof(float),
                                            sizeof(float) * row));
    for (auto& c : image.uint_channels)
      frame.insert(c.name, Imf::Slice::Make(Imf::UINT, c.values.data(), window, sizeof(std::uint32_t),
                                            sizeof(std::uint32_t) * row));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
  } catch (const std::exception& e) {
    return make_error(path, std::string("corrupt or truncated OpenEXR file: ") + e.what());
  }
  return image;
}

Result<ExrImage> far_field_image(const sim::FarField& f, const sim::ColourFarField* colour) {
  ExrImage image = cube_image(f.face_size());
  const std::size_t n = f.texel_count();
  ExrImage::FloatChannel y{"Y", std::vector<float>(n)}, flux{"flux", std::vector<float>(n)};
  ExrImage::UintChannel photons{"photons", std::vector<std::uint32_t>(n)};
  for (std::size_t t = 0; t < n; ++t) {
    y.values[t] = static_cast<float>(f.intensity_cd(t));
    flux.values[t] = static_cast<float>(f.flux_lm(t));
    if (f.photons(t) > std::numeric_limits<std::uint32_t>::max())
      return make_error(
          "", "a texel holds more than 4294967295 photons: too many for the EXR photons channel");
    photons.values[t] = static_cast<std::uint32_t>(f.photons(t));
  }
  image.float_channels = {std::move(y), std::move(flux)};
  image.uint_channels = {std::move(photons)};
  image.attributes = {{"gonio:quantity", "far-field luminous intensity"},
                      {"gonio:units", "Y: cd; flux: lm per texel; photons: count per texel"}};
  if (colour && !colour->empty()) {
    if (colour->x_lm.size() != n || colour->z_lm.size() != n)
      return make_error("", "the colour far field's size differs from the far field's");
    ExrImage::FloatChannel x{"X", std::vector<float>(n)}, z{"Z", std::vector<float>(n)};
    for (std::size_t t = 0; t < n; ++t) {
      const double sr = f.grid().texel_solid_angle(t);
      x.values[t] = static_cast<float>(colour->x_lm[t] / sr);
      z.values[t] = static_cast<float>(colour->z_lm[t] / sr);
    }
    image.float_channels.push_back(std::move(x));
    image.float_channels.push_back(std::move(z));
    image.attributes[1].second =
        "X, Y, Z: CIE 1931 tristimulus per sr (Y: cd); flux: lm per texel; photons: count per texel";
  }
  return image;
}

Result<sim::FarField> far_field_from_image(const ExrImage& image, const std::string& name) {
  if (image.envmap != Envmap::Cube || image.height != 6 * image.width || image.width < 1)
    return make_error(name, "not a cube-map environment image");
  const auto* flux = image.find_float("flux");
  const auto* photons = image.find_uint("photons");
  if (!flux || !photons)
    return make_error(name, "far field needs the channels 'flux' and 'photons'");
  std::vector<double> f(flux->values.begin(), flux->values.end());
  std::vector<std::uint64_t> p(photons->values.begin(), photons->values.end());
  return sim::FarField(image.width, std::move(f), std::move(p));
}

ExrImage latlong_image(int width, int height) {
  GONIO_CHECK(width >= 3 && height >= 3);
  ExrImage image;
  image.width = width;
  image.height = height;
  image.envmap = Envmap::LatLong;
  return image;
}

Vec3 latlong_direction(int width, int height, int x, int y) {
  const Imath::Box2i window(Imath::V2i(0, 0), Imath::V2i(width - 1, height - 1));
  const Imath::V3f d = Imf::LatLongMap::direction(window, Imath::V2f(static_cast<float>(x), static_cast<float>(y)));
  const Vec3 v{d.x, d.y, d.z};
  return v / std::sqrt(dot(v, v));
}

double latlong_pixel_solid_angle(int width, int height, int x, int y) {
  GONIO_CHECK(width >= 3 && height >= 3 && x >= 0 && x < width && y >= 0 && y < height);
  constexpr double kPi = 3.14159265358979323846;
  const double row_step = kPi / (height - 1);  // [rad] of latitude per row
  // Colatitude from the top pole of the band's edges.
  const double top = std::max(0.0, (y - 0.5) * row_step);
  const double bottom = std::min(kPi, (y + 0.5) * row_step);
  const double band = std::cos(top) - std::cos(bottom);
  const double column = 2.0 * kPi / (width - 1) * ((x == 0 || x == width - 1) ? 0.5 : 1.0);
  return band * column;
}

Result<double> latlong_flux_lm(const ExrImage& image, const std::string& name) {
  if (image.envmap != Envmap::LatLong || image.width < 3 || image.height < 3)
    return make_error(name, "not a latitude-longitude environment image of at least 3 x 3 pixels");
  const auto* y = image.find_float("Y");
  if (!y) return make_error(name, "no channel 'Y'");
  double flux = 0.0;
  for (int row = 0; row < image.height; ++row) {
    const double omega_inner = latlong_pixel_solid_angle(image.width, image.height, 1, row);
    for (int x = 0; x < image.width; ++x) {
      const double v = y->values[static_cast<std::size_t>(row) * static_cast<std::size_t>(image.width) +
                                 static_cast<std::size_t>(x)];
      if (!std::isfinite(v) || v < 0.0)
        return make_error(name, "pixel (" + std::to_string(x) + ", " + std::to_string(row) +
                                    ") holds " + std::to_string(v) +
                                    " cd: intensities are finite and >= 0");
      flux += v * ((x == 0 || x == image.width - 1) ? 0.5 * omega_inner : omega_inner);
    }
  }
  return flux;
}

}  // namespace gonio::io
