// Discomfort glare of luminaires with a non-uniform source luminance:
// CIE 232:2019's correction of the Unified Glare Rating from a luminance
// image of the luminaire, as CIE TN 014:2023 and TechnoTeam's open DUGR
// Calculator (v1.5.0, its manual §3.2, §4.3–4.4) describe the analysis.
//
// Standard UGR (photometry/ugr.h) takes a luminaire's luminance as its
// intensity over its whole luminous area, L_s = I / A_p. A luminaire of
// bright LEDs on a dark face glares more than that average says. CIE 232
// finds the glare source in the image instead:
// 1. the image is low-pass filtered to what the eye resolves: a Gaussian of
//    full width at half maximum d = 12 mm (CIE 232:2019 Annex A.1, the
//    eye's resolution at the standard viewing conditions; the DUGR
//    Calculator's default), σ = FWHM / (2√(2 ln 2)) = FWHM / 2.35482,
//    truncated at ⌈3σ⌉ pixels (a kernel of 2⌈3σ⌉ + 1; the image padded
//    with zeros so that blur spreading beyond it is kept);
// 2. the glare source is where the filtered luminance is at least the
//    threshold 500 cd/m² (CIE 232:2019; the DUGR Calculator's default; CIE
//    117's lower bound of glare sources, 500–700 cd/m²): its projected area
//    A_p,eff and mean filtered luminance L_eff;
// 3. the correction k² = L_eff² A_p,eff / (L_s² A_p) (the manual's eq. 4),
//    with L_s = I / A_p: k² = L_eff² A_p,eff A_p / I² (eq. 6), so that
//    UGR_corr = UGR + ΔUGR, ΔUGR = 8 log10 k² (eq. 8) — the luminaire's
//    glare as if its luminous area were A_new = A / k² (eq. 7; projected
//    A_p,new = A_p / k²). k² > 1 (ΔUGR > 0): the non-uniformity costs.
// CIE 232 evaluates the views 25° and 40° above the luminaire's plane
// (γ = 65° and 50°) lengthwise and crosswise and keeps the largest ΔUGR
// (sim/detectors/luminance_image.h's ugr_luminance_views()).
//
// The image here is orthographic (an observer at infinity): pixels are
// squares of `pixel_m` in the plane perpendicular to the view, so the
// filter's 12 mm are measured there — the DUGR Calculator measures them
// perpendicular to the line of sight too (its camera mode: the angle d
// subtends at the luminaire's farthest edge). CIE 232 asks for pixels of
// at most d/10 = 1.2 mm; coarser images are analysed but flagged.
//
// No published worked example with its image was found (CIE TN 014's two
// examples are measurements whose images are not public); the tests hold
// the analysis to closed forms of its steps (docs/luminance-and-glare.md).
#pragma once

#include <string>
#include <vector>

#include "photometry/distribution.h"

namespace gonio::photometry {

struct NonUniformGlareParameters {
  double eye_resolution_m = 0.012;     // d: the filter's FWHM [m]
  double threshold_cd_m2 = 500.0;      // glare-source threshold on the filtered image [cd/m²]
};

// A luminance image: `width` × `height` square pixels of `pixel_m`,
// row-major [cd/m²], in the plane perpendicular to the view.
struct LuminanceMap {
  int width = 0, height = 0;
  double pixel_m = 0.0;
  std::vector<double> cd_m2;
};

struct NonUniformGlare {
  bool defined = false;
  std::string why_undefined;         // e.g. "no pixel reaches 500 cd/m²"
  double fwhm_m = 0.0;               // the filter [m]
  double sigma_px = 0.0;             // its standard deviation [pixels]
  int kernel_radius_px = 0;          // ⌈3σ⌉ [pixels]
  bool resolution_ok = false;        // pixel ≤ d/10 (CIE 232's requirement)
  double image_intensity_cd = 0.0;   // Σ L · pixel area of the unfiltered image [cd]
  double intensity_cd = kNaN;        // I used for L_s [cd]
  double projected_area_m2 = kNaN;   // A_p [m²]
  double mean_luminance_cd_m2 = kNaN;   // L_s = I / A_p [cd/m²]
  double glare_area_m2 = kNaN;       // A_p,eff [m²]
  double glare_luminance_cd_m2 = kNaN;  // L_eff [cd/m²]
  double peak_filtered_cd_m2 = 0.0;  // largest filtered value [cd/m²]
  double k2 = kNaN;                  // k²
  double delta_ugr = kNaN;           // 8 log10 k²
  double corrected_projected_area_m2 = kNaN;  // A_p,new = A_p / k² [m²]
};

// The analysis above of one image, with the intensity I towards the viewer
// [cd] and the projected luminous area A_p [m²] that the standard UGR uses
// (photometry/luminance.h's projected_area_m2). Undefined without a valid
// image, with I or A_p not > 0, or when nothing reaches the threshold.
NonUniformGlare analyse_non_uniform_glare(const LuminanceMap& image, double intensity_cd, double projected_area_m2,
                                          const NonUniformGlareParameters& parameters = {});

// The filter of step 1 alone: the image padded by the kernel radius on every
// side ((width + 2r) × (height + 2r), same pixel), as analysed.
LuminanceMap eye_filtered(const LuminanceMap& image, const NonUniformGlareParameters& parameters = {});

}  // namespace gonio::photometry
