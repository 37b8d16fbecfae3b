// The setup of a simulation against model size (issue 12): each phase
// between a saved model and the first photon, on large models generated in
// code (samples/large_models.h: a faceted reflector, a lens array of one
// lens placed by EXT_mesh_gpu_instancing, a glass part), at 10⁴ … 10⁶
// triangles, the instanced lens array up to 10⁸ as placed.
//
//   cmake --build build --target gonio_setup_benchmarks
//   build/benchmarks/gonio_setup_benchmarks --benchmark_filter='glass-part'
//
// Phases: BM_Load (io::load_gltf of the .gltf and .bin), BM_Check
// (io::check_model, cold), BM_Bvh (sim::EmbreeScene::build; first argument
// 1 = robust, 0 = not; second the build quality: 0 low, 1 medium, 2 high),
// BM_EmissionTables (sim::EmissionSampler::create).
// Counters: triangles (of the loaded scene, as placed), unique_triangles
// (stored: an instanced mesh once), instances, s_per_Mtriangle (wall
// seconds per million unique triangles; goal for load + checks + BVH: ≤ 1)
// and cpu_s_per_Mtriangle (CPU seconds of all threads per million unique triangles:
// what the phase costs on a machine shared with others, where wall time
// depends on who else runs).
// The models are written once per run into a temporary folder
// (benchmarks/large_model_files.h).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "benchmarks/large_model_files.h"
#include "io/model/gltf.h"
#include "io/model/model_check.h"
#include "samples/large_models.h"
#include "sim/tracer/embree_scene.h"
#include "sim/emitters/emission.h"

namespace gonio::bench {
namespace {

using samples::LargeModel;

[[noreturn]] void fail(const std::string& what) {
  std::fprintf(stderr, "setup benchmark: %s\n", what.c_str());
  std::abort();
}

const sim::SceneDesc& scene(LargeModel kind, std::size_t triangles) { return large_model_scene(kind, triangles); }
std::string model_path(LargeModel kind, std::size_t triangles) { return large_model_file(kind, triangles); }

// CPU time of the whole process (all threads) [s].
double process_cpu_s() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Per 10⁶ unique triangles (stored, each instanced mesh once): what setup
// should grow with; `triangles` counts them as placed.
void counters(benchmark::State& state, const sim::SceneDesc& s, double cpu_s) {
  const std::size_t triangles = s.unique_triangle_count();
  state.counters["triangles"] = static_cast<double>(s.placed_triangle_count());
  state.counters["unique_triangles"] = static_cast<double>(triangles);
  state.counters["instances"] = static_cast<double>(s.instances.size());
  state.counters["cpu_s_per_Mtriangle"] =
      cpu_s / static_cast<double>(state.iterations()) / (static_cast<double>(triangles) / 1e6);
  // Seconds per iteration per 10⁶ triangles.
  state.counters["s_per_Mtriangle"] = benchmark::Counter(
      static_cast<double>(triangles) / 1e6, benchmark::Counter::kIsIterationInvariantRate |
                                                benchmark::Counter::kInvert);
}

void BM_Load(benchmark::State& state, LargeModel kind, std::size_t triangles) {
  const std::string path = model_path(kind, triangles);
  const double cpu0 = process_cpu_s();
  for (auto _ : state) {
    std::vector<Finding> findings;
    Result<sim::SceneDesc> s = io::load_gltf(path, &findings);
    if (!s.ok()) fail(to_string(s.error()));
    benchmark::DoNotOptimize(s);
  }
  counters(state, scene(kind, triangles), process_cpu_s() - cpu0);
}

void BM_Check(benchmark::State& state, LargeModel kind, std::size_t triangles) {
  const sim::SceneDesc& s = scene(kind, triangles);
  const double cpu0 = process_cpu_s();
  for (auto _ : state) {
    const std::vector<Finding> findings = io::check_model(s);
    for (const Finding& f : findings)
      if (f.severity == Severity::Error) fail(s.name + ": " + f.message);
    benchmark::DoNotOptimize(findings);
  }
  counters(state, s, process_cpu_s() - cpu0);
}

void BM_Bvh(benchmark::State& state, LargeModel kind, std::size_t triangles) {
  const sim::SceneDesc& s = scene(kind, triangles);
  sim::EmbreeSceneOptions options;
  options.robust = state.range(0) != 0;
  options.quality = static_cast<sim::EmbreeSceneOptions::Quality>(state.range(1));
  const double cpu0 = process_cpu_s();
  for (auto _ : state) {
    Result<sim::EmbreeScene> e = sim::EmbreeScene::build(s.meshes, options, s.instances);
    if (!e.ok()) fail(to_string(e.error()));
    benchmark::DoNotOptimize(e);
  }
  counters(state, s, process_cpu_s() - cpu0);
}

void BM_EmissionTables(benchmark::State& state, LargeModel kind, std::size_t triangles) {
  const sim::SceneDesc& s = scene(kind, triangles);
  const double cpu0 = process_cpu_s();
  for (auto _ : state) {
    Result<sim::EmissionSampler> e = sim::EmissionSampler::create(s);
    if (!e.ok()) fail(to_string(e.error()));
    benchmark::DoNotOptimize(e);
  }
  counters(state, s, process_cpu_s() - cpu0);
}

const bool kRegistered = [] {
  // The lens array is instanced: 10⁴ … 10⁸ triangles as placed, one
  // 960-triangle lens stored.
  for (LargeModel kind : {LargeModel::FacetedReflector, LargeModel::LensArray, LargeModel::GlassPart})
    for (std::size_t triangles : {std::size_t{10'000}, std::size_t{100'000}, std::size_t{1'000'000},
                                  std::size_t{10'000'000}, std::size_t{100'000'000}}) {
      if (kind != LargeModel::LensArray && triangles > 1'000'000) continue;
      const std::string name = samples::large_model_name(kind) + "/" + std::to_string(triangles);
      auto set = [&](benchmark::internal::Benchmark* b) {
        b->Unit(benchmark::kMillisecond)->UseRealTime();
        if (triangles >= 1'000'000 && kind != LargeModel::LensArray) b->Iterations(1);
      };
      set(benchmark::RegisterBenchmark(("BM_Load/" + name).c_str(), BM_Load, kind, triangles));
      set(benchmark::RegisterBenchmark(("BM_Check/" + name).c_str(), BM_Check, kind, triangles));
      set(benchmark::RegisterBenchmark(("BM_Bvh/" + name).c_str(), BM_Bvh, kind, triangles)
                    ->Args({1, 2})
                    ->Args({0, 2})
                    ->Args({1, 1})
                    ->Args({1, 0}));
      set(benchmark::RegisterBenchmark(("BM_EmissionTables/" + name).c_str(), BM_EmissionTables, kind,
                                       triangles));
    }
  return true;
}();

}  // namespace
}  // namespace gonio::bench

BENCHMARK_MAIN();
