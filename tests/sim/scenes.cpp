#include "tests/sim/scenes.h"

#include "sim/shapes.h"

namespace gonio::sim::test_scenes {

SceneDesc mixed_scene() {
  SceneDesc s;
  Material opal{"opal", 0.3, 0.6, 0.1};
  Material metal;
  metal.name = "brushed";
  metal.glossy = 0.9;
  metal.glossy_mx = 0.3;
  metal.glossy_my = 0.1;
  Material glass;
  glass.name = "glass";
  glass.dielectric = 1.0;
  glass.ior = 1.5;
  glass.attenuation_per_m = 5.0;
  s.materials = {opal, metal, glass};

  const ProfilePoint bowl[] = {{0.0, -0.1}, {0.08, -0.08}, {0.1, 0.0}};
  Mesh m0 = lathe(bowl, {});
  m0.name = "bowl";
  m0.material = 0;
  Mesh m1 = paraboloid(0.03, 0.1, 0.01, 16, 48);
  transform(m1, translation({0.0, 0.05, 0.0}));
  m1.name = "reflector";
  m1.material = 1;
  Mesh m2 = slab(0.05, 0.05, 0.01);
  transform(m2, translation({0.0, -0.03, 0.0}));
  m2.name = "lens";
  m2.material = 2;
  s.meshes = {m0, m1, m2};

  Emitter a;
  a.name = "lamp";
  a.position = {0.0, 0.02, 0.0};
  a.flux_lm = 800.0;
  Emitter b;
  b.name = "glow";
  b.kind = Emitter::Kind::Area;
  b.mesh = 2;
  b.flux_lm = 200.0;
  s.emitters = {a, b};
  return s;
}

SimulationSettings small_run(int threads, std::uint64_t per_iteration, int iterations, std::uint64_t seed) {
  SimulationSettings s;
  s.threads = threads;
  s.photons_per_iteration = per_iteration;
  s.iterations = iterations;
  s.face_size = 16;
  s.seed = seed;
  return s;
}

}  // namespace gonio::sim::test_scenes
