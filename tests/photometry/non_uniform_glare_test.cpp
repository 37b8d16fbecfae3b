#include "photometry/non_uniform_glare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace gonio::photometry {
namespace {

constexpr double kPi = std::numbers::pi;

LuminanceMap blank(int w, int h, double pixel_m) {
  LuminanceMap m;
  m.width = w;
  m.height = h;
  m.pixel_m = pixel_m;
  m.cd_m2.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0.0);
  return m;
}

double& at(LuminanceMap& m, int x, int y) { return m.cd_m2[static_cast<std::size_t>(y) * m.width + x]; }

TEST(NonUniformGlare, FilterIsTheStatedGaussianAndKeepsTheFlux) {
  // d = 12 mm at 0.5 mm pixels: σ = 12 / 2.35482 / 0.5 = 10.19 px, radius
  // ⌈3σ⌉ = 31 (the DUGR Calculator's filter length 2⌈3σ⌉ + 1 = 63). A
  // FWHM read as σ (a common slip) or a kernel not summing to one fails.
  LuminanceMap m = blank(40, 30, 0.0005);
  at(m, 20, 15) = 1.0e6;
  const LuminanceMap f = eye_filtered(m);
  EXPECT_EQ(f.width, 40 + 2 * 31);
  EXPECT_EQ(f.height, 30 + 2 * 31);
  double in = 0.0, out = 0.0;
  for (double v : m.cd_m2) in += v;
  for (double v : f.cd_m2) out += v;
  EXPECT_NEAR(out / in, 1.0, 1e-12);
  // Half maximum 6 mm (12 px) from the lone spot's centre, along a row.
  const auto fv = [&](int x, int y) { return f.cd_m2[static_cast<std::size_t>(y + 31) * f.width + (x + 31)]; };
  const NonUniformGlare g = analyse_non_uniform_glare(m, 1.0, 1.0);
  EXPECT_NEAR(g.sigma_px, 12.0 / 2.3548200450309493 / 0.5, 1e-9);
  EXPECT_EQ(g.kernel_radius_px, 31);
  EXPECT_NEAR(fv(32, 15) / fv(20, 15), 0.5, 0.002);
  EXPECT_NEAR(fv(20, 3) / fv(20, 15), 0.5, 0.002);
}

TEST(NonUniformGlare, IsolatedPointSourcesHaveTheClosedFormGlareArea) {
  // N single-pixel spots far apart: each blurs to a Gaussian of peak P =
  // flux / (2πσ²) per unit area; above T it is a disc of area 2πσ² ln(P/T)
  // holding (P − T)·2πσ². With P/T = e², A_eff = N·4πσ² and L_eff = (P − T)/2,
  // so k² = L_eff² A_eff A_p / I² follows in closed form.
  const double px = 0.0005, sigma = 0.012 / 2.3548200450309493;  // [m]
  const double threshold = 500.0, peak = threshold * std::exp(2.0);
  const double spot_flux = peak * 2.0 * kPi * sigma * sigma;  // [cd]
  const double spot_l = spot_flux / (px * px);
  LuminanceMap m = blank(300, 200, px);
  int n = 0;
  for (int y = 40; y < 200; y += 120)
    for (int x = 40; x < 300; x += 110) {
      at(m, x, y) = spot_l;
      ++n;
    }
  ASSERT_EQ(n, 6);
  const double intensity = n * spot_flux, ap = 0.15 * 0.1;
  const NonUniformGlare g = analyse_non_uniform_glare(m, intensity, ap);
  ASSERT_TRUE(g.defined) << g.why_undefined;
  const double a_eff = n * 4.0 * kPi * sigma * sigma, l_eff = (peak - threshold) / 2.0;
  EXPECT_NEAR(g.glare_area_m2 / a_eff, 1.0, 0.01);
  EXPECT_NEAR(g.glare_luminance_cd_m2 / l_eff, 1.0, 0.01);
  const double k2 = l_eff * l_eff * a_eff * ap / (intensity * intensity);
  EXPECT_NEAR(g.k2 / k2, 1.0, 0.02);
  EXPECT_NEAR(g.delta_ugr, 8.0 * std::log10(k2), 0.07);
  EXPECT_NEAR(g.mean_luminance_cd_m2, intensity / ap, 1e-9);
  EXPECT_NEAR(g.corrected_projected_area_m2, ap / g.k2, 1e-15);
  EXPECT_NEAR(g.image_intensity_cd / intensity, 1.0, 1e-12);
  EXPECT_TRUE(g.resolution_ok);
  // Six tiny spots spread over 150 × 100 mm glare far more than the face's
  // average says: k² ≫ 1, ΔUGR ≈ +8 here.
  EXPECT_GT(g.delta_ugr, 6.0);
}

// ∫∫ 1[Φ(x/σ)Φ(y/σ) ≥ t] over a quarter plane beyond a convex corner,
// minus the quadrant: the continuous area a corner adds (negative: it
// rounds off). Midpoint rule on a fine grid.
double corner_excess(double sigma, double t) {
  const auto phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  const double h = sigma / 200.0, reach = 6.0 * sigma;
  double inside = 0.0;
  for (double x = -reach + h / 2; x < reach; x += h)
    for (double y = -reach + h / 2; y < reach; y += h)
      if (phi(x / sigma) * phi(y / sigma) >= t) inside += h * h;
  // Within [−6σ, 6σ]² the quadrant x, y > 0 holds 36σ² and the two edge
  // strips outside add 2·6σ·x*, x* where Φ(−x*/σ) = 1 − t.
  double lo = 0.0, hi = 10.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (phi(-mid) > t ? lo : hi) = mid;
  }
  const double x_star = 0.5 * (lo + hi) * sigma;
  return inside - 36.0 * sigma * sigma - 2.0 * 6.0 * sigma * x_star;
}

TEST(NonUniformGlare, UniformPanelGrowsByTheBlurredEdgeAndCostsNothing) {
  // A uniform 80 × 60 mm panel of 10⁴ cd/m²: filtered, its edge falls as
  // L·Φ(x/σ), so the glare area reaches x* = σ·Φ⁻¹(1 − T/L) = 1.645σ
  // beyond each side, less what the four corners round off (integrated
  // numerically from the closed-form filtered corner). L_eff·A_eff is the
  // flux above the threshold, about all of it, over a larger area than the
  // panel's: k² ≈ A / A_eff < 1, a small rebate (−1.3 here; it shrinks as
  // the panel grows against the 12 mm blur).
  const double px = 0.0005, l = 1.0e4, w = 0.08, h = 0.06;
  const double sigma = 0.012 / 2.3548200450309493;
  LuminanceMap m = blank(240, 200, px);
  const int x0 = 40, y0 = 40, nx = static_cast<int>(std::lround(w / px)), ny = static_cast<int>(std::lround(h / px));
  for (int y = y0; y < y0 + ny; ++y)
    for (int x = x0; x < x0 + nx; ++x) at(m, x, y) = l;
  const double intensity = l * w * h, ap = w * h;
  const NonUniformGlare g = analyse_non_uniform_glare(m, intensity, ap);
  ASSERT_TRUE(g.defined);
  const double x_star = 1.6448536269514722 * sigma;
  const double a_eff = (w + 2 * x_star) * (h + 2 * x_star) - 4.0 * x_star * x_star + 4.0 * corner_excess(sigma, 0.05);
  EXPECT_NEAR(g.glare_area_m2 / a_eff, 1.0, 0.01);
  EXPECT_NEAR(g.mean_luminance_cd_m2, l, 1e-6);
  const double k2_bound = ap / a_eff;  // all flux above the threshold
  EXPECT_LT(g.k2, k2_bound);
  EXPECT_GT(g.k2, 0.9 * k2_bound);
  EXPECT_LT(g.delta_ugr, 0.0);
}

TEST(NonUniformGlare, DarkOrEmptyImagesAreUndefinedWithTheReason) {
  LuminanceMap m = blank(50, 50, 0.001);
  for (double& v : m.cd_m2) v = 400.0;  // everywhere under 500 cd/m²
  NonUniformGlare g = analyse_non_uniform_glare(m, 1.0, 0.0025);
  EXPECT_FALSE(g.defined);
  EXPECT_NE(g.why_undefined.find("500"), std::string::npos);
  g = analyse_non_uniform_glare(LuminanceMap{}, 1.0, 1.0);
  EXPECT_FALSE(g.defined);
  g = analyse_non_uniform_glare(m, 0.0, 1.0);
  EXPECT_FALSE(g.defined);
  // 1 mm pixels are coarser than d/10 = 1.2 mm? No: finer; 2 mm is coarser.
  EXPECT_TRUE(analyse_non_uniform_glare(m, 1.0, 1.0).resolution_ok);
  m.pixel_m = 0.002;
  EXPECT_FALSE(analyse_non_uniform_glare(m, 1.0, 1.0).resolution_ok);
}

TEST(NonUniformGlare, ThresholdAndResolutionAreParameters) {
  // A lower threshold takes in more of the blur: larger area, lower mean.
  LuminanceMap m = blank(120, 120, 0.0005);
  at(m, 60, 60) = 3.3e6;  // filtered peak ≈ 5000 cd/m²: the 500 and 100 cd/m² contours lie inside the kernel
  const NonUniformGlare a = analyse_non_uniform_glare(m, 1.0, 0.001);
  NonUniformGlareParameters p;
  p.threshold_cd_m2 = 100.0;
  const NonUniformGlare b = analyse_non_uniform_glare(m, 1.0, 0.001, p);
  ASSERT_TRUE(a.defined);
  ASSERT_TRUE(b.defined);
  EXPECT_GT(b.glare_area_m2, a.glare_area_m2);
  EXPECT_LT(b.glare_luminance_cd_m2, a.glare_luminance_cd_m2);
  p = {};
  p.eye_resolution_m = 0.024;
  const NonUniformGlare c = analyse_non_uniform_glare(m, 1.0, 0.001, p);
  EXPECT_NEAR(c.sigma_px, 2.0 * a.sigma_px, 1e-12);
}

}  // namespace
}  // namespace gonio::photometry
