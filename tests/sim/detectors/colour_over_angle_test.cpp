#include "sim/detectors/colour_over_angle.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gonio::sim {
namespace {

// A synthetic far field: uniform intensity, the lower hemisphere (γ < 90°)
// with CIE D65's chromaticity, the upper with illuminant A's (CIE 15's
// x, y), and a dim spot (5 % of the peak) of saturated green near C0, γ 90°,
// which Δu′v′ max must leave out.
TEST(ColourOverAngle, PlanesMeanAndSpreadOfAKnownField) {
  const int face = 32;
  const CGammaGrid grid{5.0, 5.0};
  const Resampler r(face, photometry::PhotometricFrame{}, grid);
  const CubeMapGrid g(face);
  std::vector<double> y(g.texel_count()), x(g.texel_count()), z(g.texel_count());
  const auto xyz = [](double cx, double cy, double yy) {  // X and Z for chromaticity x, y at Y
    return std::pair<double, double>{cx / cy * yy, (1.0 - cx - cy) / cy * yy};
  };
  for (std::size_t t = 0; t < g.texel_count(); ++t) {
    const Vec3 d = g.texel_direction(t);
    y[t] = g.texel_solid_angle(t);  // 1 cd everywhere
    std::pair<double, double> xz = d.y < 0.0 ? xyz(0.31272, 0.32903, y[t]) : xyz(0.44758, 0.40745, y[t]);
    if (d.x > 0.97) {
      y[t] *= 0.05;
      xz = xyz(0.2, 0.7, y[t]);
    }
    x[t] = xz.first;
    z[t] = xz.second;
  }
  const FarField field(face, y, std::vector<std::uint64_t>(g.texel_count(), 100));
  const ColourOverAngle c = colour_over_angle(r, field, ColourFarField{x, z});
  const photometry::UvPrime d65 = photometry::uv_prime(photometry::Chromaticity{0.31272, 0.32903});
  const photometry::UvPrime a = photometry::uv_prime(photometry::Chromaticity{0.44758, 0.40745});
  ASSERT_EQ(c.planes.size(), 4u);
  for (const ColourPlane& p : c.planes) {
    EXPECT_NEAR(p.points.front().uv.u_prime, d65.u_prime, 1e-9);  // nadir
    EXPECT_NEAR(p.points.back().uv.v_prime, a.v_prime, 1e-9);     // zenith
    EXPECT_NEAR(p.points[6].cct.cct_k, 6504.0, 2.0);              // γ 30°: D65
    EXPECT_NEAR(p.points[30].cct.cct_k, 2856.0, 1.0);             // γ 150°: A
  }
  EXPECT_NEAR(c.total.Y, 4.0 * M_PI, 0.2);
  // Mean of two equal halves: the midpoint; Δu′v′ max half their distance.
  EXPECT_NEAR(c.mean_uv.u_prime, 0.5 * (d65.u_prime + a.u_prime), 2e-3);
  EXPECT_NEAR(c.delta_uv_max, 0.5 * photometry::delta_uv_prime(a, d65), 3e-3);
  EXPECT_LT(c.delta_uv_max, 0.5 * photometry::delta_uv_prime(a, d65) + 3e-3);  // the green spot is out
  EXPECT_LT(c.bins_counted, grid.bin_count());
}

}  // namespace
}  // namespace gonio::sim
