// One CMA-ES stage by pagmo2 (design/optimize_cmaes.h): the only file that
// includes pagmo's headers, built as the module gonio_cmaes.so.
#include "design/optimize_cmaes.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include <pagmo/algorithms/cmaes.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>
#include <pagmo/types.hpp>

namespace gonio::design::detail {
namespace {

// What the problem's fitness does: record the points asked for (the dry run
// of a generation), or look their merits up (the real one).
struct Ledger {
  bool recording = false;
  std::vector<std::vector<double>> asked;
  std::map<std::vector<double>, double> merits;
  const BatchEvaluate* evaluate = nullptr;
  bool stop = false;  // a lookup that missed and whose evaluation said stop
  int missed = 0;     // evaluations made at lookup (none expected)
};

// pagmo's user-defined problem: the unit box, a pointer to the ledger
// (pagmo copies problems; all copies share it).
struct UnitBoxProblem {
  Ledger* ledger = nullptr;
  std::size_t n = 1;
  pagmo::vector_double fitness(const pagmo::vector_double& x) const {
    if (ledger->recording) {
      ledger->asked.push_back(x);
      return {0.0};
    }
    const auto it = ledger->merits.find(x);
    if (it != ledger->merits.end()) return {it->second};
    // Not sampled in the dry run (pagmo changed how it samples): evaluate it
    // alone, still in the order pagmo asks.
    std::vector<double> merits;
    ++ledger->missed;
    if (!(*ledger->evaluate)({x}, &merits)) ledger->stop = true;
    const double m = merits.empty() ? std::numeric_limits<double>::max() : merits.front();
    ledger->merits.emplace(x, m);
    return {m};
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const {
    return {pagmo::vector_double(n, 0.0), pagmo::vector_double(n, 1.0)};
  }
  std::string get_name() const { return "gonio merit"; }
};

// The root-mean-square distance of a generation's points from their mean
// (λ − 1 in the denominator): an estimate of CMA-ES's step σ·√tr C from all
// λ draws, not from one.
double generation_spread(const std::vector<std::vector<double>>& points) {
  if (points.size() < 2) return std::numeric_limits<double>::infinity();
  const std::size_t n = points.front().size();
  std::vector<double> mean(n, 0.0);
  for (const std::vector<double>& p : points)
    for (std::size_t j = 0; j < n; ++j) mean[j] += p[j] / static_cast<double>(points.size());
  double sum = 0.0;
  for (const std::vector<double>& p : points)
    for (std::size_t j = 0; j < n; ++j) sum += (p[j] - mean[j]) * (p[j] - mean[j]);
  return std::sqrt(sum / static_cast<double>(points.size() - 1));
}

}  // namespace

}  // namespace gonio::design::detail

using gonio::design::detail::BatchEvaluate;
using gonio::design::detail::CmaesStage;
using gonio::design::detail::cmaes_population;

extern "C" int gonio_cmaes_module_version() { return gonio::design::detail::kCmaesModuleVersion; }

extern "C" bool gonio_cmaes_run(const CmaesStage* stage_in, const BatchEvaluate* evaluate_in, int* used_out,
                                std::string* error) {
  using namespace gonio::design::detail;
  const CmaesStage& stage = *stage_in;
  const BatchEvaluate& evaluate = *evaluate_in;
  const std::size_t n = stage.start.size();
  const int lambda = stage.population > 0 ? std::max(5, stage.population) : cmaes_population(n);
  Ledger ledger;
  ledger.evaluate = &evaluate;
  int used = 0;
  try {
    // gen 1 per evolve with memory: one generation at a time, the adapted
    // mean, step and covariance kept between calls; ftol 0 (a population of
    // equal merits, as at the start, must not end the stage); the points
    // kept inside the box. xtol 0 too: pagmo 2.18 tests its xtol on the step
    // of the generation's last point alone (one normal draw: with one
    // variable |N(0, 1)| < 1/16 in 5 % of generations), which ended whole
    // stages at random (λ = 12 after the start, λ = 6 after one generation);
    // the stage's xtol is tested below on the generation's spread.
    pagmo::cmaes algorithm(1u, -1.0, -1.0, -1.0, -1.0, stage.sigma, 0.0, 0.0, true, true, stage.seed);
    pagmo::population population{pagmo::problem{UnitBoxProblem{&ledger, n}}, 0u, stage.seed};
    for (int i = 0; i < lambda; ++i) population.push_back(stage.start, {stage.start_merit});
    while (used < stage.budget) {
      // The dry run: the generation's points, as the real run will ask them.
      pagmo::cmaes probe = algorithm;
      pagmo::population dry = population;
      ledger.recording = true;
      ledger.asked.clear();
      dry = probe.evolve(dry);
      ledger.recording = false;
      if (ledger.asked.empty()) break;
      if (generation_spread(ledger.asked) < stage.xtol) break;  // the steps are below the stage's xtol
      std::vector<std::vector<double>> points = ledger.asked;
      const bool cut = static_cast<int>(points.size()) > stage.budget - used;
      if (cut) points.resize(static_cast<std::size_t>(stage.budget - used));
      std::vector<double> merits;
      const bool go = evaluate(points, &merits);
      used += static_cast<int>(points.size());
      if (!go || cut || merits.size() != points.size()) break;
      ledger.merits.clear();
      for (std::size_t i = 0; i < points.size(); ++i) ledger.merits.emplace(points[i], merits[i]);
      population = algorithm.evolve(population);
      used += ledger.missed;
      ledger.missed = 0;
      if (ledger.stop) break;
    }
  } catch (const std::exception& e) {
    *used_out = used;
    *error = std::string("pagmo's CMA-ES: ") + e.what();
    return false;
  }
  *used_out = used;
  return true;
}
