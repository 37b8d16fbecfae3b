// Colour over angle: the chromaticity of a spectral run's far field per
// direction of the luminaire's photometric frame, as report.json gives it
// (issue 24): u′v′, CCT and Duv per γ in the principal C-planes, the whole
// luminaire's colour, and Δu′v′ max — the largest distance in the CIE 1976
// UCS from the flux-weighted mean u′v′, over the C-γ bins whose intensity is
// at least 10 % of the peak.
//
// X, Y and Z are binned with the same overlaps as the intensity (sim/detectors/resample.h),
// so each bin's colour is that of all the light it collects. CCT and Duv by
// Ohno 2014 (photometry/colour.h). Noise: a bin's u′v′ scatters with its
// photon count, and a maximum over bins is biased upwards by it: Δu′v′ max
// is meaningful once it stops falling with more photons.
#pragma once

#include <vector>

#include "photometry/colour.h"
#include "sim/detectors/far_field.h"
#include "sim/detectors/resample.h"

namespace gonio::sim {

struct ColourAtGamma {
  double gamma_deg = 0.0;
  double intensity_cd = 0.0;
  photometry::UvPrime uv;    // NaN where the bin holds no light
  photometry::CctDuv cct;    // NaN outside Ohno's table or without light
};

struct ColourPlane {
  double c_deg = 0.0;
  std::vector<ColourAtGamma> points;  // every γ of the grid, 0 … 180°
};

struct ColourOverAngle {
  photometry::Tristimulus total;     // the whole far field: X, Y (= flux [lm]), Z
  photometry::UvPrime uv;            // of the total
  photometry::CctDuv cct;            // of the total
  std::vector<ColourPlane> planes;   // C0, C90, C180, C270 (those the grid has)
  double threshold_fraction = 0.1;   // of the peak intensity
  photometry::UvPrime mean_uv;       // flux-weighted mean u′v′ over the bins above it
  double delta_uv_max = 0.0;         // largest Δu′v′ from mean_uv over those bins
  std::size_t bins_counted = 0;      // bins above the threshold
};

// Requires `colour` on the resampler's face size (texel counts equal).
ColourOverAngle colour_over_angle(const Resampler& resampler, const FarField& y,
                                  const ColourFarField& colour, double threshold_fraction = 0.1);

}  // namespace gonio::sim
