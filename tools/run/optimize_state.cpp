// The live state of a running gonio optimize (tools/run/optimize_state.h).
#include "tools/run/optimize_state.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "io/support/file_io.h"
#include "photometry/format.h"
#include "tools/run/json_figures.h"
#include "tools/run/optimize_run.h"

namespace gonio::app {
namespace {

// The grid's column nearest C (degrees).
std::size_t nearest_column(const design::MeritGrid& grid, double c_deg) {
  std::size_t best = 0;
  double best_d = 1e300;
  for (std::size_t i = 0; i < grid.c_deg.size(); ++i) {
    double d = std::fmod(std::abs(grid.c_deg[i] - c_deg), 360.0);
    d = std::min(d, 360.0 - d);
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  return best;
}

}  // namespace

OptimizeProgress::OptimizeProgress(std::string path, const std::string& design_path, const std::string& target_path,
                                   const std::string& method, long long max_evals, double max_time_s,
                                   std::vector<design::OptimizeVariable> variables, const design::MeritSpec& spec,
                                   const design::MeritGrid& grid, const design::MeritTarget& target)
    : path_(std::move(path)),
      variables_(std::move(variables)),
      grid_(grid),
      absolute_(spec.absolute),
      target_flux_(target.flux_lm),
      max_evals_(max_evals),
      max_time_s_(max_time_s) {
  nlohmann::json start = nlohmann::json::object();
  for (const design::OptimizeVariable& v : variables_) start[v.name] = v.value;
  state_ = {{"kind", "optimize"},
            {"run", 1},
            {"model", design_path},
            {"status", "running"},
            {"status_text", std::string(method) + ": starting"},
            {"iteration", 0},
            {"iterations", max_evals},
            {"photons", 0},
            {"elapsed_s", 0.0},
            {"time_left_s", nullptr},
            {"flux_lm", nullptr},
            {"lor", nullptr},
            {"max_cd", nullptr},
            {"curves", nullptr},
            {"previous_curves", curves_of(target.candela)},
            {"findings", nlohmann::json::array()},
            {"last_error", nullptr},
            {"optimize",
             {{"design", design_path},
              {"target", target_path},
              {"method", method},
              {"evaluation", 0},
              {"stage", nullptr},
              {"max_evals", max_evals},
              {"best_merit", nullptr},
              {"start_merit", nullptr},
              {"best_index", nullptr},
              {"start_values", start},
              {"best_values", start},
              {"candela_rms_pct", nullptr},
              {"beam_angle_deg", nullptr},
              {"target_beam_angle_deg", json_number(target.beam_deg)},
              {"history", nlohmann::json::array()}}}};
  write();
}

nlohmann::json OptimizeProgress::curves_of(const std::vector<double>& candela) const {
  const std::size_t ng = grid_.gamma_deg.size();
  nlohmann::json curves = {{"gamma_deg", grid_.gamma_deg}};
  for (const auto& [key, c] : {std::pair<const char*, double>{"c0", 0.0}, {"c180", 180.0}, {"c90", 90.0},
                               {"c270", 270.0}}) {
    const std::size_t column = nearest_column(grid_, c);
    std::vector<double> plane(ng, 0.0);
    for (std::size_t g = 0; g < ng && column * ng + g < candela.size(); ++g) plane[g] = candela[column * ng + g];
    curves[key] = plane;
  }
  return curves;
}

void OptimizeProgress::traced(const std::vector<double>& values, std::uint64_t photons, std::uint64_t seed,
                              const std::vector<double>& candela, const design::MeritValue& merit) {
  // Scaled as evaluate_merit scales it: to the target's flux unless absolute.
  double flux = 0.0;
  for (std::size_t k = 0; k < candela.size() && k < grid_.solid_angle_sr.size(); ++k)
    flux += candela[k] * grid_.solid_angle_sr[k];
  const double scale = absolute_ ? 1.0 : flux > 0.0 ? target_flux_ / flux : 0.0;
  Traced t{candela, merit};
  for (double& v : t.candela) v *= scale;
  std::lock_guard lock(mutex_);
  // A row waits for its evaluation's record (a CMA-ES generation traces all
  // its points first, up to --population). A row never claimed (a
  // constraint's own call) belongs to a finished stage once the photons
  // change: those are dropped then, not every waiting row past a count.
  if (photons != photons_) {
    std::erase_if(traced_, [&](const auto& row) { return row.first.second.first != photons; });
    photons_ = photons;
  }
  traced_[{values, {photons, seed}}] = std::move(t);
}

void OptimizeProgress::evaluation(const design::EvaluationRecord& r) {
  std::optional<Traced> t;
  {
    std::lock_guard lock(mutex_);
    const auto it = traced_.find({r.values, {r.photons, r.seed}});
    if (it != traced_.end()) {
      t = std::move(it->second);
      traced_.erase(it);
    }
  }
  nlohmann::json& o = state_["optimize"];
  o["history"].push_back(evaluation_json(r, variables_));
  o["evaluation"] = r.index;
  state_["elapsed_s"] = r.time_s;
  if (r.stage < 0) {
    state_["status_text"] = "evaluation " + std::to_string(r.index) + ": the noise floor (independent seeds)";
    write();
    return;
  }
  o["stage"] = r.stage + 1;
  state_["iteration"] = r.index;
  state_["photons"] = r.photons;
  if (o["start_merit"].is_null() && std::isfinite(r.merit)) o["start_merit"] = r.merit;
  if (max_time_s_ > 0.0)
    state_["time_left_s"] = std::max(max_time_s_ - r.time_s, 0.0);
  else if (r.index < max_evals_ && r.index > 0)
    state_["time_left_s"] = r.time_s / r.index * static_cast<double>(max_evals_ - r.index);
  else
    state_["time_left_s"] = 0.0;
  // The stage's best: this evaluation where its merit is the best so far.
  if (std::isfinite(r.merit) && r.merit == r.best) {
    o["best_merit"] = r.merit;
    o["best_index"] = r.index;
    nlohmann::json values = nlohmann::json::object();
    for (std::size_t i = 0; i < variables_.size() && i < r.values.size(); ++i) values[variables_[i].name] = r.values[i];
    o["best_values"] = values;
    if (t) {
      double flux = 0.0, peak = 0.0;
      for (std::size_t k = 0; k < t->candela.size(); ++k) {
        flux += t->candela[k] * grid_.solid_angle_sr[k];
        peak = std::max(peak, t->candela[k]);
      }
      state_["curves"] = curves_of(t->candela);
      state_["flux_lm"] = flux;
      state_["max_cd"] = peak;
      state_["lor"] = json_number(t->merit.lor);
      o["candela_rms_pct"] = json_number(t->merit.candela_rms_pct);
      o["beam_angle_deg"] = json_number(t->merit.beam_deg);
    }
  }
  state_["status_text"] = "evaluation " + std::to_string(r.index) + " (stage " + std::to_string(r.stage + 1) +
                          "): merit " + format_number(r.merit, 5) + ", best " + format_number(r.best, 5);
  write();
}

void OptimizeProgress::finished(const nlohmann::json& report) {
  nlohmann::json& o = state_["optimize"];
  for (const char* key : {"stopped_by", "noise_floor", "independent_merit", "final", "evaluations"})
    if (report.contains(key)) o[key] = report.at(key);
  if (report.contains("best_merit")) o["best_merit"] = report.at("best_merit");
  if (report.contains("variables")) {
    nlohmann::json values = nlohmann::json::object();
    for (const nlohmann::json& v : report.at("variables")) values[v.at("name").get<std::string>()] = v.at("best");
    o["best_values"] = values;
  }
  state_["status"] = "finished";
  state_["time_left_s"] = 0.0;
  state_["status_text"] = "finished (" + report.value("stopped_by", std::string("?")) + "): the files are written";
  write();
}

void OptimizeProgress::failed(const std::string& error) {
  state_["status"] = "error";
  state_["status_text"] = "the optimisation failed";
  state_["last_error"] = {{"message", error}, {"time", format_number(state_.value("elapsed_s", 0.0), 4) + " s"}};
  write();
}

void OptimizeProgress::write() {
  state_["version"] = ++version_;
  // A state that cannot be written is not worth failing the run for: the
  // page just stops following it.
  (void)io::write_file_atomic(path_, state_.dump() + "\n");
}

}  // namespace gonio::app
