// What the live page shows, computed from a running simulation and published
// through tools/live/live_server.h after every iteration: the filtered far field
// (sim/filter/preview_filter.h, the --filter options), its candela table on the
// output grid (sim/detectors/resample.h), and the numbers a designer watches.
//
// state.json (every publish; NaN numbers are null):
//   version, run (1, 2, … one per model load), model, status ("loading",
//   "running", "finished", "error"), status_text,
//   iteration, iterations, photons, photons_per_s, elapsed_s, time_left_s,
//   estimated_rms_error_pct, target_error_pct (null: none), stopped_by,
//   flux_lm (escaped, the ledger's, as report.json's escaped_lm),
//   emitted_lm, lor (escaped / emitted), max_cd, max_c_deg,
//   max_gamma_deg, beam_angle_c0_c180_deg, beam_angle_c90_c270_deg,
//   field_angle_c0_c180_deg, field_angle_c90_c270_deg (gonio info --json's
//   keys, tools/run/json_figures.h; photometry/beam.h, of the filtered candela
//   table), curves {gamma_deg, c0, c180, c90, c270} [cd]
//   (filtered), previous_curves (the last iteration of the run before, or
//   null), field {face_size, max_cd, white_cd (the colour scale's top:
//   io/outputs/cube_cross.h's 99 % flux quantile), version} (GET /field.f32), findings
//   [{severity, code, message, where}] (the model's check findings),
//   last_error (null, or {message, time}), load_to_preview_s (from the
//   change being noticed to this run's first preview), read_to_preview_s
//   (from the model having been read to this run's first preview), colour (a spectral
//   run: {cie_x, cie_y, u_prime, v_prime, cct_k, duv, delta_uv_max}, as
//   report.json's colour and colour_over_angle; null otherwise).
// A run that fails leaves the last good field, curves and numbers up, with
// last_error set and status "error".
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "photometry/diagnostics.h"
#include "sim/filter/preview_filter.h"
#include "sim/detectors/resample.h"
#include "sim/scene.h"
#include "tools/live/live_server.h"
#include "tools/run/progressive_run.h"
#include "tools/run/simulation_run.h"

namespace gonio::app {

class LiveView {
 public:
  // Starts the server (tools/live/live_server.h) for runs planned as `plan`.
  static Result<std::unique_ptr<LiveView>> start(const std::string& host, int port, const SimulatePlan& plan);

  std::string url() const { return server_->url(); }

  // The output grid's resampler for a scene's frame (kept while the frame
  // stays the same: building one takes ~0.3 s at the defaults).
  const sim::Resampler& resampler_for(const sim::SceneDesc& scene);

  // The model is being (re)loaded; `since` is when its change was noticed.
  void loading(const std::string& model, std::chrono::steady_clock::time_point since);
  // The model has been read (read_to_preview_s counts from here).
  void model_read();
  // A run of `model` begins, with the model's check findings.
  void begin_run(const std::string& model, const sim::SceneDesc& scene, std::vector<Finding> findings);
  void iteration(const IterationReport& report, const sim::Simulation& simulation);
  void run_finished(const ProgressiveOutcome& run);
  // The model could not be read or run: the last good result stays up.
  void run_failed(const Error& error, std::vector<Finding> findings = {});
  // A status line (e.g. "retrying: the model may still be being written").
  void note(const std::string& text);

  const nlohmann::json& state() const { return state_; }

 private:
  LiveView(std::unique_ptr<LiveServer> server, const SimulatePlan& plan);
  void publish(bool with_field);

  std::unique_ptr<LiveServer> server_;
  SimulatePlan plan_;
  sim::PreviewFilter filter_;
  std::unique_ptr<sim::Resampler> resampler_;
  photometry::PhotometricFrame resampler_frame_;
  nlohmann::json state_;
  nlohmann::json last_curves_;  // of the current run's latest iteration
  std::string field_;           // float32 bytes of the latest preview
  int run_ = 0;
  std::uint64_t version_ = 0;
  std::chrono::steady_clock::time_point since_{};
  std::chrono::steady_clock::time_point read_at_{};
  bool first_preview_ = true;
};

}  // namespace gonio::app
