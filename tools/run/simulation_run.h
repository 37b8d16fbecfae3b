// A planned simulation run and the files it leaves: what `gonio simulate`
// and `gonio watch` (tools/cli/simulate_command.h) resolve their options into,
// what the live page shows runs of (tools/live/live_view.h), and the writing of a
// finished run's files and report.json (the code: tools/run/simulation_run.cpp).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/photometric/ies.h"
#include "io/support/cache_folder.h"
#include "sim/preview_filter.h"
#include "sim/resample.h"
#include "tools/run/model_input.h"
#include "tools/run/preview_output.h"
#include "tools/run/progressive_run.h"
#include "tools/run/simulation_outputs.h"

namespace gonio::cli {

// The options checked and resolved.
struct SimulatePlan {
  std::string model;
  std::string out_dir;
  std::string stem;
  sim::CGammaGrid grid;
  std::optional<photometry::Symmetry> symmetry;  // none: auto
  std::vector<OutputFormat> formats;
  bool tm25 = false;  // --format …,tm25: STEM.tm25ray of the escaping photons
  io::IesVersion ies_version = io::IesVersion::LM63_2019;
  bool preview = false;  // write preview.{exr,png} per iteration
  sim::PreviewFilterParams preview_params;
  ProgressiveSettings progressive;
  double min_lor = 0.0;
  double flux_tolerance = 0.005;
  ModelInputOptions model_input;  // the model checks' cache folder
  std::uint64_t cache_limit_bytes = io::kDefaultCacheLimitBytes;  // io/support/cache_folder.h; 0: none
};

// Writes the files and report.json of a finished run into plan.out_dir
// (`preview`: the run's preview output, or null; `start`: when the command or
// the run began, for wall_s; `input_times`: what loading and checking the
// model took; `ranks_report`: report.json's "mpi" object,
// tools/run/distributed_run.h, left out where null), prints the summary, and
// returns the exit code (the energy checks). `failures`: what already failed
// (the preview); a failure while writing does not stop the other files:
// report.json lists what was written and what failed, and the exit code is 1.
int write_run_files(const SimulatePlan& plan, const ProgressiveOutcome& run, const ModelInputTimes& input_times,
                    const PreviewOutput* preview, std::chrono::steady_clock::time_point start,
                    const nlohmann::json& ranks_report = nullptr, std::vector<Error> failures = {});

}  // namespace gonio::cli
