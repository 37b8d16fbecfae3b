#include "io/model/gltf_material.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

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

}  // namespace
}  // namespace gonio::io
