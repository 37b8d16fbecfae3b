// Scenes built in code for the benchmarks (and the tests that time or
// compare them): stand-ins for the glTF samples until those are on main.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/tracer/embree_scene.h"
#include "sim/scene.h"
#include "sim/tracer/tracer.h"

namespace gonio::bench {

// The thesis' test luminaire: a bell-shaped pendant shade of opal glass
// (60 % diffuse transmission, 30 % diffuse reflection, 10 % mirror), open at
// the bottom, 0.4 m across and 0.25 m tall, with an isotropic 1000 lm point
// emitter inside and a grey socket above it. `segments` facets around the
// axis, `rings` along the profile (≈ 2·segments·rings triangles).
sim::SceneDesc bell_scene(int segments = 256, int rings = 96);

// A scene of about `triangles` triangles for raw Embree rates: a sphere.
sim::SceneDesc sphere_scene(int segments, int rings);

// Random rays that leave the scene's surfaces: origins uniform in area over
// every triangle, moved off the surface by `tracer` (Tracer::offset) to the
// side the ray leaves towards, directions uniform over the sphere.
// What bare Embree costs for rays that start where scattered photons start
// (a ray leaving a surface first crosses the BVH nodes around its origin);
// the uniform rays in the bounding box of EmbreeScene::measure_random_rays
// mostly start in empty space.
std::vector<sim::RayQuery> random_surface_rays(const sim::SceneDesc& scene, const sim::Tracer& tracer,
                                               std::uint64_t count, std::uint64_t seed);

}  // namespace gonio::bench
