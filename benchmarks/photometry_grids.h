// The distributions the photometry benchmarks time (flux, planning figures):
// one smooth asymmetric downlight on grids of any step.
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

#include "photometry/distribution.h"

namespace gonio::bench {

// from, from + step, …, to [deg].
inline std::vector<double> steps(double from, double to, double step) {
  std::vector<double> out;
  const long n = std::lround((to - from) / step);
  for (long i = 0; i <= n; ++i) out.push_back(from + static_cast<double>(i) * step);
  return out;
}

// A smooth asymmetric downlight with some uplight (1000 cos⁴γ (1 + 0.3 cos²C)
// below, 40 |cos γ| above), C 0…c_to, γ 0…180, one 5000 lm lamp of 40 W.
inline photometry::Distribution smooth_downlight(double c_step, double gamma_step,
                                                 photometry::Symmetry sym = photometry::Symmetry::None,
                                                 double c_to = 360.0) {
  photometry::Distribution d;
  d.symmetry = sym;
  d.horizontal_deg = steps(0, c_to, c_step);
  d.vertical_deg = steps(0, 180, gamma_step);
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg) {
      const double cg = std::cos(g * std::numbers::pi / 180), cc = std::cos(c * std::numbers::pi / 180);
      d.candela.push_back(cg > 0 ? 1000 * std::pow(cg, 4) * (1 + 0.3 * cc * cc) : 40 * -cg);
    }
  d.lamps = {photometry::LampSet{1, "LED", 5000.0, "", "", 40.0}};
  return d;
}

}  // namespace gonio::bench
