#include "sim/bsdfs/volume.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
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

namespace volume_detail {

ExponentialZiggurat::ExponentialZiggurat() {
  const double m = 0x1.0p53;
  double de = kR, te = kR;
  const double q = kV / std::exp(-de);
  k[0] = static_cast<std::uint64_t>((de / q) * m);
  k[1] = 0;
  w[0] = q / m;
  w[255] = de / m;
  f[0] = 1.0;
  f[255] = std::exp(-de);
  for (int i = 254; i >= 1; --i) {
    de = -std::log(kV / de + std::exp(-de));
    k[i + 1] = static_cast<std::uint64_t>((de / te) * m);
    te = de;
    f[i] = std::exp(-de);
    w[i] = de / m;
  }
}
const ExponentialZiggurat kExponentialZiggurat;

double standard_exponential_rest(PhotonRandom& rng, std::uint64_t bits) {
  const ExponentialZiggurat& z = kExponentialZiggurat;
  for (;;) {
    const unsigned i = static_cast<unsigned>(bits & 0xffU);
    const std::uint64_t j = bits >> 11;
    const double x = static_cast<double>(static_cast<std::int64_t>(j)) * z.w[i];
    if (j < z.k[i]) return x;
    if (i == 0) return ExponentialZiggurat::kR - std::log(rng.uniform_open0());
    // The wedge between layer i's rectangle and the curve: a uniform height
    // between f[i] and f[i − 1], accepted under e^−x.
    if (z.f[i] + rng.uniform() * (z.f[i - 1] - z.f[i]) < std::exp(-x)) return x;
    bits = rng.next_u64();
  }
}

}  // namespace volume_detail

}  // namespace gonio::sim
