// The application's one way to simulate a luminaire model, for every front
// end: `gonio simulate` and `gonio simulate --serve` (tools/cli), the Python
// module, tests. Plain options in, a checked plan, then one call that loads
// and checks the model, traces it progressively (reporting each iteration,
// stopping when asked), and, where the plan names a folder, writes the
// run's files and report.json (tools/run/simulation_run.h).
//
//   SimulateOptions options;                      // gonio simulate's defaults
//   options.out_dir = "out";
//   Result<SimulatePlan> plan = plan_simulation("lamp.gltf", options);
//   SimulateHooks hooks;
//   hooks.on_iteration = [](const IterationReport& r, const sim::Simulation&) { ...; return true; };
//   std::optional<SimulateResult> run = simulate(plan.value(), hooks);
//   // run->files: what was written, report.json's content, the energy checks
//
// `gonio watch` (tools/live/watch.h) runs the same plan again whenever the
// model changes, from the same parts.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "io/support/cache_folder.h"
#include "photometry/diagnostics.h"
#include "sim/tracer/next_event.h"
#include "sim/detectors/resample.h"
#include "sim/scene.h"
#include "tools/run/console.h"
#include "tools/run/grid_options.h"
#include "tools/run/model_input.h"
#include "tools/run/option_bounds.h"
#include "tools/run/preview_output.h"
#include "tools/run/progressive_run.h"
#include "tools/run/simulation_run.h"

namespace gonio::app {

// The options' bounds (tools/run/option_bounds.h).
inline constexpr Bounds<long long> kPhotonsBounds{1, 4'294'967'295LL};
inline constexpr Bounds<long long> kIterationsBounds{1, 1'000'000};
inline constexpr Bounds<long long> kSeedBounds{0, 9'223'372'036'854'775'807LL};
inline constexpr Bounds<long long> kThreadsBounds{0, 4096};
inline constexpr Bounds<long long> kMaxBouncesBounds{0, 1'000'000};
inline constexpr Bounds<long long> kFaceSizeBounds{1, 4096};
inline constexpr Bounds<long long> kTm25RaysBounds{1, 100'000'000};
inline constexpr Bounds<long long> kCacheLimitMbBounds{0, 1'000'000'000};
inline constexpr Bounds<long long> kConnectionsBounds{1, 1024};
inline constexpr Bounds<double> kGridStepBounds{sim::kMinGridStepDeg, sim::kMaxGridStepDeg};
inline constexpr Bounds<double> kGammaStepBounds{sim::kMinGammaStepDeg, sim::kMaxGridStepDeg};
inline constexpr Bounds<double> kFractionBounds{0.0, 1.0};      // --min-lor, --flux-tolerance
inline constexpr Bounds<double> kTargetErrorBounds{0.0, 100.0};  // --target-error [%]

// The options of a simulation as a front end gives them: `gonio simulate
// --help`'s options by the same names, with its defaults.
struct SimulateOptions {
  std::string out_dir;  // --out DIR: the run's files (created if missing); empty: none
  long long photons = 1'000'000, iterations = 10, seed = 1, threads = 0, max_bounces = 100;
  long long face_size = 0;  // --face-size F; 0: two texels per grid step
  double c_step = 5.0, gamma_step = 2.5, min_lor = 0.0, flux_tolerance = 0.005;
  double target_error_pct = 0.0;  // --target-error PCT; 0: none
  // Non-uniform grids (tools/run/grid_options.h): --c-angles LIST,
  // --gamma-angles LIST, --grid-like FILE; each replaces the step it covers.
  std::optional<std::string> c_angles, gamma_angles, grid_like;
  std::string symmetry_name = "auto", format_list = "all", ies_version = "2019", stem;
  std::string bvh_quality = "auto";        // --bvh-quality auto|low|medium|high
  std::optional<long long> tm25_rays;      // --tm25-rays N (format tm25 only; default 1000000)
  std::optional<std::string> near_field;   // --near-field D1,D2,… [m]
  std::string sampler = "sobol";           // --sampler sobol|random (sim/samplers/sampler.h)
  std::string next_event = "auto";         // --next-event auto|on|off (sim/tracer/next_event.h)
  long long connections = sim::kDefaultConnections;  // --connections M
  std::optional<std::string> luminance_images;       // --luminance-image C:G[,C:G…] or ugr
  std::optional<std::string> cache_dir;    // --cache DIR; none: io::default_cache_dir()
  bool no_cache = false;                   // --no-cache
  long long cache_limit_mb = io::kDefaultCacheLimitBytes >> 20;  // --cache-limit MB; 0: none
  ModelInputOptions model_input;  // --allow-outside-paths, --no-instancing (cache_dir: from the above)
  PreviewOptions preview;         // --preview and the filter's options
};

// Checks the options for `model` and resolves them into a plan. Errors name
// the option as the command line spells it ("--near-field: …").
Result<SimulatePlan> plan_simulation(const std::string& model, const SimulateOptions& options);

// How a front end follows a run; every member may be empty.
struct SimulateHooks {
  // Each message as it arises: the model's warnings and errors, and the
  // error that stops the run (tools/run/console.h; empty: printed to stderr).
  MessageSink on_message;
  // The model loaded and checked, before tracing (on the rank that writes):
  // may return the output grid's resampler (plan.grid, the plan's face size,
  // the scene's frame; kept alive by the caller) for the error estimate
  // after each iteration. Null, or no hook: one is made only where the plan
  // needs it (a target error), so the estimate is NaN otherwise.
  std::function<const sim::Resampler*(const sim::SceneDesc& scene, const std::vector<Finding>& findings)>
      on_loaded;
  // The model loaded and checked, before anything else sees it: may change
  // the scene (gonio tolerance's perturbed trials); an error stops the run
  // as the loader's would, told and given to on_failed.
  std::function<Status(sim::SceneDesc& scene)> adjust_scene;
  // After each iteration, once the preview is written (on the rank that
  // writes); false stops the run (StopReason::Cancelled).
  IterationCallback on_iteration;
  // Asked between slices of photons; true stops the run at once.
  CancelCheck cancel;
  // A run stopped by on_iteration or cancel (StopReason::Cancelled): true
  // keeps what was traced, and its files are written as for a finished run
  // (the Python module's callback returning False); empty or false: nothing
  // is written (Ctrl-C on the command line).
  std::function<bool()> keep_when_stopped;
  // The trace ended (all iterations, the target error, or cancelled),
  // before any file is written.
  std::function<void(const ProgressiveOutcome&)> on_traced;
  // The error that stopped the run, whatever stopped it (the model could not
  // be loaded or has errors, the folder could not be made, the trace
  // failed), as a value, once it was told to on_message; the run returns
  // nothing after it. Not called where the ranks disagree (each rank's own
  // problem is told).
  std::function<void(const Error&)> on_failed;
};

struct SimulateResult {
  ProgressiveOutcome run;  // stopped_by Cancelled: nothing was written, unless keep_when_stopped
  ModelInputTimes input_times;
  std::vector<Finding> findings;  // the model's: reader, checks, ray sets asked for too many photons
  bool lead = true;  // this process writes: the only one, or rank 0 of an MPI job
  // The files and report.json: where the plan names a folder, on the rank
  // that writes, unless the run was cancelled (and not kept).
  std::optional<RunFiles> files;
};

// Simulates plan.model: loads and checks it (an error stops it), creates
// plan.out_dir, traces the photons progressively (the preview written after
// each iteration where the plan asks for it), and, unless stopped, writes
// the run's files. Under MPI (plan.progressive.simulation.ranks; null: one
// process) every rank calls it: the ranks agree on model and settings before
// tracing, trace their shares, and rank 0 alone writes. Returns nothing
// where the run could not start or failed, each problem told to
// hooks.on_message as it arose. `start`: when the command began (report.json's
// wall_s).
std::optional<SimulateResult> simulate(const SimulatePlan& plan, const SimulateHooks& hooks = {},
                                       std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now());

}  // namespace gonio::app
