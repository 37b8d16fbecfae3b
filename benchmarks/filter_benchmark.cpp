// gonio_filter_benchmarks: the preview filter's cost per iteration.
//
// The goal (brief): at the defaults, on faces of 256 texels with 10⁶ photons
// per iteration, the filter takes ≤ 5 % of an iteration, i.e. ≤ 25 ms when
// the tracer runs at 2 M photons/s. The histogram is a lit lower hemisphere
// with strut shadows sampled at 2.5 photons per texel (the first iteration)
// and at 160 (the 64th). Times are wall-clock (the filter is parallel);
// `budget` is the mean time as a fraction of the 25 ms allowance.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <unistd.h>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <utility>

#include "sim/far_field_sampler.h"
#include "sim/preview_filter.h"
#include "sim/pyramid.h"
#include "tools/preview_output.h"

namespace {

using namespace gonio::sim;

constexpr double kBudgetSeconds = 0.025;

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

// Runs `body` once per benchmark iteration and reports, besides the time,
// `budget`: the mean wall time per iteration over the 25 ms allowance.
template <class Body>
void run_timed(benchmark::State& state, const Body& body) {
  double seconds = 0.0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    body();
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  state.counters["budget"] = seconds / static_cast<double>(state.iterations()) / kBudgetSeconds;
}

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
  gonio::cli::PreviewOutput output(dir.string(), n, PreviewFilterParams{});
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
