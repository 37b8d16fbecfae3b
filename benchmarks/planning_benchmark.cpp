// The light-planning figures of one file (photometry/planning.h), each and
// all together, against summarize() — what `gonio info` computed before
// them — on the same grids: the ratio is the cost they add per file.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <string>

#include "photometry/planning.h"
#include "photometry/summary.h"

namespace {

using namespace gonio::photometry;

std::vector<double> steps(double from, double to, double step) {
  std::vector<double> out;
  const long n = std::lround((to - from) / step);
  for (long i = 0; i <= n; ++i) out.push_back(from + static_cast<double>(i) * step);
  return out;
}

// A smooth asymmetric downlight with some uplight, full C 0..360, with a
// 0.6 × 0.6 m opening.
Distribution grid(double c_step, double gamma_step) {
  Distribution d;
  d.symmetry = Symmetry::None;
  d.horizontal_deg = steps(0, 360, c_step);
  d.vertical_deg = steps(0, 180, gamma_step);
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg) {
      const double cg = std::cos(g * std::numbers::pi / 180), cc = std::cos(c * std::numbers::pi / 180);
      d.candela.push_back(cg > 0 ? 1000 * std::pow(cg, 4) * (1 + 0.3 * cc * cc) : 40 * -cg);
    }
  d.lamps = {LampSet{1, "LED", 5000.0, "", "", 40.0}};
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
