// gonio optimize: a design's variables toward a target (docs/design.md,
// "Optimisation"; docs/commands/optimize.md).
//
//   gonio optimize DESIGN.design.toml --target FILE --out DIR [--method bobyqa|cobyla]
//                  [--max-evals N] [--max-time S] [--stages N] [--photons-per-bin N] [--no-smooth]
//                  [--seed S] [--threads T] [--gamma-step DEG] [--final-photons N] [--name NAME]
//
// Every evaluation is one app::simulate of the design at the variables'
// values (written to DIR/.evaluation.design.toml beside copies of the
// emitters' files), keeping the escaped photons, whose merit design/merit.h
// computes; design/optimize.h drives NLopt over them. DIR gets the best
// design (NAME.design.toml), its trace with an independent seed (NAME.ies,
// NAME.ldt, report.json with an "optimize" section) and history.json.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "design/design_file.h"
#include "design/design_scene.h"
#include "design/merit.h"
#include "design/optimize.h"
#include "io/photometric/photometric_file.h"
#include "io/support/file_io.h"
#include "io/support/text.h"
#include "photometry/format.h"
#include "sim/ledger.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/simulate_command.h"
#include "tools/run/json_figures.h"
#include "tools/run/photometric_input.h"
#include "tools/run/resampler_cache.h"
#include "tools/run/simulate.h"

namespace gonio::cli {
namespace {

namespace fs = std::filesystem;

int fail(const std::string& message) {
  print_error("optimize: " + message);
  return kExitFailure;
}

// The escaped photons of a finished simulation, in the photometric frame,
// each with its flux, and the light output ratio.
std::vector<design::MeritPhoton> escaped_photons(const sim::Simulation& simulation, double* lor) {
  const std::vector<sim::EscapedRay>& rays = simulation.escaped_rays();
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

// What one traced design gives: its merit's terms, or the run's error.
struct Traced {
  std::optional<design::MeritValue> merit;
  std::string error;
  std::optional<app::SimulatePlan> plan;
  std::optional<app::SimulateResult> result;
  double estimated_error_pct = std::nan("");
};

}  // namespace

int run_optimize(const Args& args) {
  const auto start = std::chrono::steady_clock::now();
  std::string design_path, target_path, out_dir, method_name = "bobyqa", name;
  long long max_evals = 200, stages = 3, seed = 1, threads = 0, final_photons = 1'000'000;
  std::optional<double> photons_per_bin;
  double gamma_step = 1.0, max_time = 0.0;
  bool no_smooth = false;
  std::optional<std::string> scan;
  ArgParser p("optimize", "DESIGN.design.toml --target FILE --out DIR [options]",
              "Optimises a design file's variables (each with min and max) toward a target\n"
              "distribution, minimising the merit of the design's [merit] table (default: the\n"
              "candela RMS against the target on a rotational 5° γ grid, flux-normalised).\n"
              "Every evaluation traces the same photons (one seed per stage), and each photon's\n"
              "flux is spread over the merit grid's neighbouring nodes, so the merit is a\n"
              "deterministic function of the variables, continuous in the photons' directions\n"
              "(no plateaus); the photons grow 4× per\n"
              "stage as the steps halve. A line per evaluation (merit, best, photons, time).\n"
              "DIR gets NAME.design.toml (the best design), NAME.ies and NAME.ldt (it traced\n"
              "with an independent seed), report.json (an \"optimize\" section: the variables,\n"
              "the merit's terms, its noise floor) and history.json (every evaluation).");
  p.positional("DESIGN", &design_path, "the design file (NAME.design.toml)");
  p.option("target", &target_path, "FILE", "the target distribution (IES, LDT, TM-33); default: [merit] target");
  p.option("out", &out_dir, "DIR", "output directory (created if missing)");
  p.choice("method", &method_name, {"bobyqa", "cobyla"}, "NLopt's method: bobyqa (default) or cobyla");
  p.option("max-evals", &max_evals, 1, 1'000'000, "N", "evaluations of all stages together (default 200)");
  p.option("max-time", &max_time, 0.0, 1e7, "S",
           "no evaluation of a stage starts after S seconds (default 0: no limit); the best so far is kept");
  p.option("stages", &stages, 1, 8, "N", "stages of growing photons and shrinking steps (default 3)");
  p.option("photons-per-bin", &photons_per_bin, 40.0, 1e6, "N",
           "the first stage's photons per merit node (default: [merit] photons_per_bin, 40)");
  p.flag("no-smooth", &no_smooth, "count each photon in its nearest node (a piecewise constant merit)");
  p.option("seed", &seed, 0, 1'000'000'000'000LL, "S", "the seed of the stages' photons (default 1)");
  p.option("threads", &threads, 0, 4096, "T", "threads of each trace (default 0: all cores)");
  p.option("gamma-step", &gamma_step, 0.1, 90.0, "DEG",
           "γ step of the written files, which the tessellation follows (default 1)");
  p.option("final-photons", &final_photons, 1, 4'294'967'295LL, "N",
           "photons of the best design's final trace (default 1000000)");
  p.option("name", &name, "NAME", "the files' name (default: the design file's)");
  p.option("scan", &scan, "VAR:N",
           "no optimisation: the merit at N values of variable VAR across its bounds (the others as given), at the first\n"
           "stage's photons and seed, printed and written to DIR/scan.json");
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run) return ArgParser::exit_code(outcome);
  if (out_dir.empty()) {
    print_usage_error("optimize", p, "--out DIR is required");
    return kExitUsage;
  }
  if (!design::is_design_path(design_path)) {
    print_usage_error("optimize", p, "DESIGN must be a design file (NAME.design.toml), got " + io::shown(design_path));
    return kExitUsage;
  }
  if (name.empty()) {
    name = fs::path(design_path).filename().string();
    name = name.substr(0, name.size() - std::string(".design.toml").size());
  }
  if (name.empty() || name.find_first_of("/\\*?[]") != std::string::npos || name.front() == '.') {
    print_usage_error("optimize", p, "--name must be a plain name (no / \\ * ? [ ], not starting with .)");
    return kExitUsage;
  }
  const design::OptimizeMethod method = *design::parse_optimize_method(method_name);

  // The design, its variables and merit.
  Result<design::Design> read = design::read_design_file(design_path);
  if (!read.ok()) return fail(to_string(read.error()));
  design::Design design = std::move(read.value());
  std::vector<design::OptimizeVariable> variables;
  for (const design::Variable& v : design.variables) {
    if (!v.min || !v.max)
      return fail(design.path + ":" + std::to_string(v.line) + ": variable '" + v.name +
                  "' has no " + (!v.min ? "min" : "max") + ": the optimiser searches between a variable's bounds");
    if (!(*v.min < *v.max))
      return fail(design.path + ":" + std::to_string(v.line) + ": variable '" + v.name +
                  "': min must be below max to search between them");
    variables.push_back({v.name, v.value, *v.min, *v.max});
  }
  if (variables.empty())
    return fail(design.path + ": the design has no variables ({ value = …, min = …, max = … }) to optimise");
  Result<design::MeritSpec> spec_read = design::read_merit(design::resolved_document(design), design.path);
  if (!spec_read.ok()) return fail(to_string(spec_read.error()));
  design::MeritSpec spec = spec_read.value();
  if (no_smooth) spec.smooth = false;
  if (photons_per_bin) spec.photons_per_bin = *photons_per_bin;
  if (target_path.empty()) target_path = spec.target;
  if (target_path.empty()) {
    print_usage_error("optimize", p, "--target FILE is required (the design's [merit] table names none)");
    return kExitUsage;
  }
  Result<io::PhotometricFile> target_file = app::read_input(target_path, app::InputOptions{}, false);
  if (!target_file.ok()) return kExitFailure;
  const design::MeritGrid grid = design::merit_grid(spec);
  Result<design::MeritTarget> target = design::merit_target(grid, target_file->distribution);
  if (!target.ok()) return fail(target_path + ": " + target.error().message);

  // DIR with the files the design reads (its emitters' profiles and ray files).
  if (Status s = io::make_directories(out_dir); !s.ok()) return fail(to_string(s.error()));
  const fs::path folder = fs::absolute(fs::path(design_path)).parent_path();
  const std::vector<std::string> files = design::design_files(design_path);
  for (std::size_t i = 1; i < files.size(); ++i) {
    const fs::path rel = fs::absolute(fs::path(files[i])).lexically_normal().lexically_relative(folder);
    if (rel.empty() || rel.is_absolute() || *rel.begin() == "..")
      return fail(files[i] + ": the design's file lies outside its folder; gonio optimize copies the design's files into "
                  "DIR, so keep them in or under the design's folder");
    Result<std::string> bytes = io::read_file(files[i], std::size_t{1} << 30);
    if (!bytes.ok()) return fail(to_string(bytes.error()));
    const fs::path to = fs::path(out_dir) / rel;
    if (Status s = io::make_directories(to.parent_path().string()); !s.ok()) return fail(to_string(s.error()));
    if (Status s = io::write_file_atomic(to.string(), *bytes); !s.ok()) return fail(to_string(s.error()));
  }
  // The [merit] table's target, where it lies in or under the design's folder,
  // so that the best design's table names a file beside it.
  if (!spec.target.empty()) {
    const fs::path rel = fs::absolute(fs::path(spec.target)).lexically_normal().lexically_relative(folder);
    if (!rel.empty() && !rel.is_absolute() && *rel.begin() != "..") {
      Result<std::string> bytes = io::read_file(spec.target, std::size_t{256} << 20);
      if (!bytes.ok()) return fail(to_string(bytes.error()));
      const fs::path to = fs::path(out_dir) / rel;
      if (Status s = io::make_directories(to.parent_path().string()); !s.ok()) return fail(to_string(s.error()));
      if (Status s = io::write_file_atomic(to.string(), *bytes); !s.ok()) return fail(to_string(s.error()));
    }
  }
  const std::string evaluation_path = (fs::path(out_dir) / ".evaluation.design.toml").string();

  // One trace of the design at `values`: the merit of its escaped photons.
  const auto trace = [&](const std::vector<double>& values, std::uint64_t photons, std::uint64_t trace_seed,
                         const std::string& path, bool files_out) {
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
    app::SimulateOptions o;
    o.photons = static_cast<long long>(photons);
    o.iterations = 1;
    o.seed = static_cast<long long>(trace_seed);
    o.threads = threads;
    o.gamma_step = gamma_step;
    o.no_cache = true;
    o.next_event = "off";  // every escape a photon of the merit
    o.format_list = "ies,ldt";
    o.stem = name;
    if (files_out) o.out_dir = out_dir;
    Result<app::SimulatePlan> planned = app::plan_simulation(path, o);
    if (!planned.ok()) {
      t.error = planned.error().message;
      return t;
    }
    app::SimulatePlan* plan = &t.plan.emplace(std::move(planned.value()));
    plan->progressive.simulation.capture_escaped_photons = photons;
    app::SimulateHooks hooks;
    hooks.on_message = [&](Severity severity, const std::string& text) {
      if (severity == Severity::Error && t.error.empty()) t.error = text;
      if (files_out && severity != Severity::Error) app::tell({}, severity, text);
    };
    std::optional<sim::Resampler> resampler;
    if (files_out)
      hooks.on_loaded = [&](const sim::SceneDesc& scene, const std::vector<Finding>&) {
        return &resampler.emplace(
            app::cached_resampler(plan->progressive.simulation.face_size, scene.frame, plan->grid, std::string()));
      };
    hooks.on_traced = [&](const app::ProgressiveOutcome& run) {
      double lor = 0.0;
      const std::vector<design::MeritPhoton> escaped = escaped_photons(run.simulation, &lor);
      t.merit = design::evaluate_merit(spec, grid, *target, design::bin_photons(grid, escaped), lor);
      t.estimated_error_pct = run.estimated_rms_error_pct;
    };
    t.result = app::simulate(*plan, hooks, start);
    if (!t.result && t.error.empty()) t.error = "the trace failed";
    if (!t.result) t.merit.reset();
    return t;
  };

  design::OptimizeOptions oo;
  oo.method = method;
  oo.max_evaluations = static_cast<int>(max_evals);
  oo.stages = static_cast<int>(stages);
  oo.seed = static_cast<std::uint64_t>(seed);
  oo.max_time_s = max_time;
  oo.start_photons = static_cast<std::uint64_t>(std::ceil(spec.photons_per_bin * static_cast<double>(grid.size())));
  std::printf("optimize: %zu variables, %s, merit grid %zu nodes (%s), %llu photons in stage 1\n", variables.size(),
              design::to_string(method), grid.size(), spec.smooth ? "smooth" : "binned",
              static_cast<unsigned long long>(oo.start_photons));
  std::fflush(stdout);
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
      print_usage_error("optimize", p, "--scan " + io::shown(*scan) + ": give VAR:N, a variable of the design and 2 ≤ N ≤ 100000");
      return kExitUsage;
    }
    nlohmann::json rows = nlohmann::json::array();
    std::vector<double> values;
    for (const design::OptimizeVariable& v : variables) values.push_back(v.value);
    const design::OptimizeVariable& v = variables[index];
    for (int k = 0; k < static_cast<int>(*n); ++k) {
      values[index] = v.min + (v.max - v.min) * k / (*n - 1.0);
      Traced t = trace(values, oo.start_photons, oo.seed, evaluation_path, false);
      const double m = t.merit ? t.merit->merit : std::nan("");
      std::printf("scan: %s = %s: merit %s%s\n", v.name.c_str(), format_number(values[index], 8).c_str(),
                  format_number(m, 8).c_str(), t.merit ? "" : (" (" + t.error + ")").c_str());
      rows.push_back({{"value", values[index]}, {"merit", app::json_number(m)}});
    }
    std::error_code ignored_scan;
    fs::remove(evaluation_path, ignored_scan);
    nlohmann::json out = {{"variable", v.name}, {"photons", oo.start_photons}, {"seed", oo.seed},
                          {"smooth", spec.smooth}, {"scan", rows}};
    if (Status s = io::write_file_atomic((fs::path(out_dir) / "scan.json").string(), out.dump(1) + "\n"); !s.ok())
      return fail(to_string(s.error()));
    return kExitOk;
  }
  const design::MeritFunction merit = [&](const std::vector<double>& values, std::uint64_t photons,
                                          std::uint64_t trace_seed) -> Result<double> {
    Traced t = trace(values, photons, trace_seed, evaluation_path, false);
    if (!t.merit) return make_error(t.error);
    return t.merit->merit;
  };
  const auto on_evaluation = [&](const design::EvaluationRecord& r) {
    std::string where = r.stage < 0 ? "noise" : "stage " + std::to_string(r.stage + 1);
    const std::string left =
        max_time > 0.0 && r.stage >= 0 ? ", " + format_number(std::max(max_time - r.time_s, 0.0), 3) + " s left" : "";
    if (std::isfinite(r.merit))
      std::printf("optimize: %d (%s): merit %s, best %s, %llu photons, %s s%s\n", r.index, where.c_str(),
                  format_number(r.merit, 5).c_str(), format_number(r.best, 5).c_str(),
                  static_cast<unsigned long long>(r.photons), format_number(r.time_s, 3).c_str(), left.c_str());
    else
      std::printf("optimize: %d (%s): failed (%s), best %s\n", r.index, where.c_str(), r.error.c_str(),
                  format_number(r.best, 5).c_str());
    std::fflush(stdout);
    return true;
  };
  Result<design::OptimizeResult> run = design::optimize(variables, merit, oo, on_evaluation);
  std::error_code ignored;
  fs::remove(evaluation_path, ignored);
  if (!run.ok()) return fail(design.path + ": " + run.error().message);

  // The best design, traced with an independent seed into DIR.
  for (std::size_t i = 0; i < variables.size(); ++i)
    if (Status s = design::set_variable(design, variables[i].name, run->best_values[i]); !s.ok())
      return fail(to_string(s.error()));
  const std::string best_path = (fs::path(out_dir) / (name + ".design.toml")).string();
  const std::uint64_t final_seed = static_cast<std::uint64_t>(seed) + 7'000'003ULL;
  Traced final = trace(run->best_values, static_cast<std::uint64_t>(final_photons), final_seed, best_path, true);
  if (!final.result || !final.result->files || !final.merit)
    return fail("the best design's final trace failed: " + final.error);
  // The design file again, with a header (trace wrote it bare).
  const std::string text = design::write_design(
      design.document, {"Optimised by gonio optimize (docs/design.md) from " + fs::path(design_path).filename().string() +
                            " against " + fs::path(target_path).filename().string() + ".",
                        std::string("Method ") + design::to_string(method) + ", " + std::to_string(run->evaluations) +
                            " evaluations, merit " + format_number(run->best_merit, 5) + "."});
  if (Status s = io::write_file_atomic(best_path, text); !s.ok()) return fail(to_string(s.error()));
  const int code = print_run_files(*final.plan, final.result->run, *final.result->files);

  // history.json and the report.
  nlohmann::json history = nlohmann::json::array();
  for (const design::EvaluationRecord& r : run->history) {
    nlohmann::json values = nlohmann::json::object();
    for (std::size_t i = 0; i < variables.size(); ++i) values[variables[i].name] = r.values[i];
    nlohmann::json e = {{"index", r.index},  {"stage", r.stage + 1}, {"merit", app::json_number(r.merit)},
                        {"best", app::json_number(r.best)}, {"photons", r.photons}, {"seed", r.seed},
                        {"time_s", r.time_s}, {"values", values}};
    if (r.stage < 0) e["stage"] = "noise";
    if (!r.error.empty()) e["error"] = r.error;
    history.push_back(e);
  }
  const std::string history_path = (fs::path(out_dir) / "history.json").string();
  if (Status s = io::write_file_atomic(history_path, history.dump(1) + "\n"); !s.ok()) return fail(to_string(s.error()));
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
      {"variables", vars},
      {"merit",
       {{"c_step_deg", spec.c_step_deg},
        {"gamma_step_deg", spec.gamma_step_deg},
        {"nodes", grid.size()},
        {"normalize", spec.absolute ? "absolute" : "flux"},
        {"smooth", spec.smooth},
        {"photons_per_bin", spec.photons_per_bin},
        {"weights", {{"candela", spec.candela_weight}, {"lor", spec.lor_weight}, {"beam", spec.beam_weight}}},
        {"gamma_weights", weights}}},
      {"evaluations", run->evaluations},
      {"stages", stages},
      {"stopped_by", run->stopped_by},
      {"start_merit", app::json_number(run->start_merit)},
      {"best_merit", app::json_number(run->best_merit)},
      {"stage_photons", run->final_photons},
      {"independent_merit", app::json_number(run->independent_merit)},
      {"noise_floor", app::json_number(run->noise_floor)},
      {"final",
       {{"photons", final_photons},
        {"seed", final_seed},
        {"merit", app::json_number(fm.merit)},
        {"candela_rms_pct", app::json_number(fm.candela_rms_pct)},
        {"lor", app::json_number(fm.lor)},
        {"beam_angle_deg", app::json_number(fm.beam_deg)},
        {"target_beam_angle_deg", app::json_number(fm.target_beam_deg)},
        {"estimated_rms_error_pct", app::json_number(final.estimated_error_pct)}}},
      {"files", {best_path, history_path}},
      {"wall_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()}};
  if (Status s = io::write_file_atomic(final.result->files->report_path, report.dump(2) + "\n"); !s.ok())
    return fail(to_string(s.error()));
  std::printf("optimize: %s: merit %s → %s in %d evaluations (%s); independent seed %s, noise floor %s\n",
              best_path.c_str(), format_number(run->start_merit, 5).c_str(), format_number(run->best_merit, 5).c_str(),
              run->evaluations, run->stopped_by.c_str(), format_number(run->independent_merit, 5).c_str(),
              format_number(run->noise_floor, 3).c_str());
  std::printf("optimize: final trace (%lld photons): candela RMS %s %% of the target's peak, LOR %s, estimated error %s %%\n",
              final_photons, format_number(fm.candela_rms_pct, 4).c_str(), format_number(fm.lor, 4).c_str(),
              format_number(final.estimated_error_pct, 3).c_str());
  return code;
}

}  // namespace gonio::cli
