// OpenEXR images: the far field as a cube-map environment map, and any
// image of named channels (previews, equirectangular maps). io/outputs/exr.cpp is
// the one file that includes OpenEXR.
//
// Cube maps follow OpenEXR's layout (ImfEnvmap.h), which sim/detectors/cube_map.h
// already uses: an N × 6N image, faces +X, −X, +Y, −Y, +Z, −Z from top to
// bottom, so pixel (x, face·N + y) is texel (face·N + y)·N + x and a
// channel's values in texel order are its pixels row by row.
//
// Files are written whole to memory and then atomically (io/support/file_io.h).
// Pixels are stored losslessly (ZIP compression).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/vec3.h"
#include "sim/detectors/far_field.h"

namespace gonio::io {

enum class Envmap { None, Cube, LatLong };

// An image of width × height pixels, each channel row-major from the top.
struct ExrImage {
  int width = 0;
  int height = 0;
  Envmap envmap = Envmap::None;
  struct FloatChannel {
    std::string name;
    std::vector<float> values;  // width · height
  };
  struct UintChannel {
    std::string name;
    std::vector<std::uint32_t> values;  // width · height, exact
  };
  std::vector<FloatChannel> float_channels;
  std::vector<UintChannel> uint_channels;
  // Free-form string attributes (units, software, settings): name → value.
  std::vector<std::pair<std::string, std::string>> attributes;
  // ZIP compression (lossless, the default); off for files rewritten every
  // iteration (previews), where it cost more than the filter itself.
  bool compress = true;

  const FloatChannel* find_float(const std::string& name) const;
  const UintChannel* find_uint(const std::string& name) const;
  const std::string* find_attribute(const std::string& name) const;
};

// An empty cube-map image for a face size (N × 6N, envmap cube).
ExrImage cube_image(int face_size);

// Writes the image. Errors: inconsistent channel sizes, no channel, a
// channel name repeated, OpenEXR's own (named), the write (atomic).
Status write_exr(const std::string& path, const ExrImage& image);

// Reads any scanline OpenEXR image with FLOAT, HALF (as float) and UINT
// channels. Errors name the file: not OpenEXR, truncated or corrupt,
// more than 2²⁸ pixels or 64 channels (checked before allocating).
Result<ExrImage> read_exr(const std::string& path);

// The far field as farfield.exr holds it: channel `Y` = intensity [cd]
// (float), `photons` = photon count per texel (UINT, exact), `flux` = flux
// per texel [lm] (float), envmap cube, attributes `gonio:quantity`,
// `gonio:units`. Error if a count exceeds 2³² − 1. A spectral run's
// `colour` (sim/detectors/far_field.h; null or empty: none) adds the channels `X` and
// `Z` beside `Y`: the CIE 1931 tristimulus values per steradian, in the
// units of Y (so x = X/(X+Y+Z) per texel).
Result<ExrImage> far_field_image(const sim::FarField& far_field,
                                 const sim::ColourFarField* colour = nullptr);

// A far field back from such an image (flux from the `flux` channel, counts
// from `photons`); errors if it is not a cube map or lacks the channels.
Result<sim::FarField> far_field_from_image(const ExrImage& image, const std::string& name);

// Equirectangular (latitude-longitude) maps, OpenEXR's ENVMAP_LATLONG
// convention (ImfEnvmap.h, LatLongMap): pixel centres run from latitude +90°
// (top row, world +Y) to −90° (bottom row) and from longitude +180° (left
// column) to −180° (right column), both ends included, so the top and bottom
// rows are the poles and the first and last columns the same meridian; the
// direction at latitude φ, longitude λ is (sin λ cos φ, sin φ, cos λ cos φ)
// (longitude 0 is +Z, +90° is +X). Renderers read such files as environment
// lights directly.
//
// Each pixel stands for a region of the sphere: a band of latitude reaching
// half a row to either side (a polar cap of half a row for the top and bottom
// rows) and a sector of longitude of one column, the first and last column
// sharing one (each counted half). latlong_flux_lm() integrates Y over these
// regions; an image whose Y is the mean intensity over each region holds the
// far field's flux exactly.

// An empty latitude-longitude image (envmap latlong). Requires width ≥ 3 and
// height ≥ 3.
ExrImage latlong_image(int width, int height);

// World direction (unit) of the centre of pixel (x, y), from OpenEXR's own
// LatLongMap::direction.
Vec3 latlong_direction(int width, int height, int x, int y);

// Solid angle [sr] of the region pixel (x, y) stands for (see above); the
// pixels of an image add up to 4π.
double latlong_pixel_solid_angle(int width, int height, int x, int y);

// Flux [lm] of a latitude-longitude image: Σ Y · solid angle over its pixels.
// Errors: not a latlong map, no channel `Y`, a value not finite or negative
// (named with its pixel).
Result<double> latlong_flux_lm(const ExrImage& image, const std::string& name);

}  // namespace gonio::io
