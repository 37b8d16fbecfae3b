// The glossy lobe's energy: the single-scattering albedo by quadrature
// against the sampler's own mean weight, the white furnace per roughness
// with and without Kulla–Conty's compensation, and its reciprocity.
#include "sim/bsdfs/glossy_energy.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "sim/bsdfs/lobes.h"
#include "sim/bsdfs/material.h"
#include "sim/samplers/sampling.h"
#include "tests/sim/bsdfs/lobe_checks.h"

namespace gonio::sim {
namespace {

using test::incident;

Material glossy(double mx, double my, double f0, bool compensation) {
  Material m;
  m.name = "glossy";
  m.glossy = 1.0;
  m.glossy_mx = mx;
  m.glossy_my = my;
  m.glossy_f0 = f0;
  m.glossy_compensation = compensation;
  prepare(m);
  return m;
}

TEST(GlossyEnergy, QuadratureIsTheSamplersMeanWeight) {
  // Two independent routes to E_F(wi): the slope-space quadrature and the
  // visible-normal sampler's mean weight F·G2/G1. A wrong Jacobian or a
  // mis-mapped slope in either makes them part.
  for (auto [mx, my, f0] : {std::tuple{0.3, 0.3, 1.0}, std::tuple{1.0, 1.0, 1.0}, std::tuple{0.5, 0.15, 0.4}}) {
    const Material m = glossy(mx, my, f0, false);
    for (double ti : {0.0, 45.0, 75.0, 87.0}) {
      const Vec3 wi = incident(ti, 30.0);
      const int n = 200000;
      double sum = 0.0, sq = 0.0;
      for (int k = 0; k < n; ++k) {
        PhotonRandom rng(9, static_cast<std::uint64_t>(k));
        const double w = sample_glossy(m, wi, rng).weight;
        sum += w;
        sq += w * w;
      }
      const double mean = sum / n, sigma = std::sqrt((sq / n - mean * mean) / n);
      EXPECT_NEAR(glossy_single_albedo(mx, my, f0, wi), mean, 5.0 * sigma + 5e-4) << mx << " " << my << " " << ti;
    }
  }
}

TEST(GlossyEnergy, WhiteFurnacePerRoughness) {
  // f0 = 1. Single scattering loses light between facets, more with
  // roughness; compensated, ∫ f cos θo dωo = 1 at every incidence (the
  // table's own error aside) and the tracer lets every photon go.
  const SurfaceFrame frame{{0, 0, 1}, {0, 0, 1}, {1, 0, 0}};
  std::printf("  glTF roughness: single-scattering albedo at 0 / 60 / 80 deg -> compensated\n");
  for (double r : {0.2, 0.4, 0.6, 0.8, 1.0}) {
    const double alpha = r * r;
    const Material single = glossy(alpha, alpha, 1.0, false);
    const Material comp = glossy(alpha, alpha, 1.0, true);
    double e[3];
    int i = 0;
    for (double ti : {0.0, 60.0, 80.0}) {
      const Vec3 wi = incident(ti);
      e[i++] = lobe_albedo(single, Lobe::Glossy, wi);
      EXPECT_NEAR(lobe_albedo(comp, Lobe::Glossy, wi), 1.0, 1e-9) << r << " " << ti;
      // ∫ evaluate by the lobe's own importance sampling (narrow lobes
      // defeat a grid): the table's E(μ) against the exact one.
      double sum = 0.0;
      const int m = 100000;
      for (int k = 0; k < m; ++k) {
        PhotonRandom rng(29, static_cast<std::uint64_t>(k));
        sum += lobe_sample(comp, Lobe::Glossy, wi, rng).weight;
      }
      EXPECT_NEAR(sum / m, 1.0, 2e-3) << "roughness " << r << " at " << ti;
      int survived = 0;
      const int n = 50000;
      for (int k = 0; k < n; ++k) {
        PhotonRandom rng(13, static_cast<std::uint64_t>(k));
        survived += scatter(comp, Lobe::Glossy, frame, -wi, rng).absorbed ? 0 : 1;
      }
      EXPECT_EQ(survived, n) << "roughness " << r << " at " << ti;
    }
    std::printf("  %.1f: %.4f %.4f %.4f -> 1\n", r, e[0], e[1], e[2]);
    if (r >= 0.8) {
      EXPECT_LT(e[0], 0.9);
    }
  }
  // The figure: glTF roughness 1 reflects 0.46 of a white lobe's
  // light at normal incidence without compensation.
  EXPECT_NEAR(lobe_albedo(glossy(1.0, 1.0, 1.0, false), Lobe::Glossy, incident(0.0)), 0.46, 0.01);
}

TEST(GlossyEnergy, FresnelScalesTheSecondLobeByKullaContysFactor) {
  // f0 < 1: albedo = E_F(wi) + κ (1 − E(wi)), κ = F_avg² E_avg/(1 − F_avg(1 − E_avg)).
  const Material m = glossy(0.6, 0.6, 0.5, true);
  const double f_avg = 0.5 + 0.5 / 21.0;
  const double e_avg = m.tables->glossy->e_avg;
  EXPECT_NEAR(m.tables->glossy_kappa, f_avg * f_avg * e_avg / (1.0 - f_avg * (1.0 - e_avg)), 1e-15);
  const SurfaceFrame frame{{0, 0, 1}, {0, 0, 1}, {1, 0, 0}};
  for (double ti : {0.0, 50.0}) {
    const Vec3 wi = incident(ti);
    const double expected = glossy_single_albedo(0.6, 0.6, 0.5, wi) +
                            m.tables->glossy_kappa * (1.0 - glossy_single_albedo(0.6, 0.6, 1.0, wi));
    const int n = 200000;
    int survived = 0;
    for (int k = 0; k < n; ++k) {
      PhotonRandom rng(23, static_cast<std::uint64_t>(k));
      survived += scatter(m, Lobe::Glossy, frame, -wi, rng).absorbed ? 0 : 1;
    }
    EXPECT_NEAR(survived / static_cast<double>(n), expected, 5.0 * std::sqrt(0.25 / n)) << ti;
  }
}

TEST(GlossyEnergy, CompensatedLobeIsReciprocal) {
  for (const Material& m : {glossy(0.5, 0.5, 1.0, true), glossy(0.8, 0.3, 0.7, true)}) {
    for (int k = 0; k < 300; ++k) {
      PhotonRandom rng(31, static_cast<std::uint64_t>(k));
      const Vec3 a = sample_cosine_hemisphere(rng), b = sample_cosine_hemisphere(rng);
      const double fab = lobe_evaluate(m, Lobe::Glossy, a, b) / b.z;
      const double fba = lobe_evaluate(m, Lobe::Glossy, b, a) / a.z;
      EXPECT_NEAR(fab, fba, 1e-12 * fab);
    }
  }
}

TEST(GlossyEnergy, UnpreparedOrSwitchedOffIsSingleScattering) {
  // Without tables (or with compensation off) a glossy photon that masking
  // stops is absorbed: the draws and bytes of single scattering.
  Material raw;
  raw.glossy = 1.0;
  raw.glossy_mx = raw.glossy_my = 1.0;
  const Material off = glossy(1.0, 1.0, 1.0, false);
  const SurfaceFrame frame{{0, 0, 1}, {0, 0, 1}, {1, 0, 0}};
  for (int k = 0; k < 2000; ++k) {
    PhotonRandom a(3, static_cast<std::uint64_t>(k)), b(3, static_cast<std::uint64_t>(k));
    const ScatterResult ra = scatter(raw, Lobe::Glossy, frame, Vec3{0.3, 0.0, -0.95}, a);
    const ScatterResult rb = scatter(off, Lobe::Glossy, frame, Vec3{0.3, 0.0, -0.95}, b);
    ASSERT_EQ(ra.absorbed, rb.absorbed);
    ASSERT_EQ(a.draws(), b.draws());
  }
}

}  // namespace
}  // namespace gonio::sim
