// Sampled spectra: a spectral power distribution, reflectance or
// transmittance given at increasing wavelengths, linear between them and zero
// outside (the CIE's recommended interpolation for measured spectra when
// nothing better is known, CIE 15:2004 section 7.2.1.1), and Planck's law.
// Standard library only.
#pragma once

#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::photometry {

struct SampledSpectrum {
  std::vector<double> wavelengths_nm{};  // strictly increasing, finite, > 0 [nm]
  std::vector<double> values{};          // one per wavelength, finite, >= 0 (relative units,
                                       // or a fraction for reflectance/transmittance)

  // Linear interpolation between the samples; 0 outside [first, last] (a
  // single sample: its value at that wavelength alone).
  double at(double wavelength_nm) const;
  bool empty() const { return wavelengths_nm.empty(); }
  double first_nm() const { return wavelengths_nm.front(); }
  double last_nm() const { return wavelengths_nm.back(); }
};

// A TM-33 spectrum as the photometric files keep it (photometry::Spectrum,
// distribution.h) as a sampled spectrum: the same samples.
SampledSpectrum sampled(const Spectrum& s);

// Checks the contract above: as many values as wavelengths, at least two
// samples, wavelengths strictly increasing and finite in (0, 10⁵) nm,
// values finite and >= 0, not all zero. `max_value` bounds the values
// (1 for reflectance and transmittance; infinity for power). The message
// names the offending index.
Status validate_spectrum(const SampledSpectrum& s, double max_value = 1e300);

// Every sample's value multiplied by the other spectrum's value at the same
// wavelength, over the union of both grids inside their common range (the
// product of two piecewise-linear functions sampled at both knots).
SampledSpectrum product(const SampledSpectrum& a, const SampledSpectrum& b);

// Second radiation constant c₂ = hc/k used for Planckian radiators,
// as CIE 15:2004 (ITS-90) gives it [m·K].
inline constexpr double kPlanckC2_mK = 1.4388e-2;
// First radiation constant for spectral radiance c₁L = 2hc² [W·m²·sr⁻¹].
inline constexpr double kPlanckC1L_Wm2_sr = 1.191042972e-16;

// Planck's law: spectral radiance of a blackbody at `temperature_k` and
// wavelength λ in vacuum, L = c₁L λ⁻⁵ / (exp(c₂/(λT)) − 1) [W·m⁻²·sr⁻¹·m⁻¹].
// 0 for T <= 0.
double planck_radiance(double wavelength_nm, double temperature_k);

// A blackbody's relative spectrum sampled from `first_nm` to `last_nm` in
// `step_nm` steps, scaled so its largest sample is 1.
SampledSpectrum blackbody_spectrum(double temperature_k, double first_nm = 360.0,
                            double last_nm = 830.0, double step_nm = 1.0);

}  // namespace gonio::photometry
