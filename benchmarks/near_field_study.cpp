// gonio_near_field_study: the far-field distance of issue 33's disc.
//
// A black Lambertian disc of radius 0.25 m facing the nadir (1000 lm) with
// near-field planes at 0.5, 2, 5 and 10 m (or those given): per plane the
// verdict of sim/detectors/near_field.h's criterion, its bounds and the photons it
// would need, and the far-field distance. On the axis the near field is
// within 1 % of the far field from D = a·√99 = 2.49 m.
//
// Usage: gonio_near_field_study [--photons N] [--threads T] [--seed S]
//                               [--planes D1,D2,...]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "sim/detectors/near_field.h"
#include "sim/shapes.h"
#include "sim/simulation.h"

int main(int argc, char** argv) {
  using namespace gonio::sim;
  double photons = 1e7;
  int threads = 0;
  std::uint64_t seed = 1;
  std::vector<double> planes = {0.5, 2.0, 5.0, 10.0};
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--photons")) photons = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--seed")) seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (!std::strcmp(argv[i], "--planes")) {
      planes.clear();
      for (const char* p = argv[i + 1]; *p;) {
        char* end = nullptr;
        planes.push_back(std::strtod(p, &end));
        p = *end == ',' ? end + 1 : end;
      }
    }
  }
  SceneDesc scene;
  Material black;
  black.name = "black";
  scene.materials = {black};
  Mesh d = disc(0.25, 256);
  flip(d);  // facing −Y, the default frame's nadir
  scene.meshes = {d};
  Emitter e;
  e.kind = Emitter::Kind::Area;
  e.flux_lm = 1000.0;
  scene.emitters = {e};
  SimulationSettings s;
  s.threads = threads;
  s.seed = seed;
  s.face_size = 16;
  s.sampler = SamplerKind::Sobol;
  const auto total = static_cast<std::uint64_t>(photons);
  s.iterations = static_cast<int>((total + (1u << 24) - 1) / (1u << 24));
  s.photons_per_iteration = total / static_cast<std::uint64_t>(s.iterations);
  s.near_field_distances_m = planes;
  auto sim = simulate(scene, s);
  if (!sim.ok()) {
    std::fprintf(stderr, "%s\n", sim.error().message.c_str());
    return 1;
  }
  const gonio::Vec3 c = sim->near_field_planes()->centre;
  std::printf("disc r = 0.25 m, %.3g photons (%s), seed %llu; centre (%.4g, %.4g, %.4g) m; %.1f s tracing\n",
              static_cast<double>(sim->stats().photons), "sobol", static_cast<unsigned long long>(seed), c.x, c.y,
              c.z, sim->stats().trace_s);
  std::printf("%8s %10s %6s %10s %10s %10s %10s %6s %12s\n", "D [m]", "verdict", "cells", "max |d| %", "upper %",
              "lower %", "pixel max %", "z_n", "to tell");
  const std::vector<NearFieldPlane> result = sim->near_field();
  for (const NearFieldPlane& p : result)
    std::printf("%8.3g %10s %6d %10.4f %10.4f %10.4f %10.4f %6.3f %12.3g\n", p.distance_m, to_string(p.verdict),
                p.cells_compared, p.cell_deviation_pct, p.upper_bound_pct, p.lower_bound_pct, p.max_deviation_pct,
                p.z_fail, p.photons_to_tell);
  const FarFieldDistance fd = far_field_distance(result);
  if (fd.distance_m)
    std::printf("far-field distance: %g m\n", *fd.distance_m);
  else
    std::printf("far-field distance: none (farthest plane %s%s)\n", to_string(fd.farthest),
                fd.photons_to_tell > 0 ? (", " + std::to_string(fd.photons_to_tell) + " photons would tell").c_str()
                                       : "");
  return 0;
}
