// gonio tolerance as a library function (issue 42, docs/tolerance.md): what
// the command (tools/cli/cmd_tolerance.cpp) and the Python module's
// gonio.tolerance both call. Every trace is app::simulate on the model with
// the tolerances applied to the loaded scene (SimulateHooks::adjust_scene),
// all with the same seed (common random numbers). The nominal is traced
// again with K other seeds for the noise floor; then each tolerance alone at
// its limits (sensitivity), and N Monte Carlo trials with all of them drawn
// at once from a Latin hypercube. DIR gets report.json (every trace's
// parameters and figures), sensitivity.txt, tornado_FIGURE.svg,
// nominal.ies/.ldt, the best and worst trials' IES and LDT, and those of the
// trials at the --percentile choices (pP_FIGURE.ies/.ldt).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "photometry/diagnostics.h"
#include "sim/distributed.h"
#include "tools/run/console.h"
#include "tools/run/simulate.h"

namespace gonio::app {

struct ToleranceRunOptions {
  std::string model, tolerances_path, out_dir;
  std::string spec_text;  // FIGURE=LO..HI,… (empty: none)
  std::string percentile_text;  // P or FIGURE:P,…: the trials at those percentiles written as IES/LDT (empty: none)
  long long trials = 20, noise_seeds = 3, sampling_seed = 1, bins = 10;
  long long inverse_steps = 4;
  long long parallel_trials = 1;  // Monte Carlo trials traced at once (threads; each with simulate.threads)
  bool resume = false;            // read DIR/journal.jsonl back and trace only what it lacks  // bisection steps of the traced inverse sensitivity (0: the linear estimate alone)
  SimulateOptions simulate;  // photons, seed, c_step, gamma_step for report.json (the plan's own)
  // The MPI job this process is a rank of (null: one process). Each trace
  // runs in one rank; the traces are split over the ranks and rank 0 writes
  // DIR (docs/tolerance.md, "Trials over MPI ranks"). Every rank calls
  // tolerance_analysis with the same options.
  const sim::Ranks* ranks = nullptr;
};

struct ToleranceRunHooks {
  std::function<void(const std::string&)> on_output;   // progress lines and the sensitivity table
  std::function<void(const std::string&)> on_warning;  // a tornado chart not drawn
  MessageSink on_message;                              // the model's messages (first trace) and errors
};

struct ToleranceRunOutcome {
  nlohmann::json report;  // report.json as written
  nlohmann::json timing;  // timing.json: seconds per trace
  std::string report_path;
  std::string table;      // sensitivity.txt
  bool lead = true;       // false on MPI ranks other than 0: they traced their share and wrote nothing
};

// Runs gonio tolerance with `plan` (app::plan_simulation of options.model
// and options.simulate). Errors name the file (and line); where `usage` is
// given, a mistake of the options sets it true (the command's exit 2).
Result<ToleranceRunOutcome> tolerance_analysis(const ToleranceRunOptions& options, const SimulatePlan& plan,
                                               const ToleranceRunHooks& hooks, bool* usage = nullptr);

}  // namespace gonio::app
