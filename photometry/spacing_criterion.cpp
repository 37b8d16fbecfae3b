#include "photometry/spacing_criterion.h"

#include <cmath>
#include <functional>
#include <numbers>

#include "photometry/intensity_sampler.h"

namespace gonio::photometry {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kMaxRatio = 4.0;
constexpr double kStep = 0.0005;

// E₁ at horizontal distance x [h] along plane c_deg, h = 1.
double e1(const IntensitySampler& s, double c_deg, double x) {
  const double g = std::atan(x);
  const double c = std::cos(g);
  return s.cd(c_deg, g / kDeg) * c * c * c;
}

// Smallest S in (0, kMaxRatio] with sum(S) ≤ e0, refined linearly.
SpacingValue solve(const std::function<double(double)>& sum, double e0) {
  double prev_s = 0.0, prev_v = sum(0.0) - e0;
  for (double s = kStep; s <= kMaxRatio + 1e-12; s += kStep) {
    const double v = sum(s) - e0;
    if (v <= 0.0) {
      const double t = prev_v > v ? prev_v / (prev_v - v) : 1.0;
      return {prev_s + t * (s - prev_s), ""};
    }
    prev_s = s;
    prev_v = v;
  }
  return {std::nullopt, "the illuminance does not fall to the criterion within 4 mounting heights"};
}

}  // namespace

SpacingCriterion spacing_criterion(const Distribution& d) {
  GONIO_CHECK_MSG(validate(d).ok(), "spacing_criterion needs a valid distribution");
  const IntensitySampler s(d);
  SpacingCriterion sc;
  const double e0 = s.cd(0.0, 0.0);
  if (!(e0 > 0.0)) {
    const SpacingValue none{std::nullopt, "no light straight down (the method needs a downlight)"};
    sc.c0_c180 = sc.c90_c270 = sc.diagonal = none;
    return sc;
  }
  sc.c0_c180 = solve([&](double x) { return e1(s, 0.0, x / 2) + e1(s, 180.0, x / 2); }, e0);
  sc.c90_c270 = solve([&](double x) { return e1(s, 90.0, x / 2) + e1(s, 270.0, x / 2); }, e0);
  sc.diagonal = solve(
      [&](double x) {
        const double r = x / std::sqrt(2.0);
        return e1(s, 45.0, r) + e1(s, 135.0, r) + e1(s, 225.0, r) + e1(s, 315.0, r);
      },
      e0);
  return sc;
}

}  // namespace gonio::photometry
