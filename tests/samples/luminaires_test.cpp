// The generated samples load without error findings, pass the model checks
// and carry the emitters, materials and frames their READMEs describe.
#include "samples/luminaires.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "io/model/gltf.h"
#include "io/model/model_check.h"
#include "tests/support/test_support.h"

namespace gonio::samples {
namespace {

constexpr double kPi = std::numbers::pi;

std::string describe(const std::vector<Finding>& findings) {
  std::string out;
  for (const Finding& f : findings)
    out += std::string(to_string(f.severity)) + " " + f.code + ": " + f.message + "\n";
  return out;
}

class Samples : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    const Status written = write_samples(dir_->path().string());
    ASSERT_TRUE(written.ok()) << to_string(written.error());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }

  // Loads a sample and checks it: no error findings from the loader or the
  // model checks.
  static sim::SceneDesc load(const std::string& name) {
    const std::string path = (dir_->path() / name / (name + ".gltf")).string();
    std::vector<Finding> findings;
    Result<sim::SceneDesc> scene = io::load_gltf(path, &findings);
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : to_string(scene.error()));
    if (!scene.ok()) return {};
    EXPECT_NE(worst(findings), Severity::Error) << describe(findings);
    const std::vector<Finding> checks = io::check_model(*scene);
    EXPECT_NE(worst(checks), Severity::Error) << describe(checks);
    EXPECT_TRUE(checks.empty()) << describe(checks);
    return std::move(scene).value();
  }

  static const sim::Material& material_of(const sim::SceneDesc& s, const std::string& mesh) {
    for (const sim::Mesh& m : s.meshes)
      if (m.name.rfind(mesh + "/", 0) == 0) return s.materials.at(m.material);
    ADD_FAILURE() << "no mesh " << mesh;
    static const sim::Material none;
    return none;
  }

  static test::TempDir* dir_;
};

test::TempDir* Samples::dir_ = nullptr;

TEST_F(Samples, GenerationIsReproducible) {
  const std::vector<Sample> a = make_samples(), b = make_samples();
  ASSERT_EQ(a.size(), 4u);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].files.size(), b[i].files.size());
    for (std::size_t f = 0; f < a[i].files.size(); ++f) {
      EXPECT_EQ(a[i].files[f].name, b[i].files[f].name);
      EXPECT_TRUE(a[i].files[f].bytes == b[i].files[f].bytes) << a[i].files[f].name;
    }
    // What was written is what was generated.
    for (const SampleFile& f : a[i].files)
      EXPECT_TRUE(test::read_file(dir_->path() / a[i].name / f.name) == f.bytes) << f.name;
  }
}

TEST_F(Samples, BellIsTheThesisOpalShadeAroundAnIsotropicLamp) {
  const sim::SceneDesc s = load("bell");
  ASSERT_EQ(s.emitters.size(), 1u);
  EXPECT_EQ(s.emitters[0].kind, sim::Emitter::Kind::Point);
  EXPECT_EQ(s.emitters[0].profile, nullptr);
  EXPECT_NEAR(s.emitters[0].flux_lm, 1000.0, 1e-9);
  EXPECT_NEAR(s.emitters[0].position.y, -0.090, 1e-12);
  const sim::Material& opal = material_of(s, "shade");
  EXPECT_NEAR(opal.diffuse_transmit, 0.6, 1e-12);
  EXPECT_NEAR(opal.diffuse_reflect, 0.3, 1e-12);
  EXPECT_NEAR(opal.mirror, 0.1, 1e-12);
  EXPECT_EQ(opal.glossy + opal.dielectric, 0.0);
  EXPECT_EQ(s.frame.up.y, 1.0);
  EXPECT_EQ(s.frame.c0.x, 1.0);
}

TEST_F(Samples, DownlightAimsItsIesProfileDownWithC0AlongX) {
  const sim::SceneDesc s = load("downlight");
  ASSERT_EQ(s.emitters.size(), 1u);
  const sim::Emitter& led = s.emitters[0];
  ASSERT_NE(led.profile, nullptr);
  // Integrated flux of the written profile: 1000 lm within the quadrature
  // error of a 2.5° grid.
  EXPECT_NEAR(led.flux_lm, 1000.0, 5.0);
  const Vec3 nadir = led.frame.to_world(photometry::direction_from_c_gamma(0.0, 0.0));
  EXPECT_NEAR(nadir.y, -1.0, 1e-9);
  EXPECT_NEAR(led.frame.c0.x, 1.0, 1e-9);
  EXPECT_NEAR(led.frame.c90.z, -1.0, 1e-9);
  // Semi-specular aluminium: the glossy lobe with α = roughness² = 0.3².
  const sim::Material& reflector = material_of(s, "reflector");
  EXPECT_EQ(reflector.mirror, 0.0);
  EXPECT_NEAR(reflector.glossy, 0.92, 1e-12);
  EXPECT_NEAR(reflector.glossy_mx, 0.09, 1e-12);
  EXPECT_NEAR(reflector.glossy_my, 0.09, 1e-12);
  // The reflector reaches from the focal plane to the rim 60 mm below.
  float lo = 1, hi = -1;
  for (const sim::Mesh& m : s.meshes)
    if (m.name.rfind("reflector/", 0) == 0)
      for (const sim::Vec3f& p : m.positions) {
        lo = std::min(lo, p.y);
        hi = std::max(hi, p.y);
      }
  EXPECT_NEAR(lo, -0.060, 1e-6);
  EXPECT_NEAR(hi, 0.0, 1e-6);
}

TEST_F(Samples, SpotlightHasAClosedPmmaLensAndACosSquaredLed) {
  const sim::SceneDesc s = load("spotlight");
  ASSERT_EQ(s.emitters.size(), 1u);
  const sim::Emitter& led = s.emitters[0];
  EXPECT_NEAR(led.flux_lm, 500.0, 1e-9);
  ASSERT_NE(led.profile, nullptr);
  const photometry::Distribution e = photometry::expand_symmetry(*led.profile);
  const double i0 = 1500.0 / (2 * kPi);
  for (double g : {0.0, 20.0, 45.0, 70.0})
    EXPECT_NEAR(photometry::interpolate(e, 0.0, g), i0 * std::pow(std::cos(g * kPi / 180), 2),
                1e-3 * i0);
  const Vec3 axis = led.frame.to_world(photometry::direction_from_c_gamma(0.0, 0.0));
  EXPECT_NEAR(axis.y, -1.0, 1e-12);
  const sim::Material& pmma = material_of(s, "lens");
  EXPECT_NEAR(pmma.dielectric, 1.0, 1e-12);
  EXPECT_NEAR(pmma.ior, 1.49, 1e-12);
  EXPECT_NEAR(pmma.attenuation_per_m, -std::log(0.92) / 0.5, 1e-12);
}

TEST_F(Samples, LedArrayHasNineAreaEmittersOfOneHundredLumens) {
  const sim::SceneDesc s = load("led-array");
  ASSERT_EQ(s.emitters.size(), 9u);
  // The die is one mesh placed by nine nodes: stored once, nine instances.
  ASSERT_EQ(s.instances.size(), 9u);
  for (std::uint32_t k = 0; k < 9; ++k) {
    const sim::Emitter& e = s.emitters[k];
    EXPECT_EQ(e.kind, sim::Emitter::Kind::Area);
    EXPECT_FALSE(e.two_sided);
    EXPECT_NEAR(e.flux_lm, 100.0, 1e-9);
    EXPECT_EQ(e.instance, k);
    const sim::Mesh& m = s.meshes.at(e.mesh);
    EXPECT_TRUE(m.instanced);
    EXPECT_EQ(s.instances[k].mesh, e.mesh);
    // Each die faces down, placed.
    const sim::Affine& place = s.instances[k].to_world;
    auto at = [&](std::size_t i) {
      const sim::Vec3f& p = m.positions[m.indices[i]];
      return place.point(Vec3{p.x, p.y, p.z});
    };
    const Vec3 n = cross(at(1) - at(0), at(2) - at(0));
    EXPECT_LT(n.y, 0.0);
    EXPECT_NEAR(at(0).y, 0.0495, 1e-6);
  }
  EXPECT_NEAR(s.total_flux_lm(), 900.0, 1e-9);
  const sim::Material& diffuser = material_of(s, "diffuser");
  EXPECT_NEAR(diffuser.diffuse_transmit, 0.55, 1e-12);
  EXPECT_NEAR(diffuser.diffuse_reflect + diffuser.mirror, 0.40, 1e-12);
}

// The emissive luminance in the file alone (without the node's flux_lm)
// gives the same 100 lm: the two statements of the LED's output agree.
TEST_F(Samples, LedArrayLuminanceAndFluxAgree) {
  const std::string path = (dir_->path() / "led-array" / "led-array.gltf").string();
  std::string text = test::read_file(path);
  std::size_t at;
  while ((at = text.find("\"flux_lm\"")) != std::string::npos) text.replace(at, 9, "\"flux_xx\"");
  const std::string copy = (dir_->path() / "led-array" / "no-flux.gltf").string();
  test::write_file(copy, text);
  std::vector<Finding> findings;
  Result<sim::SceneDesc> s = io::load_gltf(copy, &findings);
  ASSERT_TRUE(s.ok());
  for (const sim::Emitter& e : s->emitters) EXPECT_NEAR(e.flux_lm, 100.0, 1e-3);
}

}  // namespace
}  // namespace gonio::samples
