#include "sim/material.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "sim/sampling.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

Material glossy(double mx, double my, double f0 = 1.0) {
  Material m;
  m.name = "glossy";
  m.glossy = 1.0;
  m.glossy_mx = mx;
  m.glossy_my = my;
  m.glossy_f0 = f0;
  return m;
}

// Midpoint quadrature over the upper hemisphere in (cos θ, φ).
template <class F>
double integrate_hemisphere(F f, int nz = 600, int np = 600) {
  double sum = 0.0;
  for (int i = 0; i < nz; ++i) {
    const double z = (i + 0.5) / nz;
    const double s = std::sqrt(1.0 - z * z);
    for (int j = 0; j < np; ++j) {
      const double p = (j + 0.5) * 2.0 * kPi / np;
      sum += f(Vec3{s * std::cos(p), s * std::sin(p), z});
    }
  }
  return sum * (1.0 / nz) * (2.0 * kPi / np);
}

Vec3 incident(double theta_deg, double phi_deg = 0.0) {
  const double t = theta_deg * kDeg, p = phi_deg * kDeg;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

TEST(Material, ValidateNamesTheMaterial) {
  Material m;
  m.name = "opal";
  m.diffuse_reflect = 0.7;
  m.diffuse_transmit = 0.4;
  Status s = validate(m);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("'opal'"), std::string::npos);
  m.diffuse_transmit = 0.3;
  EXPECT_TRUE(validate(m).ok());
  m.mirror = -0.1;
  EXPECT_FALSE(validate(m).ok());
  m.mirror = 0.0;
  m.attenuation_per_m = std::nan("");
  EXPECT_FALSE(validate(m).ok());
  m.attenuation_per_m = 0.0;
  m.ior = 0.0;
  EXPECT_FALSE(validate(m).ok());
  m = glossy(0.0, 0.1);
  EXPECT_FALSE(validate(m).ok());
  m = glossy(0.1, 0.1, 1.5);
  EXPECT_FALSE(validate(m).ok());
}

TEST(Material, LobesAreChosenByTheirWeights) {
  Material m;
  m.diffuse_reflect = 0.3;
  m.diffuse_transmit = 0.6;
  m.mirror = 0.05;
  EXPECT_EQ(choose_lobe(m, 0.0), Lobe::DiffuseReflect);
  EXPECT_EQ(choose_lobe(m, 0.2999), Lobe::DiffuseReflect);
  EXPECT_EQ(choose_lobe(m, 0.3), Lobe::DiffuseTransmit);
  EXPECT_EQ(choose_lobe(m, 0.92), Lobe::Mirror);
  EXPECT_EQ(choose_lobe(m, 0.96), Lobe::Absorb);
  Material black;
  EXPECT_EQ(choose_lobe(black, 0.0), Lobe::Absorb);
  // The precomputed form agrees everywhere.
  m.glossy = 0.02;
  m.dielectric = 0.01;
  const LobeCdf cdf = lobe_cdf(m);
  for (int i = 0; i < 1000; ++i) {
    const double u = i / 1000.0;
    EXPECT_EQ(choose_lobe(cdf, u), choose_lobe(m, u)) << u;
  }
  EXPECT_EQ(choose_lobe(lobe_cdf(black), 0.0), Lobe::Absorb);
}

TEST(Dielectric, FresnelClosedForms) {
  // Normal incidence: ((n − 1)/(n + 1))², either way round.
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.0, 1.52), std::pow(0.52 / 2.52, 2), 1e-15);
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.52, 1.0), std::pow(0.52 / 2.52, 2), 1e-15);
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.0, 1.52), 0.0426, 5e-5);
  // At Brewster's angle p is not reflected: R = rs²/2.
  const double tb = std::atan(1.5);
  const double ci = std::cos(tb), ct = std::cos(std::asin(std::sin(tb) / 1.5));
  const double rs = (ci - 1.5 * ct) / (ci + 1.5 * ct);
  EXPECT_NEAR(fresnel_dielectric(ci, 1.0, 1.5), 0.5 * rs * rs, 1e-14);
  // Total internal reflection beyond the critical angle, 1 at grazing.
  const double critical = std::asin(1.0 / 1.5);
  EXPECT_EQ(fresnel_dielectric(std::cos(critical + 1e-6), 1.5, 1.0), 1.0);
  EXPECT_LT(fresnel_dielectric(std::cos(critical - 1e-3), 1.5, 1.0), 1.0);
  EXPECT_NEAR(fresnel_dielectric(0.0, 1.0, 1.5), 1.0, 1e-12);
  // Reciprocity: the same R from either side along the same ray path.
  const double t1 = 40 * kDeg, t2 = std::asin(std::sin(t1) / 1.5);
  EXPECT_NEAR(fresnel_dielectric(std::cos(t1), 1.0, 1.5), fresnel_dielectric(std::cos(t2), 1.5, 1.0), 1e-14);
}

TEST(Dielectric, RefractionFollowsSnell) {
  const Vec3 n{0, 0, 1};
  const Vec3 wi = incident(50.0, 30.0);
  Vec3 wt;
  ASSERT_TRUE(refract(wi, n, 1.0 / 1.5, &wt));
  EXPECT_NEAR(length(wt), 1.0, 1e-14);
  EXPECT_LT(wt.z, 0.0);
  const double sin_t = std::hypot(wt.x, wt.y);
  EXPECT_NEAR(sin_t, std::sin(50 * kDeg) / 1.5, 1e-14);
  // In the plane of incidence, on the far side of the normal.
  EXPECT_NEAR(wt.x * wi.y - wt.y * wi.x, 0.0, 1e-14);
  EXPECT_LT(wt.x * wi.x + wt.y * wi.y, 0.0);
  EXPECT_FALSE(refract(incident(60.0), n, 1.5, &wt));  // total internal reflection
  const Vec3 r = reflect(wi, n);
  EXPECT_NEAR(r.z, wi.z, 1e-15);
  EXPECT_NEAR(r.x, -wi.x, 1e-15);
}

TEST(Glossy, DistributionIsNormalised) {
  for (auto [mx, my] : {std::pair{0.1, 0.1}, std::pair{0.3, 0.1}, std::pair{0.5, 0.8}}) {
    const double norm = integrate_hemisphere([&](const Vec3& h) { return beckmann_d(mx, my, h) * h.z; },
                                             2000, 400);
    EXPECT_NEAR(norm, 1.0, 2e-3) << mx << " " << my;
  }
}

TEST(Glossy, HalfVectorsFollowTheDistribution) {
  // Anisotropic: histogram in (θh, φh) against ∫ D cos θh dω per bin.
  const double mx = 0.15, my = 0.4;
  const int nt = 10, np = 12, n = 400000;
  const double tmax = std::atan(my * 3.5);  // covers all but e^-12 of the mass
  std::vector<double> obs(nt * np, 0.0), exp(nt * np, 0.0);
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(13, static_cast<std::uint64_t>(k));
    double c, s;
    sample_unit_circle(rng, &c, &s);
    const Vec3 h = sample_beckmann_half_vector(mx, my, rng.uniform_open0(), c, s);
    ASSERT_NEAR(length(h), 1.0, 1e-12);
    const double t = std::acos(h.z);
    double p = std::atan2(h.y, h.x);
    if (p < 0) p += 2 * kPi;
    if (t >= tmax) continue;
    obs[static_cast<int>(t / tmax * nt) * np + std::min(np - 1, static_cast<int>(p / (2 * kPi) * np))] += 1;
  }
  const int sub = 30;
  for (int i = 0; i < nt * sub; ++i) {
    const double t0 = i * tmax / (nt * sub), t1 = (i + 1) * tmax / (nt * sub);
    const double tm = 0.5 * (t0 + t1), dz = std::cos(t0) - std::cos(t1);
    for (int j = 0; j < np * sub; ++j) {
      const double p = (j + 0.5) * 2 * kPi / (np * sub);
      const Vec3 h{std::sin(tm) * std::cos(p), std::sin(tm) * std::sin(p), std::cos(tm)};
      exp[(i / sub) * np + j / sub] += n * beckmann_d(mx, my, h) * h.z * dz * 2 * kPi / (np * sub);
    }
  }
  double chi2 = 0.0;
  int dof = -1;
  for (std::size_t b = 0; b < obs.size(); ++b) {
    if (exp[b] < 10.0) continue;
    chi2 += (obs[b] - exp[b]) * (obs[b] - exp[b]) / exp[b];
    ++dof;
  }
  EXPECT_GT(dof, 60);
  EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof));
}

TEST(Glossy, PdfIntegratesToOneAndMatchesTheSampleWeights) {
  const Material m = glossy(0.2, 0.35, 0.3);
  for (double ti : {0.0, 30.0, 60.0}) {
    const Vec3 wi = incident(ti, 20.0);
    // ∫ pdf over the whole sphere: the part below the horizon is where the
    // sampler returns weight 0.
    const double up = integrate_hemisphere([&](const Vec3& o) { return glossy_pdf(m, wi, o); }, 1500, 600);
    const double down = integrate_hemisphere(
        [&](const Vec3& o) { return glossy_pdf(m, wi, Vec3{o.x, o.y, -o.z}); }, 300, 300);
    EXPECT_NEAR(up + down, 1.0, 3e-3) << ti;
    // The weight a sample carries is f · cos θo / pdf.
    for (int k = 0; k < 200; ++k) {
      PhotonRandom rng(17, static_cast<std::uint64_t>(k));
      double c, s;
      sample_unit_circle(rng, &c, &s);
      const GlossySample g = sample_glossy(m, wi, rng.uniform_open0(), c, s);
      if (g.weight == 0.0) continue;
      const double expected = glossy_brdf(m, wi, g.wo) * g.wo.z / glossy_pdf(m, wi, g.wo);
      ASSERT_NEAR(g.weight, expected, 1e-9 * expected);
    }
  }
}

TEST(Glossy, ReciprocityAndEnergy) {
  const Material m = glossy(0.25, 0.1, 0.6);
  for (int k = 0; k < 100; ++k) {
    PhotonRandom rng(19, static_cast<std::uint64_t>(k));
    const Vec3 a = sample_cosine_hemisphere(rng), b = sample_cosine_hemisphere(rng);
    EXPECT_NEAR(glossy_brdf(m, a, b), glossy_brdf(m, b, a), 1e-12 * glossy_brdf(m, a, b));
  }
  // Albedo ∫ f cos θo dωo: ≈ f0 for a smooth lobe at any incidence (α = ½),
  // and at most 1 for moderate roughness up to 60°.
  const Material smooth = glossy(0.05, 0.05, 1.0);
  for (double ti : {0.0, 45.0, 70.0}) {
    const Vec3 wi = incident(ti);
    const double albedo = integrate_hemisphere(
        [&](const Vec3& o) { return glossy_brdf(smooth, wi, o) * o.z; }, 3000, 1200);
    EXPECT_NEAR(albedo, 1.0, 0.03) << ti;
  }
  const Material rough = glossy(0.3, 0.3, 1.0);
  for (double ti : {0.0, 30.0, 60.0}) {
    const Vec3 wi = incident(ti);
    const double albedo = integrate_hemisphere(
        [&](const Vec3& o) { return glossy_brdf(rough, wi, o) * o.z; }, 1500, 600);
    EXPECT_LE(albedo, 1.0) << ti;
    EXPECT_GT(albedo, 0.8) << ti;
    // The mean sample weight estimates the same albedo.
    double sum = 0.0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
      PhotonRandom rng(23, static_cast<std::uint64_t>(k));
      double c, s;
      sample_unit_circle(rng, &c, &s);
      sum += sample_glossy(rough, wi, rng.uniform_open0(), c, s).weight;
    }
    EXPECT_NEAR(sum / n, albedo, 0.01) << ti;
  }
}

TEST(Scatter, DirectionsLeaveOnTheRightSide) {
  const SurfaceFrame f{{0, 0, 1}, {0, 0, 1}, {1, 0, 0}};
  const Vec3 down = normalize(Vec3{0.3, 0.1, -1.0});  // arriving on the front
  auto run = [&](const Material& m, const Vec3& d, int* reflected, int* transmitted, int* absorbed) {
    for (int k = 0; k < 20000; ++k) {
      PhotonRandom rng(31, static_cast<std::uint64_t>(k));
      const ScatterResult r = scatter(m, f, d, rng);
      if (r.absorbed) {
        ++*absorbed;
        continue;
      }
      ASSERT_NEAR(length(r.direction), 1.0, 1e-9);
      const bool same_side = (r.direction.z > 0) == (d.z < 0);
      ++*(same_side ? reflected : transmitted);
    }
  };
  Material opal;
  opal.diffuse_reflect = 0.3;
  opal.diffuse_transmit = 0.6;
  int re = 0, tr = 0, ab = 0;
  run(opal, down, &re, &tr, &ab);
  EXPECT_NEAR(re / 20000.0, 0.3, 0.02);
  EXPECT_NEAR(tr / 20000.0, 0.6, 0.02);
  EXPECT_NEAR(ab / 20000.0, 0.1, 0.01);
  // From the back the sides swap.
  re = tr = ab = 0;
  run(opal, -down, &re, &tr, &ab);
  EXPECT_NEAR(tr / 20000.0, 0.6, 0.02);

  Material mirror;
  mirror.mirror = 1.0;
  PhotonRandom rng(1, 1);
  const ScatterResult mr = scatter(mirror, f, down, rng);
  EXPECT_FALSE(mr.absorbed);
  EXPECT_NEAR(mr.direction.z, -down.z, 1e-12);
  EXPECT_NEAR(mr.direction.x, down.x, 1e-12);

  // A shading normal that would send the mirror ray through the surface
  // falls back to the geometric normal.
  const SurfaceFrame tilted{{0, 0, 1}, normalize(Vec3{1, 0, 0.2}), {}};
  const Vec3 grazing = normalize(Vec3{1, 0, -0.1});
  const ScatterResult fb = scatter(mirror, tilted, grazing, rng);
  EXPECT_GT(fb.direction.z, 0.0);

  // Dielectric at normal incidence: R = 0.0426 for n = 1.52, the rest
  // refracted straight through.
  Material glass;
  glass.dielectric = 1.0;
  glass.ior = 1.52;
  re = tr = ab = 0;
  int n = 0;
  for (int k = 0; k < 200000; ++k, ++n) {
    PhotonRandom r2(37, static_cast<std::uint64_t>(k));
    const ScatterResult r = scatter(glass, f, {0, 0, -1}, r2);
    ASSERT_FALSE(r.absorbed);
    if (r.direction.z > 0) {
      ++re;
    } else {
      ++tr;
      ASSERT_NEAR(r.direction.z, -1.0, 1e-12);
    }
  }
  EXPECT_NEAR(re / static_cast<double>(n), 0.0426, 5 * std::sqrt(0.0426 * 0.9574 / n));
}

TEST(Scatter, GlossyRouletteKeepsPowerEqualBelowOne) {
  // With f0 = 0.2 every weight is below 1: survivors keep power 1 and the
  // survival rate is the lobe's albedo.
  const Material m = glossy(0.1, 0.1, 0.2);
  const SurfaceFrame f{{0, 0, 1}, {0, 0, 1}, {}};
  const Vec3 d = -incident(30.0);
  int survived = 0;
  const int n = 100000;
  double weights = 0.0;
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(41, static_cast<std::uint64_t>(k));
    const ScatterResult r = scatter(m, f, d, rng);
    if (!r.absorbed) {
      ++survived;
      ASSERT_EQ(r.power_factor, 1.0);
    }
    PhotonRandom rng2(43, static_cast<std::uint64_t>(k));
    double c, s;
    sample_unit_circle(rng2, &c, &s);
    weights += sample_glossy(m, -d, rng2.uniform_open0(), c, s).weight;
  }
  EXPECT_NEAR(survived / static_cast<double>(n), weights / n, 0.01);
}

}  // namespace
}  // namespace gonio::sim
