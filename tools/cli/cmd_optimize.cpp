// gonio optimize: a design's variables toward a target (docs/design.md,
// "Optimisation"; docs/commands/optimize.md).
//
//   gonio optimize DESIGN.design.toml --target FILE --out DIR [--method bobyqa|cobyla|neldermead|cmaes]
//                  [--max-evals N] [--max-time S] [--stages N] [--photons-per-bin N] [--no-smooth]
//                  [--seed S] [--threads T] [--jobs J] [--population N] [--gamma-step DEG]
//                  [--final-photons N] [--name NAME]
//
// Ctrl-C (SIGINT) stops the search after the evaluation under way and keeps
// the best so far: its final trace and every file are written as at the end
// (a second Ctrl-C ends the process at once).
//
// Every evaluation is one app::simulate of the design at the variables'
// values (written to DIR/.evaluation.design.toml beside copies of the
// emitters' files), keeping the escaped photons, whose merit design/merit.h
// computes; design/optimize.h drives NLopt over them. DIR gets the best
// design (NAME.design.toml), its trace with an independent seed (NAME.ies,
// NAME.ldt, report.json with an "optimize" section) and history.json.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "design/merit.h"
#include "design/optimize.h"
#include "io/support/text.h"
#include "photometry/format.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/simulate_command.h"
#include "tools/run/console.h"
#include "tools/run/distributed_run.h"
#include "tools/run/optimize_run.h"

namespace gonio::cli {
namespace {

namespace fs = std::filesystem;

// Set by the first SIGINT; the handler then gives the signal back to its
// default, so that a second Ctrl-C ends the process.
std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) {
  g_interrupted.store(true);
  std::signal(SIGINT, SIG_DFL);
}

// The exit code of a run that wrote every file but could not improve the
// design (docs/commands/optimize.md "Exit codes").
constexpr int kExitCannotImprove = 3;

int fail(const std::string& message) {
  print_error("optimize: " + message);
  return kExitFailure;
}

// Under MPI, the job's exit code on every rank (each rank's own otherwise):
// a rank's failure or usage error first (rank 0's files that could not be
// written, say), else rank 0's (0, or 3 for a run that cannot improve).
// Collective: every rank reaches it once, after optimize_design.
int agreed(const sim::Ranks& ranks, int code) {
  if (!ranks.distributed()) return code;
  const std::vector<std::uint64_t> codes = ranks.gather(static_cast<std::uint64_t>(code));
  for (const std::uint64_t c : codes)
    if (c != static_cast<std::uint64_t>(kExitOk) && c != static_cast<std::uint64_t>(kExitCannotImprove))
      return static_cast<int>(c);
  return static_cast<int>(codes.front());
}

}  // namespace

int run_optimize(const Args& args) {
  const auto start = std::chrono::steady_clock::now();
  std::string design_path, target_path, out_dir, method_name = "bobyqa", name;
  long long max_evals = 200, stages = 3, seed = 1, threads = 0, final_photons = 1'000'000, jobs = 0, population = 0;
  std::optional<double> photons_per_bin;
  double gamma_step = 1.0, max_time = 0.0;
  bool no_smooth = false, no_step = false, no_common_random = false;
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
              "the merit's terms, its noise floor), history.json and history.svg (every\n"
              "evaluation), NAME.gltf and NAME.step (the best design's parts), compare.json\n"
              "and compare.svg (gonio compare of the target and NAME.ies). Ctrl-C stops and\n"
              "keeps the best so far, writing every file.\n"
              "Exit codes: 0 optimised, every file written; 1 failed; 2 usage error;\n"
              "3 cannot improve the design (flat, pinned or no_improvement): every file\n"
              "written, the reason on stderr and in report.json (optimize.cannot_improve).");
  p.positional("DESIGN", &design_path, "the design file (NAME.design.toml)");
  p.option("target", &target_path, "FILE", "the target distribution (IES, LDT, TM-33); default: [merit] target");
  p.option("out", &out_dir, "DIR", "output directory (created if missing)");
  p.choice("method", &method_name, {"bobyqa", "cobyla", "neldermead", "cmaes"},
           "NLopt's bobyqa (default), cobyla or neldermead, or pagmo2's cmaes (a population, global)");
  p.option("max-evals", &max_evals, 1, 1'000'000, "N", "evaluations of all stages together (default 200)");
  p.option("max-time", &max_time, 0.0, 1e7, "S",
           "no evaluation of a stage starts after S seconds (default 0: no limit); the best so far is kept");
  p.option("stages", &stages, 1, 8, "N", "stages of growing photons and shrinking steps (default 3)");
  p.option("photons-per-bin", &photons_per_bin, 40.0, 1e6, "N",
           "the first stage's photons per merit node (default: [merit] photons_per_bin, 40)");
  p.flag("no-smooth", &no_smooth, "count each photon in its nearest node (a piecewise constant merit)");
  p.flag("no-common-random", &no_common_random,
         "each evaluation traces photons of its own seed (a merit that is noisy in the variables: for comparison)");
  p.option("seed", &seed, 0, 1'000'000'000'000LL, "S", "the seed of the stages' photons (default 1)");
  p.option("threads", &threads, 0, 4096, "T", "threads of each trace (default 0: all cores)");
  p.option("jobs", &jobs, 0, 4096, "J",
           "cmaes: a generation's evaluations traced J at a time (default 0: one per core); the same run for any J");
  p.option("population", &population, 0, 100000, "N",
           "cmaes: points per generation (default 0: 4 + 3 ln(variables), at least 5)");
  p.option("gamma-step", &gamma_step, 0.1, 90.0, "DEG",
           "γ step of the written files, which the tessellation follows (default 1)");
  p.option("final-photons", &final_photons, 1, 4'294'967'295LL, "N",
           "photons of the best design's final trace (default 1000000)");
  p.flag("no-step", &no_step, "no NAME.step of the best design (its glTF is written all the same)");
  p.option("name", &name, "NAME", "the files' name (default: the design file's)");
  p.option("scan", &scan, "VAR:N",
           "no optimisation: the merit at N values of variable VAR across its bounds (the others as given), at the first\n"
           "stage's photons and seed, printed and written to DIR/scan.json");
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run) return ArgParser::exit_code(outcome);
  app::OptimizeRunOptions o;
  o.design_path = design_path;
  o.target_path = target_path;
  o.out_dir = out_dir;
  o.name = name;
  o.method = *design::parse_optimize_method(method_name);
  o.max_evals = max_evals;
  o.stages = stages;
  o.seed = seed;
  o.threads = threads;
  o.jobs = jobs;
  o.population = population;
  o.final_photons = final_photons;
  o.photons_per_bin = photons_per_bin;
  o.gamma_step = gamma_step;
  o.max_time = max_time;
  o.no_smooth = no_smooth;
  o.no_step = no_step;
  o.no_common_random = no_common_random;
  o.scan = scan;
  // Under mpirun/srun: one rank of the job (tools/run/distributed_run.h); the
  // ranks share each evaluation (CMA-ES: a generation's points), rank 0
  // alone prints and writes.
  std::optional<sim::Ranks> ranks = app::join_job("optimize");
  if (!ranks) return kExitFailure;
  o.ranks = &ranks.value();
  app::OptimizeRunHooks hooks;
  hooks.on_start = [&](const std::vector<design::OptimizeVariable>& variables, const design::MeritSpec& spec,
                       std::size_t nodes, std::uint64_t start_photons) {
    std::printf("optimize: %zu variables, %s, merit grid %zu nodes (%s), %llu photons in stage 1\n", variables.size(),
                design::to_string(o.method), nodes, spec.smooth ? "smooth" : "binned",
                static_cast<unsigned long long>(start_photons));
    std::fflush(stdout);
  };
  hooks.on_scan = [](const std::string& variable, double value, double merit, const std::string& error) {
    std::printf("scan: %s = %s: merit %s%s\n", variable.c_str(), format_number(value, 8).c_str(),
                format_number(merit, 8).c_str(), error.empty() ? "" : (" (" + error + ")").c_str());
  };
  hooks.on_evaluation = [&](const design::EvaluationRecord& r) {
    std::string where = r.stage < 0 ? "noise" : "stage " + std::to_string(r.stage + 1);
    // The time left: to --max-time, else at the mean pace so far to the end
    // of the evaluation budget (an estimate: a stage may converge sooner).
    std::string left;
    if (max_time > 0.0 && r.stage >= 0)
      left = ", " + format_number(std::max(max_time - r.time_s, 0.0), 3) + " s left";
    else if (r.stage >= 0 && r.index < max_evals)
      left = ", ~" + format_number(r.time_s / r.index * static_cast<double>(max_evals - r.index), 2) + " s left";
    if (std::isfinite(r.merit))
      std::printf("optimize: %d (%s): merit %s, best %s, %llu photons, %s s%s\n", r.index, where.c_str(),
                  format_number(r.merit, 5).c_str(), format_number(r.best, 5).c_str(),
                  static_cast<unsigned long long>(r.photons), format_number(r.time_s, 3).c_str(), left.c_str());
    else
      std::printf("optimize: %d (%s): failed (%s), best %s\n", r.index, where.c_str(), r.error.c_str(),
                  format_number(r.best, 5).c_str());
    std::fflush(stdout);
    if (g_interrupted.load()) {
      std::printf("optimize: interrupted: keeping the best so far and writing its files (Ctrl-C again to quit)\n");
      std::fflush(stdout);
      return false;
    }
    return true;
  };
  hooks.on_message = [](Severity severity, const std::string& text) { app::tell({}, severity, text); };
  bool usage = false;
  g_interrupted.store(false);
  using Handler = void (*)(int);
  const Handler previous = std::signal(SIGINT, on_interrupt);
  Result<app::OptimizeRunOutcome> outcome = app::optimize_design(o, hooks, start, &usage);
  std::signal(SIGINT, previous == SIG_ERR ? SIG_DFL : previous);
  if (!outcome.ok()) {
    if (usage) {
      print_usage_error("optimize", p, outcome.error().message);
      return agreed(*ranks, kExitUsage);
    }
    return agreed(*ranks, fail(to_string(outcome.error())));
  }
  if (outcome->scanned) return agreed(*ranks, kExitOk);
  if (!outcome->lead) return agreed(*ranks, outcome->cannot_improve.empty() ? kExitOk : kExitCannotImprove);
  const design::OptimizeResult& run = outcome->run;
  const design::MeritValue& fm = outcome->final_merit;
  const int code = print_run_files(*outcome->plan, outcome->result->run, *outcome->result->files);
  std::printf("optimize: %s: merit %s → %s in %d evaluations (%s); independent seed %s, noise floor %s\n",
              outcome->best_path.c_str(), format_number(run.start_merit, 5).c_str(),
              format_number(run.best_merit, 5).c_str(), run.evaluations, run.stopped_by.c_str(),
              format_number(run.independent_merit, 5).c_str(), format_number(run.noise_floor, 3).c_str());
  for (const std::string& f : outcome->extra_files) std::printf("optimize: %s\n", f.c_str());
  for (const std::string& note : outcome->notes) app::tell({}, Severity::Warning, "optimize: " + note);
  std::printf("optimize: final trace (%lld photons): candela RMS %s %% of the target's peak, LOR %s, estimated error %s %%\n",
              final_photons, format_number(fm.candela_rms_pct, 4).c_str(), format_number(fm.lor, 4).c_str(),
              format_number(outcome->final_estimated_error_pct, 3).c_str());
  // The [merit] table's hard limits in the final trace.
  for (const design::MeritLimitValue& l : fm.limits)
    std::printf("optimize: limit %s: %s against %s (%s)\n", l.name.c_str(), format_number(l.value, 5).c_str(),
                format_number(l.limit, 5).c_str(),
                l.c <= 0.0 ? "within" : ("over by " + format_number(100.0 * l.c, 3) + " %").c_str());
  if (code == kExitOk && !outcome->cannot_improve.empty()) {
    std::printf("optimize: cannot improve (%s): exit %d\n", outcome->cannot_improve_kind.c_str(), kExitCannotImprove);
    std::fflush(stdout);
    return agreed(*ranks, kExitCannotImprove);
  }
  return agreed(*ranks, code);
}

}  // namespace gonio::cli
