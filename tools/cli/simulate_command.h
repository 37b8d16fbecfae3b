// What `gonio simulate` and `gonio watch` share on the command line: the
// simulation's options and their checks into a plan (tools/run/simulation_run.h,
// which also writes a finished run's files; the code lives in
// tools/cli/cmd_simulate.cpp; watch runs the same steps per model change).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/support/cache_folder.h"
#include "tools/cli/cli.h"
#include "tools/cli/input_options.h"
#include "tools/run/model_input.h"
#include "tools/run/simulation_run.h"

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
  std::string cache_dir;  // --cache DIR (the model checks' results, the outputs' resamplers)
  bool no_cache = false;  // --no-cache
  long long cache_limit_mb = io::kDefaultCacheLimitBytes >> 20;  // --cache-limit MB; 0: none
  ModelInputOptions model_input;  // --allow-outside-paths
  PreviewOptions preview;
};

// Registers every option but MODEL and --out (callers word those).
void add_simulate_options(ArgParser& p, SimulateOptions* options);

// Checks the options for `model`; on a problem prints "COMMAND: …" and the
// usage line to stderr and returns nothing (exit kExitUsage).
std::optional<SimulatePlan> plan_simulation(const std::string& command, const std::string& model,
                                            const SimulateOptions& options, const ArgParser& p);

}  // namespace gonio::cli
