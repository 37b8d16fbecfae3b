// gonio optimize as a library function (docs/design.md "Optimisation";
// docs/commands/optimize.md): what the command (tools/cli/cmd_optimize.cpp)
// and the Python module's gonio.optimize both call. Every evaluation is one
// app::simulate of the design at the variables' values (written to
// DIR/.evaluation.design.toml beside copies of the emitters' files), keeping
// the escaped photons, whose merit design/merit.h computes; design/optimize.h
// drives NLopt over them. DIR gets the best design (NAME.design.toml), its
// trace with an independent seed (NAME.ies, NAME.ldt, report.json with an
// "optimize" section) and history.json.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "design/merit.h"
#include "design/optimize.h"
#include "photometry/diagnostics.h"
#include "tools/run/simulate.h"

namespace gonio::app {

struct OptimizeRunOptions {
  std::string design_path, target_path, out_dir, name;  // name: default the design file's
  design::OptimizeMethod method = design::OptimizeMethod::Bobyqa;
  long long max_evals = 200, stages = 3, seed = 1, threads = 0, final_photons = 1'000'000;
  // CMA-ES: evaluations of a generation traced at a time (0: one per core;
  // each trace then gets threads / jobs threads where threads is 0) and the
  // population (0: pagmo's default for the variables); the run is the same
  // for any jobs.
  long long jobs = 0, population = 0;
  std::optional<double> photons_per_bin;
  double gamma_step = 1.0, max_time = 0.0;
  bool no_smooth = false;
  bool no_step = false;           // no NAME.step (and its sidecar) of the best design
  bool no_common_random = false;  // each evaluation its own seed (for comparison)
  std::optional<std::string> scan;  // VAR:N: the merit across VAR's bounds, no optimisation
  // A [merit] table that replaces the design's (Python's merit=): its errors
  // name "DESIGN (merit=)" and the key, not a line.
  std::optional<io::TomlNode> merit;
  // evaluate_only: no optimisation, no file but the evaluation's: the merit
  // at each of `evaluate` (the variables' values in the design's order), each
  // traced with `seed` (common random numbers) and evaluate_photons (0: the
  // first stage's); OptimizeRunOutcome::merits (gonio.Merit).
  bool evaluate_only = false;
  std::vector<std::vector<double>> evaluate;
  std::uint64_t evaluate_photons = 0;
  // The MPI job to run on (gonio optimize under mpirun; null: this process
  // alone). Every rank calls optimize_design with the same options: a
  // one-point evaluation's photons are shared by the ranks as gonio simulate
  // shares them, a CMA-ES generation's points are dealt to the ranks (point i
  // to rank i mod K, then put back in the points' order), and rank 0 alone
  // writes the files; the same history and best design for any rank count.
  const sim::Ranks* ranks = nullptr;
};

struct OptimizeRunHooks {
  // Once the merit is set up: the variables, the grid's nodes and stage 1's photons.
  std::function<void(const std::vector<design::OptimizeVariable>&, const design::MeritSpec&, std::size_t nodes,
                     std::uint64_t start_photons)>
      on_start;
  // After each evaluation (the noise floor's too); false stops (the best is kept).
  std::function<bool(const design::EvaluationRecord&)> on_evaluation;
  // --scan: each value's merit (NaN and the error where it failed).
  std::function<void(const std::string& variable, double value, double merit, const std::string& error)> on_scan;
  // The final trace's messages (not its errors).
  std::function<void(Severity, const std::string&)> on_message;
};

struct OptimizeRunOutcome {
  std::vector<design::OptimizeVariable> variables;  // as in the design (start values)
  design::OptimizeResult run;
  design::MeritValue final_merit;
  double final_estimated_error_pct = 0.0;  // the final trace's estimated RMS error [%]
  std::optional<SimulatePlan> plan;      // the final trace's
  std::optional<SimulateResult> result;  // its files (result->files) and run
  nlohmann::json report;                 // report.json as written (its "optimize" section)
  nlohmann::json history;                // history.json as written
  std::string best_path, history_path;
  // The best design's other files (NAME.gltf, NAME.step, history.svg,
  // compare.json, compare.svg), and why one is missing (not an error).
  std::vector<std::string> extra_files;
  std::vector<std::string> notes;
  bool scanned = false;                  // --scan or evaluate: no optimisation
  std::vector<design::MeritValue> merits;  // evaluate: the merit at each
  std::uint64_t evaluate_photons = 0;      // evaluate: the photons of each trace
  // Under MPI: false on the ranks other than 0, which write nothing and
  // hold only `variables`, `run` and `cannot_improve`.
  bool lead = true;
  // Why the run cannot improve the design (empty: it can): the reason, and
  // its kind, "no_improvement" (no evaluation bettered the start),
  // "pinned" (every variable of the best at a bound) or "flat" (the merit
  // within its noise floor everywhere stage 1 looked); report.json's
  // optimize.cannot_improve and cannot_improve_kind.
  std::string cannot_improve, cannot_improve_kind;
};

// One evaluation as history.json holds it: index, stage (1-based, or
// "noise"), merit, best, photons, seed, time_s, values {name: value}, error.
nlohmann::json evaluation_json(const design::EvaluationRecord& record,
                               const std::vector<design::OptimizeVariable>& variables);

// history.svg: the merit and the best so far against the evaluations, and
// the best against the wall time (the noise floor's traces as points).
Status write_history_chart(const std::string& path, const std::vector<design::EvaluationRecord>& history,
                           const std::string& title);

// Runs gonio optimize. Errors name the file (and line); where `usage` is
// given, a mistake of the options sets it true (the command's exit 2).
Result<OptimizeRunOutcome> optimize_design(const OptimizeRunOptions& options, const OptimizeRunHooks& hooks,
                                           std::chrono::steady_clock::time_point start, bool* usage = nullptr);

}  // namespace gonio::app
