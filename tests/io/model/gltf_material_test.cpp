#include "io/model/gltf_material.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "sim/bsdfs/lobes.h"

namespace gonio::io {
namespace {

const SourceLoc kWhere{"model.gltf"};

sim::Material map_ok(const GltfMaterial& m, const MaterialExtras& x = {},
                     std::vector<Finding>* findings_out = nullptr) {
  std::vector<Finding> findings;
  Result<sim::Material> r = map_material(m, x, kWhere, "material 'm'", findings);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : to_string(r.error()));
  if (findings_out) *findings_out = findings;
  return r.ok() ? *r : sim::Material{};
}

bool has_code(const std::vector<Finding>& findings, const std::string& code) {
  for (const Finding& f : findings)
    if (f.code == code) return true;
  return false;
}

TEST(GltfMaterial, LuminanceUsesRec709Weights) {
  EXPECT_DOUBLE_EQ(luminance({1, 1, 1}), 1.0);
  EXPECT_DOUBLE_EQ(luminance({0, 1, 0}), 0.7152);
  EXPECT_DOUBLE_EQ(luminance({1, 0, 0}), 0.2126);
}

TEST(GltfMaterial, PolishedMetalIsAMirrorWithBaseColourReflectance) {
  GltfMaterial m;
  m.base_color = {0.9, 0.9, 0.9};
  m.metallic = 1.0;
  m.roughness = 0.02;
  const sim::Material s = map_ok(m);
  EXPECT_NEAR(s.mirror, 0.9, 1e-12);
  EXPECT_EQ(s.glossy, 0.0);
  EXPECT_EQ(s.diffuse_reflect, 0.0);
  EXPECT_EQ(s.dielectric, 0.0);
}

TEST(GltfMaterial, RoughMetalIsAGlossyLobeWithAlphaRoughness) {
  GltfMaterial m;
  m.base_color = {0.8, 0.8, 0.8};
  m.roughness = 0.4;
  const sim::Material s = map_ok(m);
  EXPECT_NEAR(s.glossy, 0.8, 1e-12);
  EXPECT_NEAR(s.glossy_mx, 0.16, 1e-12);
  EXPECT_NEAR(s.glossy_my, 0.16, 1e-12);
  EXPECT_EQ(s.glossy_f0, 1.0);
  EXPECT_EQ(s.mirror, 0.0);
}

TEST(GltfMaterial, WhitePaintIsMostlyLambertianWithAFresnelCoat) {
  GltfMaterial m;
  m.base_color = {0.85, 0.85, 0.85};
  m.metallic = 0.0;
  m.roughness = 0.9;
  const sim::Material s = map_ok(m);
  const double f0 = 0.04;  // ior 1.5
  EXPECT_NEAR(s.glossy, f0, 1e-12);
  EXPECT_NEAR(s.diffuse_reflect, (1 - f0) * 0.85, 1e-12);
  EXPECT_NEAR(s.total(), f0 + 0.96 * 0.85, 1e-12);
}

TEST(GltfMaterial, ClearGlassWithVolumeIsADielectricWithAttenuation) {
  GltfMaterial m;
  m.metallic = 0.0;
  m.roughness = 0.0;
  m.transmission = 1.0;
  m.ior = 1.49;
  m.has_volume = true;
  m.thickness_m = 0.01;
  m.attenuation_distance_m = 0.5;
  m.attenuation_color = {0.9, 0.9, 0.9};
  std::vector<Finding> findings;
  const sim::Material s = map_ok(m, {}, &findings);
  EXPECT_NEAR(s.dielectric, 1.0, 1e-12);
  EXPECT_NEAR(s.ior, 1.49, 1e-12);
  EXPECT_NEAR(s.attenuation_per_m, -std::log(0.9) / 0.5, 1e-12);
  EXPECT_EQ(s.mirror + s.glossy + s.diffuse_reflect + s.diffuse_transmit, 0.0);
  EXPECT_FALSE(has_code(findings, "thin-walled-transmission"));

  m.has_volume = false;
  map_ok(m, {}, &findings);
  EXPECT_TRUE(has_code(findings, "thin-walled-transmission"));
}

TEST(GltfMaterial, DiffuseTransmissionMakesAnOpal) {
  GltfMaterial m;
  m.metallic = 0.0;
  m.roughness = 1.0;
  m.base_color = {0.5, 0.5, 0.5};
  m.diffuse_transmission = 0.6;
  m.diffuse_transmission_color = {1, 1, 1};
  m.specular = 0.0;  // no coat
  const sim::Material s = map_ok(m);
  EXPECT_NEAR(s.diffuse_transmit, 0.6, 1e-12);
  EXPECT_NEAR(s.diffuse_reflect, 0.4 * 0.5, 1e-12);
  EXPECT_EQ(s.glossy, 0.0);
}

TEST(GltfMaterial, SpecularExtensionScalesTheCoat) {
  GltfMaterial m;
  m.metallic = 0.0;
  m.roughness = 0.5;
  m.ior = 2.0;
  m.specular = 0.5;
  m.specular_color = {1, 1, 1};
  const sim::Material s = map_ok(m);
  EXPECT_NEAR(s.glossy, 0.5 / 9.0, 1e-12);  // ((2-1)/(2+1))² · 0.5
}

TEST(GltfMaterial, DatasheetExtrasGiveTheThesisOpal) {
  // The thesis' bell: 60 % diffuse transmission, 30 % diffuse reflection,
  // 10 % mirror.
  MaterialExtras x;
  x.reflectance = 0.4;
  x.diffuse_reflectance = 0.3;
  x.transmittance = 0.6;
  x.diffusion = 1.0;
  const sim::Material s = map_ok(GltfMaterial{}, x);
  EXPECT_NEAR(s.diffuse_transmit, 0.6, 1e-12);
  EXPECT_NEAR(s.diffuse_reflect, 0.3, 1e-12);
  EXPECT_NEAR(s.mirror, 0.1, 1e-12);
  EXPECT_EQ(s.glossy, 0.0);
  EXPECT_EQ(s.dielectric, 0.0);
  EXPECT_NEAR(s.total(), 1.0, 1e-12);
}

TEST(GltfMaterial, DatasheetRegularTransmissionIsDielectricAndRoughnessMakesGloss) {
  MaterialExtras x;
  x.reflectance = 0.1;
  x.diffuse_reflectance = 0.02;
  x.transmittance = 0.85;
  x.diffusion = 0.2;
  x.ior = 1.49;
  x.mx = 0.05;
  const sim::Material s = map_ok(GltfMaterial{}, x);
  EXPECT_NEAR(s.dielectric, 0.85 * 0.8, 1e-12);
  EXPECT_NEAR(s.diffuse_transmit, 0.85 * 0.2, 1e-12);
  EXPECT_NEAR(s.glossy, 0.08, 1e-12);
  EXPECT_EQ(s.glossy_mx, 0.05);
  EXPECT_EQ(s.glossy_my, 0.05);  // my follows mx when only mx is given
  EXPECT_EQ(s.ior, 1.49);
}

TEST(GltfMaterial, ThesisExtrasSetTheLobesDirectly) {
  GltfMaterial m;  // white rough metal by default: overridden completely
  MaterialExtras x;
  x.kd = 0.2;
  x.ks = 0.7;
  x.mx = 0.05;
  x.my = 0.3;
  x.f0 = 0.9;
  const sim::Material s = map_ok(m, x);
  EXPECT_EQ(s.diffuse_reflect, 0.2);
  EXPECT_EQ(s.glossy, 0.7);
  EXPECT_EQ(s.glossy_mx, 0.05);
  EXPECT_EQ(s.glossy_my, 0.3);
  EXPECT_EQ(s.glossy_f0, 0.9);
  EXPECT_EQ(s.mirror, 0.0);
  EXPECT_EQ(s.diffuse_transmit, 0.0);
  EXPECT_EQ(s.dielectric, 0.0);
}

TEST(GltfMaterial, BadExtrasAreErrorsNamingMaterialAndKey) {
  std::vector<Finding> findings;
  auto fails_with = [&](MaterialExtras x, const std::string& needle) {
    Result<sim::Material> r = map_material(GltfMaterial{}, x, kWhere, "material 'm'", findings);
    ASSERT_FALSE(r.ok()) << needle;
    EXPECT_EQ(r.error().where.file, "model.gltf");
    EXPECT_NE(r.error().message.find("material 'm'"), std::string::npos);
    EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
  };
  MaterialExtras a;
  a.kd = 1.2;
  fails_with(a, "kd");
  MaterialExtras b;
  b.kd = 0.6;
  b.mirror = 0.6;
  fails_with(b, "sum to");
  MaterialExtras c;
  c.reflectance = 0.7;
  c.transmittance = 0.5;
  fails_with(c, "exceeds 1");
  MaterialExtras d;
  d.kd = 0.5;
  d.reflectance = 0.5;
  fails_with(d, "mixes");
  MaterialExtras e;
  e.ior = 0.5;
  fails_with(e, "ior");
  MaterialExtras f;
  f.reflectance = 0.2;
  f.diffuse_reflectance = 0.3;
  fails_with(f, "diffuse_reflectance");
  MaterialExtras g;
  g.mx = 0.0;
  fails_with(g, "mx");
}

TEST(GltfMaterial, OutOfRangeFactorsAreClampedWithAWarning) {
  GltfMaterial m;
  m.metallic = 1.5;
  m.base_color = {2.0, 0.5, 0.5};
  std::vector<Finding> findings;
  const sim::Material s = map_ok(m, {}, &findings);
  EXPECT_TRUE(has_code(findings, "material-factor-range"));
  EXPECT_LE(s.total(), 1.0);
}

// Energy: whatever a file says, the derived weights are in [0, 1] and sum to
// at most 1.
TEST(GltfMaterial, DerivedWeightsNeverExceedOne) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 5000; ++i) {
    GltfMaterial m;
    m.base_color = {u(rng), u(rng), u(rng)};
    m.metallic = u(rng);
    m.roughness = u(rng);
    m.transmission = u(rng);
    m.diffuse_transmission = u(rng);
    m.diffuse_transmission_color = {u(rng), u(rng), u(rng)};
    m.ior = 1.0 + 2.0 * u(rng);
    m.specular = u(rng);
    m.specular_color = {u(rng), u(rng), u(rng)};
    std::vector<Finding> findings;
    Result<sim::Material> r = map_material(m, {}, kWhere, "m", findings);
    ASSERT_TRUE(r.ok());
    for (double w : {r->diffuse_reflect, r->diffuse_transmit, r->mirror, r->glossy, r->dielectric}) {
      EXPECT_GE(w, 0.0);
      EXPECT_LE(w, 1.0);
    }
    EXPECT_LE(r->total(), 1.0 + 1e-12);
  }
}

TEST(GltfMaterial, EmissiveLuminanceIsStrengthTimesFactorLuminance) {
  GltfMaterial m;
  m.emissive = {1, 1, 1};
  m.emissive_strength = 2500.0;
  EXPECT_DOUBLE_EQ(emissive_luminance_cd_m2(m, {}), 2500.0);
  m.emissive = {0, 1, 0};
  EXPECT_DOUBLE_EQ(emissive_luminance_cd_m2(m, {}), 2500.0 * 0.7152);
  MaterialExtras x;
  x.luminance_cd_m2 = 1234.0;
  EXPECT_DOUBLE_EQ(emissive_luminance_cd_m2(m, x), 1234.0);
  EXPECT_DOUBLE_EQ(emissive_luminance_cd_m2(GltfMaterial{}, {}), 0.0);
}

// ∫ f(wi, wo) cos θo dωo over the upper hemisphere by the midpoint rule in
// (cos θo, φo), `f_cos` a function of (wi, wo) in the local frame (z the
// normal): a directional albedo by quadrature, independent of any sampler.
template <class F>
double hemisphere_integral(const F& f_cos, const Vec3& wi, int n_mu = 1600, int n_phi = 720) {
  double sum = 0.0;
  for (int i = 0; i < n_mu; ++i) {
    const double mu = (i + 0.5) / n_mu, s = std::sqrt(1.0 - mu * mu);
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2.0 * std::numbers::pi * (j + 0.5) / n_phi;
      sum += f_cos(wi, Vec3{s * std::cos(phi), s * std::sin(phi), mu});
    }
  }
  return sum * (1.0 / n_mu) * (2.0 * std::numbers::pi / n_phi);
}

// glTF 2.0's own reference BRDF for a dielectric (the specification's
// appendix B: fresnel_mix of a Lambertian base and a GGX specular layer,
// Schlick's F at v·h with F0 = 0.04, height-correlated Smith visibility),
// times cos θo: what glTF's sample viewer would reflect, for comparison.
double gltf_reference_f_cos(double rho, double roughness, const Vec3& wi, const Vec3& wo) {
  const double a2 = std::pow(roughness * roughness, 2.0);
  const Vec3 h = normalize(wi + wo);
  const double nl = wo.z, nv = wi.z, nh = h.z, vh = std::abs(dot(wi, h));
  const double f = 0.04 + 0.96 * std::pow(1.0 - vh, 5.0);
  const double d = a2 / (std::numbers::pi * std::pow(nh * nh * (a2 - 1.0) + 1.0, 2.0));
  const double v = 0.5 / (nl * std::sqrt(nv * nv * (1.0 - a2) + a2) + nv * std::sqrt(nl * nl * (1.0 - a2) + a2));
  return ((1.0 - f) * rho / std::numbers::pi + f * d * v) * nl;
}

// Issue 44: the albedo a white glTF dielectric (base colour 0.8, metallic
// 0) is expected to have. Gonio's mapping gives a coat of weight F0 = 0.04
// (glossy, f0 = 1, Kulla–Conty compensated, or a mirror below roughness
// 0.1) over (1 − F0)·0.8 = 0.768 Lambertian; the compensated white lobe
// reflects all it receives, so the directional albedo is 0.768 + 0.04 =
// 0.808 at every angle of incidence and roughness. Here it is computed by
// quadrature of the material's own BRDF (sim::surface_evaluate, the
// non-delta lobes, plus the mirror's weight), not by the tracer's sampling.
// A mapping that gave the diffuse base ρ instead of (1 − F0)ρ (0.84), a
// coat without compensation (0.79 at roughness 1) or a lobe whose evaluate
// lost or gained energy would miss 0.808 by more than the quadrature's 2e-3.
// glTF's reference BRDF is integrated alike and printed beside it
// (docs/materials.md, "The white dielectric's albedo").
TEST(GltfMaterial, WhiteDielectricAlbedoByQuadrature) {
  std::printf("  glTF white dielectric (base 0.8): directional albedo at 0/30/60/80 deg, Gonio | glTF reference\n");
  for (double roughness : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    GltfMaterial g;
    g.base_color = {0.8, 0.8, 0.8};
    g.metallic = 0.0;
    g.roughness = roughness;
    sim::Material m = map_ok(g);
    EXPECT_NEAR(m.diffuse_reflect, 0.768, 1e-12);
    EXPECT_NEAR(m.glossy + m.mirror, 0.04, 1e-12);
    sim::prepare(m);
    std::printf("    roughness %.2f:", roughness);
    double reference[4] = {0.0, 0.0, 0.0, 0.0};  // none for the mirror (a delta the grid cannot hold)
    int k = 0;
    for (double ti : {0.0, 30.0, 60.0, 80.0}) {
      const double t = ti * std::numbers::pi / 180.0;
      const Vec3 wi{std::sin(t), 0.0, std::cos(t)};
      const double albedo =
          m.mirror + hemisphere_integral([&](const Vec3& a, const Vec3& b) { return sim::surface_evaluate(m, a, b); }, wi);
      if (roughness > 0.0)
        reference[k] = hemisphere_integral(
            [&](const Vec3& a, const Vec3& b) { return gltf_reference_f_cos(0.8, roughness, a, b); }, wi);
      ++k;
      std::printf(" %.4f", albedo);
      EXPECT_NEAR(albedo, 0.808, 2e-3) << "roughness " << roughness << ", " << ti << " deg";
    }
    std::printf(" |");
    for (double r : reference) std::printf(" %.4f", r);
    std::printf("\n");
    // glTF's reference formula agrees with Gonio's coat near normal
    // incidence (within its single-scattering loss at roughness 1); towards
    // grazing it weights the base by 1 − F(v·h) per outgoing direction, not
    // by the coat's albedo, and gains energy where the lobe is narrow (1.08
    // at roughness 0.25 and 80°): a figure printed, not Gonio's target.
    if (roughness > 0.0) {
      for (int i = 0; i < 2; ++i) {
        EXPECT_NEAR(reference[i], 0.808, 0.03) << roughness;
      }
    }
  }
}

}  // namespace
}  // namespace gonio::io
