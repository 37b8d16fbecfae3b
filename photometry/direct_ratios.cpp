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
  for (int i = 0; i < kPlanes; ++i) {
    const double c = (i + 0.5) * dc;
    const double ac = std::abs(std::cos(c)), as = std::abs(std::sin(c));
    for (int j = 0; j < kRings; ++j) {
      const double g = (j + 0.5) * dg;
      const double intensity = d.type == PhotometricType::C
                                   ? interpolate(e, c / kDeg, g / kDeg)
                                   : intensity_toward(e, direction_from_c_gamma(c, g));
      const double flux = intensity * std::sin(g) * dc * dg;
      total += flux;
      if (g >= kPi / 2 || flux == 0.0) continue;
      const double t = std::tan(g);
      for (std::size_t q = 0; q < N; ++q) {
        const double u = t / (2.0 * room_index[q]);
        direct[q] += flux * std::max(0.0, 1.0 - u * ac) * std::max(0.0, 1.0 - u * as);
      }
    }
  }
  for (double& r : direct) r = total > 0.0 ? r / total : 0.0;
  return direct;
}

}  // namespace

std::array<double, 10> direct_ratios(const Distribution& d) { return ratios(d, kDirectRatioRoomIndices); }

double direct_ratio(const Distribution& d, double room_index) {
  GONIO_CHECK_MSG(room_index > 0.0, "direct_ratio needs a positive room index");
  return ratios(d, std::array<double, 1>{room_index})[0];
}

}  // namespace gonio::photometry
