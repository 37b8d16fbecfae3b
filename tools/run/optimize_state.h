// The live state of a running `gonio optimize` (docs/commands/watch.md "An
// optimisation"): DIR/state.json, written atomically after every evaluation
// and once more when the run ends, which `gonio watch DIR` serves as the live
// page's GET /state.json (tools/live/watch_optimize.h). The live page's keys
// where they mean the same (version, run, model, status, status_text,
// iteration = the evaluation, iterations = --max-evals, photons, elapsed_s,
// time_left_s, flux_lm, lor, max_cd, curves, previous_curves), and:
//   kind          "optimize"
//   curves        the current best's candela at the merit grid's nodes, as
//                 the merit saw it (scaled to the target's flux unless the
//                 merit is absolute): {gamma_deg, c0, c180, c90, c270} [cd],
//                 each plane the grid's nearest C-plane
//   previous_curves  the target's, on the same nodes (the page draws it dashed)
//   optimize      {design, target, method, evaluation, stage, max_evals,
//                 best_merit, start_merit, best_index, best_values {name: value},
//                 candela_rms_pct, beam_angle_deg, target_beam_angle_deg (the
//                 best's, at its stage's photons and seed), history (every
//                 evaluation so far, history.json's rows), and once finished
//                 stopped_by, noise_floor, independent_merit, final (report.json's
//                 optimize.final)}
// status is "running" while the search goes on, then "finished" (the files
// are written) or "error" (the run failed: last_error says why).
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "design/merit.h"
#include "design/optimize.h"

namespace gonio::app {

class OptimizeProgress {
 public:
  // `path`: the state file (DIR/state.json). Writes the first state
  // ("running", no evaluation yet).
  OptimizeProgress(std::string path, const std::string& design_path, const std::string& target_path,
                   const std::string& method, long long max_evals, double max_time_s,
                   std::vector<design::OptimizeVariable> variables, const design::MeritSpec& spec,
                   const design::MeritGrid& grid, const design::MeritTarget& target);

  // One traced evaluation's candela at the grid's nodes (design::bin_photons)
  // and its merit's terms; thread-safe (CMA-ES traces several at once).
  void traced(const std::vector<double>& values, std::uint64_t photons, std::uint64_t seed,
              const std::vector<double>& candela, const design::MeritValue& merit);
  // After each evaluation (in order): adds its history row and, where it is
  // its stage's best, makes its candela the best's; writes the state.
  void evaluation(const design::EvaluationRecord& record);
  // The run's end: "finished" with report.json's optimize section (stopped_by,
  // noise floor, final figures, best values), or "error" with `error`.
  void finished(const nlohmann::json& report_optimize);
  void failed(const std::string& error);

  const nlohmann::json& state() const { return state_; }
  // The state's curves of candela at the grid's nodes (for tests).
  nlohmann::json curves_of(const std::vector<double>& candela) const;

 private:
  void write();
  struct Traced {
    std::vector<double> candela;  // scaled as the merit scales it
    design::MeritValue merit;
  };
  std::string path_;
  std::vector<design::OptimizeVariable> variables_;
  design::MeritGrid grid_;
  bool absolute_ = false;
  double target_flux_ = 0.0;
  long long max_evals_ = 0;
  double max_time_s_ = 0.0;
  std::mutex mutex_;
  std::map<std::pair<std::vector<double>, std::pair<std::uint64_t, std::uint64_t>>, Traced> traced_;
  std::uint64_t photons_ = 0;  // the photons of the last traced row (its stage's)
  nlohmann::json state_;
  std::uint64_t version_ = 0;
};

}  // namespace gonio::app
