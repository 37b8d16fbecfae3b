// What `gonio simulate` and `gonio watch` share on the command line: the
// simulation's options (tools/run/simulate.h's SimulateOptions) registered on
// a parser, the plan or a usage error, and what is printed once a run's
// files are written (tools/cli/simulate_command.cpp).
#pragma once

#include <optional>
#include <string>

#include "tools/cli/cli.h"
#include "tools/run/simulate.h"

namespace gonio::cli {

// Registers every option but MODEL and --out (callers word those).
void add_simulate_options(ArgParser& p, app::SimulateOptions* options);

// Prints "gonio: COMMAND: message" and the usage line to stderr.
void print_usage_error(const std::string& command, const ArgParser& p, const std::string& message);

// The plan of `options` for `model`, or nothing after print_usage_error
// (exit kExitUsage).
std::optional<app::SimulatePlan> plan_or_usage(const std::string& command, const std::string& model,
                                               const app::SimulateOptions& options, const ArgParser& p);

// Prints what a finished run wrote (the ledger, the LOR, every file with its
// flux read back, report.json; each failure and failed energy check on
// stderr) and returns the exit code: 1 where a file or report.json could not
// be written or an energy check failed, else 0.
int print_run_files(const app::SimulatePlan& plan, const app::ProgressiveOutcome& run, const app::RunFiles& files);

}  // namespace gonio::cli
