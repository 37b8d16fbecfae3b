// The reference cache's key: hashes of the model file and of the scene.
#include "tools/bench/bench_reference.h"
#include "tools/run/scene_hash.h"

#include <gtest/gtest.h>

#include "sim/shapes.h"

namespace gonio::cli {
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

}  // namespace
}  // namespace gonio::cli
