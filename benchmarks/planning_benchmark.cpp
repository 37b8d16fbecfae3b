// The light-planning figures of one file (photometry/planning.h), each and
// all together, against summarize() — what `gonio info` computed before
// them — on the same grids: the ratio is the cost they add per file.
#include <benchmark/benchmark.h>

#include <string>

#include "benchmarks/photometry_grids.h"
#include "photometry/planning.h"
#include "photometry/summary.h"

namespace {

using namespace gonio::photometry;

// The flux benchmarks' downlight, full C 0..360, with a 0.6 × 0.6 m opening.
Distribution grid(double c_step, double gamma_step) {
  Distribution d = gonio::bench::smooth_downlight(c_step, gamma_step);
  d.opening.shape = OpeningShape::Rectangular;
  d.opening.length_m = d.opening.width_m = 0.6;
  return d;
}

void grids(benchmark::internal::Benchmark* b) { b->Args({1, 1})->Args({5, 5}); }

template <typename F>
void run(benchmark::State& state, F f) {
  const Distribution d = grid(static_cast<double>(state.range(0)), static_cast<double>(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(f(d));
  state.SetLabel(std::to_string(d.horizontal_count()) + "x" + std::to_string(d.vertical_count()));
}

void BM_SummarizeBaseline(benchmark::State& s) { run(s, [](const Distribution& d) { return summarize(d); }); }
void BM_PlanningFigures(benchmark::State& s) { run(s, [](const Distribution& d) { return planning_figures(d); }); }
void BM_UgrTable(benchmark::State& s) { run(s, [](const Distribution& d) { return ugr_table(d); }); }
void BM_CuTable(benchmark::State& s) { run(s, [](const Distribution& d) { return cu_table(d); }); }
void BM_SpacingCriterion(benchmark::State& s) { run(s, [](const Distribution& d) { return spacing_criterion(d); }); }
void BM_BugRating(benchmark::State& s) { run(s, [](const Distribution& d) { return bug_rating(d); }); }
void BM_LuminanceTable(benchmark::State& s) { run(s, [](const Distribution& d) { return luminance_table(d); }); }

BENCHMARK(BM_SummarizeBaseline)->Apply(grids)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanningFigures)->Apply(grids)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UgrTable)->Apply(grids)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CuTable)->Apply(grids)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SpacingCriterion)->Apply(grids)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BugRating)->Apply(grids)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LuminanceTable)->Apply(grids)->Unit(benchmark::kMillisecond);

}  // namespace
