// The progressive preview of `gonio simulate --preview`: after every
// iteration the far field is filtered (sim/filter/preview_filter.h) and written as
//   DIR/preview.exr — the filtered cube map (OpenEXR cube environment map,
//                     like farfield.exr), channel Y = intensity [cd];
//   DIR/preview.png — the unfolded cube (io/outputs/cube_cross.h), exposed robustly
//                     (io::cube_cross_preview: 99 % flux quantile, soft shoulder),
// each replaced atomically, so a viewer can watch the files. The preview is
// for looking at: farfield.exr and the photometric files come from the raw
// histogram, never from the preview.
#pragma once

#include <optional>
#include <string>

#include "io/outputs/exr.h"
#include "photometry/diagnostics.h"
#include "sim/detectors/cube_map.h"
#include "sim/detectors/far_field.h"
#include "sim/filter/preview_filter.h"
#include "tools/run/console.h"
#include "tools/run/option_bounds.h"

namespace gonio::app {

// The preview as a front end asks for it (gonio simulate's --preview and
// the filter's options, with their defaults).
inline constexpr Bounds<double> kThresholdBounds{0.0, 1e15};  // --threshold [photons]
inline constexpr Bounds<long long> kLevelsBounds{0, 15};      // --levels
inline constexpr Bounds<double> kSigmaBounds{1e-3, 100.0};    // --sigma-d, --sigma-r
struct PreviewOptions {
  bool enabled = false;              // --preview: write the files after every iteration
  std::string filter = "bilateral";  // --filter none|bilinear|bilateral
  std::optional<double> threshold;   // --threshold PHOTONS (none: 6400 adaptive, 100 fixed)
  long long levels = 0;              // --levels N (0: automatic)
  double sigma_d = 0.5;              // --sigma-d
  double sigma_r = 0.2;              // --sigma-r
  bool adaptive = false;             // --adaptive (the default)
  bool no_adaptive = false;          // --no-adaptive: the thesis's fixed threshold
};

// The filter parameters the options ask for. Error: --adaptive with
// --no-adaptive, an unknown filter, a value out of its range.
Result<sim::PreviewFilterParams> preview_params(const PreviewOptions& options);

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

}  // namespace gonio::app
