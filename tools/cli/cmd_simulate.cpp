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
// Writes DIR/STEM.ies, STEM.ldt, farfield.exr (cube), farfield-latlong.exr, STEM.svg (the
// intensity diagram; tools/run/simulation_outputs.h) and DIR/report.json
// (settings, speed, the energy ledger, and each file read back: its flux and
// its check findings). With --preview, DIR/preview.exr and DIR/preview.png
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
#include <ctime>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "gonio/version.h"
#include "io/support/cache_folder.h"
#include "io/outputs/colour_chart.h"
#include "io/outputs/exr.h"
#include "io/support/file_io.h"
#include "io/support/text.h"
#include "io/outputs/report.h"
#include "io/photometric/tm25.h"
#include "photometry/format.h"
#include "sim/colour_over_angle.h"
#include "sim/resample.h"
#include "sim/simulation.h"
#include "sim/symmetry.h"
#include "sim/ray_set_emitter.h"
#include "tools/cli/cli.h"
#include "tools/cli/input_options.h"
#include "tools/cli/commands.h"
#include "tools/run/distributed_run.h"
#include "tools/run/json_figures.h"
#include "tools/live/live_view.h"
#include "tools/run/model_input.h"
#include "tools/run/preview_output.h"
#include "tools/run/progressive_run.h"
#include "tools/run/resampler_cache.h"
#include "tools/cli/simulate_command.h"
#include "tools/run/simulation_outputs.h"

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

std::nullopt_t usage_error(const std::string& command, const ArgParser& p, const std::string& message) {
  print_error(command + ": " + message);
  std::fprintf(stderr, "%s\n", p.usage().c_str());
  return std::nullopt;
}

}  // namespace

void add_simulate_options(ArgParser& p, SimulateOptions* o) {
  p.option("photons", &o->photons, 1, 4'294'967'295LL, "N", "photons per iteration (default 1000000)");
  p.option("iterations", &o->iterations, 1, 1'000'000, "K", "iterations (default 10): K·N photons in all");
  p.option("seed", &o->seed, 0, 9'223'372'036'854'775'807LL, "S", "random seed (default 1)");
  p.choice("sampler", &o->sampler, {"sobol", "random"},
           "where photons' numbers come from: sobol (default: Owen-scrambled Sobol' points in four "
           "independent scrambles keyed by the seed, whose spread gives the error estimate) or random "
           "(pseudo-random); either gives the same bytes for any threads or split");
  p.option("threads", &o->threads, 0, 4096, "T", "threads (default 0: every core)");
  p.option("max-bounces", &o->max_bounces, 0, 1'000'000, "B",
           "surface interactions before a photon is cut off (default 100)");
  p.option("face-size", &o->face_size, 1, 4096, "F",
           "cube-map texels per face edge (default: two texels per grid step, 128 for 5 x 2.5 deg)");
  p.option("c-step", &o->c_step, sim::kMinGridStepDeg, sim::kMaxGridStepDeg, "DEG",
           "C-plane spacing of the IES/LDT grid (default 5; divides 360)");
  p.option("gamma-step", &o->gamma_step, sim::kMinGridStepDeg, sim::kMaxGridStepDeg, "DEG",
           "gamma spacing of the IES/LDT grid (default 2.5; divides 180)");
  p.option("symmetry", &o->symmetry_name, "S",
           "auto (default: a chi-square test per symmetry on the photon counts), none, C0-C180, "
           "C90-C270, quadrant or rotational");
  p.option("format", &o->format_list, "LIST",
           "files to write, comma-separated: ies, ldt, exr, latlong, plot, report (the datasheet\n"
           "STEM.html with the energy ledger), gldf (STEM.gldf with the LDT, IES and the model as\n"
           "L3D), tm33 (STEM.xml, IES TM-33-23; a spectral run's with its spectrum), tm25\n"
           "(STEM.tm25ray: the escaping photons as an IES TM-25 ray file, see --tm25-rays), or\n"
           "all (default: every one but report, gldf, tm33 and tm25, which are written only when\n"
           "named)");
  p.option("tm25-rays", &o->tm25_rays, 1, 100'000'000, "N",
           "with --format tm25: the escapes of the run's first N photons are the ray file's rays\n"
           "(default 1000000); their fluxes add up to the escaped flux");
  p.option("near-field", &o->near_field, "D1,D2,...",
           "near-field photometry: the illuminance on planes D metres below the luminaire's centre\n"
           "(perpendicular to the nadir, 4D square, 41 x 41 pixels) from every escaping photon's\n"
           "path, against the far field's prediction, as STEM.near-field-Dm.exr, with near_field and\n"
           "far_field_distance_m in report.json (up to 16 distances, each in (0, 1e4])");
  p.choice("ies-version", &o->ies_version, {"2002", "2019"}, "IES LM-63 version (default 2019)");
  p.option("name", &o->stem, "STEM", "file names DIR/STEM.* (default: the model's file name without extension)");
  p.option("min-lor", &o->min_lor, 0.0, 1.0, "X",
           "fail when the light output ratio escaped/emitted is under X (default 0: never)");
  p.option("flux-tolerance", &o->flux_tolerance, 0.0, 1.0, "X",
           "fail when a written file's flux differs from the escaped flux by more than X "
           "(a fraction; default 0.005 = 0.5 %)");
  p.option("target-error", &o->target_error_pct, 0.0, 100.0, "PCT",
           "stop once the estimated RMS candela error (from photon counts, relative to the peak) is "
           "at or under PCT percent (default 0: run every iteration)");
  p.choice("bvh-quality", &o->bvh_quality, {"auto", "low", "medium", "high"},
           "Embree's BVH build quality: auto (default: low when the run has fewer photons than half\n"
           "the model's unique triangles, where building the better tree would cost more than it\n"
           "saves, else high), or low, medium, high");
  p.option("cache", &o->cache_dir, "DIR",
           "where the model checks' results and CAD models' meshes are kept by content hash, so "
           "that an unchanged model is not checked or meshed again, and the overlaps that resample "
           "the far field onto the files' grids (default $XDG_CACHE_HOME/gonio, else ~/.cache/gonio)");
  p.flag("no-cache", &o->no_cache,
         "neither read nor write the cache (check the model, mesh a CAD model, build the overlaps)");
  p.option("cache-limit", &o->cache_limit_mb, 0, 1'000'000'000, "MB",
           "after the run, remove the cache's least recently used entries while they hold more than "
           "MB megabytes (MiB), down to nine tenths of it; other files in the folder are left alone "
           "(default 1024; 0: no limit)");
  add_model_input_options(p, &o->model_input);
  add_preview_options(p, &o->preview);
}

std::optional<SimulatePlan> plan_simulation(const std::string& command, const std::string& model,
                                            const SimulateOptions& o, const ArgParser& p) {
  const long long photons = o.photons, iterations = o.iterations, seed = o.seed, threads = o.threads,
                  max_bounces = o.max_bounces;
  long long face_size = o.face_size;
  const double c_step = o.c_step, gamma_step = o.gamma_step;
  const std::string& symmetry_name = o.symmetry_name;
  std::string stem = o.stem;
  auto usage_error = [&](const ArgParser& parser, const std::string& message) {
    return cli::usage_error(command, parser, message);
  };
  const Result<sim::PreviewFilterParams> preview_params_result = preview_params(o.preview, p);
  if (!preview_params_result.ok()) return usage_error(p, preview_params_result.error().message);
  sim::CGammaGrid grid;
  grid.c_step_deg = c_step;
  grid.gamma_step_deg = gamma_step;
  if (Status s = sim::validate(grid); !s.ok()) return usage_error(p, s.error().message);
  std::optional<photometry::Symmetry> symmetry;
  if (symmetry_name != "auto") {
    symmetry = sim::parse_symmetry(symmetry_name);
    if (!symmetry)
      return usage_error(p, "--symmetry: unknown symmetry '" + symmetry_name +
                                "'; expected auto, none, C0-C180, C90-C270, quadrant or rotational");
    if (Status s = sim::check_grid_supports(grid, *symmetry); !s.ok()) return usage_error(p, s.error().message);
  }
  // tm25 is written here (write_ray_file), the others by write_outputs.
  bool tm25 = false;
  std::string other_formats;
  for (std::size_t start = 0; start <= o.format_list.size();) {
    const std::size_t comma = std::min(o.format_list.find(',', start), o.format_list.size());
    std::string name = o.format_list.substr(start, comma - start);
    start = comma + 1;
    while (!name.empty() && name.front() == ' ') name.erase(name.begin());
    while (!name.empty() && name.back() == ' ') name.pop_back();
    if (name == "tm25") {
      tm25 = true;
    } else {
      other_formats += (other_formats.empty() ? "" : ",") + name;
    }
  }
  std::vector<double> near_field_m;
  if (p.given("near-field")) {
    for (std::size_t start = 0; start <= o.near_field.size();) {
      const std::size_t comma = std::min(o.near_field.find(',', start), o.near_field.size());
      const std::string token = o.near_field.substr(start, comma - start);
      start = comma + 1;
      const std::optional<double> d = io::parse_number(token);
      if (!d || !(*d > 0.0 && *d <= 1e4))
        return usage_error(p, "--near-field: '" + token + "' is not a distance in metres in (0, 1e4]");
      if (std::find(near_field_m.begin(), near_field_m.end(), *d) == near_field_m.end()) near_field_m.push_back(*d);
    }
    if (near_field_m.size() > 16) return usage_error(p, "--near-field: at most 16 distances");
    std::sort(near_field_m.begin(), near_field_m.end());
  }
  if (!tm25 && p.given("tm25-rays")) return usage_error(p, "--tm25-rays applies to --format tm25 only");
  Result<std::vector<OutputFormat>> formats =
      tm25 && other_formats.empty() ? Result<std::vector<OutputFormat>>(std::vector<OutputFormat>{})
                                    : parse_formats(other_formats);
  if (!formats.ok()) return usage_error(p, formats.error().message);
  if (stem.empty()) stem = std::filesystem::path(model).stem().string();
  if (stem.empty() || stem.find_first_of("/\\") != std::string::npos || stem == "." || stem == "..")
    return usage_error(p, "--name: '" + stem + "' is not a plain file name");
  if (!p.given("face-size")) face_size = sim::face_size_for(grid);
  if (o.no_cache && p.given("cache")) return usage_error(p, "--cache and --no-cache exclude each other");

  SimulatePlan plan;
  plan.model = model;
  plan.out_dir = o.out_dir;
  plan.stem = stem;
  plan.grid = grid;
  plan.symmetry = symmetry;
  plan.formats = formats.value();
  plan.tm25 = tm25;
  plan.ies_version = o.ies_version == "2002" ? io::IesVersion::LM63_2002 : io::IesVersion::LM63_2019;
  plan.preview = o.preview.enabled;
  plan.preview_params = preview_params_result.value();
  plan.min_lor = o.min_lor;
  plan.flux_tolerance = o.flux_tolerance;
  plan.model_input = o.model_input;
  plan.model_input.gamma_step_deg = gamma_step;
  if (Status s = check_model_input(plan.model_input, {model}); !s.ok()) return usage_error(p, s.error().message);
  plan.model_input.cache_dir = o.no_cache          ? std::string()
                               : p.given("cache") ? o.cache_dir
                                                  : io::default_cache_dir();
  plan.cache_limit_bytes = static_cast<std::uint64_t>(o.cache_limit_mb) << 20;
  plan.progressive.target_error_pct = o.target_error_pct;
  sim::SimulationSettings& settings = plan.progressive.simulation;
  settings.photons_per_iteration = static_cast<std::uint64_t>(photons);
  settings.iterations = static_cast<int>(iterations);
  settings.seed = static_cast<std::uint64_t>(seed);
  settings.sampler = sim::parse_sampler(o.sampler).value_or(sim::SamplerKind::Sobol);
  settings.threads = static_cast<int>(threads);
  settings.capture_escaped_photons = tm25 ? static_cast<std::uint64_t>(o.tm25_rays) : 0;
  settings.near_field_distances_m = near_field_m;
  settings.max_bounces = static_cast<int>(max_bounces);
  settings.face_size = static_cast<int>(face_size);
  using Quality = sim::EmbreeSceneOptions::Quality;
  for (Quality q : {Quality::Low, Quality::Medium, Quality::High})
    if (o.bvh_quality == sim::to_string(q)) settings.bvh_quality = q;  // "auto" leaves it unset
  return plan;
}

int run_simulate(const Args& args) {
  const auto start = std::chrono::steady_clock::now();
  std::string model;
  SimulateOptions options;
  bool serve = false;
  long long port = kDefaultLivePort;
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
    usage_error("simulate", p, "--out DIR is required");
    return kExitUsage;
  }
  std::optional<SimulatePlan> planned = plan_simulation("simulate", model, options, p);
  if (!planned) return kExitUsage;

  // Under mpirun/srun: one rank of the job (tools/run/distributed_run.h); rank 0
  // alone writes files and shows progress.
  std::optional<sim::Ranks> ranks = join_job("simulate");
  if (!ranks) return kExitFailure;
  const bool lead = ranks->rank() == 0;
  if (serve && ranks->distributed()) {
    usage_error("simulate", p, "--serve runs in one process, not under mpirun or srun");
    return kExitUsage;
  }
  planned->progressive.simulation.ranks = &ranks.value();
  const SimulatePlan& plan = *planned;
  const std::string& out_dir = plan.out_dir;
  const sim::SimulationSettings& settings = plan.progressive.simulation;

  // Load, then check the geometry: errors stop the run, warnings are printed.
  ModelInputTimes input_times;
  std::optional<sim::SceneDesc> scene = load_checked_model(model, "simulated", plan.model_input, &input_times);
  // Ray-set emitters asked for more photons than their rays can give.
  if (scene && lead)
    for (Finding& f : sim::ray_set_photon_findings(
             *scene, settings.photons_per_iteration * static_cast<std::uint64_t>(settings.iterations))) {
      f.where.file = model;
      print_finding(f);
    }

  // The output directory is made before tracing so that previews can land in it.
  bool ready = scene.has_value();
  if (ready && lead) {
    if (Status s = io::make_directories(out_dir); !s.ok()) {
      print_error(s.error());
      ready = false;
    }
  }
  // Every rank ready, with the same model and settings, or none traces.
  std::optional<std::string> fingerprint;
  if (ready) fingerprint = ranks->distributed() ? run_fingerprint(*scene, settings) : std::string();
  if (!ranks_agree(*ranks, fingerprint, "simulate")) return kExitFailure;
  std::optional<PreviewOutput> preview;
  if (plan.preview && lead) preview.emplace(out_dir, settings.face_size, plan.preview_params);
  Status preview_status = Ok{};
  // The estimate needs the output grid's resampler (0.07 s to build at the
  // defaults, else from the cache): made only when asked for, by the live
  // page where there is one.
  std::optional<sim::Resampler> own_resampler;
  const sim::Resampler* resampler = nullptr;
  std::unique_ptr<LiveView> live;
  if (serve) {
    auto started = LiveView::start(kLiveHost, static_cast<int>(port), plan);
    if (!started.ok()) {
      print_error(started.error());
      return kExitFailure;
    }
    live = std::move(started.value());
    std::printf("live page: %s\n", live->url().c_str());
    std::fflush(stdout);
    resampler = &live->resampler_for(scene.value());
    live->begin_run(model, scene.value(), {});
  } else if (plan.progressive.target_error_pct > 0.0) {
    resampler = &own_resampler.emplace(
        cached_resampler(settings.face_size, scene->frame, plan.grid, plan.model_input.cache_dir));
  }

  const bool show_progress = lead && (force_progress || stderr_is_terminal());
  auto progress = [&](const IterationReport& r, const sim::Simulation& simulation) {
    const sim::SimulationProgress& pr = r.progress;
    if (preview && preview_status.ok()) preview_status = preview->write(simulation.far_field());
    if (live) live->iteration(r, simulation);
    if (!show_progress) return true;
    std::fprintf(stderr, "\r%s: simulate: iteration %d/%d, %sphotons/s, %s left   ", kProgramName,
                 pr.iteration, pr.iterations, format_rate(pr.photons_per_s).c_str(),
                 format_duration(pr.remaining_s).c_str());
    if (pr.iteration == pr.iterations || pr.remaining_s == 0.0) std::fputc('\n', stderr);
    std::fflush(stderr);
    return true;
  };
  // With the live page Ctrl-C is caught (the page stays up after the run):
  // during the run it stops the run, and nothing is written.
  const CancelCheck cancel = live ? CancelCheck([] { return interrupted(); }) : CancelCheck();
  Result<ProgressiveOutcome> sim = run_progressive(std::move(scene.value()), plan.progressive, resampler, progress, cancel);
  if (!sim.ok()) {
    Error e = sim.error();
    if (e.where.file.empty()) e.where.file = model;
    print_error(e);
    if (live) live->run_failed(e);
    return kExitFailure;
  }
  // Each rank's share and speed; then rank 0 alone writes.
  const nlohmann::json ranks_report = ranks_json(*ranks, sim->simulation.stats());
  if (!lead) return kExitOk;

  if (sim->stopped_by == StopReason::Cancelled) {
    print_error("simulate: interrupted; nothing was written");
    return kExitFailure;
  }
  if (live) live->run_finished(sim.value());
  // From here on a failure loses nothing (write_run_files): a preview that
  // could not be written is listed in report.json with the files that were.
  std::vector<Error> failures;
  if (!preview_status.ok()) failures.push_back(preview_status.error());
  const int code = write_run_files(plan, sim.value(), input_times, preview ? &*preview : nullptr, start,
                                   ranks_report, std::move(failures));
  if (live) {
    std::printf("live page: %s stays up until Ctrl-C\n", live->url().c_str());
    std::fflush(stdout);
    wait_for_interrupt();
  }
  return code;
}

}  // namespace gonio::cli
