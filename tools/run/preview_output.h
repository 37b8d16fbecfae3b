// The progressive preview of `gonio simulate --preview`: after every
// iteration the far field is filtered (sim/preview_filter.h) and written as
//   DIR/preview.exr — the filtered cube map (OpenEXR cube environment map,
//                     like farfield.exr), channel Y = intensity [cd];
//   DIR/preview.png — the unfolded cube (io/outputs/cube_cross.h), exposed robustly
//                     (io::cube_cross_preview: 99 % flux quantile, soft shoulder),
// each replaced atomically, so a viewer can watch the files. The preview is
// for looking at: farfield.exr and the photometric files come from the raw
// histogram, never from the preview.
#pragma once

#include <string>

#include "io/outputs/exr.h"
#include "photometry/diagnostics.h"
#include "sim/cube_map.h"
#include "sim/far_field.h"
#include "sim/preview_filter.h"
#include "tools/run/console.h"

namespace gonio::cli {

// One line describing the filter settings (report, EXR attribute).
std::string describe(const sim::PreviewFilterParams& params, int face_size);

class PreviewOutput {
 public:
  PreviewOutput(std::string directory, int face_size, const sim::PreviewFilterParams& params);

  // Filters the far field and replaces preview.exr and preview.png.
  Status write(const sim::FarField& far_field);

  const sim::PreviewStats& stats() const { return filter_.stats(); }
  std::span<const double> intensity_cd() const { return filter_.intensity_cd(); }
  std::string exr_path() const { return directory_ + "/preview.exr"; }
  std::string png_path() const { return directory_ + "/preview.png"; }

 private:
  std::string directory_;
  sim::PreviewFilter filter_;
  sim::CubeMapGrid grid_;  // its texel solid angles, for the PNG's white point
  io::ExrImage image_;
};

}  // namespace gonio::cli
