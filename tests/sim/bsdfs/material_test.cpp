#include "sim/bsdfs/material.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "sim/samplers/sampling.h"

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

TEST(Glossy, LambdaClosedFormsAndProjectedArea) {
  // Isotropic Λ at a = 1 (tan θ = 1/m): (erf 1 − 1)/2 + e⁻¹/(2√π).
  const double m = 0.4, t = std::atan(1.0 / m);
  const Vec3 w{std::sin(t), 0.0, std::cos(t)};
  EXPECT_NEAR(beckmann_lambda(m, m, w), (std::erf(1.0) - 1.0) / 2.0 + std::exp(-1.0) / (2.0 * std::sqrt(kPi)),
              1e-15);
  EXPECT_EQ(beckmann_lambda(0.3, 0.1, {0, 0, 1}), 0.0);
  EXPECT_EQ(smith_g1(0.3, 0.1, {1, 0, 0}), 0.0);
  EXPECT_EQ(smith_g1(0.3, 0.1, incident(100.0)), 0.0);
  // Large a: no cancellation, Λ small and positive, falling with a.
  const double l1 = beckmann_lambda(0.01, 0.01, incident(60.0));  // a = 57.7
  const double l2 = beckmann_lambda(0.1, 0.1, incident(70.0));    // a = 3.64
  EXPECT_GE(l1, 0.0);
  EXPECT_GT(l2, 0.0);
  EXPECT_LT(l2, 1e-6);
  // Anisotropic: only the roughness along the azimuth of w matters.
  EXPECT_NEAR(beckmann_lambda(0.3, 0.1, incident(70.0, 0.0)), beckmann_lambda(0.3, 0.3, incident(70.0)), 1e-15);
  EXPECT_NEAR(beckmann_lambda(0.3, 0.1, incident(70.0, 90.0)), beckmann_lambda(0.1, 0.1, incident(70.0)), 1e-15);
  // The facets' projected area is the surface's: ∫ G1(w) D(h) max(0, w·h) dωh
  // = cos θ at every incidence. This pins down Λ's exact form: a rational
  // approximation misses by up to 2e-3.
  for (auto [mx, my] : {std::pair{0.3, 0.3}, std::pair{0.6, 0.2}, std::pair{1.0, 0.5}}) {
    for (double ti : {0.0, 45.0, 75.0, 88.0}) {
      const Vec3 wi = incident(ti, 30.0);
      const double area = smith_g1(mx, my, wi) * integrate_hemisphere([&](const Vec3& h) {
                            return beckmann_d(mx, my, h) * std::max(0.0, dot(wi, h));
                          }, 2000, 600);
      EXPECT_NEAR(area, wi.z, 2e-4) << mx << " " << my << " " << ti;
    }
  }
}

// Histogram of half vectors in (θh, φh) bins against the expected count of
// a density over them (sub-sampled midpoint quadrature); returns χ² − dof
// in units of √(2 dof).
template <class Sample, class Density>
double half_vector_chi2_sigma(Sample sample, Density density, double tmax, int n, int* dof_out) {
  const int nt = 10, np = 12;
  std::vector<double> obs(nt * np + 1, 0.0), exp(nt * np + 1, 0.0);
  for (int k = 0; k < n; ++k) {
    const Vec3 h = sample(k);
    EXPECT_NEAR(length(h), 1.0, 1e-12);
    const double t = std::acos(std::clamp(h.z, -1.0, 1.0));
    double p = std::atan2(h.y, h.x);
    if (p < 0) p += 2 * kPi;
    if (t >= tmax) {
      obs[nt * np] += 1;  // the rest, pooled
      continue;
    }
    obs[static_cast<int>(t / tmax * nt) * np + std::min(np - 1, static_cast<int>(p / (2 * kPi) * np))] += 1;
  }
  const int sub = 30;
  double inside = 0.0;
  for (int i = 0; i < nt * sub; ++i) {
    const double t0 = i * tmax / (nt * sub), t1 = (i + 1) * tmax / (nt * sub);
    const double tm = 0.5 * (t0 + t1), dz = std::cos(t0) - std::cos(t1);
    for (int j = 0; j < np * sub; ++j) {
      const double p = (j + 0.5) * 2 * kPi / (np * sub);
      const Vec3 h{std::sin(tm) * std::cos(p), std::sin(tm) * std::sin(p), std::cos(tm)};
      const double e = n * density(h) * dz * 2 * kPi / (np * sub);
      exp[(i / sub) * np + j / sub] += e;
      inside += e;
    }
  }
  exp[nt * np] = std::max(0.0, n - inside);
  double chi2 = 0.0;
  int dof = -1;
  for (std::size_t b = 0; b < obs.size(); ++b) {
    if (exp[b] < 10.0) continue;
    chi2 += (obs[b] - exp[b]) * (obs[b] - exp[b]) / exp[b];
    ++dof;
  }
  *dof_out = dof;
  return (chi2 - dof) / std::sqrt(2.0 * dof);
}

TEST(Glossy, VisibleHalfVectorsStartFromWaltersFormulas) {
  // Where masking hides nothing (normal incidence, or Λ vanishing beside 1)
  // the draw is Walter's half vector h or its mirror image (−hx, −hy, hz)
  // from the same random numbers, the mirror half the time (t is symmetric)
  // and, away from the normal, more often the one that faces wi more.
  for (const Vec3& wi : {Vec3{0, 0, 1}, incident(30.0, 70.0)}) {
    int mirrored = 0, facing = 0;
    const int n = 40000;
    ASSERT_EQ(beckmann_lambda(0.3, 0.1, wi), 0.0);
    for (int k = 0; k < n; ++k) {
      PhotonRandom a(47, static_cast<std::uint64_t>(k)), b(47, static_cast<std::uint64_t>(k));
      const Vec3 h = sample_visible_half_vector(0.3, 0.1, wi, a);
      double c, s;
      sample_unit_circle(b, &c, &s);
      const Vec3 w = sample_beckmann_half_vector(0.3, 0.1, b.uniform_open0(), c, s);
      const bool mirror = h.x * w.x + h.y * w.y < 0.0;
      const double sign = mirror ? -1.0 : 1.0;
      ASSERT_NEAR(h.x, sign * w.x, 1e-12);
      ASSERT_NEAR(h.y, sign * w.y, 1e-12);
      ASSERT_NEAR(h.z, w.z, 1e-12);
      mirrored += mirror;
      facing += dot(wi, h) > dot(wi, Vec3{-h.x, -h.y, h.z});
    }
    const double sigma = 0.5 / std::sqrt(n);
    EXPECT_NEAR(mirrored / static_cast<double>(n), 0.5, 5.0 * sigma);
    if (wi.z == 1.0) {
      EXPECT_EQ(facing, 0);  // a tie every time
    } else {
      // P = E[(1 + |t|)/2] with t = X/a, E|X| = 1/√π for Walter's slopes.
      const double inv_a = std::hypot(0.3 * wi.x, 0.1 * wi.y) / wi.z;
      EXPECT_NEAR(facing / static_cast<double>(n), 0.5 + inv_a / (2.0 * std::sqrt(kPi)), 5.0 * sigma);
    }
  }
}

TEST(Glossy, VisibleHalfVectorsFollowTheirDensity) {
  // Normal incidence (Walter's draw itself), oblique, and grazing where the
  // tail component carries much of the mass (Λ = 0.62 for the third case,
  // 1.9 for the fourth); anisotropic and turned against the tangent.
  struct Case {
    double mx, my, theta, phi;
  };
  for (const Case c : {Case{0.3, 0.3, 0.0, 0.0}, Case{0.1, 0.1, 60.0, 0.0}, Case{0.5, 0.2, 80.0, 30.0},
                       Case{0.05, 0.4, 88.0, 100.0}}) {
    const Vec3 wi = incident(c.theta, c.phi);
    const double norm = integrate_hemisphere(
        [&](const Vec3& h) { return visible_half_vector_pdf(c.mx, c.my, wi, h); }, 2000, 800);
    EXPECT_NEAR(norm, 1.0, 2e-3) << c.theta;
    const double tmax = std::atan(std::max(c.mx, c.my) * 3.0);
    int dof = 0;
    const double z = half_vector_chi2_sigma(
        [&](int k) {
          PhotonRandom rng(29, static_cast<std::uint64_t>(k));
          return sample_visible_half_vector(c.mx, c.my, wi, rng);
        },
        [&](const Vec3& h) { return visible_half_vector_pdf(c.mx, c.my, wi, h); }, tmax, 300000, &dof);
    EXPECT_GT(dof, 30) << c.theta;
    EXPECT_LT(std::abs(z), 5.0) << c.mx << " " << c.my << " " << c.theta << "°";
  }
}

TEST(Glossy, PdfIntegratesToOneAndMatchesTheSampleWeights) {
  const Material m = glossy(0.2, 0.35, 0.3);
  for (double ti : {0.0, 30.0, 60.0, 85.0}) {
    const Vec3 wi = incident(ti, 20.0);
    // ∫ pdf over the whole sphere is 1; the part above the surface is the
    // fraction of samples that leave (the rest get weight 0).
    const double up = integrate_hemisphere([&](const Vec3& o) { return glossy_pdf(m, wi, o); }, 1500, 600);
    const double down = integrate_hemisphere(
        [&](const Vec3& o) { return glossy_pdf(m, wi, Vec3{o.x, o.y, -o.z}); }, 600, 600);
    EXPECT_NEAR(up + down, 1.0, 3e-3) << ti;
    const int n = 100000;
    int above = 0;
    for (int k = 0; k < n; ++k) {
      PhotonRandom rng(17, static_cast<std::uint64_t>(k));
      const GlossySample g = sample_glossy(m, wi, rng);
      if (g.weight == 0.0) continue;
      ++above;
      // The weight a sample carries is f · cos θo / pdf, and at most 1.
      const double expected = glossy_brdf(m, wi, g.wo) * g.wo.z / glossy_pdf(m, wi, g.wo);
      ASSERT_NEAR(g.weight, expected, 1e-9 * expected);
      ASSERT_LE(g.weight, 1.0);
    }
    EXPECT_NEAR(above / static_cast<double>(n), up, 5.0 * std::sqrt(up * (1.0 - up) / n) + 2e-3) << ti;
  }
  // At and below the horizon nothing is seen: weight 0. Just above it the
  // weight tends to F G2/G1 → F (Λ(wi) → ∞), never NaN.
  for (const Vec3& wi : {Vec3{1, 0, 0}, Vec3{0.6, 0, -0.8}}) {
    PhotonRandom rng(3, 0);
    EXPECT_EQ(sample_glossy(m, wi, rng).weight, 0.0) << wi.z;
    EXPECT_EQ(glossy_pdf(m, wi, Vec3{0, 0, 1}), 0.0) << wi.z;
  }
  for (int k = 0; k < 1000; ++k) {
    PhotonRandom rng(3, static_cast<std::uint64_t>(k));
    const double w = sample_glossy(m, Vec3{1, 0, 1e-300}, rng).weight;
    ASSERT_TRUE(w >= 0.0 && w <= 1.0) << w;
  }
}

TEST(Glossy, ExtremeRoughnessStaysFinite) {
  // From a near-mirror (glTF's floor, 1e-4) to extras far beyond glTF's
  // range: unit directions, weights in [0, 1], never NaN.
  for (auto [mx, my] : {std::pair{1e-4, 1e-4}, std::pair{1e-4, 2.0}, std::pair{3.0, 3.0}, std::pair{100.0, 0.5}}) {
    const Material m = glossy(mx, my, 0.9);
    for (int k = 0; k < 5000; ++k) {
      PhotonRandom rng(43, static_cast<std::uint64_t>(k));
      const Vec3 wi = sample_cosine_hemisphere(rng);
      const GlossySample g = sample_glossy(m, wi, rng);
      ASSERT_TRUE(g.weight >= 0.0 && g.weight <= 1.0) << mx << " " << my << " " << g.weight;
      if (g.weight > 0.0) {
        ASSERT_NEAR(length(g.wo), 1.0, 1e-9);
        ASSERT_GT(g.wo.z, 0.0);
      }
    }
  }
}

TEST(Glossy, Reciprocity) {
  for (const Material& m : {glossy(0.25, 0.1, 0.6), glossy(0.8, 0.8, 0.04), glossy(0.02, 0.3, 1.0)}) {
    for (int k = 0; k < 200; ++k) {
      PhotonRandom rng(19, static_cast<std::uint64_t>(k));
      const Vec3 a = sample_cosine_hemisphere(rng), b = sample_cosine_hemisphere(rng);
      const double fab = glossy_brdf(m, a, b);
      EXPECT_NEAR(fab, glossy_brdf(m, b, a), 1e-12 * fab);
    }
  }
}

// Albedo ∫ f cos θo dωo from two independent samplers: the lobe's own
// (visible normals, weight ≤ 1) and Walter's D cos θh with its weight
// computed here from glossy_brdf and beckmann_d. Both are unbiased; they
// must agree.
struct AlbedoEstimate {
  double visible, visible_sigma, walter, walter_sigma;
  double max_weight;  // largest weight of the lobe's own sampler
};
AlbedoEstimate estimate_albedo(const Material& m, const Vec3& wi, int n, std::uint64_t seed) {
  double s1 = 0, q1 = 0, s2 = 0, q2 = 0, wmax = 0;
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(seed, static_cast<std::uint64_t>(k));
    const double w = sample_glossy(m, wi, rng).weight;
    s1 += w;
    q1 += w * w;
    wmax = std::max(wmax, w);
    double c, s;
    sample_unit_circle(rng, &c, &s);
    const Vec3 h = sample_beckmann_half_vector(m.glossy_mx, m.glossy_my, rng.uniform_open0(), c, s);
    const Vec3 o = 2.0 * dot(wi, h) * h - wi;
    double v = 0.0;
    if (dot(wi, h) > 0.0 && o.z > 0.0)
      v = glossy_brdf(m, wi, o) * o.z * 4.0 * dot(o, h) / (beckmann_d(m.glossy_mx, m.glossy_my, h) * h.z);
    s2 += v;
    q2 += v * v;
  }
  const double m1 = s1 / n, m2 = s2 / n;
  return {m1, std::sqrt(std::max(0.0, q1 / n - m1 * m1) / n), m2, std::sqrt(std::max(0.0, q2 / n - m2 * m2) / n),
          wmax};
}

TEST(Glossy, WhiteFurnace) {
  // f0 = 1: the lobe reflects at most what reaches it, for every roughness
  // glTF's mapping gives (α = roughness² ≤ 1) and every incidence; smooth
  // lobes reflect nearly all of it away from the horizon.
  const std::pair<double, double> roughness[] = {{0.01, 0.01}, {0.03, 0.03}, {0.1, 0.1}, {0.3, 0.3},
                                                 {0.5, 0.5},   {1.0, 1.0},   {0.05, 0.5}, {1.0, 0.1}};
  double max_weight = 0.0;
  for (auto [mx, my] : roughness) {
    const Material m = glossy(mx, my, 1.0);
    std::printf("  albedo mx %.2f my %.2f:", mx, my);
    for (double ti : {0.0, 30.0, 60.0, 75.0, 85.0, 89.0}) {
      for (double phi : {0.0, 30.0, 90.0}) {
        if (phi > 0.0 && mx == my) continue;
        const AlbedoEstimate a = estimate_albedo(m, incident(ti, phi), 20000, 101);
        const double sigma = std::hypot(a.visible_sigma, a.walter_sigma);
        EXPECT_NEAR(a.visible, a.walter, 5.0 * sigma + 1e-9) << mx << " " << my << " " << ti << " " << phi;
        EXPECT_LE(a.visible, 1.0 + 5.0 * a.visible_sigma + 1e-12);
        EXPECT_LE(a.walter, 1.0 + 5.0 * a.walter_sigma) << mx << " " << my << " " << ti << " " << phi;
        EXPECT_LE(a.max_weight, 1.0);
        max_weight = std::max(max_weight, a.max_weight);
        if (phi == 0.0) std::printf(" %.0f°: %.4f", ti, a.visible);
        if (mx == my && (mx <= 0.03 ? ti <= 75.0 : mx <= 0.1 && ti <= 60.0)) {
          EXPECT_GT(a.visible, 0.999) << mx << " " << ti;
        }
      }
    }
    std::printf("\n");
  }
  std::printf("  largest sample weight %.6f\n", max_weight);
  // Normal incidence, where no light leaves below the horizon: the
  // single-scattering albedo falls with roughness.
  const Vec3 n{0, 0, 1};
  EXPECT_NEAR(estimate_albedo(glossy(0.1, 0.1), n, 20000, 3).visible, 1.0, 1e-4);
  const double a05 = estimate_albedo(glossy(0.5, 0.5), n, 20000, 3).visible;
  const double a10 = estimate_albedo(glossy(1.0, 1.0), n, 20000, 3).visible;
  EXPECT_GT(a05, 0.9);
  EXPECT_LT(a10, a05);
  EXPECT_GT(a10, 0.4);
  // Fresnel: f0 < 1 reflects less, and Schlick's F rises towards grazing.
  const Material dull = glossy(0.1, 0.1, 0.5);
  const double at0 = estimate_albedo(dull, n, 20000, 5).visible;
  EXPECT_NEAR(at0, 0.5, 2e-3);
  EXPECT_GT(estimate_albedo(dull, incident(80.0), 20000, 5).visible, at0 + 0.05);
}

TEST(Glossy, AlbedoByQuadrature) {
  // The sampler's mean weight against ∫ f cos θo dωo by quadrature, where
  // the lobe is wide enough for a grid.
  for (const Material& m : {glossy(0.3, 0.3, 1.0), glossy(0.5, 0.2, 0.6)}) {
    for (double ti : {0.0, 40.0, 70.0}) {
      const Vec3 wi = incident(ti, 25.0);
      const double albedo = integrate_hemisphere([&](const Vec3& o) { return glossy_brdf(m, wi, o) * o.z; }, 1500, 600);
      EXPECT_LE(albedo, 1.0);
      const AlbedoEstimate a = estimate_albedo(m, wi, 100000, 7);
      EXPECT_NEAR(a.visible, albedo, 5.0 * a.visible_sigma + 1e-3) << m.glossy_mx << " " << ti;
    }
  }
}

TEST(Glossy, TheThesisLobeIsTheSmoothMirrorLimit) {
  // f_thesis = F D / (4 (wo·h) √((wi·n)(wo·n))) (section 5.2, α = ½).
  auto thesis = [](const Material& m, const Vec3& wi, const Vec3& wo) {
    const Vec3 h = normalize(wi + wo);
    return schlick_fresnel(m.glossy_f0, dot(wo, h)) * beckmann_d(m.glossy_mx, m.glossy_my, h) /
           (4.0 * dot(wo, h) * std::sqrt(wi.z * wo.z));
  };
  // In the mirror direction of a smooth lobe they agree to G2 ≈ 1.
  const Material smooth = glossy(0.05, 0.05, 0.8);
  for (double ti : {0.0, 30.0, 60.0}) {
    const Vec3 wi = incident(ti, 10.0);
    const Vec3 mirror{-wi.x, -wi.y, wi.z};
    EXPECT_NEAR(glossy_brdf(smooth, wi, mirror) / thesis(smooth, wi, mirror), 1.0, 1e-6) << ti;
  }
  // A rough lobe at grazing incidence: the thesis's creates light, this one
  // does not.
  const Material rough = glossy(0.5, 0.5, 1.0);
  const Vec3 wi = incident(85.0);
  const double old_albedo =
      integrate_hemisphere([&](const Vec3& o) { return thesis(rough, wi, o) * o.z; }, 1500, 600);
  const double new_albedo =
      integrate_hemisphere([&](const Vec3& o) { return glossy_brdf(rough, wi, o) * o.z; }, 1500, 600);
  std::printf("  mx = my = 0.5 at 85 deg: thesis albedo %.3f, microfacet albedo %.3f\n", old_albedo, new_albedo);
  EXPECT_GT(old_albedo, 1.2);
  EXPECT_LT(new_albedo, 1.0);
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

TEST(Scatter, GlossySurvivorsFollowTheLobe) {
  // Photons that the glossy lobe lets go leave with density ks · f · cos θo
  // and full power: a histogram of their directions in (θo, φo) against
  // the lobe's integral over each bin. Anisotropic, turned against the
  // tangent, at an incidence where Walter's weights would straddle 1.
  Material m = glossy(0.3, 0.12, 0.5);
  m.glossy = 0.8;
  const SurfaceFrame f{{0, 0, 1}, {0, 0, 1}, {1, 0, 0}};
  for (double ti : {50.0, 80.0}) {
    const Vec3 wi = incident(ti, 40.0);
    const int nt = 18, np = 24, n = 400000;
    std::vector<double> obs(nt * np, 0.0), exp(nt * np, 0.0);
    int survived = 0;
    for (int k = 0; k < n; ++k) {
      PhotonRandom rng(41, static_cast<std::uint64_t>(k));
      const ScatterResult r = scatter(m, f, -wi, rng);
      if (r.absorbed) continue;
      ASSERT_EQ(r.lobe, Lobe::Glossy);
      ASSERT_GT(r.direction.z, 0.0);
      ++survived;
      const double t = std::acos(std::min(1.0, r.direction.z));
      double p = std::atan2(r.direction.y, r.direction.x);
      if (p < 0) p += 2 * kPi;
      obs[std::min(nt - 1, static_cast<int>(t / (kPi / 2) * nt)) * np +
          std::min(np - 1, static_cast<int>(p / (2 * kPi) * np))] += 1;
    }
    const int sub = 40;
    double expected_total = 0.0;
    for (int i = 0; i < nt * sub; ++i) {
      const double t0 = i * (kPi / 2) / (nt * sub), t1 = (i + 1) * (kPi / 2) / (nt * sub);
      const double tm = 0.5 * (t0 + t1), dz = std::cos(t0) - std::cos(t1);
      for (int j = 0; j < np * sub; ++j) {
        const double p = (j + 0.5) * 2 * kPi / (np * sub);
        const Vec3 o{std::sin(tm) * std::cos(p), std::sin(tm) * std::sin(p), std::cos(tm)};
        const double e = n * m.glossy * glossy_brdf(m, wi, o) * o.z * dz * 2 * kPi / (np * sub);
        exp[(i / sub) * np + j / sub] += e;
        expected_total += e;
      }
    }
    EXPECT_NEAR(survived, expected_total, 5.0 * std::sqrt(expected_total) + 2e-3 * expected_total) << ti;
    double chi2 = 0.0;
    int dof = -1;
    for (std::size_t b = 0; b < obs.size(); ++b) {
      if (exp[b] < 10.0) continue;
      chi2 += (obs[b] - exp[b]) * (obs[b] - exp[b]) / exp[b];
      ++dof;
    }
    EXPECT_GT(dof, 30) << ti;
    EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof)) << ti << "°, dof " << dof;
  }
}

}  // namespace
}  // namespace gonio::sim
