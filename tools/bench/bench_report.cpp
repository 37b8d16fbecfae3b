#include "tools/bench/bench_report.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>

#include "io/outputs/plot.h"
#include "photometry/format.h"

namespace gonio::app {
namespace {

namespace fs = std::filesystem;

// Six significant digits, or fixed with six decimals (times); empty for NaN.
std::string csv_number(double v, bool fixed = false) {
  if (!std::isfinite(v)) return "";
  char buf[40];
  if (fixed)
    std::snprintf(buf, sizeof buf, "%.6f", v);
  else
    std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

using Metric = std::function<double(const SeriesPoint&)>;

double table_rms(const SeriesPoint& p) { return p.table.rms_pct; }
double cube_rmse(const SeriesPoint& p) { return p.cube.rmse; }
double time_of(const SeriesPoint& p) { return p.time_s; }
double traced_of(const SeriesPoint& p) { return static_cast<double>(p.photons_traced); }

io::Series curve(const SeriesResult& r, const Metric& x, const Metric& y) {
  io::Series s;
  s.label = r.spec.label;
  for (const SeriesPoint& p : r.points) {
    s.x.push_back(x(p));
    s.y.push_back(y(p));
  }
  if (r.spec.name == "raw" || r.spec.name == "sobol") {
    s.markers = true;
  } else if (r.spec.name.rfind("bilinear", 0) == 0) {
    s.style = io::LineStyle::Dashed;
  } else if (r.spec.name == "adaptive" || r.spec.name == "guided-adaptive" || r.spec.name == "sobol-adaptive") {
    s.style = io::LineStyle::Dashed;
    s.markers = true;
  } else if (r.spec.name == "guided") {
    s.markers = true;
  }
  return s;
}

const SeriesResult* find(const std::vector<SeriesResult>& series, const std::string& name) {
  for (const SeriesResult& r : series)
    if (r.spec.name == name) return &r;
  return nullptr;
}

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// Panels of one metric against time: bilinear family, bilateral family, and
// guided emission (when measured), each with raw and adaptive for comparison.
std::vector<io::Chart> family_panels(const BenchOutcome& o, const Metric& metric, const std::string& y_label,
                                     bool log_y, std::optional<double> target) {
  std::vector<io::Chart> charts;
  const SeriesResult* raw = find(o.series, "raw");
  const SeriesResult* adaptive = find(o.series, "adaptive");
  auto panel = [&](const std::string& title, const std::function<bool(const SeriesResult&)>& take) {
    io::LineChart c;
    c.title = title;
    c.x_label = "time [s]";
    c.y_label = y_label;
    c.log_x = true;
    c.log_y = log_y;
    if (raw) c.series.push_back(curve(*raw, time_of, metric));
    for (const SeriesResult& r : o.series)
      if (take(r)) c.series.push_back(curve(r, time_of, metric));
    if (adaptive) c.series.push_back(curve(*adaptive, time_of, metric));
    if (target && raw && !raw->points.empty()) {
      io::Series t;
      t.label = "target";
      t.style = io::LineStyle::Dotted;
      t.x = {raw->points.front().time_s, raw->points.back().time_s};
      t.y = {*target, *target};
      c.series.push_back(t);
    }
    charts.push_back(c);
  };
  panel("bilinear (fixed thresholds)", [](const SeriesResult& r) { return starts_with(r.spec.name, "bilinear"); });
  panel("bilateral (fixed thresholds)", [](const SeriesResult& r) { return starts_with(r.spec.name, "bilateral"); });
  if (find(o.series, "guided"))
    panel("importance-guided emission", [](const SeriesResult& r) { return r.spec.guided; });
  if (find(o.series, "sobol"))
    panel("samplers: pseudo-random against Sobol'", [](const SeriesResult& r) {
      return r.spec.name == "sobol" || r.spec.name == "sobol-adaptive";
    });
  return charts;
}

io::LineChart photons_panel(const BenchOutcome& o, const Metric& metric, const std::string& y_label) {
  io::LineChart c;
  c.title = y_label + " against photons";
  c.x_label = "photons traced";
  c.y_label = y_label;
  c.log_x = c.log_y = true;
  for (const char* name :
       {"raw", "bilinear-100", "bilateral-100", "adaptive", "guided", "guided-adaptive", "sobol", "sobol-adaptive"})
    if (const SeriesResult* r = find(o.series, name)) c.series.push_back(curve(*r, traced_of, metric));
  if (const SeriesResult* raw = find(o.series, "raw"); raw && !raw->points.empty()) {
    // Slope −½ through half the first raw point that has a value (below
    // the raw curve, which it would hide otherwise).
    for (const SeriesPoint& p : raw->points) {
      const double y0 = 0.5 * metric(p);
      if (!(std::isfinite(y0) && y0 > 0.0)) continue;
      io::Series half;
      half.label = "slope −1/2";
      half.style = io::LineStyle::Dotted;
      const double x0 = traced_of(p), x1 = traced_of(raw->points.back());
      half.x = {x0, x1};
      half.y = {y0, y0 * std::sqrt(x0 / x1)};
      c.series.push_back(half);
      break;
    }
  }
  return c;
}

// Bench charts carry up to eight curves that cross: their legends go under
// the charts, where they hide none of them.
Status write_figure_pair(const std::string& dir, const std::string& stem, io::Figure f, bool png) {
  for (io::Chart& c : f.charts)
    if (auto* line = std::get_if<io::LineChart>(&c)) line->key_below = true;
  f.height_px = 760;
  if (Status s = io::write_figure((fs::path(dir) / (stem + ".svg")).string(), f); !s.ok()) return s;
  if (png)
    if (Status s = io::write_figure((fs::path(dir) / (stem + ".png")).string(), f); !s.ok()) return s;
  return Ok{};
}

std::string relative_link(const std::string& target, const std::string& page_path) {
  const fs::path base = fs::absolute(fs::path(page_path)).parent_path();
  return fs::absolute(fs::path(target)).lexically_normal().lexically_relative(base.lexically_normal()).generic_string();
}

// "12.3 s", "≤ 0.05 s" (already below at the first iteration), "> 40 s" (not
// reached), for the candela target or (cube) the cube-map one.
std::string time_to_target(const SeriesResult& r, double target, bool cube = false) {
  if (r.points.empty()) return "—";
  const double t = cube ? r.time_to_cube_target_s : r.time_to_target_s;
  const double first = cube ? r.points.front().cube.rmse : r.points.front().table.rms_pct;
  char buf[64];
  if (std::isnan(t)) {
    std::snprintf(buf, sizeof buf, "> %.3g s", r.points.back().time_s);
  } else if (t == r.points.front().time_s && !(first > target)) {
    std::snprintf(buf, sizeof buf, "≤ %.3g s", t);
  } else {
    std::snprintf(buf, sizeof buf, "%.3g s", t);
  }
  return buf;
}

// The fixed-threshold series that reaches a target first (not reached: the
// first of them).
const SeriesResult* best_fixed(const std::vector<SeriesResult>& series, bool cube) {
  constexpr double kNever = std::numeric_limits<double>::infinity();
  const SeriesResult* best = nullptr;
  double best_t = kNever;
  for (const SeriesResult& r : series) {
    if (!r.spec.filtered || r.spec.guided || r.spec.name == "adaptive" || r.spec.name == "sobol-adaptive") continue;
    const double t0 = cube ? r.time_to_cube_target_s : r.time_to_target_s;
    const double t = std::isnan(t0) ? kNever : t0;
    if (!best || t < best_t) {
      best = &r;
      best_t = t;
    }
  }
  return best;
}

std::string photons_text(double n) {
  if (std::isnan(n)) return "—";
  char buf[32];
  if (n >= 1e6)
    std::snprintf(buf, sizeof buf, "%.3g M", n / 1e6);
  else if (n >= 1e3)
    std::snprintf(buf, sizeof buf, "%.3g k", n / 1e3);
  else
    std::snprintf(buf, sizeof buf, "%.0f", n);
  return buf;
}

// A headline cell: the time and, since timings depend on the machine's
// load, the photons traced (deterministic for a seed).
std::string headline_cell(const SeriesResult& r, double level, bool cube) {
  std::string cell = time_to_target(r, level, cube);
  const double n = cube ? r.photons_to_cube_target : r.photons_to_target;
  if (!std::isnan(n)) cell += ", " + photons_text(n);
  return cell;
}

}  // namespace

std::string format_value(double v, int precision) {
  return std::isfinite(v) ? format_number(v, precision) : "—";
}

std::string series_csv(const std::vector<SeriesResult>& series) {
  std::ostringstream s;
  s << "series,iteration,photons,photons_traced,trace_s,filter_s,time_s,cube_rmse,cube_psnr_db,"
       "cube_snr_db,cube_raw_mse,table_rms_pct,table_raw_rms_pct,table_max_pct,flux_pct,estimated_rms_pct\n";
  for (const SeriesResult& r : series) {
    for (const SeriesPoint& p : r.points) {
      s << r.spec.name << ',' << p.iteration << ',' << p.photons << ',' << p.photons_traced << ','
        << csv_number(p.trace_s, true) << ',' << csv_number(p.filter_s, true) << ','
        << csv_number(p.time_s, true) << ',' << csv_number(p.cube.rmse) << ','
        << csv_number(p.cube.psnr_db) << ',' << csv_number(p.cube.snr_db) << ','
        << csv_number(p.cube.raw_mse) << ',' << csv_number(p.table.rms_pct) << ','
        << csv_number(p.table.raw_rms_pct) << ',' << csv_number(p.table.max_pct) << ','
        << csv_number(p.table.flux_pct) << ',' << csv_number(p.estimated_rms_pct) << '\n';
    }
  }
  return s.str();
}

nlohmann::json bench_json(const BenchOutcome& o) {
  using nlohmann::json;
  const BenchSettings& st = o.settings;
  json j;
  j["model"] = o.model;
  j["settings"] = {{"photons", st.photons},
                   {"first_photons", st.first_photons},
                   {"steps_per_doubling", st.steps_per_doubling},
                   {"seed", st.seed},
                   {"threads", st.threads},
                   {"max_bounces", st.max_bounces},
                   {"face_size", st.face_size},
                   {"grid", o.grid},
                   {"target_pct", st.target_pct},
                   {"cube_target", st.cube_target},
                   {"importance", st.importance}};
  j["settings"]["sampler"] = std::string(sim::to_string(st.sampler));
  j["settings"]["compare_samplers"] = st.compare_samplers;
  // Next-event estimation of the unguided series (bench --next-event).
  j["settings"]["next_event"] = std::string(sim::to_string(st.next_event));
  j["settings"]["next_event_connections"] = st.next_event_connections;
  if (st.importance)
    j["settings"]["importance_settings"] = {{"emission_face_size", st.importance_settings.emission_face_size},
                                            {"min_acceptance", st.importance_settings.min_acceptance}};
  const Reference& r = o.reference;
  j["reference"] = {{"key", r.key.to_json()},
                    {"trace_s", r.trace_s},
                    {"threads", r.threads},
                    {"reused", r.reused},
                    {"noise",
                     {{"cube_map_estimated", r.noise.cube_map_estimated},
                      {"cube_map_measured", r.noise.cube_map_measured},
                      {"table_estimated_pct", r.noise.table_estimated_pct},
                      {"table_measured_pct", r.noise.table_measured_pct}}},
                    {"smallest_raw_error_pct", o.smallest_raw_error_pct},
                    {"noise_over_smallest_error", r.noise.table_estimated_pct / o.smallest_raw_error_pct}};
  j["timing"] =
      "time_s = shared tracing time (trace_s) + the series's own filter time (filter_s, one filter "
      "application per iteration); error evaluation is not charged; guided series trace their own run "
      "and include the guide's update";
  json series = json::array();
  for (const SeriesResult& s : o.series) {
    json e = {{"name", s.spec.name},
              {"label", s.spec.label},
              {"sampler", std::string(sim::to_string(s.spec.sampler))},
              {"time_to_target_s", s.time_to_target_s},
              {"photons_to_target", s.photons_to_target},
              {"time_to_cube_target_s", s.time_to_cube_target_s},
              {"photons_to_cube_target", s.photons_to_cube_target},
              {"cube_slope", s.cube_slope},
              {"table_slope", s.table_slope},
              {"filter_ms_per_iteration", s.filter_ms_per_iteration}};
    if (!s.points.empty()) {
      const SeriesPoint& p = s.points.back();
      e["final"] = {{"photons", p.photons},       {"photons_traced", p.photons_traced},
                    {"time_s", p.time_s},          {"cube_rmse", p.cube.rmse},
                    {"cube_psnr_db", p.cube.psnr_db}, {"cube_snr_db", p.cube.snr_db},
                    {"table_rms_pct", p.table.rms_pct}, {"table_max_pct", p.table.max_pct},
                    {"flux_pct", p.table.flux_pct}};
    }
    series.push_back(e);
  }
  j["series"] = series;
  return j;
}

Status write_charts(const BenchOutcome& o, bool png) {
  const std::string title = o.name + ": ";
  {
    io::Figure f;
    f.title = title + "RMS candela error (" + o.grid + ", % of the reference peak) against time";
    for (io::Chart& c : family_panels(o, table_rms, "RMS error [% of peak]", true, o.settings.target_pct))
      f.charts.push_back(std::move(c));
    f.width_px = 600 * static_cast<int>(f.charts.size());
    if (Status s = write_figure_pair(o.directory, "candela-time", f, png); !s.ok()) return s;
  }
  {
    io::Figure f;
    f.title = title + "cube-map RMSE after mean scaling against time";
    for (io::Chart& c : family_panels(o, cube_rmse, "RMSE", true, std::nullopt)) f.charts.push_back(std::move(c));
    f.width_px = 600 * static_cast<int>(f.charts.size());
    if (Status s = write_figure_pair(o.directory, "cubemap-time", f, png); !s.ok()) return s;
  }
  {
    io::Figure f;
    f.title = title + "error against photons (log-log)";
    f.charts.push_back(photons_panel(o, table_rms, "RMS candela error [% of peak]"));
    f.charts.push_back(photons_panel(o, cube_rmse, "cube-map RMSE"));
    if (Status s = write_figure_pair(o.directory, "photons", f, png); !s.ok()) return s;
  }
  {
    io::Figure f;
    f.title = title + "PSNR and SNR of the cube map against time";
    for (const auto& [metric, label] :
         {std::pair<Metric, std::string>{[](const SeriesPoint& p) { return p.cube.psnr_db; }, "PSNR [dB]"},
          std::pair<Metric, std::string>{[](const SeriesPoint& p) { return p.cube.snr_db; }, "SNR [dB]"}}) {
      io::LineChart c;
      c.title = label;
      c.x_label = "time [s]";
      c.y_label = label;
      c.log_x = true;
      for (const SeriesResult& r : o.series)
        if (!starts_with(r.spec.name, "bilinear") && !r.spec.guided) c.series.push_back(curve(r, time_of, metric));
      f.charts.push_back(c);
    }
    if (Status s = write_figure_pair(o.directory, "psnr-snr", f, png); !s.ok()) return s;
  }
  return Ok{};
}

std::string results_page(const std::vector<BenchOutcome>& outcomes, const std::string& page_path,
                         const std::string& machine, const std::string& command) {
  std::ostringstream s;
  s << "# Speed against accuracy\n\n"
    << "How much accuracy each second of simulation buys, for every sample luminaire: the error of "
       "the far field against a long reference run, per iteration, for the raw photon map, the preview "
       "filter in the thesis's fixed-threshold modes and in its adaptive default";
  const bool guided = !outcomes.empty() && find(outcomes.front().series, "guided");
  const bool sobol = !outcomes.empty() && find(outcomes.front().series, "sobol");
  if (guided) s << ", and importance-guided emission";
  if (sobol) s << "; pseudo-random photons against Owen-scrambled Sobol' points (sim/samplers/sampler.h)";
  s << ".\n\nGenerated by `" << command << "`.\n" << machine << "\n\n";
  s << "Definitions (sim/convergence.h, tools/bench/bench_series.h): *candela error* is the RMS over the "
       "sphere (solid-angle weighted) of the resampled Type C table minus the reference's, in % of the "
       "reference's peak intensity, with the reference's own noise variance taken out; *cube-map RMSE* is "
       "the thesis's RMSE of the texel intensities after scaling both maps by their means, likewise. "
       "*Time* is the shared tracing time plus the series's own filter time (one filter application per "
       "iteration; all filtered series filter the same trace, since the filter does not change the "
       "photons); computing the errors is not charged. Iterations grow by √2 from a first sparse one.\n\n";

  const double target = outcomes.empty() ? 1.0 : outcomes.front().settings.target_pct;
  const double cube_target = outcomes.empty() ? 0.1 : outcomes.front().settings.cube_target;
  for (const bool cube : {false, true}) {
    const char* cells =
        "Each cell: time, and photons traced (timings depend on the machine's load; photon counts do not, "
        "for a seed). ≤: already at the first iteration; >: not reached in the run.\n\n";
    if (cube)
      s << "## Time to cube-map RMSE " << format_value(cube_target, 3)
        << " (the thesis's measure)\n\nRelative to the peak, a candela error is small wherever the peak "
           "towers over the rest (the downlight's collimated beam); the thesis's RMSE after mean scaling "
           "weighs every texel alike and tells the settings apart there too.\n\n";
    else
      s << "## Time to " << format_value(target, 3) << " % RMS candela error\n\n" << cells;
    s << "| sample | raw | best fixed-threshold filter | adaptive filter |"
      << (guided ? " guided, raw | guided, adaptive |" : "") << (sobol ? " Sobol', raw | Sobol', adaptive |" : "")
      << "\n|---|---|---|---|" << (guided ? "---|---|" : "") << (sobol ? "---|---|" : "") << "\n";
    const double level = cube ? cube_target : target;
    for (const BenchOutcome& o : outcomes) {
      s << "| " << o.name << " | ";
      if (const SeriesResult* raw = find(o.series, "raw")) s << headline_cell(*raw, level, cube);
      s << " | ";
      if (const SeriesResult* best = best_fixed(o.series, cube))
        s << headline_cell(*best, level, cube) << " (" << best->spec.label << ")";
      s << " | ";
      if (const SeriesResult* a = find(o.series, "adaptive")) s << headline_cell(*a, level, cube);
      s << " |";
      if (guided) {
        for (const char* name : {"guided", "guided-adaptive"}) {
          s << " ";
          if (const SeriesResult* g = find(o.series, name)) s << headline_cell(*g, level, cube);
          s << " |";
        }
      }
      if (sobol) {
        for (const char* name : {"sobol", "sobol-adaptive"}) {
          s << " ";
          if (const SeriesResult* g = find(o.series, name)) s << headline_cell(*g, level, cube);
          s << " |";
        }
      }
      s << "\n";
    }
    s << "\n";
  }

  for (const BenchOutcome& o : outcomes) {
    const Reference& r = o.reference;
    s << "## " << o.name << "\n\n";
    s << "Model `" << o.model << "`; " << o.settings.photons << " photons per series from " << o.settings.first_photons
      << " (seed " << o.settings.seed << "), cube map of " << o.settings.face_size << "² texels per face, table "
      << o.grid << ".\n";
    s << "Reference: " << r.key.photons << " photons (seed " << r.key.seed << "), traced in "
      << format_value(r.trace_s, 3) << " s on " << r.threads << " threads"
      << (r.reused ? " (cached)" : "") << ". Its own noise, candela: " << format_value(r.noise.table_estimated_pct, 3)
      << " % estimated from photon statistics, " << format_value(r.noise.table_measured_pct, 3)
      << " % measured from its two halves; cube map: " << format_value(r.noise.cube_map_estimated, 3) << " and "
      << format_value(r.noise.cube_map_measured, 3) << ". That is "
      << format_value(r.noise.table_estimated_pct / o.smallest_raw_error_pct, 2)
      << " × the smallest raw candela error charted (" << format_value(o.smallest_raw_error_pct, 3)
      << " %), and its variance is subtracted.\n\n";
    s << "| series | time to " << format_value(target, 3) << " % | photons to " << format_value(target, 3)
      << " % | time to RMSE " << format_value(cube_target, 3)
      << " | candela RMS, 1st iteration [%] | candela RMS / max / flux error at the end [%] | cube RMSE, 1st "
         "iteration / at the end | slope (candela, cube) | filter [ms/iteration] |\n"
         "|---|---|---|---|---|---|---|---|---|\n";
    for (const SeriesResult& sr : o.series) {
      if (sr.points.empty()) continue;
      const SeriesPoint& first = sr.points.front();
      const SeriesPoint& last = sr.points.back();
      s << "| " << sr.spec.label << " | " << time_to_target(sr, target) << " | " << photons_text(sr.photons_to_target)
        << " | " << time_to_target(sr, cube_target, true) << " | " << format_value(first.table.rms_pct, 3) << " | "
        << format_value(last.table.rms_pct, 3) << " / " << format_value(last.table.max_pct, 3) << " / "
        << format_value(last.table.flux_pct, 2) << " | " << format_value(first.cube.rmse, 3) << " / "
        << format_value(last.cube.rmse, 3) << " | " << format_value(sr.table_slope, 3) << ", "
        << format_value(sr.cube_slope, 3) << " | " << format_value(sr.filter_ms_per_iteration, 3) << " |\n";
    }
    s << "\n";
    for (const char* chart : {"candela-time", "cubemap-time", "photons", "psnr-snr"}) {
      const std::string link = relative_link((fs::path(o.directory) / (std::string(chart) + ".svg")).string(), page_path);
      s << "![" << o.name << ": " << chart << "](" << link << ")\n\n";
    }
  }
  return s.str();
}

}  // namespace gonio::app
