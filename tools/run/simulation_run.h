// A planned simulation run and the files it leaves: what the options of
// `gonio simulate` and `gonio watch` resolve into (tools/run/simulate.h), what
// the live page shows runs of (tools/live/live_view.h), and the writing of a
// finished run's files and report.json.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/photometric/ies.h"
#include "io/support/cache_folder.h"
#include "sim/filter/preview_filter.h"
#include "sim/detectors/resample.h"
#include "tools/run/model_input.h"
#include "tools/run/preview_output.h"
#include "sim/detectors/near_field.h"
#include "tools/run/progressive_run.h"
#include "tools/run/simulation_outputs.h"

namespace gonio::app {

// The options checked and resolved.
struct SimulatePlan {
  std::string model;
  std::string out_dir;
  std::string stem;
  sim::CGammaGrid grid;
  // --grid-like: the angles added to the file's own (tools/run/grid_options.h); empty: none.
  std::string grid_note;
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

// STEM.tm25ray as written (--format tm25).
struct RayFileWritten {
  std::string path;
  std::size_t rays = 0;
  double flux_lm = 0.0;  // their luminous flux: the escaped flux [lm]
};

// What write_run_files left in the folder, and what a front end tells the
// user about it.
struct RunFiles {
  std::string report_path;            // DIR/report.json
  nlohmann::json report;              // its content
  std::optional<Error> report_error;  // report.json could not be written (the files listed may have been)
  OutputResult outputs;               // the photometric and image files, read back; the symmetry chosen
  std::optional<RayFileWritten> ray_file;
  std::vector<std::string> preview;   // preview.exr and preview.png, where the run had a preview
  std::vector<std::string> written;   // every file of the run besides report.json
  std::vector<Error> failures;        // what failed after tracing (the other files were written)
  EnergyCheck energy;                 // report.json's "energy"
  std::optional<sim::FarFieldDistance> far_field_distance;  // with near-field planes (report.json's too)
  // Everything written and every check passed.
  bool passed() const { return !report_error && failures.empty() && energy.passed(); }
};

// Writes the files and report.json of a finished run into plan.out_dir
// (`preview`: the run's preview output, or null; `start`: when the command or
// the run began, for wall_s; `input_times`: what loading and checking the
// model took; `ranks_report`: report.json's "mpi" object,
// tools/run/distributed_run.h, left out where null), and trims the cache
// folder to its limit. `failures`: what already failed (the preview); a
// failure while writing does not stop the other files: report.json lists
// what was written and what failed. `resampler`: the output grid's, where the
// run built one for its estimate (OutputRequest::resampler); null: made or
// read from the cache. Prints nothing.
RunFiles write_run_files(const SimulatePlan& plan, const ProgressiveOutcome& run, const ModelInputTimes& input_times,
                         const PreviewOutput* preview, std::chrono::steady_clock::time_point start,
                         const nlohmann::json& ranks_report = nullptr, std::vector<Error> failures = {},
                         const sim::Resampler* resampler = nullptr);

}  // namespace gonio::app
