#include "tools/run/preview_output.h"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "io/outputs/cube_cross.h"
#include "io/outputs/image.h"

namespace gonio::cli {

std::string describe(const sim::PreviewFilterParams& p, int face_size) {
  const char* kind = p.interpolation == sim::Interpolation::None       ? "none"
                     : p.interpolation == sim::Interpolation::Bilinear ? "bilinear"
                                                                       : "bilateral";
  int levels = p.levels == 0 ? sim::PreviewFilter::auto_levels(face_size) : p.levels;
  levels = std::min(levels, sim::CubePyramid::max_levels(face_size));
  char buf[256];
  if (p.adaptive) {
    std::snprintf(buf, sizeof buf, "%s, adaptive (z = %g, always kept above %g photons), %d levels", kind,
                  p.adaptive_z, p.threshold_photons, levels);
  } else {
    std::snprintf(buf, sizeof buf, "%s, fixed threshold %g photons, %d levels", kind, p.threshold_photons, levels);
  }
  std::string text = buf;
  if (p.interpolation == sim::Interpolation::Bilateral) {
    std::snprintf(buf, sizeof buf, ", sigma_d %g, sigma_r %g", p.sigma_d, p.sigma_r);
    text += buf;
  }
  return text;
}

PreviewOutput::PreviewOutput(std::string directory, int face_size, const sim::PreviewFilterParams& params)
    : directory_(std::move(directory)), filter_(face_size, params), grid_(face_size), image_(io::cube_image(face_size)) {
  image_.float_channels.push_back({"Y", std::vector<float>(filter_.intensity_cd().size())});
  image_.compress = false;
  image_.attributes = {{"gonio:quantity", "preview of the far-field luminous intensity (filtered; not a measurement)"},
                       {"gonio:units", "Y: cd"},
                       {"gonio:filter", describe(params, face_size)}};
}

Status PreviewOutput::write(const sim::FarField& far_field) {
  filter_.apply(far_field);
  const std::span<const double> preview = filter_.intensity_cd();
  std::vector<float>& y = image_.float_channels.front().values;
  for (std::size_t t = 0; t < preview.size(); ++t) y[t] = static_cast<float>(preview[t]);
  if (Status s = io::write_exr(exr_path(), image_); !s.ok()) return s;
  return io::write_png(png_path(), io::cube_cross_preview(grid_, preview));
}

}  // namespace gonio::cli
