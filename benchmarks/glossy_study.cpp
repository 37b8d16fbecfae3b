// gonio_glossy_study: the measurement behind the glossy lobe's sampling
// (sim/bsdfs/material.h).
//
// For a grid of roughness and incidence (f0 = 1, the white furnace) it
// prints, from the same number of samples each:
//   albedo   ∫ f cos θo dωo of the microfacet lobe: the mean weight of
//            sample_glossy (visible normals, every weight ≤ 1);
//   thesis   the same for the thesis's lobe (Kurt et al. 2010 with α = ½,
//            f = F D / (4 (wo·h) √((wi·n)(wo·n)))), as the mean of its
//            weight F √(cos θo / cos θi) / cos θh under Walter's sampling;
//   w>1      the fraction of samples whose weight exceeds 1 when the
//            microfacet lobe is sampled with Walter's D cos θh alone
//            (weight F G2 (wi·h) / ((wi·n)(h·n))), and its largest weight;
//   clip     what surviving with min(w, 1) would lose of the albedo [%].
//
// Usage: gonio_glossy_study [--samples N]   (default 400000 per cell)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <utility>

#include "sim/bsdfs/material.h"
#include "sim/samplers/sampling.h"

namespace {

using gonio::Vec3;
using namespace gonio::sim;

struct Cell {
  double albedo = 0, thesis = 0, over = 0, max_w = 0, clip_percent = 0;
};

Cell measure(const Material& m, const Vec3& wi, int n) {
  double visible = 0, thesis = 0, walter = 0, clipped = 0, max_w = 0;
  int over = 0;
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(2024, static_cast<std::uint64_t>(k));
    visible += sample_glossy(m, wi, rng).weight;
    double c, s;
    sample_unit_circle(rng, &c, &s);
    const Vec3 h = sample_beckmann_half_vector(m.glossy_mx, m.glossy_my, rng.uniform_open0(), c, s);
    const double ih = dot(wi, h);
    if (ih <= 0.0) continue;
    const Vec3 wo = 2.0 * ih * h - wi;
    if (wo.z <= 0.0) continue;
    const double f = schlick_fresnel(m.glossy_f0, ih);
    thesis += f * std::sqrt(wo.z / wi.z) / h.z;
    const double w = f * smith_g2(m.glossy_mx, m.glossy_my, wi, wo) * ih / (wi.z * h.z);
    walter += w;
    clipped += std::min(w, 1.0);
    over += w > 1.0;
    max_w = std::max(max_w, w);
  }
  Cell c;
  c.albedo = visible / n;
  c.thesis = thesis / n;
  c.over = over / static_cast<double>(n);
  c.max_w = max_w;
  c.clip_percent = walter > 0.0 ? 100.0 * (walter - clipped) / walter : 0.0;
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  int n = 400000;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--samples") == 0 && i + 1 < argc) {
      n = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: gonio_glossy_study [--samples N]\n");
      return 2;
    }
  }
  if (n <= 0) {
    std::fprintf(stderr, "gonio_glossy_study: --samples must be > 0\n");
    return 2;
  }
  constexpr double kDeg = std::numbers::pi / 180.0;
  const std::pair<double, double> roughness[] = {{0.01, 0.01}, {0.09, 0.09}, {0.3, 0.3}, {0.5, 0.5},
                                                 {1.0, 1.0},   {0.05, 0.5},  {1.0, 0.1}};
  std::printf("%5s %5s %5s %5s  %8s %8s  %6s %7s %7s\n", "mx", "my", "theta", "phi", "albedo", "thesis", "w>1",
              "max w", "clip %");
  for (auto [mx, my] : roughness) {
    Material m;
    m.glossy = 1.0;
    m.glossy_mx = mx;
    m.glossy_my = my;
    m.glossy_f0 = 1.0;
    for (double theta : {0.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0}) {
      for (double phi : {0.0, 90.0}) {
        if (phi > 0.0 && mx == my) continue;
        const Vec3 wi{std::sin(theta * kDeg) * std::cos(phi * kDeg), std::sin(theta * kDeg) * std::sin(phi * kDeg),
                      std::cos(theta * kDeg)};
        const Cell c = measure(m, wi, n);
        std::printf("%5.2f %5.2f %5.0f %5.0f  %8.5f %8.4f  %6.3f %7.3f %7.2f\n", mx, my, theta, phi, c.albedo,
                    c.thesis, c.over, c.max_w, c.clip_percent);
      }
    }
  }
  return 0;
}
