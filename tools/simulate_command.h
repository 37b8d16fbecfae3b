// What `gonio simulate` and `gonio watch` share: the simulation's options,
// their checks, and the files and report of a finished run (the code lives in
// tools/cmd_simulate.cpp; watch runs the same steps per model change).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/support/cache_folder.h"
#include "io/photometric/ies.h"
#include "sim/next_event.h"
#include "sim/preview_filter.h"
#include "sim/resample.h"
#include "tools/cli.h"
#include "tools/model_input.h"
#include "tools/preview_output.h"
#include "tools/progressive_run.h"
#include "tools/simulation_outputs.h"

namespace gonio::cli {

// The options as parsed (defaults as `gonio simulate --help` states them).
struct SimulateOptions {
  std::string out_dir;
  long long photons = 1'000'000, iterations = 10, seed = 1, threads = 0, max_bounces = 100;
  long long face_size = 0;
  double c_step = 5.0, gamma_step = 2.5, min_lor = 0.0, flux_tolerance = 0.005;
  double target_error_pct = 0.0;  // --target-error PCT; 0: none
  std::string symmetry_name = "auto", format_list = "all", ies_version = "2019", stem;
  std::string bvh_quality = "auto";  // --bvh-quality
  long long tm25_rays = 1'000'000;   // --tm25-rays N: the ray file's photons
  std::string near_field;            // --near-field D1,D2,… [m]; empty: none
  std::string sampler = "sobol";     // --sampler (sim/sampler.h)
  std::string next_event = "auto";   // --next-event auto|on|off (sim/next_event.h)
  long long connections = sim::kDefaultConnections;  // --connections M
  std::string luminance_images;      // --luminance-image C:g[,C:g…] or ugr; empty: none
  std::string cache_dir;  // --cache DIR (the model checks' results, the outputs' resamplers)
  bool no_cache = false;  // --no-cache
  long long cache_limit_mb = io::kDefaultCacheLimitBytes >> 20;  // --cache-limit MB; 0: none
  ModelInputOptions model_input;  // --allow-outside-paths
  PreviewOptions preview;
};

// Registers every option but MODEL and --out (callers word those).
void add_simulate_options(ArgParser& p, SimulateOptions* options);

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

// Checks the options for `model`; on a problem prints "COMMAND: …" and the
// usage line to stderr and returns nothing (exit kExitUsage).
std::optional<SimulatePlan> plan_simulation(const std::string& command, const std::string& model,
                                            const SimulateOptions& options, const ArgParser& p);

// Writes the files and report.json of a finished run into plan.out_dir
// (`preview`: the run's preview output, or null; `start`: when the command or
// the run began, for wall_s; `input_times`: what loading and checking the
// model took; `ranks_report`: report.json's "mpi" object,
// tools/distributed_run.h, left out where null), prints the summary, and
// returns the exit code (the energy checks). `failures`: what already failed
// (the preview); a failure while writing does not stop the other files:
// report.json lists what was written and what failed, and the exit code is 1.
int write_run_files(const SimulatePlan& plan, const ProgressiveOutcome& run, const ModelInputTimes& input_times,
                    const PreviewOutput* preview, std::chrono::steady_clock::time_point start,
                    const nlohmann::json& ranks_report = nullptr, std::vector<Error> failures = {});

}  // namespace gonio::cli
