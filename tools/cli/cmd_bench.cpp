// gonio bench: speed against accuracy on a luminaire model.
//
//   gonio bench MODEL... --out DIR [--photons N] [--first N] [--steps K]
//               [--reference N] [--seed S] [--reference-seed S] [--threads T]
//               [--max-bounces B] [--c-step DEG] [--gamma-step DEG]
//               [--face-size F] [--target PCT] [--importance
//               [--emission-face-size E] [--min-acceptance A]]
//               [--sampler random|sobol|both]
//               [--page FILE] [--no-png]
//
// The options become tools/bench/bench.h's BenchOptions; app::bench runs, for
// each model, a cached reference run (tools/bench/bench_reference.h), the
// series (tools/bench/bench_series.h), and writes DIR/series.csv,
// DIR/bench.json and the charts (tools/bench/bench_report.h); with several
// models each gets DIR/<name>/. --page writes a Markdown page over all of
// them (scripts/results.sh makes docs/results.md this way). This file
// prints each model's summary and the progress.
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "gonio/version.h"
#include "tools/bench/bench.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/input_options.h"
#include "tools/run/distributed_run.h"
#include "tools/run/simulate.h"

namespace gonio::cli {
namespace {

void print_summary(const app::BenchOutcome& o) {
  const app::Reference& r = o.reference;
  std::printf("%s: reference %llu photons (seed %llu) %s %.1f s; its noise %.3g %% of peak "
              "(measured from its halves: %.3g %%), %.2f x the smallest raw error charted\n",
              o.model.c_str(), static_cast<unsigned long long>(r.key.photons),
              static_cast<unsigned long long>(r.key.seed), r.reused ? "reused, traced in" : "traced in",
              r.trace_s, r.noise.table_estimated_pct, r.noise.table_measured_pct,
              r.noise.table_estimated_pct / o.smallest_raw_error_pct);
  char candela[32], cube[32];
  std::snprintf(candela, sizeof candela, "to %g %% [s]", o.settings.target_pct);
  std::snprintf(cube, sizeof cube, "to RMSE %g [s]", o.settings.cube_target);
  std::printf("  %-28s %12s %12s %16s %14s %12s %8s\n", "series", candela, "photons", cube, "final RMS [%]",
              "cube RMSE", "slope");
  for (const app::SeriesResult& s : o.series) {
    if (s.points.empty()) continue;
    std::printf("  %-28s %12s %12s %16s %14s %12s %8s\n", s.spec.label.c_str(),
                app::format_value(s.time_to_target_s, 3).c_str(), app::format_value(s.photons_to_target, 3).c_str(),
                app::format_value(s.time_to_cube_target_s, 3).c_str(),
                app::format_value(s.points.back().table.rms_pct, 3).c_str(),
                app::format_value(s.points.back().cube.rmse, 3).c_str(), app::format_value(s.table_slope, 3).c_str());
  }
  std::printf("  wrote %s/{series.csv,bench.json,candela-time,cubemap-time,photons,psnr-snr}\n",
              o.directory.c_str());
}

// Progress on stderr, over itself: the reference, then each run's iterations.
void show_progress(app::BenchHooks& hooks) {
  hooks.on_reference = [](const std::string& name, std::uint64_t done, std::uint64_t total) {
    std::fprintf(stderr, "\r%s: bench %s: reference %.0f %%   ", kProgramName, name.c_str(),
                 100.0 * static_cast<double>(done) / static_cast<double>(total));
    if (done == total) std::fputc('\n', stderr);
    std::fflush(stderr);
  };
  hooks.on_series = [](const std::string& name, const app::BenchProgress& pr) {
    std::fprintf(stderr, "\r%s: bench %s: %s run, iteration %d/%d   ", kProgramName, name.c_str(), pr.run,
                 pr.iteration, pr.iterations);
    if (pr.iteration == pr.iterations) std::fputc('\n', stderr);
    std::fflush(stderr);
  };
}

}  // namespace

int run_bench(const Args& args) {
  app::BenchOptions o;
  ArgParser p("bench", "MODEL... --out DIR [options]",
              "Measures speed against accuracy on luminaire models (glTF 2.0, or STEP/IGES with a\n"
              "sidecar, see --parts). A long reference run (cached in DIR, reused while model,\n"
              "program, tracer sources and settings match) is the truth; series of progressive\n"
              "iterations from one seed are compared with it after every iteration: the raw far\n"
              "field, the preview filter bilinear and bilateral at fixed thresholds 50..300 and\n"
              "adaptive, and with --importance the thesis's importance-guided emission. Errors: the\n"
              "cube map's RMSE, PSNR and SNR after mean scaling, and the resampled candela table's\n"
              "RMS and max error (% of peak) and flux error. Writes DIR/series.csv, DIR/bench.json\n"
              "and charts (SVG, PNG) of error against time and photons; several models go to\n"
              "DIR/<name>/.");
  p.positional_list("MODEL", &o.models, 1, "luminaire models (.gltf, .glb, .step, .stp, .iges or .igs)");
  p.option("out", &o.out_dir, "DIR", "output directory (created if missing)");
  p.option("photons", &o.photons, app::kBenchPhotonsBounds.min, app::kBenchPhotonsBounds.max, "N", "photons of each series in all (default 33554432 = 2^25)");
  p.option("first", &o.first, app::kBenchFirstBounds.min, app::kBenchFirstBounds.max, "N", "photons of the first iteration (default 16384)");
  p.option("steps", &o.steps, app::kBenchStepsBounds.min, app::kBenchStepsBounds.max, "K", "iterations per doubling of the photons (default 2)");
  p.option("reference", &o.reference_photons, app::kBenchReferenceBounds.min, app::kBenchReferenceBounds.max, "N",
           "photons of the reference run (default 16 x --photons: its noise is 1/4 of the last raw error)");
  p.option("seed", &o.seed, app::kBenchSeedBounds.min, app::kBenchSeedBounds.max, "S", "seed of the series (default 1)");
  p.option("reference-seed", &o.reference_seed, app::kBenchReferenceSeedBounds.min,
           app::kBenchReferenceSeedBounds.max, "S",
           "seed of the reference (default: series seed + 1; must differ)");
  p.option("threads", &o.threads, app::kThreadsBounds.min, app::kThreadsBounds.max, "T", "threads (default 0: every core)");
  p.option("max-bounces", &o.max_bounces, app::kMaxBouncesBounds.min, app::kMaxBouncesBounds.max, "B", "bounce limit (default 100)");
  p.option("c-step", &o.c_step, app::kGridStepBounds.min, app::kGridStepBounds.max, "DEG", "C-plane step of the table (default 5)");
  p.option("gamma-step", &o.gamma_step, app::kGridStepBounds.min, app::kGridStepBounds.max, "DEG", "gamma step of the table (default 2.5)");
  p.option("face-size", &o.face_size, app::kBenchFaceSizeBounds.min, app::kBenchFaceSizeBounds.max, "F", "cube-map texels per face edge (default: what the grid needs, 128)");
  p.option("target", &o.target, app::kBenchTargetBounds.min, app::kBenchTargetBounds.max, "PCT", "RMS candela error to time [% of peak] (default 1)");
  p.option("cube-target", &o.cube_target, app::kBenchCubeTargetBounds.min, app::kBenchCubeTargetBounds.max, "E", "cube-map RMSE to time (default 0.1)");
  p.flag("importance", &o.importance, "add importance-guided emission (thesis 5.4.1), raw and adaptive");
  p.choice("next-event", &o.next_event, {"auto", "on", "off"},
           "next-event estimation of the unguided series (as gonio simulate: default auto)");
  p.choice("sampler", &o.sampler, {"random", "sobol", "both"},
           "sampler of the series (sim/samplers/sampler.h): random, sobol, or both (default: the pseudo-random\n"
           "series and Sobol' raw and adaptive, charted against each other); the reference is\n"
           "pseudo-random either way (its noise is taken out as Poisson noise)");
  p.option("emission-face-size", &o.emission_face_size, app::kBenchFaceSizeBounds.min,
           app::kBenchFaceSizeBounds.max, "E",
           "guided emission: emission grid texels per face edge (default 32)");
  p.option("min-acceptance", &o.min_acceptance, app::kMinAcceptanceBounds.min, app::kMinAcceptanceBounds.max, "A",
           "guided emission: smallest acceptance, photon power <= 1/A (default 1/16)");
  p.option("page", &o.page, "FILE", "also write a Markdown results page over all models");
  p.flag("no-png", &o.no_png, "write the charts as SVG only");
  add_model_input_options(p, &o.model_input);
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run) return ArgParser::exit_code(outcome);
  o.command = "gonio bench";
  for (const std::string& a : args) o.command += " " + a;
  Result<app::BenchPlan> plan = app::plan_bench(o);
  if (!plan.ok()) {
    print_error("bench: " + plan.error().message);
    std::fprintf(stderr, "%s\n", p.usage().c_str());
    return kExitUsage;
  }
  // Under mpirun/srun the reference runs are shared by the ranks
  // (tools/run/distributed_run.h); rank 0 alone runs the series and writes.
  std::optional<sim::Ranks> ranks = app::join_job("bench");
  if (!ranks) return kExitFailure;
  app::BenchHooks hooks;
  if (ranks->rank() == 0 && stderr_is_terminal()) show_progress(hooks);
  hooks.on_model = print_summary;
  if (!app::bench(plan.value(), hooks, &ranks.value())) return kExitFailure;
  if (!o.page.empty() && ranks->rank() == 0) std::printf("wrote %s\n", o.page.c_str());
  return kExitOk;
}

}  // namespace gonio::cli
