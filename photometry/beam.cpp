#include "photometry/beam.h"

#include <cmath>
#include <numbers>
#include <vector>

#include "photometry/angles.h"
#include "photometry/frame.h"

namespace gonio::photometry {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kTol = 1e-9;  // [deg]

// The plane's curve: nodes in increasing θ, with `gap_after[i]` set where the
// interval to the next node (circularly) is not measured.
struct Curve {
  std::vector<double> theta;  // [deg], increasing, within [−180, 180)
  std::vector<double> value;  // [cd]
  std::vector<char> gap_after;
};

Curve curve_c(const Distribution& e, double c_deg) {
  Curve k;
  const auto& g = e.vertical_deg;
  const bool from_nadir = g.front() <= kTol, to_zenith = g.back() >= 180.0 - kTol;
  // The opposite half-plane, zenith side first (θ = −γ).
  for (std::size_t j = g.size(); j-- > 0;) {
    if (from_nadir && j == 0) break;  // the nadir comes with the other half
    k.theta.push_back(-g[j]);
    k.value.push_back(interpolate(e, c_deg + 180.0, g[j]));
    k.gap_after.push_back(0);
  }
  if (!k.gap_after.empty() && !from_nadir) k.gap_after.back() = 1;
  for (std::size_t j = 0; j < g.size(); ++j) {
    if (to_zenith && j + 1 == g.size() && !k.theta.empty()) break;  // the zenith is already first
    k.theta.push_back(g[j]);
    k.value.push_back(interpolate(e, c_deg, g[j]));
    k.gap_after.push_back(0);
  }
  k.gap_after.back() = to_zenith ? 0 : 1;
  return k;
}

Curve curve_sampled(const Distribution& e, double c_deg) {
  Curve k;
  const int n = 3600;
  for (int i = 0; i < n; ++i) {
    const double theta = -180.0 + 360.0 * i / n;
    const Vec3 dir = theta >= 0 ? direction_from_c_gamma(c_deg * kDeg, theta * kDeg)
                                : direction_from_c_gamma((c_deg + 180.0) * kDeg, -theta * kDeg);
    k.theta.push_back(theta);
    k.value.push_back(intensity_toward(e, dir));
    k.gap_after.push_back(0);
  }
  return k;
}

struct Edge {
  double theta;  // unwrapped about the axis [deg]
  bool open;
  bool looped;  // went all the way round without falling to the threshold
};

// Walks from node `axis` in direction `dir` (+1 or −1) to the threshold.
Edge walk(const Curve& k, std::size_t axis, int dir, double threshold) {
  const std::size_t n = k.theta.size();
  std::size_t i = axis;
  double theta = k.theta[axis];
  for (std::size_t steps = 0; steps < n; ++steps) {
    const std::size_t j = dir > 0 ? (i + 1) % n : (i + n - 1) % n;
    const bool gap = dir > 0 ? k.gap_after[i] : k.gap_after[j];
    if (gap) return {theta, true, false};
    double step = dir > 0 ? k.theta[j] - k.theta[i] : k.theta[i] - k.theta[j];
    if (step <= 0.0) step += 360.0;  // across the zenith
    if (k.value[j] <= threshold) {
      const double drop = k.value[i] - k.value[j];
      const double t = drop > 0.0 ? (k.value[i] - threshold) / drop : 0.0;
      return {theta + dir * t * step, false, false};
    }
    theta += dir * step;
    i = j;
  }
  return {theta, false, true};
}

}  // namespace

BeamSpread beam_spread(const Distribution& d, double c_deg, double fraction) {
  GONIO_CHECK_MSG(validate(d).ok(), "beam_spread needs a valid distribution");
  GONIO_CHECK_MSG(fraction > 0.0 && fraction <= 1.0, "beam_spread needs a fraction in (0, 1]");
  const Distribution e = expand_symmetry(d);
  const Curve k = d.type == PhotometricType::C ? curve_c(e, c_deg) : curve_sampled(e, c_deg);

  BeamSpread b;
  b.fraction = fraction;
  std::size_t axis = 0;
  for (std::size_t i = 1; i < k.value.size(); ++i) {
    const double a = std::abs(k.theta[i]), best = std::abs(k.theta[axis]);
    if (k.value[i] > k.value[axis] ||
        (k.value[i] == k.value[axis] && (a < best || (a == best && k.theta[i] > k.theta[axis]))))
      axis = i;
  }
  b.max_cd = k.value[axis];
  b.threshold_cd = fraction * b.max_cd;
  b.axis_deg = k.theta[axis];
  if (!(b.max_cd > 0.0)) return b;

  const Edge lo = walk(k, axis, -1, b.threshold_cd), hi = walk(k, axis, +1, b.threshold_cd);
  if (lo.looped || hi.looped) return b;
  b.lower_edge_deg = lo.theta;
  b.upper_edge_deg = hi.theta;
  b.lower_open = lo.open;
  b.upper_open = hi.open;
  b.angle_deg = hi.theta - lo.theta;
  return b;
}

}  // namespace gonio::photometry
