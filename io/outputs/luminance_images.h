// A run's luminance images as files and report figures: each image
// (sim/detectors/luminance_image.h) as STEM.luminance-C<C>-G<γ>.exr —
// float channel `L` [cd/m²], and `x`, `y` (CIE 1931 chromaticity) in
// spectral runs — plus a false-colour PNG of the luminaire's part of it
// (log scale over three decades below the 99.5th percentile of its lit
// pixels, brighter clipping to white; the same name with .png), and CIE 232:2019's analysis of it (photometry/
// non_uniform_glare.h) with the intensity the image carries and the
// luminous opening's projected area towards the view, as the UGR table
// uses it. Files are written atomically; a failure is listed and the
// others are still written.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"
#include "photometry/non_uniform_glare.h"
#include "sim/detectors/luminance_image.h"

namespace gonio::io {

struct LuminanceOutputs {
  // report.json's "luminance_images": per image {c_deg, gamma_deg, file,
  // picture, pixels, pixel_m, cone_deg, intensity_cd, max_cd_m2, thumbnail
  // {size, cd_m2 (≤ 48 × 48 block means over the luminaire's part, row-major
  // from the top)}, cie232 {defined, why_undefined, intensity_cd,
  // projected_area_m2, mean_luminance_cd_m2, glare_area_m2,
  // glare_luminance_cd_m2, peak_filtered_cd_m2, k2, delta_ugr,
  // corrected_projected_area_m2, resolution_ok}}.
  nlohmann::json images = nlohmann::json::array();
  // report.json's "cie232": {delta_ugr (the largest; null when no view has
  // one), c_deg, gamma_deg (its view), eye_resolution_mm, threshold_cd_m2,
  // method}.
  nlohmann::json cie232;
  std::vector<std::string> written;  // paths
  std::vector<Error> failures;
};

// Per image {c_deg, gamma_deg, intensity_cd, max_cd_m2, thumbnail} (as
// write_luminance_images reports them), for the live page.
nlohmann::json luminance_thumbnails(const std::vector<sim::LuminanceImage>& images);

// The file name of a view's image: STEM.luminance-C<c>-G<γ>.exr.
std::string luminance_image_name(const std::string& stem, const sim::LuminanceView& view);

// CIE 232:2019's analysis of one image (photometry/non_uniform_glare.h): its
// luminance, the intensity it carries, and the opening's projected area
// towards its view as A_p — what write_luminance_images reports per image.
photometry::NonUniformGlare cie232_of(const sim::LuminanceImage& image, const photometry::LuminousOpening& opening,
                                      const photometry::NonUniformGlareParameters& parameters = {});

// The largest ΔUGR over the images where it is defined (report.json's
// cie232.delta_ugr) and the index of its image; NaN and npos where none is.
struct LargestDeltaUgr {
  double delta_ugr = photometry::kNaN;
  std::size_t image = static_cast<std::size_t>(-1);
  photometry::NonUniformGlare glare;  // that image's analysis
};
LargestDeltaUgr largest_delta_ugr(const std::vector<sim::LuminanceImage>& images,
                                  const photometry::LuminousOpening& opening,
                                  const photometry::NonUniformGlareParameters& parameters = {});

// Writes the images into `out_dir`; `opening`: the luminous opening the
// run's photometric files carry (its projected area is A_p).
LuminanceOutputs write_luminance_images(const std::string& out_dir, const std::string& stem,
                                        const std::vector<sim::LuminanceImage>& images,
                                        const photometry::LuminousOpening& opening, double cone_deg,
                                        const photometry::NonUniformGlareParameters& parameters = {});

}  // namespace gonio::io
