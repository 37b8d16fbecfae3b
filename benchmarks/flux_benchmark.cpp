// Flux integration runs on every file read: how long it takes on the grids
// files carry, against a plain pass over the same candela (the memory-bound
// floor of any integration rule).
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>

#include "benchmarks/photometry_grids.h"
#include "photometry/angles.h"
#include "photometry/compare.h"
#include "photometry/direct_ratios.h"
#include "photometry/flux.h"
#include "photometry/resample.h"
#include "photometry/summary.h"
#include "photometry/validation.h"

namespace {

using namespace gonio;
using namespace gonio::photometry;

using bench::steps;

// A smooth asymmetric downlight with some uplight, on a full C 0..360 grid.
Distribution grid(double c_step, double gamma_step, Symmetry sym = Symmetry::None, double c_to = 360.0) {
  return bench::smooth_downlight(c_step, gamma_step, sym, c_to);
}

// Grid sizes as (C step, γ step): 361 × 181 (1°), 73 × 37 (5°).
void grids(benchmark::internal::Benchmark* b) { b->Args({1, 1})->Args({5, 5}); }

void BM_SumCandelaBaseline(benchmark::State& state) {
  const Distribution d = grid(state.range(0), state.range(1));
  for (auto _ : state) {
    double sum = 0;
    for (double v : d.candela) sum += v;
    benchmark::DoNotOptimize(sum);
  }
  state.SetLabel(std::to_string(d.horizontal_count()) + "x" + std::to_string(d.vertical_count()));
}
BENCHMARK(BM_SumCandelaBaseline)->Apply(grids)->Unit(benchmark::kMicrosecond);

void BM_TotalFlux(benchmark::State& state) {
  const Distribution d = grid(state.range(0), state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(total_flux_lm(d));
  state.SetLabel(std::to_string(d.horizontal_count()) + "x" + std::to_string(d.vertical_count()));
  state.counters["intensities/s"] = benchmark::Counter(
      static_cast<double>(d.candela.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_TotalFlux)->Apply(grids)->Unit(benchmark::kMicrosecond);

void BM_TotalFluxQuadrant(benchmark::State& state) {
  const Distribution d = grid(state.range(0), state.range(1), Symmetry::Quadrant, 90);
  for (auto _ : state) benchmark::DoNotOptimize(total_flux_lm(d));
  state.SetLabel(std::to_string(d.horizontal_count()) + "x" + std::to_string(d.vertical_count()));
}
BENCHMARK(BM_TotalFluxQuadrant)->Apply(grids)->Unit(benchmark::kMicrosecond);

void BM_ZonalFlux(benchmark::State& state) {
  const Distribution d = grid(state.range(0), state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(zonal_flux_lm(d, 0, 41.41));
}
BENCHMARK(BM_ZonalFlux)->Apply(grids)->Unit(benchmark::kMicrosecond);

void BM_TotalFluxTypeB(benchmark::State& state) {
  Distribution d;
  d.type = PhotometricType::B;
  d.symmetry = Symmetry::Lateral;
  d.horizontal_deg = steps(0, 90, 1);
  d.vertical_deg = steps(-90, 90, 1);
  for (double h : d.horizontal_deg)
    for (double v : d.vertical_deg) {
      const double c = -direction_from_grid(PhotometricType::B, h, v).z;
      d.candela.push_back(1e4 * std::pow(std::max(c, 0.0), 20));
    }
  d.absolute = true;
  for (auto _ : state) benchmark::DoNotOptimize(total_flux_lm(d));
  state.SetLabel("91x181 lateral");
}
BENCHMARK(BM_TotalFluxTypeB)->Unit(benchmark::kMicrosecond);

void BM_Check(benchmark::State& state) {
  const Distribution d = grid(state.range(0), state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(check(d));
}
BENCHMARK(BM_Check)->Apply(grids)->Unit(benchmark::kMicrosecond);

void BM_Summarize(benchmark::State& state) {
  const Distribution d = grid(state.range(0), state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(summarize(d));
}
BENCHMARK(BM_Summarize)->Apply(grids)->Unit(benchmark::kMillisecond);

void BM_DirectRatios(benchmark::State& state) {
  const Distribution d = grid(5, 5);
  for (auto _ : state) benchmark::DoNotOptimize(direct_ratios(d));
}
BENCHMARK(BM_DirectRatios)->Unit(benchmark::kMillisecond);

void BM_Compare(benchmark::State& state) {
  const Distribution a = grid(1, 1), b = grid(5, 2.5);
  for (auto _ : state) benchmark::DoNotOptimize(compare(a, b));
}
BENCHMARK(BM_Compare)->Unit(benchmark::kMillisecond);

}  // namespace
