#include "tools/bench/bench_series.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "sim/simulation.h"
#include "tools/run/progressive_run.h"

namespace gonio::cli {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void summarise(SeriesResult& r, double target_pct, double cube_target) {
  std::vector<double> time, traced, cube, table;
  for (const SeriesPoint& p : r.points) {
    time.push_back(p.time_s);
    traced.push_back(static_cast<double>(p.photons_traced));
    cube.push_back(p.cube.rmse);
    table.push_back(p.table.rms_pct);
  }
  r.time_to_target_s = sim::crossing(time, table, target_pct);
  r.photons_to_target = sim::crossing(traced, table, target_pct);
  r.time_to_cube_target_s = sim::crossing(time, cube, cube_target);
  r.photons_to_cube_target = sim::crossing(traced, cube, cube_target);
  r.cube_slope = sim::log_log_slope(traced, cube);
  r.table_slope = sim::log_log_slope(traced, table);
  r.filter_ms_per_iteration =
      r.points.empty() ? 0.0 : 1e3 * r.points.back().filter_s / static_cast<double>(r.points.size());
}

}  // namespace

std::vector<std::uint64_t> photon_schedule(std::uint64_t first, std::uint64_t photons, int steps_per_doubling) {
  GONIO_CHECK(first >= 1 && photons >= 1 && steps_per_doubling >= 1);
  std::vector<std::uint64_t> out;
  for (int k = 0;; ++k) {
    const double p = static_cast<double>(first) * std::exp2(static_cast<double>(k) / steps_per_doubling);
    if (!(p < static_cast<double>(photons))) break;
    const auto n = static_cast<std::uint64_t>(std::llround(p));
    if (n >= photons) break;
    if (out.empty() || n > out.back()) out.push_back(n);
  }
  out.push_back(photons);
  return out;
}

std::vector<SeriesSpec> default_series(bool importance, sim::SamplerKind sampler, bool add_sobol) {
  std::vector<SeriesSpec> out;
  out.push_back({"raw", "raw", false, {}, false});
  for (const auto& [interp, word] :
       {std::pair{sim::Interpolation::Bilinear, "bilinear"}, std::pair{sim::Interpolation::Bilateral, "bilateral"}}) {
    for (int threshold : {50, 100, 150, 200, 300}) {
      sim::PreviewFilterParams p;
      p.interpolation = interp;
      p.adaptive = false;
      p.threshold_photons = threshold;
      out.push_back({std::string(word) + "-" + std::to_string(threshold),
                     std::string(word) + " " + std::to_string(threshold), true, p, false});
    }
  }
  out.push_back({"adaptive", "adaptive (default filter)", true, sim::PreviewFilterParams{}, false});
  if (importance) {
    out.push_back({"guided", "guided emission, raw", false, {}, true});
    out.push_back({"guided-adaptive", "guided emission, adaptive", true, sim::PreviewFilterParams{}, true});
  }
  if (sampler == sim::SamplerKind::Sobol) {
    for (SeriesSpec& s : out) {
      s.sampler = sampler;
      s.label = "Sobol' " + s.label;
    }
  } else if (add_sobol) {
    out.push_back({"sobol", "Sobol' raw", false, {}, false, sim::SamplerKind::Sobol});
    out.push_back({"sobol-adaptive", "Sobol', adaptive", true, sim::PreviewFilterParams{}, false,
                   sim::SamplerKind::Sobol});
  }
  return out;
}

Result<std::vector<SeriesResult>> run_series(const sim::SceneDesc& scene, const BenchSettings& settings,
                                             const std::vector<SeriesSpec>& specs,
                                             const sim::ConvergenceReference& reference,
                                             const std::function<void(const BenchProgress&)>& progress) {
  const std::vector<std::uint64_t> schedule =
      photon_schedule(settings.first_photons, settings.photons, settings.steps_per_doubling);
  std::vector<SeriesResult> results(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) results[i].spec = specs[i];

  // One run per (guided, sampler); the filtered series share their run's trace.
  using Kind = sim::SamplerKind;
  for (const auto& [guided, sampler] : {std::pair{false, Kind::Random}, std::pair{true, Kind::Random},
                                        std::pair{false, Kind::Sobol}, std::pair{true, Kind::Sobol}}) {
    std::vector<std::size_t> mine;
    for (std::size_t i = 0; i < specs.size(); ++i)
      if (specs[i].guided == guided && specs[i].sampler == sampler) mine.push_back(i);
    if (mine.empty()) continue;

    sim::SimulationSettings s;
    s.photons_per_iteration = 1;  // every iteration below names its size
    s.iterations = 1;
    s.seed = settings.seed;
    s.sampler = sampler;
    s.sobol_replicates = settings.sobol_replicates;
    s.threads = settings.threads;
    s.max_bounces = settings.max_bounces;
    s.face_size = settings.face_size;
    s.bvh_quality = sim::EmbreeSceneOptions::Quality::High;  // one tree for every photon count
    if (guided) {
      s.importance = settings.importance_settings;
      s.importance.enabled = true;
    }
    auto created = sim::Simulation::create(scene, s);
    if (!created.ok()) return created.error();
    sim::Simulation& sim = created.value();
    std::optional<sim::PreviewFilter> filter;
    for (std::size_t i : mine)
      if (specs[i].filtered && !filter) filter.emplace(settings.face_size, specs[i].filter);
    std::vector<double> filter_s(specs.size(), 0.0);

    for (std::size_t k = 0; k < schedule.size(); ++k) {
      // One iteration; run_iteration takes < 2³² photons at a time.
      while (sim.stats().photons < schedule[k])
        sim.run_iteration(std::min<std::uint64_t>(schedule[k] - sim.stats().photons, 0xffffffffu));
      const sim::SimulationStats st = sim.stats();
      const sim::FarField field = sim.far_field();
      const std::vector<double> raw = sim::texel_intensities(field);
      // The run's own error estimate, for its raw series (once per iteration).
      const bool any_raw = std::any_of(mine.begin(), mine.end(), [&](std::size_t i) { return !specs[i].filtered; });
      const double estimated = any_raw ? estimated_rms_error_pct(sim, reference.resampler())
                                       : std::numeric_limits<double>::quiet_NaN();
      for (std::size_t i : mine) {
        std::span<const double> map = raw;
        if (specs[i].filtered) {
          filter->set_params(specs[i].filter);
          const auto start = std::chrono::steady_clock::now();
          filter->apply(field);
          filter_s[i] += seconds_since(start);
          map = filter->intensity_cd();
        }
        SeriesPoint p;
        p.iteration = static_cast<int>(k) + 1;
        p.photons = st.photons;
        p.photons_traced = st.photons_traced;
        p.trace_s = st.trace_s;
        p.filter_s = filter_s[i];
        p.time_s = p.trace_s + p.filter_s;
        p.cube = reference.cube_map_error(map);
        p.table = reference.table_error(map);
        p.estimated_rms_pct = specs[i].filtered ? std::numeric_limits<double>::quiet_NaN() : estimated;
        results[i].points.push_back(p);
      }
      if (progress)
        progress({guided ? (sampler == Kind::Sobol ? "guided, sobol" : "guided")
                         : (sampler == Kind::Sobol ? "sobol" : "plain"),
                  static_cast<int>(k) + 1, static_cast<int>(schedule.size()),
                  st.photons});
    }
  }
  for (SeriesResult& r : results) summarise(r, settings.target_pct, settings.cube_target);
  return results;
}

}  // namespace gonio::cli
