// The tracer's speed against the physical limit measured in the same run:
// bare rtcIntersect1 on the same scene with random rays (origins uniform in
// the bounding box, uniform directions).
//
//   cmake --build build --target gonio_sim_benchmarks   (also writes the samples)
//   build/benchmarks/gonio_sim_benchmarks --benchmark_filter='Sample/bell'
//
// Scenes: the four sample luminaires (build/samples/*), the bell built in
// code (49k triangles), a closed 100k-triangle white sphere, and bare Embree
// on that sphere; and the samples with importance-guided emission
// (BM_TracerSampleGuided, counters below). Each tracer benchmark runs 2^20 photons per iteration on
// 1 and 2 threads. The large generated models with each BVH build quality
// and robust mode on and off (BM_TracerLarge), and what robust mode keeps
// from slipping through a closed mesh (BM_RobustLeaks).
//
// Counters: photons_per_s and rays_per_s of the tracer (wall clock),
// photons_per_cpu_s (per CPU-second of all threads), raw_rays_per_s of
// bare Embree on the same scene and thread count, and ratio = rays_per_s /
// raw_rays_per_s (goal ≥ 0.8); surface_rays_per_s of bare Embree on random
// rays leaving random surface points (bench_scenes.h) and surface_ratio =
// rays_per_s / that; replay_rays_per_s of bare rtcIntersect1 on
// the tracer's own recorded rays, replayed after every iteration, and
// replay_ratio, the median over iterations of the iteration's rays/s ÷ the
// replay's right after it (what the tracer's own work costs on top of
// Embree's), with replay_ratio_min, _max and replay_pairs. The sample and
// bell benchmarks run for at least 3 s (several pairs), the large models
// three iterations.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "benchmarks/bench_scenes.h"
#include "benchmarks/large_model_files.h"
#include "io/model/gltf.h"
#include "sim/samplers/random.h"
#include "sim/samplers/sampling.h"
#include "sim/simulation.h"

namespace gonio::bench {
namespace {

constexpr std::uint64_t kPhotonsPerIteration = 1u << 20;

// CPU time of the whole process (all threads) [s]: on a shared machine the
// wall-clock rate depends on who else runs; photons per CPU-second do less.
double process_cpu_s() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

sim::Simulation make_simulation(const sim::SceneDesc& scene, int threads,
                                const sim::EmbreeSceneOptions& embree = {}) {
  sim::SimulationSettings s;
  s.robust_embree = embree.robust;
  s.bvh_quality = embree.quality;
  s.photons_per_iteration = kPhotonsPerIteration;
  s.iterations = 1;
  s.threads = threads;
  auto sim = sim::Simulation::create(scene, s);
  if (!sim.ok()) {
    std::fprintf(stderr, "benchmark scene: %s\n", to_string(sim.error()).c_str());
    std::abort();
  }
  return std::move(sim.value());
}

void run_tracer(benchmark::State& state, const sim::SceneDesc& scene, const sim::EmbreeSceneOptions& embree = {}) {
  const int threads = static_cast<int>(state.range(0));
  sim::Simulation sim = make_simulation(scene, threads, embree);
  // Bare rtcIntersect1 on the tracer's own rays (as many photons' as an
  // iteration traces), recorded once and replayed right after every
  // iteration: each iteration's tracer rate is paired with a replay under the
  // same conditions, and replay_ratio is the median of the pairs' ratios
  // (this machine's rates drift by ±20 % between single runs).
  std::vector<sim::RayQuery> rays;
  sim.tracer().record_rays(sim.settings().seed, 0, kPhotonsPerIteration, &rays);
  std::vector<double> pair_ratios;
  double replayed_rays = 0.0, replay_s = 0.0, replay_cpu_s = 0.0;
  const double cpu0 = process_cpu_s();
  for (auto _ : state) {
    const sim::SimulationStats before = sim.stats();
    sim.run_iteration();
    const sim::SimulationStats after = sim.stats();
    const double rate = static_cast<double>(after.rays - before.rays) / (after.trace_s - before.trace_s);
    const double replay_cpu0 = process_cpu_s();
    const auto replay = sim.tracer().embree().measure_rays(rays, threads);
    replay_cpu_s += process_cpu_s() - replay_cpu0;
    replayed_rays += static_cast<double>(replay.rays);
    replay_s += replay.seconds;
    pair_ratios.push_back(rate / replay.rays_per_s());
  }
  const double cpu = process_cpu_s() - cpu0 - replay_cpu_s;
  const sim::SimulationStats st = sim.stats();
  // The raw rate on the same scene and threads, right after.
  const auto raw = sim.tracer().embree().measure_random_rays(2'000'000, 7, threads);
  // Random rays leaving random surface points: what Embree costs for rays
  // that start where scattered photons do, without the tracer's choices.
  const auto surface =
      sim.tracer().embree().measure_rays(random_surface_rays(scene, sim.tracer(), 2'000'000, 7), threads);
  std::sort(pair_ratios.begin(), pair_ratios.end());
  const std::size_t n = pair_ratios.size();
  state.counters["photons_per_s"] = st.photons_per_s();
  state.counters["photons_per_cpu_s"] = static_cast<double>(st.photons) / cpu;
  state.counters["rays_per_s"] = st.rays_per_s();
  state.counters["rays_per_photon"] = static_cast<double>(st.rays) / static_cast<double>(st.photons);
  state.counters["raw_rays_per_s"] = raw.rays_per_s();
  state.counters["ratio"] = st.rays_per_s() / raw.rays_per_s();
  state.counters["surface_rays_per_s"] = surface.rays_per_s();
  state.counters["surface_ratio"] = st.rays_per_s() / surface.rays_per_s();
  state.counters["replay_rays_per_s"] = replayed_rays / replay_s;
  state.counters["replay_ratio"] = n % 2 ? pair_ratios[n / 2] : 0.5 * (pair_ratios[n / 2 - 1] + pair_ratios[n / 2]);
  state.counters["replay_ratio_min"] = pair_ratios.front();
  state.counters["replay_ratio_max"] = pair_ratios.back();
  state.counters["replay_pairs"] = static_cast<double>(n);
  state.counters["triangles"] = static_cast<double>(sim.tracer().embree().triangle_count());
  state.counters["bvh_s"] = st.tracer_setup.bvh_s;
  state.SetItemsProcessed(static_cast<std::int64_t>(st.photons));
}

void BM_TracerBell(benchmark::State& state) { run_tracer(state, bell_scene()); }
BENCHMARK(BM_TracerBell)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

// The sample luminaires themselves (target gonio_samples writes them).
void run_sample(benchmark::State& state, const std::string& name) {
  const std::string path = std::string(GONIO_SAMPLES_DIR) + "/" + name + "/" + name + ".gltf";
  auto scene = io::load_gltf(path, nullptr);
  if (!scene.ok()) {
    state.SkipWithError(("cannot load the sample: " + to_string(scene.error())).c_str());
    return;
  }
  run_tracer(state, scene.value());
}
const bool kSamplesRegistered = [] {
  for (const char* name : {"bell", "downlight", "spotlight", "led-array"})
    benchmark::RegisterBenchmark((std::string("BM_TracerSample/") + name).c_str(),
                                 [name](benchmark::State& st) { run_sample(st, name); })
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MinTime(3.0);
  return true;
}();

// A 100k-triangle white sphere (ρ = 0.8, closed) around an isotropic point:
// every ray hits, about five per photon.
void BM_TracerSphere100k(benchmark::State& state) { run_tracer(state, sphere_scene(317, 158)); }
BENCHMARK(BM_TracerSphere100k)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(3.0);

// Bare Embree on a 100k-triangle sphere (the reference figure of the brief).
void BM_RawEmbreeSphere100k(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  sim::Simulation sim = make_simulation(sphere_scene(317, 158), threads);
  double rays = 0, seconds = 0;
  for (auto _ : state) {
    const auto raw = sim.tracer().embree().measure_random_rays(1'000'000, 11, threads);
    rays += static_cast<double>(raw.rays);
    seconds += raw.seconds;
  }
  state.counters["raw_rays_per_s"] = rays / seconds;
  state.counters["triangles"] = static_cast<double>(sim.tracer().embree().triangle_count());
}
BENCHMARK(BM_RawEmbreeSphere100k)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// The large generated models (samples/large_models.h) at 10⁵ and 10⁶
// triangles on 2 threads, for each BVH build quality (second argument: 0
// low, 1 medium, 2 high) and robust mode (third: 1 on, 0 off): the tracer's
// rates and replay_ratio as above, and bvh_s, the BVH's build time.
const bool kLargeRegistered = [] {
  using samples::LargeModel;
  for (LargeModel kind : {LargeModel::FacetedReflector, LargeModel::LensArray, LargeModel::GlassPart})
    for (std::size_t triangles : {std::size_t{100'000}, std::size_t{1'000'000}}) {
      const std::string name =
          "BM_TracerLarge/" + samples::large_model_name(kind) + "/" + std::to_string(triangles);
      auto* b = benchmark::RegisterBenchmark(name.c_str(), [kind, triangles](benchmark::State& st) {
        sim::EmbreeSceneOptions o;
        o.quality = static_cast<sim::EmbreeSceneOptions::Quality>(st.range(1));
        o.robust = st.range(2) != 0;
        run_tracer(st, large_model_scene(kind, triangles), o);
      });
      for (int quality : {0, 1, 2}) b->Args({2, quality, 1});
      b->Args({2, 2, 0});
      b->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
    }
  return true;
}();

// What robust mode keeps in: rays leaving random points of a closed glass
// sphere's surface into the glass (origins moved inside by the tracer's
// offset rule, directions uniform over the inner hemisphere of the facet)
// must all hit the sphere again. Argument: robust (1) or not (0). Counters:
// rays, misses (rays that slipped out through an edge or a vertex),
// miss_fraction and raw rays/s.
void BM_RobustLeaks(benchmark::State& state, std::size_t triangles) {
  const sim::SceneDesc& scene = large_model_scene(samples::LargeModel::GlassPart, triangles);
  sim::TracerSettings ts;
  ts.embree.robust = state.range(0) != 0;
  auto tracer = sim::Tracer::create(scene, 8, ts);
  if (!tracer.ok()) {
    state.SkipWithError(to_string(tracer.error()).c_str());
    return;
  }
  const sim::Mesh& mesh = scene.meshes.at(0);
  std::vector<sim::RayQuery> rays(2'000'000);
  for (std::uint64_t i = 0; i < rays.size(); ++i) {
    sim::PhotonRandom rng(5, i);
    const auto t = std::min<std::size_t>(static_cast<std::size_t>(rng.uniform() * static_cast<double>(mesh.triangle_count())),
                                         mesh.triangle_count() - 1);
    Vec3 p[3];
    for (int k = 0; k < 3; ++k) {
      const sim::Vec3f& q = mesh.positions[mesh.indices[3 * t + static_cast<std::size_t>(k)]];
      p[k] = {q.x, q.y, q.z};
    }
    const Vec3 n = normalize(cross(p[1] - p[0], p[2] - p[0]));  // outward
    const sim::Barycentric b = sim::sample_uniform_triangle(rng.uniform(), rng.uniform());
    Vec3 d = sim::sample_uniform_sphere(rng);
    if (dot(d, n) > 0.0) d = -d;
    const Vec3 origin = p[0] + b.b1 * (p[1] - p[0]) + b.b2 * (p[2] - p[0]);
    rays[i] = sim::ray_query(tracer->offset(origin, -n, 0.0), d);
  }
  std::uint64_t misses = 0;
  double rays_per_s = 0.0;
  for (auto _ : state) {
    const auto rate = tracer->embree().measure_rays(rays, 2);
    misses = rate.rays - rate.hits;
    rays_per_s = rate.rays_per_s();
  }
  state.counters["rays"] = static_cast<double>(rays.size());
  state.counters["misses"] = static_cast<double>(misses);
  state.counters["miss_fraction"] = static_cast<double>(misses) / static_cast<double>(rays.size());
  state.counters["raw_rays_per_s"] = rays_per_s;
  state.counters["triangles"] = static_cast<double>(scene.placed_triangle_count());
}
const bool kLeaksRegistered = [] {
  for (std::size_t triangles : {std::size_t{10'000}, std::size_t{1'000'000}})
    benchmark::RegisterBenchmark(("BM_RobustLeaks/glass-part/" + std::to_string(triangles)).c_str(),
                                 BM_RobustLeaks, triangles)
        ->Arg(1)
        ->Arg(0)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Iterations(1);
  return true;
}();

// Importance-guided emission (sim/emitters/emission_guide.h) on the samples, after the
// two plain iterations the guide learns from: photons drawn per
// second (the rate the far field's noise depends on, with unequal power),
// photons traced per second, and plain_ratio = photons drawn per CPU-second
// over the plain path's on the same scene in the same run (the guide's own
// cost per photon, < 1, against the tracing it saves by dropping photons).
void run_guided(benchmark::State& state, const std::string& name) {
  const std::string path = std::string(GONIO_SAMPLES_DIR) + "/" + name + "/" + name + ".gltf";
  auto scene = io::load_gltf(path, nullptr);
  if (!scene.ok()) {
    state.SkipWithError(("cannot load the sample: " + to_string(scene.error())).c_str());
    return;
  }
  const int threads = static_cast<int>(state.range(0));
  sim::SimulationSettings s;
  s.photons_per_iteration = kPhotonsPerIteration;
  s.iterations = 1;
  s.threads = threads;
  s.importance.enabled = true;
  auto guided = sim::Simulation::create(scene.value(), s);
  if (!guided.ok()) {
    state.SkipWithError(to_string(guided.error()).c_str());
    return;
  }
  guided->run_iteration();  // the far field for imp(T)
  guided->run_iteration();  // back-projected: guidance starts now
  const sim::SimulationStats before = guided->stats();
  const double cpu0 = process_cpu_s();
  for (auto _ : state) guided->run_iteration();
  const double cpu = process_cpu_s() - cpu0;
  const sim::SimulationStats after = guided->stats();
  const double drawn = static_cast<double>(after.photons - before.photons);
  const double traced = static_cast<double>(after.photons_traced - before.photons_traced);
  const double wall = after.trace_s - before.trace_s;
  // The plain path on the same scene, right after.
  sim::Simulation plain = make_simulation(scene.value(), threads);
  const double plain_cpu0 = process_cpu_s();
  plain.run_iteration();
  plain.run_iteration();
  const double plain_cpu = process_cpu_s() - plain_cpu0;
  const double plain_per_cpu_s = 2.0 * static_cast<double>(kPhotonsPerIteration) / plain_cpu;
  state.counters["photons_per_s"] = drawn / wall;
  state.counters["traced_per_s"] = traced / wall;
  state.counters["traced_fraction"] = traced / drawn;
  state.counters["photons_per_cpu_s"] = drawn / cpu;
  state.counters["plain_ratio"] = drawn / cpu / plain_per_cpu_s;
  state.SetItemsProcessed(static_cast<std::int64_t>(drawn));
}
const bool kGuidedRegistered = [] {
  for (const char* name : {"bell", "downlight", "spotlight", "led-array"})
    benchmark::RegisterBenchmark((std::string("BM_TracerSampleGuided/") + name).c_str(),
                                 [name](benchmark::State& st) { run_guided(st, name); })
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  return true;
}();

}  // namespace
}  // namespace gonio::bench

BENCHMARK_MAIN();
