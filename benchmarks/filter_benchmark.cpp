// gonio_filter_benchmarks: the preview filter's cost per iteration.
//
// The goal (brief): at the defaults, on faces of 256 texels with 10⁶ photons
// per iteration, the filter takes ≤ 5 % of an iteration. The iteration is
// measured in the same run: 10⁶ photons of the downlight sample (the
// fastest of the four) traced on every core into faces of 256 texels, the
// best of three iterations (build/samples/, target gonio_samples). Every
// timed benchmark reports `of_iteration`: its mean wall time over that
// iteration's. BM_FilterDownlight filters the downlight's own far field
// after that first iteration; the others filter a lit lower hemisphere with
// strut shadows sampled at 2.5 photons per texel (the first iteration) and at
// 160 (the 64th). Times are wall-clock (the filter is parallel).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <unistd.h>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <utility>

#include "io/model/gltf.h"
#include "sim/detectors/far_field_sampler.h"
#include "sim/filter/preview_filter.h"
#include "sim/filter/pyramid.h"
#include "sim/simulation.h"
#include "tools/run/preview_output.h"

namespace {

using namespace gonio::sim;

constexpr int kIterationFaceSize = 256;
constexpr std::uint64_t kIterationPhotons = 1'000'000;

double struts(const gonio::Vec3& d) {
  if (d.y >= 0.0) return 0.02;
  const double c = std::atan2(d.z, d.x) + std::numbers::pi / 4;
  return std::abs(std::remainder(c, std::numbers::pi / 2)) < 3.0 * std::numbers::pi / 180.0 ? 0.03
                                                                                              : -d.y + 0.02;
}

// Histograms are built once per (face size, photons per texel).
const FarField& histogram(int n, double photons_per_texel) {
  static std::map<std::pair<int, double>, FarField> cache;
  auto it = cache.find({n, photons_per_texel});
  if (it == cache.end()) {
    const CubeMapGrid grid(n);
    const FarFieldSampler sampler(expected_texel_flux(grid, struts, 1));
    FarField field(n);
    std::mt19937_64 rng(1);
    sampler.add_photons(field, static_cast<std::uint64_t>(photons_per_texel * grid.texel_count()), 1e-3, rng);
    it = cache.emplace(std::pair{n, photons_per_texel}, std::move(field)).first;
  }
  return it->second;
}

// The traced iteration: its wall time and the far field after the first.
struct TracedIteration {
  double seconds = 0.0;
  double photons_per_s = 0.0;
  int threads = 0;
  std::optional<FarField> first;
  std::string error;
};

const TracedIteration& downlight_iteration() {
  static const TracedIteration traced = [] {
    TracedIteration t;
    const std::string path = std::string(GONIO_SAMPLES_DIR) + "/downlight/downlight.gltf";
    auto scene = gonio::io::load_gltf(path, nullptr);
    if (!scene.ok()) {
      t.error = "cannot load the downlight sample (build target gonio_samples): " + to_string(scene.error());
      return t;
    }
    SimulationSettings s;
    s.photons_per_iteration = kIterationPhotons;
    s.iterations = 3;
    s.threads = 0;
    s.face_size = kIterationFaceSize;
    auto sim = Simulation::create(scene.value(), s);
    if (!sim.ok()) {
      t.error = "downlight: " + to_string(sim.error());
      return t;
    }
    double best = 0.0;
    for (int i = 0; i < s.iterations; ++i) {
      const double before = sim->stats().trace_s;
      sim->run_iteration();
      const double seconds = sim->stats().trace_s - before;
      best = i == 0 ? seconds : std::min(best, seconds);
      if (i == 0) t.first.emplace(sim->far_field());
    }
    t.seconds = best;
    t.photons_per_s = static_cast<double>(kIterationPhotons) / best;
    t.threads = sim->stats().threads;
    std::fprintf(stderr, "downlight: 10^6 photons into faces of %d texels in %.1f ms (best of 3, %d threads)\n",
                 kIterationFaceSize, 1e3 * best, t.threads);
    return t;
  }();
  return traced;
}

// Runs `body` once per benchmark iteration and reports, besides the time,
// `of_iteration`: the mean wall time over the traced iteration's.
template <class Body>
void run_timed(benchmark::State& state, const Body& body) {
  const TracedIteration& iteration = downlight_iteration();
  if (!iteration.error.empty()) {
    state.SkipWithError(iteration.error.c_str());
    return;
  }
  double seconds = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    body();
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  state.counters["of_iteration"] = seconds / static_cast<double>(state.iterations()) / iteration.seconds;
}

// The traced iteration itself, for the record: its time is the benchmark's
// (one iteration, measured before any benchmark runs).
void BM_DownlightIteration(benchmark::State& state) {
  const TracedIteration& iteration = downlight_iteration();
  if (!iteration.error.empty()) {
    state.SkipWithError(iteration.error.c_str());
    return;
  }
  for (auto _ : state) state.SetIterationTime(iteration.seconds);
  state.counters["photons_per_s"] = iteration.photons_per_s;
  state.counters["threads"] = iteration.threads;
}
BENCHMARK(BM_DownlightIteration)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);

// The defaults on the downlight's far field after its first iteration.
void BM_FilterDownlight(benchmark::State& state) {
  const TracedIteration& iteration = downlight_iteration();
  if (!iteration.first) {
    state.SkipWithError(iteration.error.c_str());
    return;
  }
  PreviewFilter filter(kIterationFaceSize, PreviewFilterParams{});
  run_timed(state, [&] {
    filter.apply(*iteration.first);
    benchmark::DoNotOptimize(filter.intensity_cd().data());
  });
}
BENCHMARK(BM_FilterDownlight)->Unit(benchmark::kMillisecond)->UseRealTime();

// Arguments: face size, photons per texel × 10, configuration.
void BM_PreviewFilter(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const FarField& field = histogram(n, static_cast<double>(state.range(1)) / 10.0);
  PreviewFilterParams p;  // the defaults
  const int config = static_cast<int>(state.range(2));
  if (config == 2 || config == 3) p.interpolation = Interpolation::Bilinear;
  if (config == 1 || config == 3) {
    p.adaptive = false;
    p.threshold_photons = 100.0;
  }
  PreviewFilter filter(n, p);
  run_timed(state, [&] {
    filter.apply(field);
    benchmark::DoNotOptimize(filter.intensity_cd().data());
  });
  static const char* const names[] = {"defaults", "fixed-threshold", "adaptive-bilinear", "fixed-bilinear"};
  state.SetLabel(names[config]);
}
BENCHMARK(BM_PreviewFilter)
    ->ArgsProduct({{128, 256}, {25, 1600}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The defaults on one thread, for the parallel speed-up.
void BM_PreviewFilterOneThread(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const FarField& field = histogram(n, 2.5);
  PreviewFilter filter(n, PreviewFilterParams{});
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  run_timed(state, [&] {
    filter.apply(field);
    benchmark::DoNotOptimize(filter.intensity_cd().data());
  });
}
BENCHMARK(BM_PreviewFilterOneThread)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();

// Everything `--preview` does per iteration: the filter, preview.exr
// (OpenEXR, ZIP) and preview.png (OpenImageIO), written atomically to a
// temporary folder.
void BM_PreviewOutput(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const FarField& field = histogram(n, 2.5);
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("gonio_preview_bench_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  gonio::app::PreviewOutput output(dir.string(), n, PreviewFilterParams{});
  run_timed(state, [&] {
    if (!output.write(field).ok()) state.SkipWithError("preview write failed");
  });
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_PreviewOutput)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();

// The pull phase alone, and a plain pass over the histogram (intensity of
// every texel) as the floor any filter pays for reading its input.
void BM_Pull(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const FarField& field = histogram(n, 2.5);
  CubePyramid pyramid(n, 99);
  run_timed(state, [&] {
    pyramid.pull(field);
    benchmark::DoNotOptimize(pyramid.flux_lm(1).data());
  });
}
BENCHMARK(BM_Pull)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_RawIntensity(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const FarField& field = histogram(n, 2.5);
  std::vector<double> out(field.texel_count());
  run_timed(state, [&] {
    for (std::size_t t = 0; t < out.size(); ++t) out[t] = field.intensity_cd(t);
    benchmark::DoNotOptimize(out.data());
  });
}
BENCHMARK(BM_RawIntensity)->Arg(256)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
