#include "photometry/direct_ratios.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "photometry/angles.h"
#include "photometry/frame.h"

namespace gonio::photometry {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr int kPlanes = 360;  // 1° cells in C
constexpr int kRings = 720;   // 0.25° cells in γ over the sphere

template <std::size_t N>
std::array<double, N> ratios(const Distribution& d, const std::array<double, N>& room_index) {
  GONIO_CHECK_MSG(validate(d).ok(), "direct_ratios needs a valid distribution");
  const Distribution e = expand_symmetry(d);
  std::array<double, N> direct{};
  double total = 0.0;
  const double dc = 2 * kPi / kPlanes, dg = kPi / kRings;
  std::vector<double> c_deg(kPlanes), g_deg(kRings), sin_g(kRings);
  for (int i = 0; i < kPlanes; ++i) c_deg[i] = (i + 0.5) * dc / kDeg;
  for (int j = 0; j < kRings; ++j) {
    g_deg[j] = (j + 0.5) * dg / kDeg;
    sin_g[j] = std::sin(g_deg[j] * kDeg);
  }
  std::vector<double> intensity;
  if (d.type == PhotometricType::C) {
    intensity = interpolate_grid(e, c_deg, g_deg);
  } else {
    intensity.resize(c_deg.size() * g_deg.size());
    for (int i = 0; i < kPlanes; ++i)
      for (int j = 0; j < kRings; ++j)
        intensity[i * kRings + j] =
            intensity_toward(e, direction_from_c_gamma(c_deg[i] * kDeg, g_deg[j] * kDeg));
  }
  // u = tan γ / (2k) per ring and room index.
  std::vector<std::array<double, N>> u(kRings / 2);
  for (int j = 0; j < kRings / 2; ++j)
    for (std::size_t q = 0; q < N; ++q) u[j][q] = std::tan(g_deg[j] * kDeg) / (2.0 * room_index[q]);
  for (int i = 0; i < kPlanes; ++i) {
    const double c = c_deg[i] * kDeg;
    const double ac = std::abs(std::cos(c)), as = std::abs(std::sin(c));
    for (int j = 0; j < kRings; ++j) {
      const double flux = intensity[i * kRings + j] * sin_g[j] * dc * dg;
      total += flux;
      if (j >= kRings / 2 || flux == 0.0) continue;  // the upper hemisphere never lands
      for (std::size_t q = 0; q < N; ++q)
        direct[q] += flux * std::max(0.0, 1.0 - u[j][q] * ac) * std::max(0.0, 1.0 - u[j][q] * as);
    }
  }
  for (double& r : direct) r = total > 0.0 ? r / total : 0.0;
  return direct;
}

}  // namespace

std::array<double, 10> direct_ratios(const Distribution& d) {
  return ratios(d, kDirectRatioRoomIndices);
}

double direct_ratio(const Distribution& d, double room_index) {
  GONIO_CHECK_MSG(room_index > 0.0, "direct_ratio needs a positive room index");
  return ratios(d, std::array<double, 1>{room_index})[0];
}

}  // namespace gonio::photometry
