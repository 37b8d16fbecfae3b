// gonio simulate: traces a luminaire model into its far field and writes the
// files light-planning programs and renderers read.
//
//   gonio simulate MODEL --out DIR [--photons N] [--iterations K] [--seed S]
//                  [--sampler sobol|random] [--threads T] [--max-bounces B] [--face-size F]
//                  [--c-step DEG] [--gamma-step DEG] [--symmetry S]
//                  [--format LIST] [--ies-version 2002|2019] [--name STEM]
//                  [--min-lor X] [--flux-tolerance X] [--target-error PCT]
//                  [--bvh-quality Q] [--cache DIR | --no-cache] [--preview [filter options]]
//                  [--serve [--port P]] [--progress]
//
// The options become tools/run/simulate.h's SimulateOptions; app::simulate
// writes DIR/STEM.ies, STEM.ldt, farfield.exr (cube), farfield-latlong.exr,
// STEM.svg (the intensity diagram; tools/run/simulation_outputs.h) and
// DIR/report.json (settings, speed, the energy ledger, and each file read
// back: its flux and its check findings; tools/run/simulation_run.h); this
// file prints the summary (tools/cli/simulate_command.h) and the exit code. With --preview, DIR/preview.exr and DIR/preview.png
// are replaced after every iteration (tools/run/preview_output.h). Progress goes
// to stderr when it is a terminal. With --target-error the run stops once the
// estimated RMS candela error (tools/run/progressive_run.h) is at or under PCT;
// report.json then says "stopped_by": "target-error" and
// "estimated_rms_error_pct". With --serve the live page of `gonio watch`
// (tools/live/live_view.h) follows the run and stays up after it until Ctrl-C.
//
// report.json adds to io/outputs/report.h's fields: "outputs" {grid, symmetry
// {chosen, reason, tests [{symmetry, chi_square, degrees_of_freedom,
// p_value, groups, rejected, detectable_deviation}]}, escaped_lm, files [{path, format, flux_lm,
// flux_difference, clean, findings, writer_notes}], failed [{path, format,
// error}]} and "energy"
// {photons_close, flux_imbalance_lm, lor, min_lor, flux_tolerance,
// files [{path, flux_ok, clean}], passed, failures [text]}.
//
// report.json's "mpi" {ranks, per_rank [{rank, threads, photons, trace_s,
// photons_per_s, wait_s, reduce_s, reduce_fastest_s}]}: each rank's share
// (tools/run/distributed_run.h).
//
// Under mpirun or srun every rank traces its share of each iteration and the
// counts are summed across the ranks (sim/distributed.h): the same files as
// one process. The ranks first agree on the model and settings (a rank that
// cannot read its model, or holds another, stops them all before tracing);
// rank 0 alone writes files, previews and progress.
//
// report.json's "cad" (STEP and IGES models only; tools/run/model_input.h):
// {format, file_unit, parts_file, tessellation {angular_deflection_deg,
// chordal_relative, chordal_min_mm, chordal_mm, exact_normals}, parts,
// placements, triangles_unique, triangles_placed, from_cache, tessellate_s,
// per_part [{name, triangles, placements, size_mm, chordal_deflection_mm}]}.
// A design file has "design_file" in its place: {file, length_unit, kinds,
// variables, tessellation, parts, placements, triangles_unique,
// triangles_placed, tessellate_s, per_part} (docs/design.md).
//
// report.json's "cache" {dir, limit_bytes, entries, bytes, removed_entries,
// removed_bytes}: the cache folder after this run's trim to --cache-limit
// (io/support/cache_folder.h); null with --no-cache.
//
// report.json also lists "written" (every file of the run besides itself)
// and "output_failures" (text): a failure after tracing (a missing plot program, a
// full disk, a path that cannot be written, the preview) loses nothing: the
// other files are written, the report lists them with the failure, and the
// exit code is 1. Where report.json itself cannot be written, stderr lists
// the files that were.
//
// Energy checks (exit 1 after everything is written, with a message):
// emitted = escaped + absorbed + cut off in photons, LOR = escaped / emitted
// at least --min-lor, every written file's flux within --flux-tolerance of
// the escaped flux, every written file clean.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "gonio/version.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/simulate_command.h"
#include "tools/live/live_view.h"
#include "tools/run/distributed_run.h"
#include "tools/run/simulate.h"

namespace gonio::cli {
namespace {

std::string format_duration(double s) {
  char buf[32];
  if (s < 60.0) {
    std::snprintf(buf, sizeof buf, "%.0f s", std::ceil(s));
  } else if (s < 3600.0) {
    std::snprintf(buf, sizeof buf, "%d min %02d s", static_cast<int>(s) / 60, static_cast<int>(s) % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%d h %02d min", static_cast<int>(s) / 3600,
                  (static_cast<int>(s) % 3600) / 60);
  }
  return buf;
}

// "gonio: simulate: iteration I/N, R photons/s, T left" on stderr, over itself.
void print_progress(const sim::SimulationProgress& pr) {
  std::fprintf(stderr, "\r%s: simulate: iteration %d/%d, %sphotons/s, %s left   ", kProgramName, pr.iteration,
               pr.iterations, format_rate(pr.photons_per_s).c_str(), format_duration(pr.remaining_s).c_str());
  if (pr.iteration == pr.iterations || pr.remaining_s == 0.0) std::fputc('\n', stderr);
  std::fflush(stderr);
}

// The live page follows the run (--serve): it begins when the model is
// loaded, shows every iteration, and stays up after the run. Ctrl-C is
// caught: during the run it stops the run, and nothing is written.
void follow_on_live_page(app::LiveView& live, const std::string& model, app::SimulateHooks& hooks) {
  hooks.on_loaded = [&live, model](const sim::SceneDesc& scene, const std::vector<Finding>& findings) {
    const sim::Resampler* resampler = &live.resampler_for(scene);
    live.begin_run(model, scene, findings);
    return resampler;
  };
  hooks.cancel = [] { return app::interrupted(); };
  hooks.on_traced = [&live](const app::ProgressiveOutcome& run) {
    if (run.stopped_by != app::StopReason::Cancelled) live.run_finished(run);
  };
  hooks.on_failed = [&live](const Error& e) { live.run_failed(e); };
}

}  // namespace

int run_simulate(const Args& args) {
  const auto start = std::chrono::steady_clock::now();
  std::string model;
  app::SimulateOptions options;
  bool serve = false;
  long long port = app::kDefaultLivePort;
  ArgParser p("simulate", "MODEL --out DIR [options]",
              "Traces photons through a luminaire model (glTF 2.0: .gltf or .glb; or CAD: STEP\n"
              "or IGES with a sidecar naming materials and emitters, see --parts) and writes\n"
              "what light-planning programs and renderers read, each file read back and\n"
              "checked: DIR/STEM.ies (LM-63-2019, computer simulation), DIR/STEM.ldt\n"
              "(EULUMDAT, cd/klm of the emitters' flux), DIR/farfield.exr (far-field cube\n"
              "map: Y = intensity in cd, flux in lm and photons per texel),\n"
              "DIR/farfield-latlong.exr (equirectangular), DIR/STEM.svg (intensity diagram),\n"
              "and DIR/report.json (settings, speed, the energy ledger per emitter, mesh and\n"
              "material, and every file's flux read back). Fails (exit 1) when the books do\n"
              "not close, the LOR is under --min-lor, a file's flux misses the escaped flux\n"
              "by more than --flux-tolerance, or a file is not clean. The same seed gives the\n"
              "same files whatever the thread count.");
  p.positional("MODEL", &model, "the luminaire model (.gltf, .glb, .step, .stp, .iges or .igs)");
  p.option("out", &options.out_dir, "DIR", "output directory (created if missing)");
  add_simulate_options(p, &options);
  p.flag("serve", &serve, "show the run on the live page of `gonio watch` (127.0.0.1), kept up until Ctrl-C");
  p.option("port", &port, 0, 65535, "P", "port of the live page (default 8765; 0: any free port, printed)");
  bool force_progress = false;
  p.flag("progress", &force_progress,
         "show progress on stderr even where it is not a terminal (under mpirun or srun, whose "
         "ranks never write to one: rank 0 shows the whole job's rate)");
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run)
    return ArgParser::exit_code(outcome);
  if (options.out_dir.empty()) {
    print_usage_error("simulate", p, "--out DIR is required");
    return kExitUsage;
  }
  std::optional<app::SimulatePlan> plan = plan_or_usage("simulate", model, options, p);
  if (!plan) return kExitUsage;
  // Under mpirun/srun: one rank of the job (tools/run/distributed_run.h); rank 0
  // alone writes files and shows progress.
  std::optional<sim::Ranks> ranks = app::join_job("simulate");
  if (!ranks) return kExitFailure;
  if (serve && ranks->distributed()) {
    print_usage_error("simulate", p, "--serve runs in one process, not under mpirun or srun");
    return kExitUsage;
  }
  plan->progressive.simulation.ranks = &ranks.value();

  app::SimulateHooks hooks;
  std::unique_ptr<app::LiveView> live;
  if (serve) {
    auto started = app::LiveView::start(app::kLiveHost, static_cast<int>(port), *plan);
    if (!started.ok()) {
      print_error(started.error());
      return kExitFailure;
    }
    live = std::move(started.value());
    std::printf("live page: %s\n", live->url().c_str());
    std::fflush(stdout);
    follow_on_live_page(*live, model, hooks);
  }
  const bool show_progress = ranks->rank() == 0 && (force_progress || stderr_is_terminal());
  hooks.on_iteration = [&](const app::IterationReport& r, const sim::Simulation& simulation) {
    if (live) live->iteration(r, simulation);
    if (show_progress) print_progress(r.progress);
    return true;
  };
  std::optional<app::SimulateResult> result = app::simulate(*plan, hooks, start);
  if (!result) return kExitFailure;  // what stopped it is printed
  if (!result->lead) return kExitOk;
  if (result->run.stopped_by == app::StopReason::Cancelled) {
    print_error("simulate: interrupted; nothing was written");
    return kExitFailure;
  }
  const int code = print_run_files(*plan, result->run, *result->files);
  if (live) {
    std::printf("live page: %s stays up until Ctrl-C\n", live->url().c_str());
    std::fflush(stdout);
    app::wait_for_interrupt();
  }
  return code;
}

}  // namespace gonio::cli
