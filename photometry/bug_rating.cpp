#include "photometry/bug_rating.h"

#include <cmath>
#include <numbers>
#include <vector>

#include "photometry/flux.h"
#include "photometry/intensity_sampler.h"

namespace gonio::photometry {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// Lowest rating r in 0…4 with every value ≤ its limit[r]; 5 if none.
template <std::size_t N>
int lowest(const std::array<double, N>& values, const std::array<std::array<double, 5>, N>& limits) {
  for (int r = 0; r < 5; ++r) {
    bool ok = true;
    for (std::size_t k = 0; k < N; ++k) ok = ok && values[k] <= limits[k][r];
    if (ok) return r;
  }
  return 5;
}

// Front share of the flux in the γ zone [a, b] [deg], from the midpoint grid.
double front_share(const IntensitySampler& s, double a, double b) {
  constexpr int kPlanes = 360;
  const int rings = std::max(1, static_cast<int>(std::lround((b - a) / 0.25)));
  const double dg = (b - a) / rings;
  std::vector<double> c_deg(kPlanes), g_deg(rings), sin_g(rings);
  for (int i = 0; i < kPlanes; ++i) c_deg[i] = i + 0.5;
  for (int j = 0; j < rings; ++j) {
    g_deg[j] = a + (j + 0.5) * dg;
    sin_g[j] = std::sin(g_deg[j] * kDeg);
  }
  const std::vector<double> cd = s.grid(c_deg, g_deg);
  double front = 0.0, all = 0.0;
  for (int i = 0; i < kPlanes; ++i) {
    for (int j = 0; j < rings; ++j) {
      const double f = cd[i * rings + j] * sin_g[j];
      all += f;
      if (c_deg[i] < 180.0) front += f;
    }
  }
  return all > 0.0 ? front / all : 0.5;
}

}  // namespace

const BugLimits& bug_limits_lm() {
  static const BugLimits limits;
  return limits;
}

BugRating rate_bug(const BugZones& z) {
  const BugLimits& l = bug_limits_lm();
  BugRating r;
  r.zones_lm = z;
  r.b = lowest<3>({z.bh, z.bm, z.bl}, {l.bh, l.bm, l.bl});
  r.u = lowest<2>({z.uh, z.ul}, {l.uh, l.ul});
  r.g = lowest<4>({z.fvh, z.bvh, z.fh, z.bh}, {l.fvh, l.bvh, l.fh, l.bh_glare});
  return r;
}

BugRating bug_rating(const Distribution& d) {
  GONIO_CHECK_MSG(validate(d).ok(), "bug_rating needs a valid distribution");
  const ZonalFlux zf(d);
  const IntensitySampler s(d);
  BugZones z;
  const auto split = [&](double a, double b, double& front, double& back) {
    const double total = zf.zone_lm(a, b);
    const double share = total > 0.0 ? front_share(s, a, b) : 0.5;
    front = total * share;
    back = total - front;
  };
  split(0, 30, z.fl, z.bl);
  split(30, 60, z.fm, z.bm);
  split(60, 80, z.fh, z.bh);
  split(80, 90, z.fvh, z.bvh);
  z.ul = zf.zone_lm(90, 100);
  z.uh = zf.zone_lm(100, 180);
  // Quadrature rounding is not light: below 1e-9 of the total, a zone is dark
  // (U0 asks for exactly none).
  const double floor_lm = 1e-9 * zf.total_lm();
  for (double* v : {&z.fl, &z.fm, &z.fh, &z.fvh, &z.bl, &z.bm, &z.bh, &z.bvh, &z.ul, &z.uh})
    if (std::abs(*v) <= floor_lm) *v = 0.0;
  return rate_bug(z);
}

std::string to_string(const BugRating& r) {
  return "B" + std::to_string(r.b) + "-U" + std::to_string(r.u) + "-G" + std::to_string(r.g);
}

}  // namespace gonio::photometry
