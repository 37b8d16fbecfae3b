#include "sim/bsdfs/volume.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim/samplers/sampling.h"

namespace gonio::sim {

double henyey_greenstein(double g, double c) {
  const double d = 1.0 + g * g - 2.0 * g * c;
  return (1.0 - g * g) / (4.0 * std::numbers::pi * d * std::sqrt(d));
}

double sample_henyey_greenstein_cos(double g, double u) {
  if (std::abs(g) < 1e-6) return 1.0 - 2.0 * u;
  const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
  return std::clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
}

Vec3 sample_henyey_greenstein(const Vec3& direction, double g, PhotonRandom& rng) {
  const double c = sample_henyey_greenstein_cos(g, rng.uniform());
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  double x, y;
  sample_unit_circle(rng, &x, &y);
  const Basis b = basis_from_normal(direction);
  return normalize(b.to_world(Vec3{s * x, s * y, c}));
}

}  // namespace gonio::sim
