#include "design/optimize.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <thread>

#include <nlopt.hpp>

#include "design/optimize_cmaes.h"
#include "io/support/process.h"
#include "photometry/format.h"

#ifndef GONIO_CMAES_MODULE_BUILD_PATH
#define GONIO_CMAES_MODULE_BUILD_PATH ""
#endif

namespace gonio::design {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// What the objective needs, through NLopt's void*.
struct Stage {
  const std::vector<OptimizeVariable>* variables = nullptr;
  const MeritFunction* merit = nullptr;
  const std::function<bool(const EvaluationRecord&)>* on_evaluation = nullptr;
  OptimizeResult* result = nullptr;
  nlopt::opt* opt = nullptr;
  std::chrono::steady_clock::time_point start;
  int stage = 0;
  std::uint64_t photons = 0, seed = 0;
  double best = std::numeric_limits<double>::infinity();
  double best_violation = std::numeric_limits<double>::infinity();
  std::vector<double> best_values;
  const OptimizeOptions* options = nullptr;
  std::uint64_t last_seed = 0;  // the seed of the last evaluation (the constraints' trace)
  double failed_merit = 0.0;  // what a failed evaluation counts as
  double max_time_s = 0.0;
  bool cancelled = false, out_of_time = false;
  bool common_random = true;
  // The seed of the evaluation `ahead` evaluations after the last recorded.
  std::uint64_t seed_of(int ahead) const {
    return common_random ? seed : fresh_seed(seed, result->evaluations + 1 + ahead);
  }
};

std::vector<double> values_of(const std::vector<OptimizeVariable>& v, const double* x) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    out[i] = std::clamp(v[i].min + std::clamp(x[i], 0.0, 1.0) * (v[i].max - v[i].min), v[i].min, v[i].max);
  return out;
}

// The record of one evaluation whose merit is `m` (index and time at the
// moment it is recorded).
EvaluationRecord make_record(Stage& s, const std::vector<double>& values, std::uint64_t seed, int stage,
                             const Result<double>& m) {
  EvaluationRecord r;
  r.index = static_cast<int>(s.result->history.size()) + 1;
  r.stage = stage;
  r.values = values;
  r.photons = s.photons;
  r.seed = seed;
  if (m.ok() && std::isfinite(*m)) {
    r.merit = *m;
  } else {
    r.merit = kNaN;
    r.error = m.ok() ? "the merit is not finite" : m.error().message;
  }
  r.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - s.start).count();
  if (s.options != nullptr && s.options->elapsed) r.time_s = s.options->elapsed(r.time_s);
  return r;
}

Result<double> call_merit(const Stage& s, const std::vector<double>& values, std::uint64_t seed) {
  try {
    return (*s.merit)(values, s.photons, seed);
  } catch (const std::exception& e) {
    return make_error(std::string("the evaluation failed: ") + e.what());
  }
}

// The largest of the hard limits' values (> 0: a limit broken) of the
// evaluation's own trace; 0 without limits.
void add_violation(const Stage& s, EvaluationRecord& r) {
  if (!std::isfinite(r.merit) || s.options == nullptr || s.options->constraint_count == 0) return;
  for (double c : s.options->constraints(r.values, s.photons, r.seed))
    r.violation = std::max(r.violation, std::isfinite(c) ? c : 1.0);
}

EvaluationRecord evaluate(Stage& s, const std::vector<double>& values, std::uint64_t seed, int stage) {
  EvaluationRecord r = make_record(s, values, seed, stage, call_merit(s, values, seed));
  add_violation(s, r);
  return r;
}

// A stage's evaluation into the run: the stage's best, the history, the
// callback (false: cancelled), the time limit; what the method is given
// (a failed evaluation as a merit worse than any seen).
double account(Stage& s, EvaluationRecord r) {
  // The best: the least violation of the hard limits first, then the merit.
  if (std::isfinite(r.merit) && (r.violation < s.best_violation || (r.violation == s.best_violation && r.merit < s.best))) {
    s.best = r.merit;
    s.best_violation = r.violation;
    s.best_values = r.values;
  }
  r.best = s.best;
  s.result->history.push_back(r);
  ++s.result->evaluations;
  if (s.result->evaluations == 1) s.result->start_merit = r.merit;
  if (*s.on_evaluation && !s.cancelled && !(*s.on_evaluation)(r)) s.cancelled = true;
  if (s.max_time_s > 0.0 && r.time_s >= s.max_time_s) s.out_of_time = true;
  if (std::isfinite(r.merit)) {
    s.failed_merit = std::max(s.failed_merit, 2.0 * r.merit + 1.0);
    return r.merit;
  }
  return s.failed_merit > 0.0 ? s.failed_merit : 1e6;
}

double objective(unsigned n, const double* x, double* /*grad*/, void* data) {
  Stage& s = *static_cast<Stage*>(data);
  (void)n;
  s.last_seed = s.seed_of(0);
  const double m = account(s, evaluate(s, values_of(*s.variables, x), s.last_seed, s.stage));
  if (s.cancelled || s.out_of_time) s.opt->force_stop();
  return m;
}

// The hard limits for COBYLA: the values the objective's trace gave.
void constraints(unsigned m, double* result, unsigned /*n*/, const double* x, double* /*grad*/, void* data) {
  Stage& s = *static_cast<Stage*>(data);
  const std::vector<double> c = s.options->constraints(values_of(*s.variables, x), s.photons, s.last_seed);
  for (unsigned k = 0; k < m; ++k) result[k] = k < c.size() && std::isfinite(c[k]) ? c[k] : 1.0;
}

// A CMA-ES generation: the points traced `jobs` at a time (each thread takes
// the next point not taken), then recorded in the points' order, so that
// the history and the best do not depend on `jobs`. False: stop.
bool evaluate_batch(Stage& s, const std::vector<std::vector<double>>& points, std::vector<double>* merits, int jobs) {
  std::vector<std::vector<double>> values;
  for (const std::vector<double>& x : points) values.push_back(values_of(*s.variables, x.data()));
  std::vector<std::optional<Result<double>>> results(points.size());
  std::vector<std::uint64_t> seeds;
  for (std::size_t i = 0; i < points.size(); ++i) seeds.push_back(s.seed_of(static_cast<int>(i)));
  if (s.options != nullptr && s.options->batch) {  // evaluated elsewhere (MPI ranks)
    std::vector<Result<double>> made = s.options->batch(values, s.photons, seeds);
    for (std::size_t i = 0; i < values.size(); ++i)
      results[i].emplace(i < made.size() ? made[i] : Result<double>(make_error("the evaluation was not made")));
  }
  std::atomic<std::size_t> next{s.options != nullptr && s.options->batch ? values.size() : 0};
  const auto work = [&] {
    for (std::size_t i = next++; i < values.size(); i = next++) results[i].emplace(call_merit(s, values[i], seeds[i]));
  };
  const std::size_t helpers = std::min<std::size_t>(static_cast<std::size_t>(std::max(jobs, 1)), values.size());
  std::vector<std::thread> threads;
  for (std::size_t t = 1; t < helpers; ++t) threads.emplace_back(work);
  work();
  for (std::thread& t : threads) t.join();
  merits->clear();
  for (std::size_t i = 0; i < values.size(); ++i)
    merits->push_back(account(s, make_record(s, values[i], seeds[i], s.stage, *results[i])));
  return !s.cancelled && !s.out_of_time;
}

// gonio_cmaes.so's entry point, or why it could not be loaded (once per
// process, at the first CMA-ES stage; the handle stays open).
struct CmaesModule {
  decltype(&gonio_cmaes_run) run = nullptr;
  std::string error;
};

CmaesModule load_cmaes_module() {
  CmaesModule m;
  std::string tried;
  for (const std::string& path : io::beside_executable(detail::kCmaesModuleName, GONIO_CMAES_MODULE_BUILD_PATH)) {
    tried += (tried.empty() ? "" : ", ") + path;
    if (access(path.c_str(), R_OK) != 0) continue;
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      m.error = "cannot load the CMA-ES module " + path + ": " + (why ? why : "unknown error");
      return m;
    }
    auto version = reinterpret_cast<decltype(&gonio_cmaes_module_version)>(dlsym(handle, "gonio_cmaes_module_version"));
    m.run = reinterpret_cast<decltype(&gonio_cmaes_run)>(dlsym(handle, "gonio_cmaes_run"));
    if (!version || !m.run || version() != detail::kCmaesModuleVersion) {
      m.run = nullptr;
      m.error = "the CMA-ES module " + path + " is not the one this gonio was built with";
    }
    return m;
  }
  m.error = std::string("the CMA-ES module ") + detail::kCmaesModuleName + " (pagmo2) is missing; looked for " + tried;
  return m;
}

}  // namespace

bool takes_constraints(OptimizeMethod method) { return method == OptimizeMethod::Cobyla; }

namespace detail {

Result<int> run_cmaes_stage(const CmaesStage& stage, const BatchEvaluate& evaluate) {
  static const CmaesModule module = load_cmaes_module();
  if (!module.run) return make_error(module.error);
  int used = 0;
  std::string error;
  if (!module.run(&stage, &evaluate, &used, &error)) return make_error(error);
  return used;
}

}  // namespace detail

std::uint64_t fresh_seed(std::uint64_t seed, int k) {
  return seed + 2'000'000'011ULL + 7'919ULL * static_cast<std::uint64_t>(k);
}

std::optional<OptimizeMethod> parse_optimize_method(const std::string& name) {
  if (name == "bobyqa") return OptimizeMethod::Bobyqa;
  if (name == "cobyla") return OptimizeMethod::Cobyla;
  if (name == "neldermead") return OptimizeMethod::NelderMead;
  if (name == "cmaes") return OptimizeMethod::Cmaes;
  return std::nullopt;
}

const char* to_string(OptimizeMethod method) {
  switch (method) {
    case OptimizeMethod::Bobyqa: return "bobyqa";
    case OptimizeMethod::Cobyla: return "cobyla";
    case OptimizeMethod::NelderMead: return "neldermead";
    case OptimizeMethod::Cmaes: return "cmaes";
  }
  return "bobyqa";
}

Result<OptimizeResult> optimize(const std::vector<OptimizeVariable>& variables, const MeritFunction& merit,
                                const OptimizeOptions& options,
                                const std::function<bool(const EvaluationRecord&)>& on_evaluation) {
  if (variables.empty()) return make_error("the design has no variables to optimise");
  for (const OptimizeVariable& v : variables)
    if (!(std::isfinite(v.min) && std::isfinite(v.max) && v.min < v.max && v.value >= v.min && v.value <= v.max))
      return make_error("variable '" + v.name + "': the optimiser needs min < max with the value between them");
  if (options.stages < 1 || options.max_evaluations < 1 || options.start_photons < 1 || options.noise_seeds < 2)
    return make_error("the optimiser needs at least one stage, one evaluation, one photon and two noise seeds");
  const std::size_t n = variables.size();
  const OptimizeMethod method = options.method;

  OptimizeResult result;
  Stage s;
  s.variables = &variables;
  s.merit = &merit;
  s.on_evaluation = &on_evaluation;
  s.result = &result;
  s.start = std::chrono::steady_clock::now();
  s.seed = options.seed;
  s.max_time_s = options.max_time_s;
  s.common_random = options.common_random;
  s.options = &options;
  if (options.constraint_count > 0 && (!takes_constraints(method) || !options.constraints))
    return make_error(std::string("hard limits as constraints need a method that takes them (cobyla), not ") +
                      to_string(method));
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = (variables[i].value - variables[i].min) / (variables[i].max - variables[i].min);
  result.stopped_by = "converged";
  for (int stage = 0; stage < options.stages; ++stage) {
    const int left = options.max_evaluations - result.evaluations;
    if (left <= 0) {
      result.stopped_by = "evaluations";
      break;
    }
    const int share = std::max(1, left / (options.stages - stage));
    const double step = 0.25 / std::pow(2.0, stage);
    s.stage = stage;
    s.photons = options.start_photons << (2 * stage);
    s.best = std::numeric_limits<double>::infinity();
    s.best_violation = std::numeric_limits<double>::infinity();
    s.best_values.clear();
    if (method == OptimizeMethod::Cmaes) {
      // The start evaluated at this stage's photons, then generations of λ
      // points around the best so far with a first step of `step`.
      s.opt = nullptr;
      const double start_merit = account(s, evaluate(s, values_of(variables, x.data()), s.seed_of(0), stage));
      if (!s.cancelled && !s.out_of_time && share > 1) {
        detail::CmaesStage c;
        c.start = x;
        c.start_merit = start_merit;
        c.sigma = step;
        c.xtol = step / 16.0;
        c.budget = share - 1;
        c.population = options.population;
        c.seed = static_cast<unsigned>((options.seed + static_cast<std::uint64_t>(stage)) & 0xffffffffu);
        const int jobs = std::max(options.jobs, 1);
        Result<int> used = detail::run_cmaes_stage(
            c, [&](const std::vector<std::vector<double>>& points, std::vector<double>* merits) {
              return evaluate_batch(s, points, merits, jobs);
            });
        if (!used.ok() && s.best_values.empty()) return used.error();
        if (used.ok() && *used >= c.budget && stage + 1 == options.stages) result.stopped_by = "evaluations";
      } else if (share <= 1 && stage + 1 == options.stages) {
        result.stopped_by = "evaluations";
      }
    } else {
      const nlopt::algorithm algorithm = method == OptimizeMethod::Cobyla       ? nlopt::LN_COBYLA
                                         : method == OptimizeMethod::NelderMead ? nlopt::LN_NELDERMEAD
                                                                                : nlopt::LN_BOBYQA;
      nlopt::opt opt(algorithm, static_cast<unsigned>(n));
      opt.set_lower_bounds(std::vector<double>(n, 0.0));
      opt.set_upper_bounds(std::vector<double>(n, 1.0));
      std::vector<double> steps(n);
      for (std::size_t i = 0; i < n; ++i) steps[i] = std::min(step, std::max(x[i], 1.0 - x[i]) * 0.999);
      opt.set_initial_step(steps);
      opt.set_xtol_abs(step / 16.0);
      opt.set_maxeval(share);
      s.opt = &opt;
      opt.set_min_objective(objective, &s);
      if (options.constraint_count > 0)
        opt.add_inequality_mconstraint(constraints, &s, std::vector<double>(options.constraint_count, 0.0));
      double value = 0.0;
      std::vector<double> start = x;
      try {
        const nlopt::result r = opt.optimize(start, value);
        if (r == nlopt::MAXEVAL_REACHED && stage + 1 == options.stages) result.stopped_by = "evaluations";
      } catch (const nlopt::forced_stop&) {
      } catch (const nlopt::roundoff_limited&) {
      } catch (const std::exception& e) {
        if (s.best_values.empty()) return make_error(std::string("NLopt: ") + e.what());
      }
      s.opt = nullptr;
    }
    if (s.best_values.empty()) {
      if (s.cancelled) return make_error("cancelled before any evaluation succeeded");
      std::string why = result.history.empty() ? "" : result.history.back().error;
      return make_error("no evaluation of stage " + std::to_string(stage + 1) + " succeeded" +
                        (why.empty() ? "" : ": " + why));
    }
    result.best_values = s.best_values;
    result.best_merit = s.best;
    result.final_photons = s.photons;
    for (std::size_t i = 0; i < n; ++i)
      x[i] = (s.best_values[i] - variables[i].min) / (variables[i].max - variables[i].min);
    if (s.cancelled) {
      result.stopped_by = "cancelled";
      return result;
    }
    if (s.out_of_time) {
      result.stopped_by = "time";
      break;
    }
  }
  // The noise floor: the best traced again with independent seeds.
  std::vector<double> merits;
  for (int k = 0; k < options.noise_seeds; ++k) {
    const std::uint64_t seed = options.seed + 1'000'003ULL * static_cast<std::uint64_t>(k + 1);
    EvaluationRecord r = evaluate(s, result.best_values, seed, -1);
    r.best = result.best_merit;
    result.history.push_back(r);
    if (on_evaluation && !on_evaluation(r)) {
      result.stopped_by = "cancelled";
      break;
    }
    if (std::isfinite(r.merit)) merits.push_back(r.merit);
  }
  result.independent_merit = merits.empty() ? kNaN : merits.front();
  if (merits.size() >= 2) {
    double mean = 0.0, var = 0.0;
    for (double m : merits) mean += m / static_cast<double>(merits.size());
    for (double m : merits) var += (m - mean) * (m - mean) / static_cast<double>(merits.size() - 1);
    result.noise_floor = std::sqrt(var);
  } else {
    result.noise_floor = kNaN;
  }
  return result;
}

}  // namespace gonio::design
