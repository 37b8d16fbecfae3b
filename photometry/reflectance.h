// A smooth reflectance spectrum for a colour: Jakob & Hanika (2019), "A
// Low-Dimensional Function Space for Efficient Spectral Upsampling"
// (Computer Graphics Forum 38(2)). The reflectance is a sigmoid of a
// quadratic in wavelength,
//   r(λ) = S(c₀t² + c₁t + c₂),  S(x) = ½ + x / (2√(1 + x²)),  t = (λ − 360)/(830 − 360),
// bounded in (0, 1) and smooth, with c found per colour by minimising the
// CIELAB difference between the colour and the spectrum's colour under
// sRGB's white, CIE D65 (colord-data's table, read at build time): a
// Levenberg–Marquardt fit on the three coefficients, walked from mid grey to
// the target in small steps (the paper's continuation), as the paper does
// to fill its tables. Linear sRGB / Rec. 709 primaries (glTF's colour space),
// IEC 61966-2-1's matrix to XYZ.
#pragma once

#include "photometry/colour.h"
#include "photometry/spectrum.h"

namespace gonio::photometry {

struct SigmoidReflectance {
  double c0 = 0.0, c1 = 0.0, c2 = 0.0;
  double at(double wavelength_nm) const;
};

struct ReflectanceFit {
  SigmoidReflectance coefficients;
  double delta_e = 0.0;  // CIELAB ΔE*ab left between the colour and the spectrum's
};

// Linear RGB components are clamped to [0, 1].
ReflectanceFit fit_reflectance(double r, double g, double b);

// The fitted spectrum sampled on the CIE table's grid (360–830 nm, 5 nm).
SampledSpectrum sampled(const SigmoidReflectance& s);

// X, Y, Z of a reflectance under D65, Y of the perfect white = 1.
Tristimulus tristimulus_under_d65(const SampledSpectrum& reflectance);

}  // namespace gonio::photometry
