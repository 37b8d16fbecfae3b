#include "photometry/spectrum.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "photometry/format.h"

namespace gonio::photometry {

double SampledSpectrum::at(double wavelength_nm) const {
  const std::size_t n = std::min(wavelengths_nm.size(), values.size());
  if (n == 0 || !(wavelength_nm >= wavelengths_nm.front()) || !(wavelength_nm <= wavelengths_nm[n - 1]))
    return 0.0;
  if (n == 1) return values[0];
  const auto it = std::upper_bound(wavelengths_nm.begin(), wavelengths_nm.begin() + static_cast<long>(n),
                                   wavelength_nm);
  std::size_t hi = static_cast<std::size_t>(it - wavelengths_nm.begin());
  if (hi >= n) return values[n - 1];
  const std::size_t lo = hi - 1;
  const double t = (wavelength_nm - wavelengths_nm[lo]) / (wavelengths_nm[hi] - wavelengths_nm[lo]);
  return values[lo] + t * (values[hi] - values[lo]);
}

SampledSpectrum sampled(const Spectrum& s) { return {s.wavelength_nm, s.values}; }

Status validate_spectrum(const SampledSpectrum& s, double max_value) {
  if (s.wavelengths_nm.size() != s.values.size())
    return make_error(std::to_string(s.wavelengths_nm.size()) + " wavelengths but " +
                      std::to_string(s.values.size()) + " values");
  if (s.wavelengths_nm.size() < 2) return make_error("a spectrum needs at least two samples");
  bool any = false;
  for (std::size_t i = 0; i < s.values.size(); ++i) {
    const double w = s.wavelengths_nm[i];
    if (!std::isfinite(w) || !(w > 0.0) || !(w < 1e5))
      return make_error("wavelength " + std::to_string(i) + " (" + format_number(w) +
                        " nm) must be finite and in (0, 100000) nm");
    if (i > 0 && !(w > s.wavelengths_nm[i - 1]))
      return make_error("wavelength " + std::to_string(i) + " (" + format_number(w) +
                        " nm) does not increase");
    const double v = s.values[i];
    if (!std::isfinite(v) || v < 0.0)
      return make_error("value " + std::to_string(i) + " (" + format_number(v) + ") must be finite and >= 0");
    if (v > max_value)
      return make_error("value " + std::to_string(i) + " (" + format_number(v) + ") exceeds " +
                        format_number(max_value));
    any = any || v > 0.0;
  }
  if (!any) return make_error("every value of the spectrum is 0");
  return Ok{};
}

SampledSpectrum product(const SampledSpectrum& a, const SampledSpectrum& b) {
  SampledSpectrum out;
  if (a.empty() || b.empty()) return out;
  const double lo = std::max(a.first_nm(), b.first_nm());
  const double hi = std::min(a.last_nm(), b.last_nm());
  if (!(lo <= hi)) return out;
  std::vector<double> knots;
  for (double w : a.wavelengths_nm)
    if (w >= lo && w <= hi) knots.push_back(w);
  for (double w : b.wavelengths_nm)
    if (w >= lo && w <= hi) knots.push_back(w);
  std::sort(knots.begin(), knots.end());
  knots.erase(std::unique(knots.begin(), knots.end()), knots.end());
  for (double w : knots) {
    out.wavelengths_nm.push_back(w);
    out.values.push_back(a.at(w) * b.at(w));
  }
  return out;
}

double planck_radiance(double wavelength_nm, double temperature_k) {
  if (!(temperature_k > 0.0) || !(wavelength_nm > 0.0)) return 0.0;
  const double lambda_m = wavelength_nm * 1e-9;
  const double x = kPlanckC2_mK / (lambda_m * temperature_k);
  if (x > 700.0) return 0.0;
  const double l5 = lambda_m * lambda_m * lambda_m * lambda_m * lambda_m;
  return kPlanckC1L_Wm2_sr / (l5 * std::expm1(x));
}

SampledSpectrum blackbody_spectrum(double temperature_k, double first_nm, double last_nm, double step_nm) {
  SampledSpectrum s;
  if (!(step_nm > 0.0) || !(last_nm >= first_nm)) return s;
  const auto n = static_cast<std::size_t>(std::floor((last_nm - first_nm) / step_nm + 1e-9)) + 1;
  double peak = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = first_nm + static_cast<double>(i) * step_nm;
    s.wavelengths_nm.push_back(w);
    s.values.push_back(planck_radiance(w, temperature_k));
    peak = std::max(peak, s.values.back());
  }
  if (peak > 0.0)
    for (double& v : s.values) v /= peak;
  return s;
}

}  // namespace gonio::photometry
