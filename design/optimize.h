// Optimisation of a design's variables toward a merit (gonio optimize,
// docs/design.md "Optimisation"), by NLopt's methods (design/optimize.cpp
// alone includes nlopt.hpp): BOBYQA (bounded, derivative-free, quadratic
// models in a trust region), COBYLA (linear models; takes constraints) or
// Nelder–Mead (a simplex); or by pagmo2's CMA-ES (design/optimize_cmaes.cpp
// alone includes pagmo's headers), a population of λ points a generation
// whose evaluations run `jobs` at a time, with the same run for any `jobs`.
//
// The variables are searched in [0, 1] each (their bounds mapped), in stages:
// stage s traces start_photons · 4^s photons with one seed for every
// evaluation (common random numbers: the merit is a deterministic function
// of the variables within a stage), starting from the best so far with an
// initial step of 0.25 / 2^s of each range and ending when a step falls
// below a sixteenth of that (NLopt's xtol) or the stage's share of the
// evaluations is spent: a photon budget that grows as the steps shrink. The
// best of the last stage is then traced with `noise_seeds` independent seeds
// at the last stage's photons: the spread of those merits is the merit's
// noise floor, the first the best design's merit with an independent seed.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::design {

struct OptimizeVariable {
  std::string name;
  double value = 0.0, min = 0.0, max = 1.0;
};

enum class OptimizeMethod { Bobyqa, Cobyla, NelderMead, Cmaes };
// "bobyqa", "cobyla", "neldermead", "cmaes".
std::optional<OptimizeMethod> parse_optimize_method(const std::string& name);
const char* to_string(OptimizeMethod method);

// Whether a method takes hard limits as NLopt inequality constraints
// (COBYLA); the others get them as penalties in the merit (design/merit.h).
bool takes_constraints(OptimizeMethod method);

// The hard limits' values c_k at an evaluation (c_k ≤ 0: within the limit),
// for the same values, photons and seed as the merit's call just before (a
// caller may keep that trace's values rather than trace again).
using ConstraintFunction = std::function<std::vector<double>(const std::vector<double>& values,
                                                             std::uint64_t photons, std::uint64_t seed)>;

struct OptimizeOptions {
  OptimizeMethod method = OptimizeMethod::Bobyqa;
  int max_evaluations = 200;  // all stages together, the noise floor's traces not counted
  int stages = 3;
  std::uint64_t start_photons = 10'000;
  std::uint64_t seed = 1;
  int noise_seeds = 4;        // ≥ 2
  double max_time_s = 0.0;    // > 0: no stage evaluation starts after this [s]; the noise
                              // floor's traces still run
  // Hard limits (takes_constraints(method) only; else leave 0): the best is
  // then the least violation first (0 within every limit), the merit second.
  std::size_t constraint_count = 0;
  ConstraintFunction constraints;
  int jobs = 1;               // CMA-ES: evaluations of a generation at a time (threads calling
                              // `merit` at once, which must then be safe to call so); the
                              // NLopt methods evaluate one at a time
  int population = 0;         // CMA-ES's λ; 0: 4 + ⌊3 ln n⌋, at least 5
  bool common_random = true;  // false: evaluation k traces the photons of its own seed
                              // (fresh_seed), not the run's: for comparison only
  // CMA-ES: a generation's evaluations made elsewhere (over the ranks of an
  // MPI job, tools/run/optimize_run.cpp): the merits of `values`, each traced
  // with `photons` and its seed, in the points' order. None: `jobs` threads
  // call `merit`.
  std::function<std::vector<Result<double>>(const std::vector<std::vector<double>>& values, std::uint64_t photons,
                                            const std::vector<std::uint64_t>& seeds)>
      batch;
  // The time since the optimisation began as the whole run agrees on it,
  // given this process's [s] (over MPI ranks: rank 0's, so that --max-time
  // stops every rank at the same evaluation). Called once per evaluation by
  // every process in the same order. None: this process's.
  std::function<double(double)> elapsed;
};

// The seed of the k-th evaluation (1-based) where common random numbers are
// off: distinct for every k, and from the run's seed and the noise floor's.
std::uint64_t fresh_seed(std::uint64_t seed, int k);

// One evaluation's merit; an error (the design cannot be built or traced at
// these values) counts as a bad merit, told once in the record.
using MeritFunction =
    std::function<Result<double>(const std::vector<double>& values, std::uint64_t photons, std::uint64_t seed)>;

struct EvaluationRecord {
  int index = 0;  // 1-based over the run
  int stage = 0;  // 0-based; −1: the noise floor's traces
  std::vector<double> values;
  double merit = 0.0;  // NaN where the evaluation failed
  double best = 0.0;   // the stage's best so far
  std::uint64_t photons = 0, seed = 0;
  double time_s = 0.0;  // since the optimisation began
  std::string error;    // why it failed
  double violation = 0.0;  // the largest c_k above 0 of the hard limits (0: within, or none)
};

struct OptimizeResult {
  std::vector<double> best_values;
  double best_merit = 0.0;          // the last stage's best, at its seed
  double independent_merit = 0.0;   // the best traced with the first independent seed
  double noise_floor = 0.0;         // standard deviation of the merit over the independent seeds
  double start_merit = 0.0;         // the first evaluation's (stage 1; BOBYQA moves a start
                                    // closer to a bound than its first step away from it)
  int evaluations = 0;              // of the stages
  std::uint64_t final_photons = 0;
  std::vector<EvaluationRecord> history;
  std::string stopped_by;           // "converged", "evaluations", "time", "cancelled"
};

// Minimises `merit` over the variables (each with min < max and value inside).
// `on_evaluation` after each one; false stops at once (the best so far is
// kept). Errors: no variables, bad bounds, every evaluation of the first
// stage failed, NLopt's own failure.
Result<OptimizeResult> optimize(const std::vector<OptimizeVariable>& variables, const MeritFunction& merit,
                                const OptimizeOptions& options,
                                const std::function<bool(const EvaluationRecord&)>& on_evaluation = {});

}  // namespace gonio::design
