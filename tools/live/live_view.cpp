#include "tools/live/live_view.h"

#include <cmath>
#include <cstring>
#include <ctime>
#include <limits>
#include <optional>
#include <utility>

#include "io/outputs/cube_cross.h"
#include "io/outputs/luminance_images.h"
#include "photometry/format.h"
#include "photometry/summary.h"
#include "tools/run/json_figures.h"
#include "tools/run/resampler_cache.h"
#include "tools/run/simulation_outputs.h"

namespace gonio::app {
namespace {

bool same_frame(const photometry::PhotometricFrame& a, const photometry::PhotometricFrame& b) {
  auto eq = [](const Vec3& x, const Vec3& y) { return x.x == y.x && x.y == y.y && x.z == y.z; };
  return eq(a.c0, b.c0) && eq(a.c90, b.c90) && eq(a.up, b.up);
}

nlohmann::json findings_json(const std::vector<Finding>& findings) {
  nlohmann::json out = nlohmann::json::array();
  for (const Finding& f : findings)
    out.push_back({{"severity", to_string(f.severity)},
                   {"code", f.code},
                   {"message", f.message},
                   {"where", to_string(f.where)}});
  return out;
}

// The row of C-plane `c_deg` of a Type C distribution over 0…360 (none: empty).
nlohmann::json plane(const photometry::Distribution& d, double c_deg) {
  for (std::size_t h = 0; h < d.horizontal_deg.size(); ++h) {
    if (std::abs(d.horizontal_deg[h] - c_deg) > 1e-9) continue;
    nlohmann::json row = nlohmann::json::array();
    for (std::size_t v = 0; v < d.vertical_deg.size(); ++v) row.push_back(d.at(h, v));
    return row;
  }
  return nlohmann::json::array();
}

}  // namespace

Result<std::unique_ptr<LiveView>> LiveView::start(const std::string& host, int port, const SimulatePlan& plan) {
  install_interrupt_handlers();
  auto server = LiveServer::start(host, port);
  if (!server.ok()) return server.error();
  return std::unique_ptr<LiveView>(new LiveView(std::move(server.value()), plan));
}

LiveView::LiveView(std::unique_ptr<LiveServer> server, const SimulatePlan& plan)
    : server_(std::move(server)),
      plan_(plan),
      filter_(plan.progressive.simulation.face_size, plan.preview_params) {
  state_ = {{"version", 0},
            {"run", 0},
            {"status", "loading"},
            {"status_text", "starting"},
            {"model", plan.model},
            {"iteration", 0},
            {"photons", 0},
            {"target_error_pct", plan.progressive.target_error_pct > 0.0
                                     ? nlohmann::json(plan.progressive.target_error_pct)
                                     : nlohmann::json(nullptr)},
            {"findings", nlohmann::json::array()},
            {"last_error", nullptr},
            {"curves", nullptr},
            {"previous_curves", nullptr},
            {"field", nullptr}};
  publish(false);
}

const sim::Resampler& LiveView::resampler_for(const sim::SceneDesc& scene) {
  if (!resampler_ || !same_frame(resampler_frame_, scene.frame)) {
    resampler_ = std::make_unique<sim::Resampler>(cached_resampler(
        plan_.progressive.simulation.face_size, scene.frame, plan_.grid, plan_.model_input.cache_dir));
    resampler_frame_ = scene.frame;
  }
  return *resampler_;
}

void LiveView::publish(bool with_field) {
  state_["version"] = ++version_;
  std::string field;
  if (with_field) field = field_;
  server_->publish(state_.dump(), std::move(field));
}

void LiveView::loading(const std::string& model, std::chrono::steady_clock::time_point since) {
  since_ = since;
  state_["model"] = model;
  state_["status"] = "loading";
  state_["status_text"] = "loading the model";
  publish(false);
}

void LiveView::model_read() { read_at_ = std::chrono::steady_clock::now(); }

void LiveView::begin_run(const std::string& model, const sim::SceneDesc& scene, std::vector<Finding> findings) {
  if (since_ == std::chrono::steady_clock::time_point{}) since_ = std::chrono::steady_clock::now();
  resampler_for(scene);
  ++run_;
  first_preview_ = true;
  if (!last_curves_.is_null()) state_["previous_curves"] = last_curves_;
  state_["run"] = run_;
  state_["model"] = model;
  state_["status"] = "running";
  state_["status_text"] = "tracing";
  state_["findings"] = findings_json(findings);
  state_["last_error"] = nullptr;
  state_["stopped_by"] = nullptr;
  // Until its first iteration the new run has no numbers of its own: the
  // field stays, the curves show as the previous run's.
  state_["iteration"] = 0;
  state_["photons"] = 0;
  state_["curves"] = nullptr;
  state_["colour"] = nullptr;
  state_["luminance_images"] = nullptr;
  publish(false);
}

void LiveView::iteration(const IterationReport& r, const sim::Simulation& simulation) {
  const sim::FarField raw = simulation.far_field();
  filter_.apply(raw);
  const std::span<const double> cd = filter_.intensity_cd();
  field_.resize(cd.size() * sizeof(float));
  double max_cd = 0.0;
  std::vector<double> flux(cd.size());
  for (std::size_t t = 0; t < cd.size(); ++t) {
    const float v = static_cast<float>(cd[t]);
    std::memcpy(field_.data() + t * sizeof(float), &v, sizeof v);
    max_cd = std::max(max_cd, cd[t]);
    flux[t] = cd[t] * raw.grid().texel_solid_angle(t);
  }
  const sim::FarField filtered(raw.face_size(), std::move(flux), std::vector<std::uint64_t>(cd.size(), 0));
  const sim::BinnedField table = resampler_->bin(filtered);
  const photometry::Distribution d = sim::to_distribution(table, photometry::Symmetry::None);

  const sim::Ledger ledger = simulation.ledger();
  const sim::SimulationStats st = simulation.stats();
  nlohmann::json& s = state_;
  s["status"] = "running";
  s["status_text"] = "tracing";
  s["iteration"] = r.progress.iteration;
  s["iterations"] = r.progress.iterations;
  s["photons"] = st.photons;
  s["photons_per_s"] = json_number(r.progress.photons_per_s);
  s["elapsed_s"] = json_number(r.progress.elapsed_s);
  s["time_left_s"] = json_number(r.progress.remaining_s);
  s["estimated_rms_error_pct"] = json_number(r.estimated_rms_error_pct);
  s["flux_lm"] = ledger.escaped.flux_lm;
  s["emitted_lm"] = ledger.emitted.flux_lm;
  s["bvh_s"] = st.tracer_setup.bvh_s;
  s["bvh_reused"] = st.tracer_setup.bvh_reused;
  s["lor"] = json_number(ledger.emitted.flux_lm > 0.0 ? ledger.escaped.flux_lm / ledger.emitted.flux_lm
                                                 : std::numeric_limits<double>::quiet_NaN());
  std::optional<photometry::Summary> sum;
  if (photometry::validate(d).ok() && table.total_flux_lm() > 0.0) sum = photometry::summarize(d);
  put_peak_and_spread(s, sum ? &*sum : nullptr);
  last_curves_ = {{"run", run_},
                  {"gamma_deg", d.vertical_deg},
                  {"c0", plane(d, 0.0)},
                  {"c90", plane(d, 90.0)},
                  {"c180", plane(d, 180.0)},
                  {"c270", plane(d, 270.0)}};
  s["curves"] = last_curves_;
  // A spectral run's colour on the output grid (as report.json's; the raw
  // far field, not the filtered one).
  s["colour"] = simulation.tracer().spectral()
                    ? live_colour_json(sim::colour_over_angle(*resampler_, raw, simulation.colour_far_field()))
                    : nlohmann::json(nullptr);
  // Luminance images (--luminance-image): their thumbnails.
  s["luminance_images"] = simulation.settings().luminance.views.empty()
                              ? nlohmann::json(nullptr)
                              : io::luminance_thumbnails(simulation.luminance_images());
  // The colour scale's white point as preview.png's: the intensity under
  // which the texels carrying 99 % of the flux lie (a bright spot must not
  // leave the rest of the picture black).
  const double white_cd = max_cd > 0.0 ? io::flux_quantile_cd(raw.grid(), cd, io::kPreviewQuantile) : 0.0;
  s["field"] = {{"face_size", raw.face_size()}, {"max_cd", max_cd}, {"white_cd", white_cd}, {"version", version_ + 1}};
  if (first_preview_) {
    const auto now = std::chrono::steady_clock::now();
    s["load_to_preview_s"] = std::chrono::duration<double>(now - since_).count();
    s["read_to_preview_s"] = read_at_ == std::chrono::steady_clock::time_point{}
                                 ? nlohmann::json(nullptr)
                                 : nlohmann::json(std::chrono::duration<double>(now - read_at_).count());
    first_preview_ = false;
  }
  publish(true);
}

void LiveView::run_finished(const ProgressiveOutcome& run) {
  state_["status"] = "finished";
  state_["stopped_by"] = to_string(run.stopped_by);
  state_["status_text"] = run.stopped_by == StopReason::TargetError ? "reached the target error" : "finished";
  state_["estimated_rms_error_pct"] = json_number(run.estimated_rms_error_pct);
  since_ = {};
  publish(false);
}

void LiveView::run_failed(const Error& error, std::vector<Finding> findings) {
  state_["status"] = "error";
  state_["status_text"] = "the model could not be used; showing the last good result";
  state_["last_error"] = {{"message", to_string(error)}, {"time", format_utc(std::time(nullptr), "%H:%M:%S UTC")}};
  if (!findings.empty()) state_["findings"] = findings_json(findings);
  since_ = {};
  publish(false);
}

void LiveView::note(const std::string& text) {
  state_["status_text"] = text;
  publish(false);
}

}  // namespace gonio::app
