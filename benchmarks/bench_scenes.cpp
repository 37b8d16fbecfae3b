#include "benchmarks/bench_scenes.h"

#include <cmath>
#include <numbers>
#include <vector>

#include "sim/samplers/alias_table.h"
#include "sim/samplers/random.h"
#include "sim/samplers/sampling.h"
#include "sim/shapes.h"

namespace gonio::bench {

sim::SceneDesc bell_scene(int segments, int rings) {
  sim::SceneDesc scene;
  scene.name = "bell (built in code)";
  sim::Material opal;
  opal.name = "opal glass";
  opal.diffuse_transmit = 0.6;
  opal.diffuse_reflect = 0.3;
  opal.mirror = 0.1;
  sim::Material grey;
  grey.name = "grey socket";
  grey.diffuse_reflect = 0.5;
  scene.materials = {opal, grey};

  // The shade: from the rim (r = 0.2 m, y = 0) up to the crown (r = 0.05 m,
  // y = 0.25 m) along a flared bell curve, then a flat crown to the axis.
  std::vector<sim::ProfilePoint> profile;
  for (int k = 0; k <= rings; ++k) {
    const double s = static_cast<double>(k) / rings;
    const double flare = std::pow(1.0 - s, 2.2);
    profile.push_back({0.05 + 0.15 * flare + 0.01 * std::sin(std::numbers::pi * s), 0.25 * s});
  }
  profile.push_back({0.0, 0.25});
  sim::LatheOptions options;
  options.segments = segments;
  sim::Mesh shade = sim::lathe(profile, options);
  shade.name = "shade";
  shade.material = 0;

  sim::Mesh socket = sim::box(0.04, 0.06, 0.04);
  sim::transform(socket, sim::translation({0.0, 0.21, 0.0}));
  socket.name = "socket";
  socket.material = 1;
  scene.meshes = {shade, socket};

  sim::Emitter lamp;
  lamp.name = "lamp";
  lamp.kind = sim::Emitter::Kind::Point;
  lamp.position = {0.0, 0.14, 0.0};
  lamp.flux_lm = 1000.0;
  scene.emitters = {lamp};
  return scene;
}

sim::SceneDesc sphere_scene(int segments, int rings) {
  sim::SceneDesc scene;
  scene.name = "sphere";
  sim::Material white;
  white.name = "white";
  white.diffuse_reflect = 0.8;
  scene.materials = {white};
  sim::Mesh s = sim::sphere(0.1, segments, rings);
  scene.meshes = {s};
  sim::Emitter e;
  e.flux_lm = 1.0;
  scene.emitters = {e};
  return scene;
}

std::vector<sim::RayQuery> random_surface_rays(const sim::SceneDesc& scene, const sim::Tracer& tracer,
                                               std::uint64_t count, std::uint64_t seed) {
  struct Triangle {
    Vec3 p0, e1, e2, n;  // corner, edges, unit normal
  };
  std::vector<Triangle> triangles;
  std::vector<double> areas;
  for (const sim::Mesh& m : scene.meshes) {
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
      Vec3 p[3];
      for (int k = 0; k < 3; ++k) {
        const sim::Vec3f& q = m.positions[m.indices[3 * t + k]];
        p[k] = {q.x, q.y, q.z};
      }
      const Vec3 c = cross(p[1] - p[0], p[2] - p[0]);
      const double len = length(c);
      if (!(len > 0.0)) continue;
      triangles.push_back({p[0], p[1] - p[0], p[2] - p[0], c / len});
      areas.push_back(0.5 * len);
    }
  }
  std::vector<sim::RayQuery> rays;
  if (triangles.empty()) return rays;
  const sim::AliasTable table(areas);
  rays.resize(count);
  for (std::uint64_t i = 0; i < count; ++i) {
    sim::PhotonRandom rng(seed, i);
    const Triangle& tri = triangles[table.sample(rng.uniform())];
    const sim::Barycentric b = sim::sample_uniform_triangle(rng.uniform(), rng.uniform());
    const Vec3 d = sim::sample_uniform_sphere(rng);
    const Vec3 p = tri.p0 + b.b1 * tri.e1 + b.b2 * tri.e2;
    rays[i] = sim::ray_query(tracer.offset(p, dot(d, tri.n) > 0.0 ? tri.n : -tri.n, 0.0), d);
  }
  return rays;
}

}  // namespace gonio::bench
