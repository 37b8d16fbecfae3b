// The large generated models (samples/large_models.h): as many triangles as
// asked for, clean for the model checks (the glass parts closed and facing
// out), one emitter, and the lens array one lens placed many times.
#include "samples/large_models.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "io/model/gltf.h"
#include "io/model/model_check.h"
#include "tests/support/test_support.h"

namespace gonio::samples {
namespace {

sim::SceneDesc load(const test::TempDir& dir, const Sample& s) {
  for (const SampleFile& f : s.files) test::write_file(dir / f.name, f.bytes);
  std::vector<Finding> findings;
  Result<sim::SceneDesc> scene = io::load_gltf((dir / s.model).string(), &findings);
  EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : to_string(scene.error()));
  for (const Finding& f : findings) EXPECT_NE(f.severity, Severity::Error) << f.message;
  return scene.ok() ? std::move(scene.value()) : sim::SceneDesc{};
}

std::size_t triangles(const sim::SceneDesc& s) { return s.placed_triangle_count(); }

TEST(LargeModels, HaveTheTrianglesAskedForAndPassTheChecks) {
  for (LargeModel kind : {LargeModel::FacetedReflector, LargeModel::LensArray, LargeModel::GlassPart})
    for (std::size_t wanted : {std::size_t{2000}, std::size_t{30000}}) {
      test::TempDir dir;
      const Sample s = large_model(kind, wanted);
      EXPECT_EQ(s.name, large_model_name(kind) + "-" + std::to_string(wanted));
      const sim::SceneDesc scene = load(dir, s);
      const double n = static_cast<double>(triangles(scene));
      EXPECT_NEAR(n, static_cast<double>(wanted), 0.1 * static_cast<double>(wanted)) << s.name;
      ASSERT_EQ(scene.emitters.size(), 1u) << s.name;
      const std::vector<Finding> findings = io::check_model(scene);
      EXPECT_TRUE(findings.empty()) << s.name << ": " << (findings.empty() ? "" : findings[0].message);
      const bool glass = kind != LargeModel::FacetedReflector;
      for (const sim::Mesh& m : scene.meshes)
        EXPECT_EQ(scene.materials[m.material].dielectric > 0.0, glass) << s.name;
    }
}

TEST(LargeModels, TheLensArrayIsOneLensPlacedByGpuInstancing) {
  const Sample s = large_model(LargeModel::LensArray, 20000);
  test::TempDir dir;
  const sim::SceneDesc scene = load(dir, s);
  // The file holds the lens once (its buffer is about one lens's size plus
  // a translation per copy), and so does the scene: one instanced mesh, one
  // instance per copy.
  const std::string* bin = nullptr;
  for (const SampleFile& f : s.files)
    if (f.name.ends_with(".bin")) bin = &f.bytes;
  ASSERT_NE(bin, nullptr);
  ASSERT_EQ(scene.meshes.size(), 1u);
  const sim::Mesh& lens = scene.meshes[0];
  EXPECT_TRUE(lens.instanced);
  EXPECT_LT(bin->size(), 2 * (lens.positions.size() * 24 + lens.indices.size() * 4) + 12 * scene.instances.size());
  ASSERT_GT(scene.instances.size(), 10u);
  for (const sim::Instance& i : scene.instances) EXPECT_EQ(i.mesh, 0u);
  // Copies side by side, none overlapping the first.
  EXPECT_NE(scene.instances[1].to_world.offset.x, scene.instances[0].to_world.offset.x);
}

}  // namespace
}  // namespace gonio::samples
