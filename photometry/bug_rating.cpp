#include "photometry/bug_rating.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
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

// Flux per 1° plane of C (planes centred on C = 0.5°, 1.5°, …) in the γ zone
// [a, b] [deg], from the 1° × 0.25° midpoint grid, in lm up to the common
// factor of the grid (the same for every zone, so sums across zones add up).
std::vector<double> plane_flux(const IntensitySampler& s, double a, double b) {
  constexpr int kPlanes = 360;
  const int rings = std::max(1, static_cast<int>(std::lround((b - a) / 0.25)));
  const double dg = (b - a) / rings;
  std::vector<double> c_deg(kPlanes), g_deg(rings), w(rings);
  for (int i = 0; i < kPlanes; ++i) c_deg[i] = i + 0.5;
  for (int j = 0; j < rings; ++j) {
    g_deg[j] = a + (j + 0.5) * dg;
    w[j] = std::sin(g_deg[j] * kDeg) * dg;
  }
  const std::vector<double> cd = s.grid(c_deg, g_deg);
  std::vector<double> per_plane(kPlanes, 0.0);
  for (int i = 0; i < kPlanes; ++i)
    for (int j = 0; j < rings; ++j) per_plane[i] += cd[i * rings + j] * w[j];
  return per_plane;
}

}  // namespace

const BugLimits& bug_limits_lm() {
  static const BugLimits limits;
  return limits;
}

BugRating rate_bug(const BugZones& z, BugGlareTable table) {
  const BugLimits& l = bug_limits_lm();
  BugRating r;
  r.zones_lm = z;
  r.glare_table = table;
  r.b = lowest<3>({z.bh, z.bm, z.bl}, {l.bh, l.bm, l.bl});
  r.u = lowest<2>({z.uh, z.ul}, {l.uh, l.ul});
  const auto& bh_glare = table == BugGlareTable::QuadrilateralSymmetric ? l.bh_glare_symmetric : l.bh_glare;
  r.g = lowest<4>({z.fvh, z.bvh, z.fh, z.bh}, {l.fvh, l.bvh, l.fh, bh_glare});
  return r;
}

bool quadrilateral_symmetric(const std::array<double, 8>& o) {
  double mean = 0.0;
  for (double v : o) mean += v / 8.0;
  if (!(mean > 0.0)) return false;
  for (double v : o)
    if (std::abs(v - mean) > 0.1 * mean) return false;
  return true;
}

BugRating bug_rating(const Distribution& d) {
  GONIO_CHECK_MSG(validate(d).ok(), "bug_rating needs a valid distribution");
  const ZonalFlux zf(d);
  const IntensitySampler s(d);
  BugZones z;
  std::array<double, 8> octants{};  // grid units until scaled below
  const auto split = [&](double a, double b, double& front, double& back) {
    const double total = zf.zone_lm(a, b);
    const std::vector<double> planes = plane_flux(s, a, b);
    double f = 0.0, all = 0.0;
    for (std::size_t i = 0; i < planes.size(); ++i) {
      all += planes[i];
      if (i < 180) f += planes[i];  // C0…C180, centred on C90
      octants[i / 45] += planes[i];
    }
    const double share = total > 0.0 && all > 0.0 ? f / all : 0.5;
    front = total * share;
    back = total - front;
  };
  split(0, 30, z.fl, z.bl);
  split(30, 60, z.fm, z.bm);
  split(60, 80, z.fh, z.bh);
  split(80, 90, z.fvh, z.bvh);
  // The octants in lm: scaled so that they add up to the exact 0–90° flux.
  const double down_lm = z.fl + z.fm + z.fh + z.fvh + z.bl + z.bm + z.bh + z.bvh;
  double down_grid = 0.0;
  for (double v : octants) down_grid += v;
  for (double& v : octants) v = down_grid > 0.0 ? v * down_lm / down_grid : 0.0;
  z.ul = zf.zone_lm(90, 100);
  z.uh = zf.zone_lm(100, 180);
  // Quadrature rounding is not light: below 1e-9 of the total, a zone is dark
  // (U0 asks for exactly none).
  const double floor_lm = 1e-9 * zf.total_lm();
  for (double* v : {&z.fl, &z.fm, &z.fh, &z.fvh, &z.bl, &z.bm, &z.bh, &z.bvh, &z.ul, &z.uh})
    if (std::abs(*v) <= floor_lm) *v = 0.0;
  BugRating r = rate_bug(z, quadrilateral_symmetric(octants) ? BugGlareTable::QuadrilateralSymmetric
                                                             : BugGlareTable::Asymmetric);
  r.octants_down_lm = octants;
  return r;
}

std::string to_string(const BugRating& r) {
  return "B" + std::to_string(r.b) + "-U" + std::to_string(r.u) + "-G" + std::to_string(r.g);
}

std::string to_string(BugGlareTable table) {
  return table == BugGlareTable::QuadrilateralSymmetric ? "Types V and VS (quadrilateral symmetric)"
                                                        : "Types I-IV (asymmetric)";
}

}  // namespace gonio::photometry
