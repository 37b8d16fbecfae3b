// One stage of gonio optimize's CMA-ES (design/optimize.h), by pagmo2's
// pagmo::cmaes (Debian's libpagmo-dev; design/optimize_cmaes.cpp alone
// includes pagmo's headers). Internal to design/optimize.cpp.
//
// libpagmo's static initialisers (Boost.Serialization's registrations) cost
// ~50 ms at every process start that links it, so gonio does not: the stage
// is the module gonio_cmaes.so (design/optimize_cmaes.cpp), which
// design/optimize.cpp loads with dlopen at the first CMA-ES stage, looking
// next to the executable, in ../lib/gonio/, then where the build wrote it
// (as io/outputs/image.cpp loads gonio_png.so). Both sides are built
// together, so C++ types cross; the version guards against a stale module.
//
// pagmo 2.18's cmaes evaluates a generation's points one by one through the
// problem's fitness and has no batch evaluator, but it samples all λ points
// of a generation from its own generator before it evaluates any. So each
// generation is first sampled on a copy of the algorithm and population (a
// fitness that records the points asked for), the points are handed to
// `evaluate` at once (which may trace them in parallel), and the generation
// is then run for real with the merits looked up: the points, their order and
// so the whole run are those of a plain sequential run, for any split of the
// evaluations over threads.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::design::detail {

struct CmaesStage {
  std::vector<double> start;  // in [0, 1]^n: the mean of the first generation
  double start_merit = 0.0;   // its merit (the population starts as λ copies of it)
  double sigma = 0.25;        // the first step, in units of each variable's range
  double xtol = 0.25 / 16.0;  // stop when a generation's step falls below this
  int budget = 100;           // evaluations at most (a last generation is cut short)
  int population = 0;         // λ; 0: cmaes_population(n)
  unsigned seed = 1;          // of pagmo's generator (the sampling)
};

// The merits of `points` (each in [0, 1]^n), in order, into `merits`; a
// failed evaluation as a bad but finite merit. False: stop now.
using BatchEvaluate = std::function<bool(const std::vector<std::vector<double>>& points, std::vector<double>* merits)>;

// Hansen's default population, 4 + ⌊3 ln n⌋, at least pagmo's 5.
inline int cmaes_population(std::size_t n) {
  return std::max(5, 4 + static_cast<int>(std::floor(3.0 * std::log(static_cast<double>(std::max<std::size_t>(n, 1))))));
}

// Runs the stage (through the module): the evaluations used, or pagmo's
// error, or why the module could not be loaded.
Result<int> run_cmaes_stage(const CmaesStage& stage, const BatchEvaluate& evaluate);

inline constexpr int kCmaesModuleVersion = 1;
inline constexpr const char* kCmaesModuleName = "gonio_cmaes.so";

}  // namespace gonio::design::detail

extern "C" {
// kCmaesModuleVersion of the module.
int gonio_cmaes_module_version();
// The stage: the evaluations used into `used`; false and `error` set where
// pagmo failed.
bool gonio_cmaes_run(const gonio::design::detail::CmaesStage* stage,
                     const gonio::design::detail::BatchEvaluate* evaluate, int* used, std::string* error);
}
