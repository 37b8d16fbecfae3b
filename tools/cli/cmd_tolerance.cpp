// gonio tolerance: how robust a luminaire is (issue 42, docs/tolerance.md).
//
//   gonio tolerance MODEL --tolerances FILE --out DIR [--trials N]
//                   [--spec FIGURE=LO..HI,…] [--noise-seeds K] [--sampling-seed S]
//                   [--photons N] [--seed S] [--threads T] [--c-step DEG] [--gamma-step DEG]
//
// Every trace is app::simulate on the model with the file's tolerances
// applied to the loaded scene (SimulateHooks::adjust_scene), all with the
// same seed: common random numbers, so a difference between two traces is
// the luminaire's. The nominal is traced again with K other seeds for the
// noise floor. Then each tolerance alone at its limits (sensitivity), and N
// Monte Carlo trials with all of them drawn at once from a Latin hypercube.
// DIR gets report.json (every trace's parameters and figures), sensitivity.txt,
// tornado_FIGURE.svg, nominal.ies/.ldt, and the best and worst trials' IES and LDT.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "photometry/format.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/simulate_command.h"
#include "tools/run/distributed_run.h"
#include "tools/run/simulate.h"
#include "tools/run/tolerance_run.h"

namespace gonio::cli {
namespace {

namespace fs = std::filesystem;

int fail(const std::string& message) {
  print_error("tolerance: " + message);
  return kExitFailure;
}

}  // namespace

int run_tolerance(const Args& args) {
  std::string model, tolerances_path, out_dir, spec_text, percentile_text;
  long long trials = 20, noise_seeds = 3, sampling_seed = 1, bins = 10, inverse_steps = 4, parallel_trials = 1;
  bool resume = false;
  app::SimulateOptions options;
  options.iterations = 1;
  options.symmetry_name = "none";
  ArgParser p("tolerance", "MODEL --tolerances FILE --out DIR [options]",
              "How robust a luminaire is: the model traced with its tolerances applied\n"
              "(docs/tolerance.md). Every trace uses the same photons (common random\n"
              "numbers), so differences are the luminaire's. First the nominal, then the\n"
              "nominal again with independent seeds (the noise floor), each tolerance\n"
              "alone at its limits (the sensitivity table and tornado charts), and N Monte\n"
              "Carlo trials with every tolerance drawn at once from a Latin hypercube (per\n"
              "figure a histogram; the yield against --spec). Writes DIR/report.json,\n"
              "DIR/sensitivity.txt, DIR/tornado_FIGURE.svg, DIR/nominal.{ies,ldt},\n"
              "DIR/best.{ies,ldt} and DIR/worst.{ies,ldt} (the trials nearest to and\n"
              "farthest from the nominal distribution by RMS difference). With --spec, the\n"
              "inverse sensitivity: per limit, how far each tolerance may grow, linear\n"
              "from its changes at its limits.");
  p.positional("MODEL", &model, "the luminaire model (glTF, STEP/IGES with its sidecar, design file)");
  p.option("tolerances", &tolerances_path, "FILE",
           "the tolerance specification (TOML, docs/tolerance.md); a design file's own [tolerances] are used as well, "
           "and alone without this option");
  p.option("out", &out_dir, "DIR", "output directory (created if missing)");
  p.option("trials", &trials, 0, 100000, "N", "Monte Carlo trials (default 20; 0: none)");
  p.option("spec", &spec_text, "LIMITS",
           "limits for the yield: FIGURE=LO..HI, FIGURE<=HI or FIGURE>=LO[,…], e.g. beam_c0=24..28,ugr<=19 (figures: "
           "peak_cd, peak_c, peak_gamma, beam_c0, beam_c90, field_c0, field_c90, flux, lor, rms, ugr, bug_b, bug_u, "
           "bug_g, cct, duv_max, axis_c0, axis_c90, dugr, ugr_cie232)");
  p.option("percentile", &percentile_text, "LIST",
           "trials written as DIR/pP_FIGURE.{ies,ldt} beside best and worst: P (the RMS difference from the nominal) "
           "or FIGURE:P, comma-separated, 0 <= P <= 100, e.g. 5,95,beam_c0:50 (nearest rank over the trials)");
  p.option("noise-seeds", &noise_seeds, 0, 1000, "K", "the nominal traced again with K independent seeds (default 3)");
  p.option("sampling-seed", &sampling_seed, 0, 9'223'372'036'854'775'807LL, "S",
           "seed of the Latin hypercube (default 1)");
  p.option("inverse-steps", &inverse_steps, 0, 50, "N",
           "with --spec: bisection steps of the traced inverse sensitivity per limit and tolerance (default 4; 0: "
           "the linear estimate alone)");
  p.option("parallel-trials", &parallel_trials, 1, 256, "P",
           "Monte Carlo trials traced at once, each with --threads threads (default 1); the report is the same bytes "
           "for any P");
  p.flag("resume", &resume,
         "read DIR/journal.jsonl of an interrupted run back and trace only what it lacks (the same report)");
  p.option("bins", &bins, 1, 1000, "B", "bins of each figure's histogram (default 10)");
  p.option("luminance-image", &options.luminance_images, "C:G,...|ugr",
           "luminance images of every trace from these directions, as gonio simulate --luminance-image\n"
           "takes them (ugr: CIE 232's views), not written: each trace's CIE 232:2019 figures dugr (the\n"
           "largest delta UGR over the views) and ugr_cie232 (ugr + dugr) in the tables and report.json");
  p.option("photons", &options.photons, 1, 4'294'967'295LL, "N", "photons per trace (default 1000000)");
  p.option("seed", &options.seed, 0, 9'223'372'036'854'775'807LL, "S",
           "seed of every trace: the common random numbers (default 1)");
  p.option("threads", &options.threads, 0, 4096, "T", "threads (default 0: all cores)");
  p.option("max-bounces", &options.max_bounces, 0, 1'000'000, "N", "bounce limit per photon (default 100)");
  p.option("c-step", &options.c_step, app::kGridStepBounds.min, app::kGridStepBounds.max, "DEG",
           "C-plane step of the traced distributions (default 5)");
  p.option("gamma-step", &options.gamma_step, app::kGammaStepBounds.min, app::kGammaStepBounds.max, "DEG",
           "γ step of the traced distributions (default 2.5)");
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run) return ArgParser::exit_code(outcome);
  for (auto [value, option] : {std::pair{&model, "MODEL"}, std::pair{&out_dir, "--out DIR"}})
    if (value->empty()) {
      print_usage_error("tolerance", p, std::string(option) + " is required");
      return kExitUsage;
    }  std::optional<app::SimulatePlan> plan = plan_or_usage("tolerance", model, options, p);
  if (!plan) return kExitUsage;
  // Under mpirun/srun the traces are split over the ranks; rank 0 writes DIR.
  std::optional<sim::Ranks> ranks = app::join_job("tolerance");
  if (!ranks) return kExitFailure;
  app::ToleranceRunOptions o;
  o.ranks = &ranks.value();
  o.model = model;
  o.tolerances_path = tolerances_path;
  o.out_dir = out_dir;
  o.spec_text = spec_text;
  o.percentile_text = percentile_text;
  o.trials = trials;
  o.noise_seeds = noise_seeds;
  o.sampling_seed = sampling_seed;
  o.bins = bins;
  o.inverse_steps = inverse_steps;
  o.parallel_trials = parallel_trials;
  o.resume = resume;
  o.simulate = options;
  app::ToleranceRunHooks hooks;
  hooks.on_output = [](const std::string& text) {  // rank 0's only
    std::fputs(text.c_str(), stdout);
    std::fflush(stdout);
  };
  hooks.on_warning = [](const std::string& text) { print_error("tolerance: warning: " + text); };
  bool usage = false;
  Result<app::ToleranceRunOutcome> outcome = app::tolerance_analysis(o, *plan, hooks, &usage);
  if (!outcome.ok()) {
    if (usage) {
      print_usage_error("tolerance", p, outcome.error().message);
      return kExitUsage;
    }
    // An error that names no file carries its own context (the file and line inside).
    const Error& e = outcome.error();
    if (e.message.empty()) return kExitFailure;  // an MPI rank whose error another rank told
    return fail(e.where.file.empty() && e.where.line == 0 ? e.message : to_string(e));
  }
  if (!outcome->lead) return kExitOk;
  const nlohmann::json& report = outcome->report;
  const nlohmann::json& yield = report["monte_carlo"]["yield"];
  const std::size_t trial_count = report["monte_carlo"]["trials"].size();
  if (yield.contains("all"))
    std::printf("yield: %s %% of %zu trials within %s\n", format_number(100.0 * yield["all"].get<double>(), 4).c_str(),
                trial_count, spec_text.c_str());
  std::printf("%zu traces, %.2f s each on average; report: %s\n", outcome->timing["traces"].get<std::size_t>(),
              outcome->timing["seconds_per_trace"].get<double>(), outcome->report_path.c_str());
  return kExitOk;
}

}  // namespace gonio::cli
