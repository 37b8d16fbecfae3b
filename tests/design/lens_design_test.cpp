// Direct design of lenses (design/lens_design.h): the refractive equation
// d(ln r)/dθ = sin(φ − θ)/(n − cos(φ − θ)) against its closed forms — the
// collimator, an ellipse of eccentricity 1/n with the source at its far
// focus, and the linear maps φ = kθ — through the map of design/flux_map.h,
// and the targets no lens can give.
#include "design/lens_design.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "design/design_file.h"
#include "design/design_scene.h"
#include "photometry/flux.h"

namespace gonio::design {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

photometry::Distribution lambertian(double cd) {
  std::vector<double> g, c;
  for (int i = 0; i <= 180; ++i) {
    g.push_back(i);
    c.push_back(i <= 90 ? cd * std::cos(i * kDeg) : 0.0);
  }
  return rotational_distribution(g, c);
}

TEST(LensDesign, CollimatorIsTheEllipseOfEccentricityOneOverNAboutItsFarFocus) {
  for (double n : {1.491, 1.585}) {
    LensDesignOptions o;
    o.ior = n;
    o.to_deg = 45.0;
    o.distance_m = 0.010;
    o.inner_radius_m = 0.004;
    LensDesign d;
    ASSERT_TRUE(integrate_lens_profile([](double) { return 0.0; }, o, d).ok());
    // r = p/(1 − e·cos θ), e = 1/n, p = r₀(n − 1)/n; the other focus on the
    // axis below, 2c = 2ae away; every point's two focal distances sum to 2a.
    const double e = 1.0 / n, p = o.distance_m * (n - 1.0) / n, a = p / (1.0 - e * e), c = a * e;
    double worst_r = 0.0, worst_sum = 0.0;
    for (std::size_t i = 0; i < d.theta.size(); ++i) {
      const double t = d.theta[i], r = d.r[i];
      worst_r = std::max(worst_r, std::abs(r / (p / (1.0 - e * std::cos(t))) - 1.0));
      const double rho = r * std::sin(t), z = -r * std::cos(t);
      worst_sum = std::max(worst_sum, std::abs((r + std::hypot(rho, z + 2.0 * c)) / (2.0 * a) - 1.0));
    }
    std::printf("n = %g: collimator profile error %.3g, focal sum %.3g\n", n, worst_r, worst_sum);
    EXPECT_LT(worst_r, 1e-12);
    EXPECT_LT(worst_sum, 1e-12);
    EXPECT_NEAR(d.largest_deviation_deg, 45.0, 1e-9);
  }
}

struct Exact {
  double k, to_deg;
  ReflectorMap map;
};

TEST(LensDesign, LinearMapsGiveTheClosedFormProfile) {
  const photometry::Distribution emitter = lambertian(100.0);
  for (const Exact& e : {Exact{0.5, 60.0, ReflectorMap::Uncrossed}, Exact{0.25, 40.0, ReflectorMap::Uncrossed},
                         Exact{0.75, 40.0, ReflectorMap::Uncrossed}, Exact{-0.5, 30.0, ReflectorMap::Crossed}}) {
    LensDesignOptions o;
    o.to_deg = e.to_deg;
    o.map = e.map;
    o.distance_m = 0.010;
    o.inner_radius_m = 0.003;
    Result<LensDesign> d = design_lens(emitter, linear_lens_target(emitter, e.k, e.to_deg, 0.01), o);
    ASSERT_TRUE(d.ok()) << d.error().message;
    double fine = 0.0, table = 0.0;
    for (std::size_t i = 0; i < d->theta.size(); ++i)
      fine = std::max(fine, std::abs(d->r[i] / linear_lens_r(e.k, o.ior, d->theta[i], o.distance_m) - 1.0));
    const PolarProfile& p = d->outer;
    for (std::size_t i = 0; i + 1 < p.theta.size(); ++i) {
      const double mid = 0.5 * (p.theta[i] + p.theta[i + 1]);
      table = std::max(table, std::abs(polar_r(p, mid) / linear_lens_r(e.k, o.ior, mid, o.distance_m) - 1.0));
    }
    std::printf("lens k = %g, cone 0…%g°: profile error %.3g (fine), %.3g (table)\n", e.k, e.to_deg, fine, table);
    EXPECT_LT(fine, 1e-4) << e.k;
    EXPECT_LT(table, 1e-4) << e.k;
  }
}

// φ = 1.5θ over 0…30°: the refracted light (0…45°) overlaps the direct light
// above 30°. The added light is the target less the direct light; above 45°
// only rounding is left of it, which must not stretch the map's end (it took
// the cone's rim to 90°, and the TIR check refused the design).
TEST(LensDesign, RefractedLightOverlappingTheDirectLightGivesTheClosedForm) {
  const photometry::Distribution emitter = lambertian(100.0);
  LensDesignOptions o;
  o.to_deg = 30.0;
  o.distance_m = 0.010;
  o.inner_radius_m = 0.003;
  Result<LensDesign> d = design_lens(emitter, linear_lens_target(emitter, 1.5, 30.0, 0.01), o);
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_NEAR(d->target_to_deg, 45.0, 0.02);  // the 0.01° target grid's ramp at its edge
  EXPECT_NEAR(d->phi.back() / kDeg, 45.0, 0.02);
  EXPECT_NEAR(d->largest_deviation_deg, 15.0, 0.02);
  double fine = 0.0, table = 0.0;
  for (std::size_t i = 0; i < d->theta.size(); ++i)
    fine = std::max(fine, std::abs(d->r[i] / linear_lens_r(1.5, o.ior, d->theta[i], o.distance_m) - 1.0));
  const PolarProfile& p = d->outer;
  for (std::size_t i = 0; i + 1 < p.theta.size(); ++i) {
    const double mid = 0.5 * (p.theta[i] + p.theta[i + 1]);
    table = std::max(table, std::abs(polar_r(p, mid) / linear_lens_r(1.5, o.ior, mid, o.distance_m) - 1.0));
  }
  std::printf("lens k = 1.5, cone 0…30° (overlapping the direct light): profile error %.3g (fine), %.3g (table)\n",
              fine, table);
  EXPECT_LT(fine, 1e-4);
  EXPECT_LT(table, 1e-4);
}

TEST(LensDesign, TheDesignFileIsTheDesignedLens) {
  const photometry::Distribution emitter = lambertian(100.0);
  LensDesignOptions o;
  o.to_deg = 60.0;
  Result<LensDesign> d = design_lens(emitter, linear_lens_target(emitter, 0.5, 60.0), o);
  ASSERT_TRUE(d.ok()) << d.error().message;
  const std::string text = write_design(lens_design_document(*d, "emitter.ies", o.ior, "lens"));
  Result<Design> design = parse_design(text, "lens.design.toml");
  ASSERT_TRUE(design.ok()) << to_string(design.error());
  EXPECT_EQ(design->variables.size(), static_cast<std::size_t>(o.nodes));
  Result<DesignParts> parts = read_design_parts(resolved_document(*design), design->path);
  ASSERT_TRUE(parts.ok()) << to_string(parts.error());
  ASSERT_EQ(parts->lenses.size(), 1u);
  const auto& outer = std::get<PolarProfile>(parts->lenses[0].outer);
  for (double t = 0.0; t <= 60.0; t += 0.7)
    EXPECT_NEAR(polar_r(outer, t * kDeg) / linear_lens_r(0.5, o.ior, t * kDeg, o.distance_m), 1.0, 1e-4) << t;
}

TEST(LensDesign, TargetsNoLensCanGiveSayWhy) {
  const photometry::Distribution emitter = lambertian(100.0);
  // 10⁴ cd within 5° (240 lm, against the emitter's 314), and the emitter's
  // direct light above the cone.
  const photometry::Distribution expanded = photometry::expand_symmetry(emitter);
  auto spot = [&](double to_deg) {
    std::vector<double> g, c;
    for (int i = 0; i <= 180; ++i) {
      g.push_back(i);
      c.push_back((i <= 5 ? 10000.0 : 0.0) + (i >= to_deg ? rotational_intensity(expanded, i) : 0.0));
    }
    return rotational_distribution(g, c);
  };
  // All of 0…80° into 5°: the rim's ray must turn by 75°, more than
  // arccos(1/1.491) = 47.9° out of PMMA.
  LensDesignOptions o;
  o.to_deg = 80.0;
  Result<LensDesign> d = design_lens(emitter, spot(80.0), o);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("total internal reflection at the outer surface"), std::string::npos)
      << d.error().message;
  // Absolute: 240 lm asked, the emitter has 130 lm in 0…40°.
  o.to_deg = 40.0;
  o.absolute = true;
  d = design_lens(emitter, spot(40.0), o);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("more flux than the emitter has there"), std::string::npos) << d.error().message;
  // A diverging map whose outer surface comes inside the inner sphere.
  o.absolute = false;
  o.distance_m = 0.0101;
  o.inner_radius_m = 0.0100;
  d = design_lens(emitter, linear_lens_target(emitter, 0.5, 40.0), o);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("thinner than zero"), std::string::npos) << d.error().message;
}

// The feedback's corrected targets may ask less than the direct light above
// the cone: with allow_deficit the lens adds nothing there (the same lens as
// for the target without the deficit), without it the error says why.
TEST(LensDesign, AllowDeficitDesignsATargetBelowTheDirectLight) {
  const photometry::Distribution emitter = lambertian(100.0);
  const photometry::Distribution exact = photometry::expand_symmetry(linear_lens_target(emitter, 0.5, 40.0, 0.05));
  std::vector<double> g, c;
  for (int i = 0; i <= 3600; ++i) {
    const double gd = 0.05 * i;
    g.push_back(gd);
    c.push_back(rotational_intensity(exact, gd) * (gd > 60.0 && gd < 80.0 ? 0.5 : 1.0));
  }
  const photometry::Distribution short_target = rotational_distribution(g, c);
  LensDesignOptions o;
  o.to_deg = 40.0;
  o.absolute = true;  // the target's candela as they are: the deficit takes no flux from the beam
  Result<LensDesign> refused = design_lens(emitter, short_target, o);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("a lens can only add light"), std::string::npos) << refused.error().message;
  o.allow_deficit = true;
  Result<LensDesign> d = design_lens(emitter, short_target, o);
  ASSERT_TRUE(d.ok()) << d.error().message;
  // The refracted light's map is the exact case's (k = 0.5): the profile its closed form.
  double worst = 0.0;
  for (std::size_t i = 0; i < d->outer.theta.size(); ++i)
    worst = std::max(worst, std::abs(d->outer.r[i] / linear_lens_r(0.5, o.ior, d->outer.theta[i], o.distance_m) - 1.0));
  EXPECT_LT(worst, 2e-3);
}

}  // namespace
}  // namespace gonio::design
