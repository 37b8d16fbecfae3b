// gonio optimize as a library function (tools/run/optimize_run.h).
#include "tools/run/optimize_run.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <system_error>
#include <thread>

#include "design/design_export.h"
#include "design/design_file.h"
#include "design/design_scene.h"
#include "io/model/cad.h"
#include "io/outputs/intensity_diagram.h"
#include "io/outputs/plot.h"
#include "io/photometric/photometric_file.h"
#include "io/support/bytes.h"
#include "io/support/file_io.h"
#include "io/support/text.h"
#include "photometry/compare.h"
#include "photometry/error_at.h"
#include "photometry/format.h"
#include "photometry/ugr.h"
#include "sim/distributed_gather.h"
#include "sim/ledger.h"
#include "tools/run/json_figures.h"
#include "tools/run/optimize_state.h"
#include "tools/run/photometric_input.h"
#include "tools/run/photometric_report.h"
#include "tools/run/resampler_cache.h"
#include "tools/run/simulation_outputs.h"

namespace gonio::app {
namespace {

namespace fs = std::filesystem;

// The escaped photons of a finished simulation, in the photometric frame,
// each with its flux, and the light output ratio.
std::vector<design::MeritPhoton> escaped_photons(const sim::Simulation& simulation,
                                                 const std::vector<sim::EscapedRay>& rays, double* lor) {
  const double total = simulation.total_flux_lm();
  const double photons = static_cast<double>(simulation.stats().photons);
  const double per_unit = photons > 0.0 ? total / photons / static_cast<double>(sim::kPowerUnits) : 0.0;
  const photometry::PhotometricFrame& frame = simulation.scene().frame;
  std::vector<design::MeritPhoton> out;
  out.reserve(rays.size());
  double escaped = 0.0;
  for (const sim::EscapedRay& r : rays) {
    const double flux = per_unit * static_cast<double>(r.power_units);
    out.push_back({frame.to_local(r.direction), flux});
    escaped += flux;
  }
  *lor = total > 0.0 ? escaped / total : 0.0;
  return out;
}

// What the merit's terms need of the traced design beyond its photons: the
// luminous opening (for UGR: as gonio simulate finds it, from the points the
// evaluation's own downward escapes leave from, so the same photons in every
// evaluation) and the size [mm] of every surface (for the size limits).
design::MeritGeometry merit_geometry(const design::MeritSpec& spec, const sim::Simulation& simulation,
                                     const std::vector<sim::EscapedRay>& rays) {
  design::MeritGeometry g;
  if (spec.ugr) {
    const photometry::PhotometricFrame& frame = simulation.scene().frame;
    std::vector<Vec3> exits;
    for (const sim::EscapedRay& r : rays)
      if (frame.to_local(r.direction).z < 0.0) exits.push_back(frame.to_local(r.origin));
    g.opening = opening_of_exits(exits).opening;
  }
  if (spec.size) {
    const photometry::PhotometricFrame& frame = simulation.scene().frame;
    double radius = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    sim::for_each_placed_vertex(simulation.scene(), [&](const Vec3& world) {
      const Vec3 p = frame.to_local(world);
      radius = std::max(radius, std::hypot(p.x, p.y));
      lo = std::min(lo, p.z);
      hi = std::max(hi, p.z);
    });
    g.radius_mm = 1000.0 * radius;
    g.height_mm = hi >= lo ? 1000.0 * (hi - lo) : 0.0;
  }
  return g;
}

// The hard limits' values c of a merit (merit_limit_names' order).
std::vector<double> limit_values(const design::MeritValue& m) {
  std::vector<double> c;
  for (const design::MeritLimitValue& l : m.limits) c.push_back(l.c);
  return c;
}

// The limits of a merit as report.json holds them.
nlohmann::json limits_json(const design::MeritValue& m) {
  nlohmann::json out = nlohmann::json::array();
  for (const design::MeritLimitValue& l : m.limits)
    out.push_back({{"name", l.name}, {"value", json_number(l.value)}, {"limit", l.limit}, {"c", json_number(l.c)},
                   {"within", l.c <= 0.0}});
  return out;
}

// The limits' tables as read (report.json's optimize.merit.limit_tables).
nlohmann::json limit_tables_json(const design::MeritSpec& spec) {
  nlohmann::json t = nlohmann::json::object();
  const auto optional = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
  if (spec.max_cd_above)
    t["max_cd_above"] = {{"gamma", spec.max_cd_above->gamma_deg},
                         {"to", spec.max_cd_above->to_deg},
                         {"limit", optional(spec.max_cd_above->limit_cd)},
                         {"weight", spec.max_cd_above->weight}};
  if (spec.ugr)
    t["ugr"] = {{"limit", optional(spec.ugr->limit)},
                {"weight", spec.ugr->weight},
                {"room", {spec.ugr->x_h, spec.ugr->y_h}},
                {"reflectances",
                 {100.0 * photometry::kUgrReflectances[spec.ugr->reflectance_set][0],
                  100.0 * photometry::kUgrReflectances[spec.ugr->reflectance_set][1],
                  100.0 * photometry::kUgrReflectances[spec.ugr->reflectance_set][2]}},
                {"view", spec.ugr->view == 1 ? "crosswise" : spec.ugr->view == 2 ? "endwise" : "larger"}};
  if (spec.bug) {
    const auto cls = [](int c) { return c >= 0 ? nlohmann::json(c) : nlohmann::json(nullptr); };
    t["bug"] = {{"b", cls(spec.bug->b)},
                {"u", cls(spec.bug->u)},
                {"g", cls(spec.bug->g)},
                {"table", spec.bug->symmetric ? "symmetric" : "asymmetric"},
                {"weight", spec.bug->weight}};
  }
  if (spec.size)
    t["size"] = {{"radius", optional(spec.size->radius_mm)},
                 {"height", optional(spec.size->height_mm)},
                 {"weight", spec.size->weight}};
  return t;
}

// What one traced design gives: its merit's terms, or the run's error.
struct Traced {
  std::optional<design::MeritValue> merit;
  std::vector<double> binned;  // the candela at the merit grid's nodes (design::bin_photons)
  std::string error;
  std::optional<SimulatePlan> plan;
  std::optional<SimulateResult> result;
  double estimated_error_pct = std::nan("");
};

// Over MPI ranks (gonio optimize under mpirun): a shared trace's escapes,
// each rank's photons, as bytes (io::append_bytes); every rank's put together
// in the photons' order (the ranks' shares are contiguous ranges of chunks, in
// rank order), which is the order one process keeps them in.
//
// Reads a value back. Unlike io::ByteReader, past the end it gives a zero
// value and still moves AT on, so that the loops over a message, which stop
// once AT reaches its end, end on a short message too.
template <class T>
T take(const std::string& bytes, std::size_t& at) {
  T value{};
  if (at + sizeof(T) <= bytes.size()) std::memcpy(&value, bytes.data() + at, sizeof(T));
  at += sizeof(T);
  return value;
}

// `origins`: whether the merit needs where the photons leave (UGR's
// opening); without, they are not sent (48 bytes a photon instead of 72).
std::vector<sim::EscapedRay> job_escaped_rays(const sim::Ranks& ranks, const std::vector<sim::EscapedRay>& mine,
                                              bool origins) {
  const std::size_t each = sizeof(std::uint64_t) * 2 + sizeof(double) * (origins ? 6 : 3);
  std::string bytes;
  bytes.reserve(mine.size() * each);
  for (const sim::EscapedRay& r : mine) {
    io::append_bytes(bytes, r.photon);
    if (origins)
      for (double v : {r.origin.x, r.origin.y, r.origin.z}) io::append_bytes(bytes, v);
    for (double v : {r.direction.x, r.direction.y, r.direction.z}) io::append_bytes(bytes, v);
    io::append_bytes(bytes, r.power_units);
  }
  const std::vector<std::string> gathered = sim::gather_bytes(ranks, bytes);
  std::size_t count = 0;
  for (const std::string& theirs : gathered) count += theirs.size() / each;
  std::vector<sim::EscapedRay> all;
  all.reserve(count);
  for (const std::string& theirs : gathered) {
    std::size_t at = 0;
    while (at + each <= theirs.size()) {
      sim::EscapedRay r;
      r.photon = take<std::uint64_t>(theirs, at);
      if (origins) {
        r.origin.x = take<double>(theirs, at);
        r.origin.y = take<double>(theirs, at);
        r.origin.z = take<double>(theirs, at);
      }
      r.direction.x = take<double>(theirs, at);
      r.direction.y = take<double>(theirs, at);
      r.direction.z = take<double>(theirs, at);
      r.power_units = take<std::uint64_t>(theirs, at);
      all.push_back(r);
    }
  }
  // The ranks' shares are contiguous in rank order, so the rays are already
  // in the photons' order; sorted only where they are not.
  const auto by_photon = [](const sim::EscapedRay& a, const sim::EscapedRay& b) { return a.photon < b.photon; };
  if (!std::is_sorted(all.begin(), all.end(), by_photon)) std::stable_sort(all.begin(), all.end(), by_photon);
  return all;
}

// What a rank made of one point of a CMA-ES generation: its merit, and
// bytes for the other ranks (the point's candela for rank 0's state.json).
struct BatchPoint {
  Result<double> merit = make_error("not evaluated");
  std::string payload;
};

// A CMA-ES generation over MPI ranks: point i is traced by rank i mod K
// (`evaluate`, each rank's points `jobs` at a time), and every rank gets
// every merit back in the points' order, whatever rank made it. Then, in a
// second gather, the payloads of the points that may become the best as
// the generation is recorded in order (each merit at most every earlier
// one's: ~ln λ of λ points), `on_other` each one another rank made.
std::vector<Result<double>> job_batch(const sim::Ranks& ranks, std::size_t points, int jobs,
                                      const std::function<BatchPoint(std::size_t)>& evaluate,
                                      const std::function<void(std::size_t, const std::string&)>& on_other) {
  const std::size_t k = static_cast<std::size_t>(ranks.size()), me = static_cast<std::size_t>(ranks.rank());
  std::vector<std::size_t> mine;
  for (std::size_t i = me; i < points; i += k) mine.push_back(i);
  std::vector<std::optional<BatchPoint>> made(mine.size());
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t j = next++; j < mine.size(); j = next++) made[j].emplace(evaluate(mine[j]));
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < std::min<int>(std::max(jobs, 1), static_cast<int>(mine.size())); ++t) helpers.emplace_back(work);
  work();
  for (std::thread& t : helpers) t.join();
  std::string bytes;
  for (std::size_t j = 0; j < mine.size(); ++j) {
    const Result<double>& m = made[j]->merit;
    const std::string error = m.ok() ? std::string() : m.error().message;
    io::append_bytes(bytes, static_cast<std::uint64_t>(mine[j]));
    io::append_bytes(bytes, static_cast<std::uint8_t>(m.ok() ? 1 : 0));
    io::append_bytes(bytes, m.ok() ? *m : 0.0);
    io::append_bytes(bytes, static_cast<std::uint64_t>(error.size()));
    bytes += error;
  }
  std::vector<Result<double>> out(points, Result<double>(make_error("no rank made this evaluation")));
  const std::vector<std::string> gathered = sim::gather_bytes(ranks, bytes);
  for (std::size_t from = 0; from < gathered.size(); ++from) {
    const std::string& theirs = gathered[from];
    std::size_t at = 0;
    while (at < theirs.size()) {
      const std::uint64_t index = take<std::uint64_t>(theirs, at);
      const bool ok = take<std::uint8_t>(theirs, at) != 0;
      const double merit = take<double>(theirs, at);
      const std::uint64_t length = take<std::uint64_t>(theirs, at);
      const std::string error = theirs.substr(std::min(at, theirs.size()), length);
      at += length;
      if (index < points) out[index] = ok ? Result<double>(merit) : Result<double>(make_error(error));
    }
  }
  std::vector<bool> may_lead(points, false);
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points; ++i)
    if (out[i].ok() && std::isfinite(*out[i]) && *out[i] <= lowest) {
      lowest = *out[i];
      may_lead[i] = true;
    }
  bytes.clear();
  for (std::size_t j = 0; j < mine.size(); ++j)
    if (may_lead[mine[j]]) {
      io::append_bytes(bytes, static_cast<std::uint64_t>(mine[j]));
      io::append_bytes(bytes, static_cast<std::uint64_t>(made[j]->payload.size()));
      bytes += made[j]->payload;
    }
  const std::vector<std::string> payloads = sim::gather_bytes(ranks, bytes);
  for (std::size_t from = 0; from < payloads.size(); ++from) {
    const std::string& theirs = payloads[from];
    std::size_t at = 0;
    while (at < theirs.size()) {
      const std::uint64_t index = take<std::uint64_t>(theirs, at);
      const std::uint64_t length = take<std::uint64_t>(theirs, at);
      const std::string payload = theirs.substr(std::min(at, theirs.size()), length);
      at += length;
      if (index < points && from != me && on_other) on_other(index, payload);
    }
  }
  return out;
}

// Why a run that found no flat merit still cannot improve the design: every
// variable of the best at one of its bounds ("pinned": the merit falls on
// beyond them), or the best is the start itself ("no_improvement": no
// evaluation of any stage bettered it). Empty where neither, and for a run
// that Ctrl-C or --max-time cut short (its stopped_by says so).
struct CannotImprove {
  std::string reason, kind;
};
CannotImprove why_no_improvement(const design::OptimizeResult& run, const std::vector<design::OptimizeVariable>& variables) {
  if (run.best_values.size() != variables.size() || variables.empty() || run.stopped_by == "cancelled" ||
      run.stopped_by == "time")
    return {};
  bool pinned = true, at_start = true;
  std::string bounds;
  for (std::size_t i = 0; i < variables.size(); ++i) {
    const design::OptimizeVariable& v = variables[i];
    const double x = run.best_values[i], tol = 1e-9 * (v.max - v.min);
    const bool at_min = std::abs(x - v.min) <= tol, at_max = std::abs(x - v.max) <= tol;
    if (!at_min && !at_max) pinned = false;
    if (std::abs(x - v.value) > tol) at_start = false;
    bounds += (bounds.empty() ? "" : ", ") + v.name + " = " + format_number(x, 8) +
              (at_min ? " (its min)" : at_max ? " (its max)" : "");
  }
  if (pinned)
    return {"every variable of the best design lies at a bound (" + bounds + ")" +
                (at_start ? ", where it started, and no evaluation bettered the start" : "") +
                ": the merit falls on beyond the bounds, so the optimiser cannot improve the design within them; "
                "widen the bounds",
            "pinned"};
  if (at_start)
    return {"no evaluation bettered the start (" + bounds + ", merit " + format_number(run.start_merit, 6) + " in " +
                std::to_string(run.evaluations) +
                " evaluations): the start is a local minimum at these steps and photons, or the evaluations "
                "were too few to leave it",
            "no_improvement"};
  return {};
}

}  // namespace

nlohmann::json evaluation_json(const design::EvaluationRecord& r, const std::vector<design::OptimizeVariable>& variables) {
  nlohmann::json values = nlohmann::json::object();
  for (std::size_t i = 0; i < variables.size() && i < r.values.size(); ++i) values[variables[i].name] = r.values[i];
  nlohmann::json e = {{"index", r.index},  {"stage", r.stage + 1}, {"merit", json_number(r.merit)},
                      {"best", json_number(r.best)}, {"photons", r.photons}, {"seed", r.seed},
                      {"time_s", r.time_s}, {"values", values}};
  if (r.stage < 0) e["stage"] = "noise";
  if (!r.error.empty()) e["error"] = r.error;
  if (r.violation > 0.0) e["violation"] = r.violation;  // the hard limits' largest excess (COBYLA)
  return e;
}

Status write_history_chart(const std::string& path, const std::vector<design::EvaluationRecord>& history,
                           const std::string& title) {
  io::Series merit{"merit", {}, {}, io::LineStyle::Dotted, true};
  io::Series best{"best so far", {}, {}, io::LineStyle::Solid, false};
  io::Series noise{"best, independent seeds", {}, {}, io::LineStyle::Solid, true};
  io::Series best_time{"best so far", {}, {}, io::LineStyle::Solid, false};
  for (const design::EvaluationRecord& r : history) {
    const double index = static_cast<double>(r.index);
    if (r.stage < 0) {
      noise.x.push_back(index);
      noise.y.push_back(r.merit);
      continue;
    }
    merit.x.push_back(index);
    merit.y.push_back(r.merit);
    best.x.push_back(index);
    best.y.push_back(r.best);
    best_time.x.push_back(r.time_s);
    best_time.y.push_back(r.best);
  }
  io::LineChart by_evaluation{"merit by evaluation", "evaluation", "merit", false, true, {}, {}, {}, {}, true, {}};
  by_evaluation.series = {merit, best};
  if (!noise.x.empty()) by_evaluation.series.push_back(noise);
  io::LineChart by_time{"best merit by wall time", "wall time [s]", "merit", false, true, {}, {}, {}, {}, true, {}};
  by_time.series = {best_time};
  io::Figure figure;
  figure.title = title;
  figure.charts = {by_evaluation, by_time};
  return io::write_figure(path, figure);
}

Result<OptimizeRunOutcome> optimize_design(const OptimizeRunOptions& options, const OptimizeRunHooks& given_hooks,
                                           std::chrono::steady_clock::time_point start, bool* usage) {
  // Under MPI every rank runs what follows in step; rank 0 alone tells and writes.
  const sim::Ranks* ranks = options.ranks && options.ranks->distributed() ? options.ranks : nullptr;
  const bool lead = !ranks || ranks->rank() == 0;
  const std::string rank_tag = ranks ? "r" + std::to_string(ranks->rank()) + "-" : std::string();
  const OptimizeRunHooks no_hooks;
  const OptimizeRunHooks& hooks = lead ? given_hooks : no_hooks;
  const std::string& design_path = options.design_path;
  std::string target_path = options.target_path;
  const std::string& out_dir = options.out_dir;
  const design::OptimizeMethod method = options.method;
  const long long max_evals = options.max_evals, stages = options.stages, seed = options.seed,
                  threads = options.threads, final_photons = options.final_photons;
  const std::optional<double>& photons_per_bin = options.photons_per_bin;
  const double gamma_step = options.gamma_step, max_time = options.max_time;
  const bool no_smooth = options.no_smooth;
  const std::optional<std::string>& scan = options.scan;
  std::string name = options.name;
  if (name.empty()) name = design::model_stem(design_path);
  if (out_dir.empty()) {
    if (usage) *usage = true;
    return make_error("--out DIR is required");
  }
  if (!design::is_design_path(design_path)) {
    if (usage) *usage = true;
    return make_error("DESIGN must be a design file (NAME.design.toml), got " + io::shown(design_path));
  }
  if (name.empty() || name.find_first_of("/\\*?[]") != std::string::npos || name.front() == '.') {
    if (usage) *usage = true;
    return make_error("--name must be a plain name (no / \\ * ? [ ], not starting with .)");
  }
  // The design, its variables and merit.
  Result<design::Design> read = design::read_design_file(design_path);
  if (!read.ok()) return read.error();
  design::Design design = std::move(read.value());
  std::vector<design::OptimizeVariable> variables;
  for (const design::Variable& v : design.variables) {
    if (!v.min || !v.max)
      return make_error(design.path, v.line, "variable '" + v.name + "' has no " + (!v.min ? "min" : "max") +
                                                 ": the optimiser searches between a variable's bounds");
    if (!(*v.min < *v.max))
      return make_error(design.path, v.line, "variable '" + v.name + "': min must be below max to search between them");
    variables.push_back({v.name, v.value, *v.min, *v.max});
  }
  if (variables.empty())
    return make_error(design.path, "the design has no variables ({ value = …, min = …, max = … }) to optimise");
  io::TomlNode resolved = design::resolved_document(design);
  std::string merit_path = design.path;
  if (options.merit) {  // merit=: the table given replaces the design's
    if (!options.merit->is_table()) {
      if (usage) *usage = true;
      return make_error("merit must be a table of the [merit] keys (a dict)");
    }
    bool replaced = false;
    for (io::TomlMember& member : resolved.table)
      if (member.first == "merit") {
        member.second = *options.merit;
        replaced = true;
      }
    if (!replaced) resolved.table.push_back({"merit", *options.merit});
    merit_path = design.path + " (merit=)";
  }
  Result<design::MeritSpec> spec_read = design::read_merit(resolved, merit_path);
  if (!spec_read.ok()) return spec_read.error();
  design::MeritSpec spec = spec_read.value();
  if (no_smooth) spec.smooth = false;
  if (photons_per_bin) spec.photons_per_bin = *photons_per_bin;
  if (target_path.empty()) target_path = spec.target;
  if (target_path.empty()) {
    if (usage) *usage = true;
    return make_error("--target FILE is required (the design's [merit] table names none)");
  }
  Result<io::PhotometricFile> target_file = io::read_photometric_file(target_path, read_options(InputOptions{}));
  if (!target_file.ok()) return target_file.error();
  for (const Finding& f : target_file->findings)
    if (f.severity != Severity::Info && hooks.on_message) hooks.on_message(f.severity, format_finding(f));
  const design::MeritGrid grid = design::merit_grid(spec);
  Result<design::MeritTarget> target = design::merit_target(grid, target_file->distribution);
  if (!target.ok()) return make_error(target_path, target.error().message);
  design::set_target_ugr(spec, grid, &target.value());  // the [merit] ugr table's room, reflectances, view
  if (Status s = design::check_merit_terms(spec, *target, design.path, target_path); !s.ok())
    return s.error();
  const std::size_t limit_count = design::merit_limit_names(spec).size();
  // Hard limits: constraints for a method that takes them, else penalties.
  const bool as_constraints = limit_count > 0 && design::takes_constraints(method);

  // DIR with the files the design reads (its emitters' profiles and ray files).
  const fs::path folder = fs::absolute(fs::path(design_path)).parent_path();
  const std::vector<std::string> files = design::design_files(design_path);
  // Nothing is written over an input: the design, the target and the
  // design's files, nor over the copies of the latter in DIR (which the best
  // design reads), by any file the run writes into DIR.
  {
    std::vector<std::string> written;
    for (const char* ext : {".design.toml", ".ies", ".ldt", ".gltf", ".bin", ".step", ".gonio.toml"})
      written.push_back(name + ext);
    for (const char* own : {"report.json", "history.json", "history.svg", "compare.json", "compare.svg",
                            "state.json", "scan.json", ".evaluation.design.toml"})
      written.push_back(own);
    std::vector<std::string> inputs = files;  // the design, then its files
    inputs.push_back(target_path);
    if (!spec.target.empty()) inputs.push_back(spec.target);
    for (const std::string& w : written) {
      const fs::path path = (fs::path(out_dir) / w).lexically_normal();
      for (std::size_t i = 0; i < inputs.size(); ++i) {
        if (io::same_file(path.string(), inputs[i]))
          return make_error(inputs[i], "gonio optimize would write " + path.string() +
                                           " over this input (the same file); give another --out or --name");
        const fs::path rel = fs::absolute(fs::path(inputs[i])).lexically_normal().lexically_relative(folder);
        if (i > 0 && (fs::path(out_dir) / rel).lexically_normal() == path)
          return make_error(inputs[i], "the design's file is copied to " + path.string() +
                                           ", which gonio optimize writes as one of its outputs; give another --name");
      }
    }
  }
  if (Status s = io::make_directories(out_dir); !s.ok()) return s.error();
  for (std::size_t i = 1; i < files.size(); ++i) {
    const fs::path rel = fs::absolute(fs::path(files[i])).lexically_normal().lexically_relative(folder);
    if (rel.empty() || rel.is_absolute() || *rel.begin() == "..")
      return make_error(files[i] + ": the design's file lies outside its folder; gonio optimize copies the design's files into "
                  "DIR, so keep them in or under the design's folder");
    Result<std::string> bytes = io::read_file(files[i], std::size_t{1} << 30);
    if (!bytes.ok()) return bytes.error();
    const fs::path to = fs::path(out_dir) / rel;
    if (Status s = io::make_directories(to.parent_path().string()); !s.ok()) return s.error();
    if (Status s = io::write_file_atomic(to.string(), *bytes); !s.ok()) return s.error();
  }
  // The [merit] table's target, where it lies in or under the design's folder,
  // so that the best design's table names a file beside it.
  if (!spec.target.empty()) {
    const fs::path rel = fs::absolute(fs::path(spec.target)).lexically_normal().lexically_relative(folder);
    if (!rel.empty() && !rel.is_absolute() && *rel.begin() != "..") {
      Result<std::string> bytes = io::read_file(spec.target, std::size_t{256} << 20);
      if (!bytes.ok()) return bytes.error();
      const fs::path to = fs::path(out_dir) / rel;
      if (Status s = io::make_directories(to.parent_path().string()); !s.ok()) return s.error();
      if (Status s = io::write_file_atomic(to.string(), *bytes); !s.ok()) return s.error();
    }
  }
  const std::string evaluation_path =
      (fs::path(out_dir) / (lead ? std::string(".evaluation.design.toml") : ".evaluation-" + rank_tag + "main.design.toml"))
          .string();
  // Evaluations run `jobs` at a time (CMA-ES): each writes its own design file.
  const long long cores = std::max(1u, std::thread::hardware_concurrency());
  const long long jobs =
      method == design::OptimizeMethod::Cmaes ? (options.jobs > 0 ? options.jobs : cores) : 1;
  const long long trace_threads = threads > 0 ? threads : std::max(1LL, cores / jobs);
  std::atomic<unsigned long long> evaluations_made{0};
  // DIR/state.json for `gonio watch DIR` (set up once the search begins).
  std::optional<OptimizeProgress> progress;

  // One trace of the design at `values`: the merit of its escaped photons.
  const auto trace = [&](const std::vector<double>& values, std::uint64_t photons, std::uint64_t trace_seed,
                         const std::string& path, bool files_out, bool shared = true) {
    // shared: under MPI the ranks share the trace's photons (every rank calls
    // it at once); not: this rank traces it alone (its share of a generation).
    const bool share = shared && ranks != nullptr;
    Traced t;
    design::Design d = design;
    for (std::size_t i = 0; i < variables.size(); ++i)
      if (Status s = design::set_variable(d, variables[i].name, values[i]); !s.ok()) {
        t.error = s.error().message;
        return t;
      }
    if (Status s = io::write_file_atomic(path, design::write_design(d.document)); !s.ok()) {
      t.error = to_string(s.error());
      return t;
    }
    SimulateOptions o;
    o.photons = static_cast<long long>(photons);
    o.iterations = 1;
    o.seed = static_cast<long long>(trace_seed);
    o.threads = files_out ? threads : trace_threads;
    o.gamma_step = gamma_step;
    o.no_cache = true;
    o.next_event = "off";  // every escape a photon of the merit
    o.format_list = "ies,ldt";
    o.stem = name;
    if (files_out) o.out_dir = out_dir;
    Result<SimulatePlan> planned = plan_simulation(path, o);
    if (!planned.ok()) {
      t.error = planned.error().message;
      return t;
    }
    SimulatePlan* plan = &t.plan.emplace(std::move(planned.value()));
    plan->progressive.simulation.capture_escaped_photons = photons;
    if (share) plan->progressive.simulation.ranks = ranks;
    SimulateHooks sim_hooks;
    sim_hooks.on_message = [&](Severity severity, const std::string& text) {
      if (severity == Severity::Error && t.error.empty()) t.error = text;
      if (files_out && severity != Severity::Error && hooks.on_message) hooks.on_message(severity, text);
    };
    std::optional<sim::Resampler> resampler;
    if (files_out)
      sim_hooks.on_loaded = [&](const sim::SceneDesc& scene, const std::vector<Finding>&) {
        return &resampler.emplace(
            cached_resampler(plan->progressive.simulation.face_size, scene.frame, plan->grid, std::string()));
      };
    sim_hooks.on_traced = [&](const ProgressiveOutcome& run) {
      if (share) return;  // the merit of every rank's photons, below
      double lor = 0.0;
      const std::vector<design::MeritPhoton> escaped =
          escaped_photons(run.simulation, run.simulation.escaped_rays(), &lor);
      t.binned = design::bin_photons(grid, escaped);
      t.merit = design::evaluate_merit(spec, grid, *target, t.binned, lor,
                                       merit_geometry(spec, run.simulation, run.simulation.escaped_rays()));
      if (progress && !files_out && t.merit->error.empty())
        progress->traced(values, photons, trace_seed, t.binned, *t.merit);
      if (!t.merit->error.empty()) {
        t.error = t.merit->error;
        t.merit.reset();
      }
      t.estimated_error_pct = run.estimated_rms_error_pct;
    };
    t.result = simulate(*plan, sim_hooks, start);
    if (share && t.result) {  // every rank: the merit of the whole job's escapes
      const sim::Simulation& simulation = t.result->run.simulation;
      const std::vector<sim::EscapedRay> rays = job_escaped_rays(*ranks, simulation.escaped_rays(), spec.ugr.has_value());
      double lor = 0.0;
      const std::vector<double> binned = design::bin_photons(grid, escaped_photons(simulation, rays, &lor));
      t.merit = design::evaluate_merit(spec, grid, *target, binned, lor, merit_geometry(spec, simulation, rays));
      if (progress && !files_out && t.merit->error.empty())
        progress->traced(values, photons, trace_seed, binned, *t.merit);
      if (!t.merit->error.empty()) {
        t.error = t.merit->error;
        t.merit.reset();
      }
      t.estimated_error_pct = t.result->run.estimated_rms_error_pct;
    }
    if (!t.result) t.merit.reset();
    if (!t.result && t.error.empty()) t.error = "the trace failed";
    return t;
  };

  design::OptimizeOptions oo;
  oo.method = method;
  oo.max_evaluations = static_cast<int>(max_evals);
  oo.stages = static_cast<int>(stages);
  oo.seed = static_cast<std::uint64_t>(seed);
  oo.max_time_s = max_time;
  oo.jobs = static_cast<int>(jobs);
  oo.common_random = !options.no_common_random;
  oo.population = static_cast<int>(options.population);
  oo.start_photons = static_cast<std::uint64_t>(std::ceil(spec.photons_per_bin * static_cast<double>(grid.size())));
  if (hooks.on_start) hooks.on_start(variables, spec, grid.size(), oo.start_photons);
  if (options.evaluate_only) {  // the merit at given values, no optimisation
    OptimizeRunOutcome evaluated;
    evaluated.variables = variables;
    evaluated.scanned = true;
    evaluated.evaluate_photons = options.evaluate_photons > 0 ? options.evaluate_photons : oo.start_photons;
    for (const std::vector<double>& values : options.evaluate) {
      if (values.size() != variables.size()) {
        if (usage) *usage = true;
        return make_error("give " + std::to_string(variables.size()) + " values (the design's variables), not " +
                          std::to_string(values.size()));
      }
      Traced t = trace(values, evaluated.evaluate_photons, oo.seed, evaluation_path, false);
      if (!t.merit) return make_error(design_path, t.error);
      evaluated.merits.push_back(*t.merit);
    }
    std::error_code ignored_evaluate;
    fs::remove(evaluation_path, ignored_evaluate);
    return evaluated;
  }
  if (scan) {  // --scan VAR:N
    const std::size_t colon = scan->rfind(':');
    const double n_value =
        colon == std::string::npos ? 0.0 : io::parse_number(scan->substr(colon + 1)).value_or(0.0);
    const double* n = &n_value;
    const std::string var = colon == std::string::npos ? *scan : scan->substr(0, colon);
    std::size_t index = variables.size();
    for (std::size_t i = 0; i < variables.size(); ++i)
      if (variables[i].name == var) index = i;
    if (index == variables.size() || !(*n >= 2 && *n <= 100000) || *n != std::floor(*n)) {
      if (usage) *usage = true;
      return make_error("--scan " + io::shown(*scan) + ": give VAR:N, a variable of the design and 2 ≤ N ≤ 100000");
    }
    nlohmann::json rows = nlohmann::json::array();
    std::vector<double> values;
    for (const design::OptimizeVariable& v : variables) values.push_back(v.value);
    const design::OptimizeVariable& v = variables[index];
    for (int k = 0; k < static_cast<int>(*n); ++k) {
      values[index] = v.min + (v.max - v.min) * k / (*n - 1.0);
      Traced t = trace(values, oo.start_photons, oo.seed, evaluation_path, false);
      const double m = t.merit ? t.merit->merit : std::nan("");
      if (hooks.on_scan) hooks.on_scan(v.name, values[index], m, t.merit ? std::string() : t.error);
      rows.push_back({{"value", values[index]}, {"merit", json_number(m)}});
    }
    std::error_code ignored_scan;
    fs::remove(evaluation_path, ignored_scan);
    nlohmann::json out = {{"variable", v.name}, {"photons", oo.start_photons}, {"seed", oo.seed},
                          {"smooth", spec.smooth}, {"scan", rows}};
    if (Status s = io::write_file_atomic((fs::path(out_dir) / "scan.json").string(), out.dump(1) + "\n"); !s.ok())
      return s.error();
    OptimizeRunOutcome scanned;
    scanned.variables = variables;
    scanned.scanned = true;
    return scanned;
  }
  // The last trace's limits, for the constraints' call at the same point.
  struct LastTrace {
    std::vector<double> values;
    std::uint64_t photons = 0, seed = 0;
    std::optional<design::MeritValue> merit;
  } last;
  const auto traced_merit = [&](const std::vector<double>& values, std::uint64_t photons,
                                std::uint64_t trace_seed) -> Result<design::MeritValue> {
    if (last.merit && last.values == values && last.photons == photons && last.seed == trace_seed) return *last.merit;
    Traced t = trace(values, photons, trace_seed, evaluation_path, false);
    last = {values, photons, trace_seed, t.merit};
    if (!t.merit) return make_error(t.error);
    return *t.merit;
  };
  const design::MeritFunction merit = [&](const std::vector<double>& values, std::uint64_t photons,
                                          std::uint64_t trace_seed) -> Result<double> {
    // One file per evaluation where several run at once (CMA-ES's jobs,
    // which take no constraints: the last trace's cache is for one thread).
    std::optional<design::MeritValue> m;
    if (jobs > 1) {
      const std::string path =
          (fs::path(out_dir) / (".evaluation-" + rank_tag + std::to_string(evaluations_made++) + ".design.toml")).string();
      Traced t = trace(values, photons, trace_seed, path, false);
      std::error_code ignored_own;
      fs::remove(path, ignored_own);
      if (!t.merit) return make_error(t.error);
      m = *t.merit;
    } else {
      Result<design::MeritValue> traced = traced_merit(values, photons, trace_seed);
      if (!traced.ok()) return traced.error();
      m = *traced;
    }
    // COBYLA minimises the terms with the limits as constraints; the other
    // methods the terms with the limits' penalties.
    return as_constraints ? m->merit - m->penalty : m->merit;
  };
  if (as_constraints) {
    oo.constraint_count = limit_count;
    oo.constraints = [&](const std::vector<double>& values, std::uint64_t photons, std::uint64_t trace_seed) {
      Result<design::MeritValue> m = traced_merit(values, photons, trace_seed);
      return m.ok() ? limit_values(*m) : std::vector<double>(limit_count, 1.0);
    };
  }
  if (lead)
    progress.emplace((fs::path(out_dir) / "state.json").string(), design_path, target_path,
                     design::to_string(method), max_evals, max_time, variables, spec, grid, *target);
  if (ranks) {
    // The job's clock and its stop (rank 0's: --max-time, Ctrl-C) for every rank.
    oo.elapsed = [ranks](double local_s) { return ranks->gather(local_s).front(); };
    if (method == design::OptimizeMethod::Cmaes)
      oo.batch = [&](const std::vector<std::vector<double>>& points, std::uint64_t photons,
                     const std::vector<std::uint64_t>& seeds) {
        // With each merit its candela and the figures state.json shows, so
        // that rank 0's state has the best's whichever rank traced it.
        const auto evaluate = [&](std::size_t i) -> BatchPoint {
          const std::string path =
              (fs::path(out_dir) / (".evaluation-" + rank_tag + std::to_string(evaluations_made++) + ".design.toml"))
                  .string();
          Traced t = trace(points[i], photons, seeds[i], path, false, false);
          std::error_code ignored_own;
          fs::remove(path, ignored_own);
          if (!t.merit) return {make_error(t.error), {}};
          BatchPoint made{t.merit->merit, {}};
          for (double v : {t.merit->lor, t.merit->candela_rms_pct, t.merit->beam_deg}) io::append_bytes(made.payload, v);
          for (double v : t.binned) io::append_bytes(made.payload, v);
          return made;
        };
        const auto on_other = [&](std::size_t i, const std::string& payload) {
          if (!progress || payload.size() < 3 * sizeof(double)) return;
          std::size_t at = 0;
          design::MeritValue m;
          m.merit = std::nan("");
          m.lor = take<double>(payload, at);
          m.candela_rms_pct = take<double>(payload, at);
          m.beam_deg = take<double>(payload, at);
          std::vector<double> binned;
          while (at + sizeof(double) <= payload.size()) binned.push_back(take<double>(payload, at));
          progress->traced(points[i], photons, seeds[i], binned, m);
        };
        return job_batch(*ranks, points.size(), static_cast<int>(jobs), evaluate, on_other);
      };
  }
  const auto on_evaluation = [&](const design::EvaluationRecord& r) {
    if (progress) progress->evaluation(r);
    const bool go = hooks.on_evaluation ? hooks.on_evaluation(r) : true;
    if (!ranks) return go;
    // Every rank must have the same merit, to the bit: a rank with another
    // would drive its copy of the method to other points and the job would
    // hang in its next collective. Stop the job instead, saying so.
    const std::vector<double> merits = ranks->gather(r.merit);
    for (int k = 1; k < ranks->size(); ++k)
      if (std::memcmp(&merits[static_cast<std::size_t>(k)], &merits[0], sizeof(double)) != 0) {
        if (hooks.on_message)
          hooks.on_message(Severity::Error, "optimize: evaluation " + std::to_string(r.index) + ": " +
                                                ranks->name_of(k) + " has the merit " +
                                                format_number(merits[static_cast<std::size_t>(k)], 17) + ", rank 0 " +
                                                format_number(merits[0], 17) + ": the ranks diverged; stopping the job");
        ranks->abort(1);
      }
    return ranks->gather(static_cast<std::uint64_t>(go ? 1 : 0)).front() != 0;
  };
  Result<design::OptimizeResult> run = design::optimize(variables, merit, oo, on_evaluation);
  std::error_code ignored;
  fs::remove(evaluation_path, ignored);
  if (!run.ok()) {
    if (progress) progress->failed(design.path + ": " + run.error().message);
    return make_error(design.path, run.error().message);
  }
  // An optimisation that cannot improve: every evaluation of the first stage
  // (one seed, one photon count) within the merit's noise floor of the others.
  std::string cannot_improve;
  {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    int counted = 0;
    for (const design::EvaluationRecord& r : run->history)
      if (r.stage == 0 && std::isfinite(r.merit)) {
        lo = std::min(lo, r.merit);
        hi = std::max(hi, r.merit);
        ++counted;
      }
    const double floor = std::isfinite(run->noise_floor) ? run->noise_floor : 0.0;
    if (counted >= 2 && hi - lo <= std::max(floor, 1e-12 * std::abs(hi))) {
      cannot_improve = "every evaluation of stage 1 (" + std::to_string(counted) + ") has the merit " +
                       format_number(lo, 6) + (hi > lo ? " … " + format_number(hi, 6) : std::string()) +
                       ", within the merit's noise floor (" + format_number(floor, 3) +
                       "): the variables do not move the merit, so the optimiser cannot improve the design";
    }
  }
  std::string cannot_improve_kind = cannot_improve.empty() ? std::string() : "flat";
  if (cannot_improve.empty()) {
    const CannotImprove why = why_no_improvement(*run, variables);
    cannot_improve = why.reason;
    cannot_improve_kind = why.kind;
  }
  if (!cannot_improve.empty() && hooks.on_message)
    hooks.on_message(Severity::Warning, design.path + ": " + cannot_improve);

  // From here a failure of rank 0 says so in DIR/state.json too (gonio
  // watch DIR would otherwise show the run "running" for ever).
  const auto failed_after_search = [&](const Error& e) {
    if (progress) progress->failed(to_string(e));
    return e;
  };
  // The best design, traced with an independent seed into DIR.
  for (std::size_t i = 0; i < variables.size(); ++i)
    if (Status s = design::set_variable(design, variables[i].name, run->best_values[i]); !s.ok())
      return failed_after_search(s.error());
  const std::string best_path = (fs::path(out_dir) / (name + ".design.toml")).string();
  const std::uint64_t final_seed = static_cast<std::uint64_t>(seed) + 7'000'003ULL;
  const std::string own_best_path =
      lead ? best_path : (fs::path(out_dir) / (".best-" + rank_tag + "main.design.toml")).string();
  Traced final = trace(run->best_values, static_cast<std::uint64_t>(final_photons), final_seed, own_best_path, true);
  if (!lead) {  // the other ranks of an MPI job: their share of the final trace traced, nothing to write
    std::error_code ignored_best;
    fs::remove(own_best_path, ignored_best);
    if (!final.result || !final.merit) return make_error("the best design's final trace failed: " + final.error);
    OptimizeRunOutcome others;
    others.lead = false;
    others.variables = variables;
    others.run = std::move(run.value());
    others.cannot_improve = cannot_improve;
    others.cannot_improve_kind = cannot_improve_kind;
    return others;
  }
  if (!final.result || !final.result->files || !final.merit) {
    progress->failed("the best design's final trace failed: " + final.error);
    return make_error("the best design's final trace failed: " + final.error);
  }
  // The design file again, with a header (trace wrote it bare).
  const std::string text = design::write_design(
      design.document, {"Optimised by gonio optimize (docs/design.md) from " + fs::path(design_path).filename().string() +
                            " against " + fs::path(target_path).filename().string() + ".",
                        std::string("Method ") + design::to_string(method) + ", " + std::to_string(run->evaluations) +
                            " evaluations, merit " + format_number(run->best_merit, 5) + "."});
  // A file that cannot be written from here on (a full disk, a path taken
  // by a folder) does not stop the others: report.json lists it
  // (optimize.output_failures) and the run then fails.
  std::vector<std::string> output_failures;
  nlohmann::json files_written = nlohmann::json::array();
  if (Status s = io::write_file_atomic(best_path, text); !s.ok())
    output_failures.push_back(to_string(s.error()));
  else
    files_written.push_back(best_path);

  // history.json and the report.
  nlohmann::json history = nlohmann::json::array();
  for (const design::EvaluationRecord& r : run->history) history.push_back(evaluation_json(r, variables));
  const std::string history_path = (fs::path(out_dir) / "history.json").string();
  if (Status s = io::write_file_atomic(history_path, history.dump(1) + "\n"); !s.ok())
    output_failures.push_back(to_string(s.error()));
  else
    files_written.push_back(history_path);
  nlohmann::json vars = nlohmann::json::array();
  for (std::size_t i = 0; i < variables.size(); ++i)
    vars.push_back({{"name", variables[i].name},
                    {"start", variables[i].value},
                    {"best", run->best_values[i]},
                    {"min", variables[i].min},
                    {"max", variables[i].max}});
  nlohmann::json weights = nlohmann::json::array();
  for (const design::GammaWeight& w : spec.gamma_weights) weights.push_back({w.from_deg, w.to_deg, w.weight});
  const design::MeritValue& fm = *final.merit;
  nlohmann::json report = final.result->files->report;
  report["optimize"] = {
      {"design", design_path},
      {"target", target_path},
      {"method", design::to_string(method)},
      {"jobs", jobs},
      {"variables", vars},
      {"merit",
       {{"c_step_deg", spec.c_step_deg},
        {"gamma_step_deg", spec.gamma_step_deg},
        {"nodes", grid.size()},
        {"normalize", spec.absolute ? "absolute" : "flux"},
        {"smooth", spec.smooth},
        {"common_random_numbers", !options.no_common_random},
        {"photons_per_bin", spec.photons_per_bin},
        {"weights",
         {{"candela", spec.candela_weight},
          {"lor", spec.lor_weight},
          {"beam", spec.beam_weight},
          {"field", spec.field_weight}}},
        {"limits", design::merit_limit_names(spec)},
        {"limit_tables", limit_tables_json(spec)},
        {"limits_as", limit_count == 0 ? "none" : as_constraints ? "constraints" : "penalties"},
        {"gamma_weights", weights}}},
      {"evaluations", run->evaluations},
      {"stages", stages},
      {"stopped_by", run->stopped_by},
      {"start_merit", json_number(run->start_merit)},
      {"best_merit", json_number(run->best_merit)},
      {"stage_photons", run->final_photons},
      {"independent_merit", json_number(run->independent_merit)},
      {"noise_floor", json_number(run->noise_floor)},
      {"improvable", cannot_improve.empty()},
      {"final",
       {{"photons", final_photons},
        {"seed", final_seed},
        {"merit", json_number(fm.merit)},
        {"candela_rms_pct", json_number(fm.candela_rms_pct)},
        {"lor", json_number(fm.lor)},
        {"beam_angle_deg", json_number(fm.beam_deg)},
        {"target_beam_angle_deg", json_number(fm.target_beam_deg)},
        {"field_angle_deg", json_number(fm.field_deg)},
        {"target_field_angle_deg", json_number(fm.target_field_deg)},
        {"max_cd_above", json_number(fm.max_cd_above)},
        {"ugr", json_number(fm.ugr)},
        {"target_ugr", json_number(fm.target_ugr)},
        {"penalty", json_number(fm.penalty)},
        {"limits", limits_json(fm)},
        {"estimated_rms_error_pct", json_number(final.estimated_error_pct)}}},
      {"files", files_written},
      {"cannot_improve", cannot_improve.empty() ? nlohmann::json(nullptr) : nlohmann::json(cannot_improve)},
      {"cannot_improve_kind",
       cannot_improve_kind.empty() ? nlohmann::json(nullptr) : nlohmann::json(cannot_improve_kind)},
      {"ranks", ranks ? ranks->size() : 1},
      {"wall_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()}};
  OptimizeRunOutcome out;
  // The best design's geometry (glTF; STEP through gonio-cad where built),
  // the history's chart and the comparison with the target, as gonio compare
  // makes it. None of them fails the run: a missing one is said why.
  const auto extra = [&](const std::string& file, const Status& status) {
    if (status.ok()) {
      out.extra_files.push_back(file);
    } else {
      out.notes.push_back(file + " not written: " + to_string(status.error()));
    }
  };
  Result<design::Design> best_read = design::read_design_file(best_path);
  if (best_read.ok()) {
    const std::string gltf = (fs::path(out_dir) / (name + ".gltf")).string();
    extra(gltf, design::write_design_gltf(*best_read, gltf, io::tessellation_for_grid(gamma_step)));
    const std::string step = (fs::path(out_dir) / (name + ".step")).string();
    if (options.no_step) {
    } else if (!io::cad_supported()) {
      out.notes.push_back(step + " not written: this gonio was built without OpenCASCADE");
    } else {
      Result<design::StepExportInfo> written = design::write_design_step(*best_read, step);
      extra(step, written.ok() ? Status(Ok{}) : Status(written.error()));
    }
  } else {
    out.notes.push_back(best_path + " does not read back: " + to_string(best_read.error()));
  }
  const std::string chart = (fs::path(out_dir) / "history.svg").string();
  extra(chart, write_history_chart(chart, run->history,
                                   std::string(design::to_string(method)) + ", " + (spec.smooth ? "smooth" : "binned") +
                                       ": " + std::to_string(run->evaluations) + " evaluations"));
  const std::string traced_path = (fs::path(out_dir) / (name + ".ies")).string();
  Result<io::PhotometricFile> traced = io::read_photometric_file(traced_path, read_options(InputOptions{}));
  if (traced.ok()) {
    photometry::CompareOptions compare;
    compare.gamma_step_deg = 90.0 / std::max(1.0, std::round(90.0 / std::max(gamma_step, 2.5)));
    compare.normalize_flux = !spec.absolute;
    Result<photometry::Comparison> cmp = photometry::compare(target_file->distribution, traced->distribution, compare);
    if (cmp.ok()) {
      nlohmann::json against = compare_json(target_path, *target_file, traced_path, *traced, *cmp, compare);
      const std::string compare_svg = (fs::path(out_dir) / "compare.svg").string();
      io::OverlayOptions overlay;
      overlay.label_a = "target " + fs::path(target_path).filename().string();
      overlay.label_b = "best " + fs::path(traced_path).filename().string();
      overlay.scale_b = cmp->scale;
      overlay.title = compare.normalize_flux ? "the best design scaled to the target's flux" : "";
      Result<io::Figure> figure = io::overlay_diagram(target_file->distribution, traced->distribution, overlay);
      const Status plotted = figure.ok() ? io::write_figure(compare_svg, *figure) : Status(figure.error());
      extra(compare_svg, plotted);
      if (plotted.ok()) against["plot"] = compare_svg;
      const std::string compare_path = (fs::path(out_dir) / "compare.json").string();
      extra(compare_path, io::write_file_atomic(compare_path, against.dump(2) + "\n"));
      report["optimize"]["compare"] = against;
    } else {
      out.notes.push_back("no comparison with the target: " + cmp.error().message);
    }
  } else {
    out.notes.push_back("no comparison with the target: " + to_string(traced.error()));
  }
  for (const std::string& f : out.extra_files) report["optimize"]["files"].push_back(f);
  if (!out.notes.empty()) report["optimize"]["notes"] = out.notes;
  report["optimize"]["output_failures"] = output_failures;
  std::string not_written;
  for (const std::string& f : output_failures) not_written += "\n  " + f;
  if (Status s = io::write_file_atomic(final.result->files->report_path, report.dump(2) + "\n"); !s.ok()) {
    Error e = s.error();
    if (!not_written.empty()) e.message += "; nor were:" + not_written;
    return failed_after_search(e);
  }
  if (!output_failures.empty())
    return failed_after_search(make_error(
        std::to_string(output_failures.size()) + " file(s) could not be written after the search (every other file "
        "and report.json were; report.json lists these under optimize.output_failures):" + not_written));
  progress->finished(report["optimize"]);
  out.variables = variables;
  out.cannot_improve = cannot_improve;
  out.cannot_improve_kind = cannot_improve_kind;
  out.run = std::move(run.value());
  out.final_merit = fm;
  out.final_estimated_error_pct = final.estimated_error_pct;
  out.report = std::move(report);
  out.best_path = best_path;
  out.history_path = history_path;
  out.history = std::move(history);
  out.plan = std::move(final.plan);
  out.result = std::move(final.result);
  return out;

}

}  // namespace gonio::app
