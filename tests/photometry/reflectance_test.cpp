#include "photometry/reflectance.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gonio::photometry {
namespace {

// Jakob–Hanika spectra reproduce sRGB colours under D65: the fit's colour
// (X, Y, Z of the spectrum under D65) against IEC 61966-2-1's matrix, the
// luminance row 0.2126 R + 0.7152 G + 0.0722 B especially; grey stays flat.
TEST(Reflectance, SigmoidSpectraReproduceSrgbColours) {
  const double colours[][3] = {{0.5, 0.5, 0.5}, {0.8, 0.2, 0.1}, {0.1, 0.6, 0.2}, {0.2, 0.3, 0.8},
                               {0.9, 0.8, 0.3}, {0.05, 0.05, 0.05}, {0.95, 0.95, 0.95}};
  for (const auto& c : colours) {
    const ReflectanceFit fit = fit_reflectance(c[0], c[1], c[2]);
    EXPECT_LT(fit.delta_e, 0.05) << c[0] << " " << c[1] << " " << c[2];
    const SampledSpectrum s = sampled(fit.coefficients);
    const Tristimulus t = tristimulus_under_d65(s);
    EXPECT_NEAR(t.Y, 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2], 2e-3);
    EXPECT_NEAR(t.X, 0.4124 * c[0] + 0.3576 * c[1] + 0.1805 * c[2], 3e-3);
    EXPECT_NEAR(t.Z, 0.0193 * c[0] + 0.1192 * c[1] + 0.9505 * c[2], 3e-3);
    for (double v : s.values) {
      EXPECT_GT(v, 0.0);
      EXPECT_LT(v, 1.0);
    }
  }
  const SampledSpectrum grey = sampled(fit_reflectance(0.5, 0.5, 0.5).coefficients);
  for (double v : grey.values) EXPECT_NEAR(v, 0.5, 1e-3);
  // A red paint reflects long wavelengths, a blue one short ones.
  const SigmoidReflectance red = fit_reflectance(0.8, 0.1, 0.05).coefficients;
  const SigmoidReflectance blue = fit_reflectance(0.05, 0.1, 0.8).coefficients;
  EXPECT_GT(red.at(650.0), 5.0 * red.at(450.0));
  EXPECT_GT(blue.at(450.0), 5.0 * blue.at(650.0));
}

}  // namespace
}  // namespace gonio::photometry
