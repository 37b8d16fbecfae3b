// Scenes shared by the sim test suites.
#pragma once

#include <cstdint>

#include "sim/scene.h"
#include "sim/simulation.h"

namespace gonio::sim::test_scenes {

// A small run: `threads` threads, `iterations` of `per_iteration` photons,
// a 16-texel cube map face, `seed`; everything else at its default.
SimulationSettings small_run(int threads, std::uint64_t per_iteration, int iterations, std::uint64_t seed);

// A small luminaire with every lobe and both kinds of emitter: an opal bowl
// (30 % diffuse reflection, 60 % diffuse transmission, 10 % mirror), a
// brushed glossy reflector (mx 0.3, my 0.1), an absorbing glass slab
// (n = 1.5, 5 /m) that also glows; an 800 lm point lamp and the slab's
// 200 lm.
SceneDesc mixed_scene();

}  // namespace gonio::sim::test_scenes
