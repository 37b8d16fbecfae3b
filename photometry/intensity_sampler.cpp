#include "photometry/intensity_sampler.h"

#include <cmath>
#include <numbers>

#include "photometry/angles.h"
#include "photometry/frame.h"

namespace gonio::photometry {

IntensitySampler::IntensitySampler(const Distribution& d) : expanded_(expand_symmetry(d)) {}

double IntensitySampler::cd(double c_deg, double gamma_deg) const {
  if (expanded_.type == PhotometricType::C) return interpolate(expanded_, c_deg, gamma_deg);
  constexpr double kDeg = std::numbers::pi / 180.0;
  return intensity_toward(expanded_, direction_from_c_gamma(c_deg * kDeg, gamma_deg * kDeg));
}

std::vector<double> IntensitySampler::grid(const std::vector<double>& c_deg,
                                           const std::vector<double>& gamma_deg) const {
  if (expanded_.type == PhotometricType::C) return interpolate_grid(expanded_, c_deg, gamma_deg);
  std::vector<double> out(c_deg.size() * gamma_deg.size());
  for (std::size_t i = 0; i < c_deg.size(); ++i)
    for (std::size_t j = 0; j < gamma_deg.size(); ++j) out[i * gamma_deg.size() + j] = cd(c_deg[i], gamma_deg[j]);
  return out;
}

double facing_rectangles_view_factor(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double p = 1 + x * x, q = 1 + y * y;
  return 2 / (std::numbers::pi * x * y) *
         (0.5 * std::log(p * q / (p + q - 1)) + x * std::sqrt(q) * std::atan(x / std::sqrt(q)) +
          y * std::sqrt(p) * std::atan(y / std::sqrt(p)) - x * std::atan(x) - y * std::atan(y));
}

}  // namespace gonio::photometry
