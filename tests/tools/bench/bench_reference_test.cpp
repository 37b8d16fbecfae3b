// The reference cache's key: hashes of the model file and of the scene.
#include "tools/bench/bench_reference.h"
#include "tools/run/scene_hash.h"

#include <gtest/gtest.h>

#include <memory>
#include <utility>
#include <vector>

#include "sim/bsdfs/tabulated_bsdf.h"
#include "sim/shapes.h"
#include "tests/support/test_support.h"

namespace gonio::app {
namespace {

TEST(BenchReference, HashesSeeWhatTheTracerSees) {
  sim::SceneDesc s;
  sim::Material m;
  m.name = "white";
  m.diffuse_reflect = 0.8;
  s.materials = {m};
  s.meshes = {sim::box(0.1, 0.1, 0.1)};
  sim::Emitter e;
  e.flux_lm = 100.0;
  s.emitters = {e};
  const std::string h = scene_hash(s);
  EXPECT_EQ(h.size(), 16u);
  EXPECT_EQ(scene_hash(s), h);
  sim::SceneDesc t = s;
  t.materials[0].diffuse_reflect = 0.81;
  EXPECT_NE(scene_hash(t), h);
  t = s;
  t.meshes[0].positions[3].y += 1e-6f;
  EXPECT_NE(scene_hash(t), h);
  t = s;
  t.emitters[0].flux_lm = 101.0;
  EXPECT_NE(scene_hash(t), h);
  t = s;
  t.materials[0].name = "renamed";  // names do not change the light
  EXPECT_EQ(scene_hash(t), h);

  ReferenceKey a;
  a.seed = 2;
  a.photons = 1000;
  ReferenceKey b = a;
  EXPECT_EQ(a.to_json(), b.to_json());
  b.photons = 1001;
  EXPECT_NE(a.to_json(), b.to_json());
  // A changed tracer (another hash of the sim/ sources) is another reference.
  b = a;
  b.tracer_revision = "0123456789abcdef";
  EXPECT_NE(a.to_json(), b.to_json());
}

// Every input the tracer reads moves the hash, one field at a time (the
// fields of sim/scene.h's Material, Emitter, RaySet, EmitterSpectrum and the
// measured BSDF): a hash that left one out (as the spectra, dispersion and
// ray sets once were) would let the bench reuse a stale reference and the
// ranks of an MPI job agree on different scenes.
TEST(BenchReference, TheSceneHashSeesEveryInputTheTracerReads) {
  sim::SceneDesc s;
  sim::Material m;
  m.diffuse_reflect = 0.5;
  m.spectral_reflectance = {{400.0, 700.0}, {0.4, 0.6}};
  m.spectral_transmittance = {{400.0, 700.0}, {0.1, 0.2}};
  m.ior_nm = {{400.0, 700.0}, {1.52, 1.50}};
  auto table = std::make_shared<sim::TabulatedBsdf>();
  table->basis = sim::PatchBasis::klems("LBNL/Klems Quarter");
  table->front.rows.push_back({0.0, std::vector<float>(table->basis.size(), 0.1f), {}, 0.0, 0.0, {}});
  m.table = table;
  m.tabulated = 0.1;
  m.over_incidence[0] = {{0.0, 90.0}, {1.0, 0.5}};
  s.materials = {m};
  s.meshes = {sim::box(0.1, 0.1, 0.1)};
  sim::Emitter point;
  point.flux_lm = 100.0;
  point.spectrum.over_gamma = {{0.0, {{400.0, 700.0}, {1.0, 2.0}}}, {90.0, {{400.0, 700.0}, {2.0, 1.0}}}};
  sim::Emitter rays;
  rays.kind = sim::Emitter::Kind::RaySet;
  rays.flux_lm = 10.0;
  auto set = std::make_shared<sim::RaySet>();
  set->position_m = {{0.0f, 0.0f, 0.0f}, {0.01f, 0.0f, 0.0f}};
  set->direction = {{0.0f, 0.0f, -1.0f}, {0.0f, 1.0f, 0.0f}};
  set->flux_lm = {1.0f, 2.0f};
  rays.rays = set;
  s.emitters = {point, rays};
  const std::string h = scene_hash(s);

  using Change = void (*)(sim::SceneDesc&);
  const std::pair<const char*, Change> changes[] = {
      {"reflectance spectrum value", [](sim::SceneDesc& t) { t.materials[0].spectral_reflectance.values[1] = 0.61; }},
      {"reflectance spectrum wavelength",
       [](sim::SceneDesc& t) { t.materials[0].spectral_reflectance.wavelengths_nm[1] = 701.0; }},
      {"transmittance spectrum", [](sim::SceneDesc& t) { t.materials[0].spectral_transmittance.values[0] = 0.11; }},
      {"dispersion table", [](sim::SceneDesc& t) { t.materials[0].ior_nm.values[0] = 1.53; }},
      {"abbe number", [](sim::SceneDesc& t) { t.materials[0].abbe_number = 40.0; }},
      {"scattering", [](sim::SceneDesc& t) { t.materials[0].scattering_per_m = 1.0; }},
      {"scattering g", [](sim::SceneDesc& t) { t.materials[0].scattering_g = 0.3; }},
      {"glossy compensation", [](sim::SceneDesc& t) { t.materials[0].glossy_compensation = false; }},
      {"abg reflect", [](sim::SceneDesc& t) { t.materials[0].abg_reflect.tis = 0.1; }},
      {"abg reflect b", [](sim::SceneDesc& t) { t.materials[0].abg_reflect.b = 0.01; }},
      {"abg transmit g", [](sim::SceneDesc& t) { t.materials[0].abg_transmit.g = 1.5; }},
      {"tabulated weight", [](sim::SceneDesc& t) { t.materials[0].tabulated = 0.2; }},
      {"tabulated row",
       [](sim::SceneDesc& t) {
         auto copy = std::make_shared<sim::TabulatedBsdf>(*t.materials[0].table);
         copy->front.rows[0].reflect[3] = 0.2f;
         t.materials[0].table = copy;
       }},
      {"tabulated side",
       [](sim::SceneDesc& t) {
         auto copy = std::make_shared<sim::TabulatedBsdf>(*t.materials[0].table);
         copy->back = copy->front;
         t.materials[0].table = copy;
       }},
      {"weight over incidence", [](sim::SceneDesc& t) { t.materials[0].over_incidence[0].factor[1] = 0.6; }},
      {"weight over incidence, another lobe",
       [](sim::SceneDesc& t) { t.materials[0].over_incidence[3] = t.materials[0].over_incidence[0]; }},
      {"emitter spectrum", [](sim::SceneDesc& t) { t.emitters[0].spectrum.over_gamma[1].spectrum.values[0] = 2.5; }},
      {"emitter spectrum angle", [](sim::SceneDesc& t) { t.emitters[0].spectrum.over_gamma[1].gamma_deg = 80.0; }},
      {"ray position",
       [](sim::SceneDesc& t) {
         auto copy = std::make_shared<sim::RaySet>(*t.emitters[1].rays);
         copy->position_m[1].y = 0.001f;
         t.emitters[1].rays = copy;
       }},
      {"ray direction",
       [](sim::SceneDesc& t) {
         auto copy = std::make_shared<sim::RaySet>(*t.emitters[1].rays);
         copy->direction[0] = {0.0f, 0.0f, 1.0f};
         t.emitters[1].rays = copy;
       }},
      {"ray flux",
       [](sim::SceneDesc& t) {
         auto copy = std::make_shared<sim::RaySet>(*t.emitters[1].rays);
         copy->flux_lm[1] = 3.0f;
         t.emitters[1].rays = copy;
       }},
      {"no rays", [](sim::SceneDesc& t) { t.emitters[1].rays = nullptr; }},
  };
  for (const auto& [what, change] : changes) {
    sim::SceneDesc t = s;
    change(t);
    EXPECT_NE(scene_hash(t), h) << what;
  }
  // The same content in another object hashes the same.
  sim::SceneDesc copy = s;
  copy.emitters[1].rays = std::make_shared<sim::RaySet>(*s.emitters[1].rays);
  copy.materials[0].table = std::make_shared<sim::TabulatedBsdf>(*s.materials[0].table);
  EXPECT_EQ(scene_hash(copy), h);
}

// The reference cache with a changed spectrum (the case a model file's own
// hash misses: a spectrum from a sidecar or a side file changes the scene,
// not the model's bytes): the same key is read back, the key of the scene
// with the changed spectrum traces again. A cache keyed on a hash blind to
// spectra would hand back the stale reference (reused).
TEST(BenchReference, AChangedSpectrumTracesTheReferenceAgain) {
  sim::SceneDesc s;
  sim::Material m;
  m.diffuse_reflect = 0.8;
  m.spectral_reflectance = {{380.0, 780.0}, {0.8, 0.8}};
  s.materials = {m};
  s.meshes = {sim::box(0.1, 0.1, 0.1)};
  sim::Emitter e;
  e.flux_lm = 100.0;
  e.position = {0.0, 0.0, 0.2};
  s.emitters = {e};
  ReferenceKey key;
  key.seed = 2;
  key.photons = 4096;
  key.face_size = 8;
  key.max_bounces = 10;
  key.scene_hash = scene_hash(s);
  test::TempDir dir;
  const auto resampler = std::make_shared<const sim::Resampler>(key.face_size, s.frame, sim::CGammaGrid{});
  Result<Reference> first = load_or_make_reference(dir.path().string(), key, s, 1, resampler, {});
  ASSERT_TRUE(first.ok()) << first.error().message;
  EXPECT_FALSE(first->reused);
  Result<Reference> again = load_or_make_reference(dir.path().string(), key, s, 1, resampler, {});
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_TRUE(again->reused);

  sim::SceneDesc t = s;
  t.materials[0].spectral_reflectance.values = {0.8, 0.2};  // the flat white turned bluish
  ReferenceKey changed = key;
  changed.scene_hash = scene_hash(t);
  Result<Reference> redone = load_or_make_reference(dir.path().string(), changed, t, 1, resampler, {});
  ASSERT_TRUE(redone.ok()) << redone.error().message;
  EXPECT_FALSE(redone->reused);
  EXPECT_NE(redone->far_field.total_flux_lm(), first->far_field.total_flux_lm());
}

}  // namespace
}  // namespace gonio::app
