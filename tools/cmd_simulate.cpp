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
// intensity diagram; tools/simulation_outputs.h) and DIR/report.json
// (settings, speed, the energy ledger, and each file read back: its flux and
// its check findings). With --preview, DIR/preview.exr and DIR/preview.png
// are replaced after every iteration (tools/preview_output.h). Progress goes
// to stderr when it is a terminal. With --target-error the run stops once the
// estimated RMS candela error (tools/progressive_run.h) is at or under PCT;
// report.json then says "stopped_by": "target-error" and
// "estimated_rms_error_pct". With --serve the live page of `gonio watch`
// (tools/live_view.h) follows the run and stays up after it until Ctrl-C.
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
// (tools/distributed_run.h).
//
// Under mpirun or srun every rank traces its share of each iteration and the
// counts are summed across the ranks (sim/distributed.h): the same files as
// one process. The ranks first agree on the model and settings (a rank that
// cannot read its model, or holds another, stops them all before tracing);
// rank 0 alone writes files, previews and progress.
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
#include "io/outputs/luminance_images.h"
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
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/distributed_run.h"
#include "tools/json_figures.h"
#include "tools/live_view.h"
#include "tools/model_input.h"
#include "tools/preview_output.h"
#include "tools/progressive_run.h"
#include "tools/resampler_cache.h"
#include "tools/simulate_command.h"
#include "tools/simulation_outputs.h"

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

std::string format_rate(double per_s) {
  char buf[32];
  if (per_s >= 1e6) {
    std::snprintf(buf, sizeof buf, "%.2f M", per_s / 1e6);
  } else if (per_s >= 1e3) {
    std::snprintf(buf, sizeof buf, "%.1f k", per_s / 1e3);
  } else {
    std::snprintf(buf, sizeof buf, "%.0f ", per_s);
  }
  return buf;
}

double percent(double part, double whole) { return whole > 0.0 ? 100.0 * part / whole : 0.0; }

std::string signed_percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.3f %%", 100.0 * fraction);
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
  p.choice("next-event", &o->next_event, {"auto", "on", "off"},
           "next-event estimation for the far field: at every diffuse or glossy surface a photon meets,\n"
           "M connection rays book what it sends out of the luminaire directly (docs/luminance-and-\n"
           "glare.md); auto (default): on where a pilot of the first photons finds >= 90 % of the\n"
           "escaping light leaving that way (the LED array sample: 0.3x the time to 1 % error; the bell:\n"
           "off); not with guided emission");
  p.option("connections", &o->connections, 1, 1024, "M", "next-event connections per surface vertex (default 16)");
  p.option("luminance-image", &o->luminance_images, "C:G,...|ugr",
           "luminance images of the luminaire seen from these directions (C and gamma in degrees; ugr:\n"
           "CIE 232's views, gamma 65 and 50 in C0 and C90), orthographic, 1.2 mm pixels, as\n"
           "STEM.luminance-C<C>-G<G>.exr (L in cd/m2; x, y in spectral runs) and .png, with CIE\n"
           "232:2019's glare-source figures and the UGR correction in report.json (up to 16 views)");
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
           "where the model checks' results are kept by content hash, so that an unchanged model "
           "is not checked again, and the overlaps that resample the far field onto the files' "
           "grids (default $XDG_CACHE_HOME/gonio, else ~/.cache/gonio)");
  p.flag("no-cache", &o->no_cache, "neither read nor write the cache (check the model, build the overlaps)");
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
  std::vector<sim::LuminanceView> views;
  if (p.given("luminance-image"))
    if (const std::string why = sim::parse_luminance_views(o.luminance_images, &views); !why.empty())
      return usage_error(p, "--luminance-image: " + why);
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
  settings.next_event = sim::parse_next_event_mode(o.next_event).value_or(sim::NextEventMode::Auto);
  settings.next_event_connections = static_cast<int>(o.connections);
  settings.luminance.views = views;
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
              "Traces photons through a luminaire model (glTF 2.0: .gltf or .glb) and writes\n"
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
  p.positional("MODEL", &model, "the luminaire model (.gltf or .glb)");
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

  // Under mpirun/srun: one rank of the job (tools/distributed_run.h); rank 0
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

namespace {

// STEM.tm25ray (--format tm25): the escapes the simulation kept
// (SimulationSettings::capture_escaped_photons), each moved along its
// direction to where it leaves the luminaire's bounding sphere (centre: the
// middle of the bounding box of every placed vertex and emitter; radius: half
// its diagonal; a start outside the sphere stays where it is), in the
// photometric frame with the ray file's axes of tools/ray_file_far_field.h
// (+x C0, −y C90, +z the nadir; millimetres from the centre). Each ray's
// luminous flux is its photon's share of the run's escaped flux (power
// units), so the rays add up to the escaped flux.
Status write_ray_file(const std::string& path, const sim::Simulation& simulation, double escaped_lm,
                      const std::string& date) {
  const sim::SceneDesc& scene = simulation.scene();
  const photometry::PhotometricFrame& f = scene.frame;
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  const auto take = [&](const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  };
  sim::for_each_placed_vertex(scene, take);
  for (const sim::Emitter& e : scene.emitters) {
    if (e.kind == sim::Emitter::Kind::RaySet && e.rays) {
      for (const sim::Vec3f& p : e.rays->position_m) take(sim::to_double(p));
    } else if (e.kind == sim::Emitter::Kind::Point) {
      take(e.position);
    }
  }
  const Vec3 centre = lo.x <= hi.x ? 0.5 * (lo + hi) : Vec3{0.0, 0.0, 0.0};
  const double radius = lo.x <= hi.x ? 0.5 * length(hi - lo) : 0.0;
  const std::vector<sim::EscapedRay>& escaped = simulation.escaped_rays();
  double units = 0.0;
  for (const sim::EscapedRay& r : escaped) units += static_cast<double>(r.power_units);
  std::vector<float> rays;
  rays.reserve(escaped.size() * 7);
  const auto local = [&](const Vec3& v) { return Vec3{dot(v, f.c0), -dot(v, f.c90), -dot(v, f.up)}; };
  for (const sim::EscapedRay& r : escaped) {
    Vec3 p = r.origin;
    const Vec3 v = p - centre;
    const double b = dot(v, r.direction), c = dot(v, v) - radius * radius;
    if (c < 0.0) p = p + (-b + std::sqrt(b * b - c)) * r.direction;
    const Vec3 x = local(p - centre) * 1000.0, k = local(r.direction);
    for (double value : {x.x, x.y, x.z, k.x, k.y, k.z, escaped_lm * static_cast<double>(r.power_units) / units})
      rays.push_back(static_cast<float>(value));
  }
  io::Tm25RaySet set = io::make_luminous_ray_set(std::move(rays));
  io::Tm25Header& h = set.header;
  h.created = date;
  h.light_source = std::filesystem::path(scene.name).stem().string();
  h.ray_file_creator = std::string("Gonio ") + kVersion;
  h.model_creator = h.ray_file_creator;
  h.equipment = "Gonio photon tracer (simulation)";
  h.additional_info = "escaping photons of the run's first " +
                      std::to_string(simulation.settings().capture_escaped_photons) + " of " +
                      std::to_string(simulation.stats().photons) +
                      " photons, started where they leave the luminaire's bounding sphere (radius " +
                      format_number(radius * 1000.0) + " mm about its centre); +x C0, -y C90, +z nadir";
  if (Status s = io::write_tm25_file(path, set); !s.ok()) return s;
  std::printf("  wrote %s: %zu rays, %s lm (the escaped flux)\n", path.c_str(), set.ray_count(),
              format_number(set.header.luminous_flux_lm).c_str());
  return Ok{};
}

// STEM.near-field-Dm.exr per plane (--near-field): channels `E` (the
// near field) and `E_far` (the far field's prediction) [lx], pixel averages,
// row-major from the top (+C90) with columns along C0; attributes give the
// distance, extent and pixel size. Returns report.json's near_field list.
nlohmann::json write_near_field(const std::string& out_dir, const std::string& stem,
                                const std::vector<sim::NearFieldPlane>& planes, std::vector<std::string>* written,
                                std::vector<Error>* failures) {
  nlohmann::json list = nlohmann::json::array();
  for (const sim::NearFieldPlane& p : planes) {
    io::ExrImage image;
    image.width = image.height = p.pixels;
    image.float_channels.push_back({"E", std::vector<float>(p.near_lx.begin(), p.near_lx.end())});
    image.float_channels.push_back({"E_far", std::vector<float>(p.far_lx.begin(), p.far_lx.end())});
    image.attributes = {{"gonio:quantity", "illuminance (E: near field, E_far: the far field's prediction)"},
                        {"gonio:units", "lx"},
                        {"gonio:distance_m", format_number(p.distance_m)},
                        {"gonio:extent_m", format_number(2.0 * p.half_width_m) + " x " +
                                               format_number(2.0 * p.half_width_m)},
                        {"gonio:pixel_size_m", format_number(p.pixel_size_m)},
                        {"gonio:axes", "columns along C0 (left -, right +), rows along C90 (top +, bottom -)"}};
    const std::string name = stem + ".near-field-" + format_number(p.distance_m) + "m.exr";
    const std::string path = (std::filesystem::path(out_dir) / name).string();
    if (Status s = io::write_exr(path, image); !s.ok()) {
      failures->push_back(s.error());
    } else {
      written->push_back(path);
    }
    list.push_back({{"distance_m", p.distance_m},
                    {"file", name},
                    {"extent_m", 2.0 * p.half_width_m},
                    {"pixel_size_m", p.pixel_size_m},
                    {"on_axis_lx", p.on_axis_lx},
                    {"far_field_on_axis_lx", p.far_field_on_axis_lx},
                    {"max_deviation_pct", p.max_deviation_pct},
                    {"max_deviation_bound_pct", p.upper_bound_pct},
                    {"min_photons_per_pixel", p.min_photons},
                    {"cells_compared", p.cells_compared},
                    {"cell_deviation_pct", p.cell_deviation_pct},
                    {"upper_bound_pct", p.upper_bound_pct},
                    {"lower_bound_pct", std::isfinite(p.lower_bound_pct) ? nlohmann::json(p.lower_bound_pct)
                                                                          : nlohmann::json(nullptr)},
                    {"z_fail", p.z_fail},
                    {"verdict", sim::to_string(p.verdict)},
                    {"photons_to_tell", std::isfinite(p.photons_to_tell) ? nlohmann::json(p.photons_to_tell)
                                                                          : nlohmann::json(nullptr)}});
  }
  return list;
}

}  // namespace

int write_run_files(const SimulatePlan& plan, const ProgressiveOutcome& run, const ModelInputTimes& input_times,
                    const PreviewOutput* preview, std::chrono::steady_clock::time_point start,
                    const nlohmann::json& ranks_report, std::vector<Error> failures) {
  const std::string& model = plan.model;
  const std::string& out_dir = plan.out_dir;
  const sim::SimulationSettings& settings = plan.progressive.simulation;
  const sim::CGammaGrid& grid = plan.grid;
  const std::optional<photometry::Symmetry>& symmetry = plan.symmetry;
  const sim::Simulation* sim = &run.simulation;
  const int max_bounces = settings.max_bounces;
  const std::string report_path = (std::filesystem::path(out_dir) / "report.json").string();
  const sim::FarField far_field = sim->far_field();
  const sim::SimulationStats st = sim->stats();
  const sim::Ledger ledger = sim->ledger();

  OutputRequest request;
  request.directory = out_dir;
  request.stem = plan.stem;
  request.formats = plan.formats;
  request.grid = grid;
  request.symmetry = symmetry;
  request.ies_version = plan.ies_version;
  request.cache_dir = plan.model_input.cache_dir;
  request.opening = simulated_opening(sim->tracer(), sim->scene(), settings.seed);
  request.run.program_version = kVersion;
  request.run.model = model;
  request.run.photons = st.photons;
  request.run.seed = settings.seed;
  request.run.max_bounces = settings.max_bounces;
  request.run.issue_date = format_utc(now_unix(), "%Y-%m-%d");
  const sim::ColourFarField colour = sim->colour_far_field();
  if (!colour.empty()) request.colour = &colour;
  // Spectral runs (sim/spectral.h): the luminaire's colour and its colour
  // over angle on the output grid (sim/colour_over_angle.h), for
  // report.json and the datasheet.
  if (sim->tracer().spectral()) {
    const sim::Resampler own =
        cached_resampler(settings.face_size, sim->scene().frame, plan.grid, plan.model_input.cache_dir);
    request.colour_report = colour_json(sim::colour_over_angle(own, far_field, colour));
  }
  std::vector<std::string> near_field_files;
  nlohmann::json near_field_list;
  sim::FarFieldDistance far_field_distance;
  nlohmann::json far_field_distance_json;
  request.near_field = nlohmann::json::object();  // report keys the datasheet reads too
  if (!settings.near_field_distances_m.empty()) {
    const std::vector<sim::NearFieldPlane> planes = sim->near_field();
    near_field_list = write_near_field(out_dir, plan.stem, planes, &near_field_files, &failures);
    far_field_distance = sim::far_field_distance(planes);
    const Vec3 centre = sim->scene().frame.to_local(sim->near_field_planes()->centre);
    const auto optional_number = [](const std::optional<double>& v) {
      return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
    };
    far_field_distance_json = {
        {"distance_m", optional_number(far_field_distance.distance_m)},
        {"farthest", sim::to_string(far_field_distance.farthest)},
        {"nearer_plane_m", optional_number(far_field_distance.nearer_plane_m)},
        {"photons_to_tell", std::isfinite(far_field_distance.photons_to_tell)
                                ? nlohmann::json(far_field_distance.photons_to_tell)
                                : nlohmann::json(nullptr)},
        {"photometric_centre_m", {centre.x, centre.y, centre.z}}};
    request.near_field["near_field"] = near_field_list;
    request.near_field["far_field_distance_m"] = optional_number(far_field_distance.distance_m);
    request.near_field["far_field_distance"] = far_field_distance_json;
  }
  // Luminance images and CIE 232's figures (io/outputs/luminance_images.h).
  io::LuminanceOutputs luminance;
  if (!settings.luminance.views.empty()) {
    luminance = io::write_luminance_images(out_dir, plan.stem, sim->luminance_images(), request.opening->opening,
                                           settings.luminance.cone_deg);
    failures.insert(failures.end(), luminance.failures.begin(), luminance.failures.end());
    request.near_field["luminance_images"] = luminance.images;
    request.near_field["cie232"] = luminance.cie232;
  }
  Result<OutputResult> written = write_outputs(far_field, sim->scene(), ledger, request);
  if (!written.ok()) failures.push_back(written.error());
  if (plan.tm25) {
    const std::string ray_path = (std::filesystem::path(out_dir) / (plan.stem + ".tm25ray")).string();
    if (Status s = write_ray_file(ray_path, *sim, ledger.escaped.flux_lm, request.run.issue_date); !s.ok())
      failures.push_back(s.error());
  }
  const OutputResult none;
  const OutputResult* outputs = written.ok() ? &written.value() : &none;
  for (const FailedFile& f : outputs->failed) failures.push_back(f.error);

  io::SimulationReport report;
  report.program_version = kVersion;
  report.model = model;
  report.photons_per_iteration = settings.photons_per_iteration;
  report.iterations = settings.iterations;
  report.seed = settings.seed;
  report.threads = st.threads;
  report.max_bounces = settings.max_bounces;
  report.face_size = settings.face_size;
  report.robust_embree = settings.robust_embree;
  report.bvh_quality = sim::to_string(sim->tracer().settings().embree.quality);
  report.bvh_quality_auto = !settings.bvh_quality.has_value();
  report.iterations_done = run.iterations_done;
  report.photons = st.photons;
  report.rays = st.rays;
  report.trace_s = st.trace_s;
  report.setup_s = st.setup_s;
  report.setup.load_s = input_times.load_s;
  report.setup.check_s = input_times.check_s;
  report.setup.validate_s = st.tracer_setup.validate_s;
  report.setup.emission_tables_s = st.tracer_setup.emission_s;
  report.setup.bvh_s = st.tracer_setup.bvh_s;
  report.setup.bvh_reused = st.tracer_setup.bvh_reused;
  report.setup.shading_s = st.tracer_setup.shading_s;
  report.setup.meshes = input_times.meshes;
  report.setup.meshes_from_cache = input_times.meshes_from_cache;
  report.setup.instances = sim->scene().instances.size();
  report.setup.triangles_unique = sim->scene().unique_triangle_count();
  report.setup.triangles_placed = sim->scene().placed_triangle_count();
  report.setup.max_rss_after_load_bytes = input_times.max_rss_after_load_bytes;
  report.setup.max_rss_after_checks_bytes = input_times.max_rss_after_checks_bytes;
  report.max_rss_bytes = io::peak_memory_bytes();
  report.ledger = ledger;
  report.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json json = io::to_json(report);
  json["stopped_by"] = to_string(run.stopped_by);
  json["settings"]["sampler"] = std::string(sim::to_string(settings.sampler));
  json["target_error_pct"] = plan.progressive.target_error_pct > 0.0 ? nlohmann::json(plan.progressive.target_error_pct)
                                                                      : nlohmann::json(nullptr);
  json["estimated_rms_error_pct"] = std::isfinite(run.estimated_rms_error_pct)
                                        ? nlohmann::json(run.estimated_rms_error_pct)
                                        : nlohmann::json(nullptr);
  if (preview) {
    const sim::PreviewStats& ps = preview->stats();
    json["preview"] = {{"exr", "preview.exr"},
                       {"png", "preview.png"},
                       {"filter", describe(plan.preview_params, settings.face_size)},
                       {"flux_lm", ps.preview_flux_lm}};
  }
  json["far_field"] = {{"face_size", settings.face_size},
                       {"texels", far_field.texel_count()},
                       {"flux_lm", far_field.total_flux_lm()}};
  for (const WrittenFile& f : outputs->files)
    if (f.format == OutputFormat::Exr) json["far_field"]["file"] = std::filesystem::path(f.path).filename().string();
  json["outputs"] = to_json(*outputs, grid, ledger.escaped.flux_lm);
  std::string colour_chart_path;
  // Spectral runs: the colour figures and the colour-over-angle chart
  // beside the intensity diagram.
  if (request.colour_report.is_object()) {
    json.update(request.colour_report);
    const std::vector<io::ColourCurve> curves = io::colour_curves(json["colour_over_angle"]);
    const std::string chart_path = (std::filesystem::path(plan.out_dir) / (plan.stem + "-colour.svg")).string();
    const nlohmann::json& dmax = json["colour_over_angle"]["delta_uv_max"];
    Result<io::Figure> chart = io::colour_over_angle_chart(curves, model + ": colour over angle",
                                                           dmax.is_number() ? dmax.get<double>() : photometry::kNaN);
    Status chart_status = chart.ok() ? io::write_figure(chart_path, *chart) : Status(chart.error());
    if (chart_status.ok()) json["colour_over_angle"]["chart"] = std::filesystem::path(chart_path).filename().string();
    else failures.push_back(chart_status.error());
    colour_chart_path = chart_status.ok() ? chart_path : std::string();
  }
  if (!ranks_report.is_null()) json["mpi"] = ranks_report;
  if (!settings.near_field_distances_m.empty()) {
    json["near_field"] = near_field_list;
    json["far_field_distance_m"] = far_field_distance_json["distance_m"];
    json["far_field_distance"] = far_field_distance_json;
    json["far_field_distance_method"] =
        "planes at D below the photometric centre (the power-weighted mean of the points where escaping light "
        "heading down leaves); each compared on 21 x 21 cells of 4D/21 where E_far >= 10 % of the plane's "
        "largest cell: a plane passes when every cell has |E - E_far| / E_far + 1.645 sigma <= 1 % (95 %, "
        "one-sided), fails when one has |E - E_far| / E_far - z sigma > 1 % (z: Sidak for the cells at 95 %), "
        "else is undecided; sigma = sqrt(photons in only one of the cell's two tallies) / photons in E_far; the "
        "distance is the smallest asked for from which that plane and every farther one pass";
  }
  {
    const sim::NextEventSummary n = sim->next_event();
    nlohmann::json ne = {{"mode", sim::to_string(n.mode)}, {"enabled", n.enabled}};
    if (n.mode != sim::NextEventMode::Off) {
      ne["pilot_covered_share"] = n.pilot_covered_share;
      ne["connections_per_vertex"] = n.connections_per_vertex;
    }
    if (n.enabled) {
      ne["vertices"] = n.vertices;
      ne["connections"] = n.connections;
      ne["connections_escaped"] = n.escaped;
      ne["booked_lm"] = n.booked_lm;
      ne["covered_lm"] = n.covered_lm;
      ne["far_field_minus_escaped_lm"] = far_field.total_flux_lm() - ledger.escaped.flux_lm;
    }
    json["next_event"] = ne;
  }
  if (!settings.luminance.views.empty()) {
    json["luminance_images"] = luminance.images;
    json["cie232"] = luminance.cie232;
  }
  // The cache folder kept to its limit, now that this run has used and
  // written its entries (each marked used, so they go last).
  if (const std::string& dir = plan.model_input.cache_dir; !dir.empty()) {
    const io::CacheTrim trim = io::trim_cache(dir, plan.cache_limit_bytes);
    json["cache"] = {{"dir", dir},
                     {"limit_bytes", plan.cache_limit_bytes},
                     {"entries", trim.entries},
                     {"bytes", trim.bytes},
                     {"removed_entries", trim.removed_entries},
                     {"removed_bytes", trim.removed_bytes}};
  } else {
    json["cache"] = nullptr;
  }
  // Every file this run left in DIR besides report.json, and what failed.
  nlohmann::json written_paths = nlohmann::json::array();
  for (const WrittenFile& f : outputs->files) written_paths.push_back(f.path);
  if (!colour_chart_path.empty()) written_paths.push_back(colour_chart_path);
  for (const std::string& path : near_field_files) written_paths.push_back(path);
  for (const std::string& path : luminance.written) written_paths.push_back(path);
  if (preview)
    for (const std::string& path : {preview->exr_path(), preview->png_path()})
      if (std::filesystem::is_regular_file(path)) written_paths.push_back(path);
  json["written"] = written_paths;
  json["output_failures"] = nlohmann::json::array();
  for (const Error& e : failures) json["output_failures"].push_back(to_string(e));

  // The energy checks, each with what it found.
  const sim::Ledger& l = ledger;
  const EnergyCheck energy = check_energy(l, outputs->files, plan.min_lor, plan.flux_tolerance);
  const double lor = energy.lor;
  json["energy"] = energy.json;
  if (Status s = io::write_json(report_path, json); !s.ok()) {
    for (const Error& e : failures) print_error(e);
    print_error(s.error());
    for (const auto& path : written_paths)
      print_error("simulate: written before the report failed: " + path.get<std::string>());
    return kExitFailure;
  }

  std::printf("%s: %llu photons in %d iteration%s, %sphotons/s, %srays/s, %d thread%s\n",
              model.c_str(), static_cast<unsigned long long>(st.photons), run.iterations_done,
              run.iterations_done == 1 ? "" : "s", format_rate(st.photons_per_s()).c_str(),
              format_rate(st.rays_per_s()).c_str(), st.threads, st.threads == 1 ? "" : "s");
  if (st.ranks > 1) std::printf("  on %d MPI ranks (threads per rank; rates of the whole job)\n", st.ranks);
  std::printf("  emitted %.6g lm: escaped %.6g lm (%.2f %%), absorbed %.6g lm (%.2f %%), cut off %.6g lm (%.2f %%)\n",
              l.emitted.flux_lm, l.escaped.flux_lm, percent(l.escaped.flux_lm, l.emitted.flux_lm),
              l.absorbed.flux_lm, percent(l.absorbed.flux_lm, l.emitted.flux_lm), l.cutoff.flux_lm,
              percent(l.cutoff.flux_lm, l.emitted.flux_lm));
  if (l.spectral)
    std::printf("  radiant (360-830 nm): emitted %.6g W: escaped %.6g W, absorbed %.6g W, cut off %.6g W\n",
                l.radiant.emitted_w, l.radiant.escaped_w, l.radiant.absorbed_w, l.radiant.cutoff_w);
  std::printf("  light output ratio %.4f (escaped / emitted)\n", lor);
  for (const auto& p : near_field_list)
    std::printf("  near field at %s m: %s lx on the axis, the far field predicts %s lx; largest deviation %s %% "
                "(E_far >= 10 %% of its maximum): %s\n",
                format_number(p["distance_m"].get<double>()).c_str(),
                format_number(p["on_axis_lx"].get<double>()).c_str(),
                format_number(p["far_field_on_axis_lx"].get<double>()).c_str(),
                format_number(p["max_deviation_pct"].get<double>()).c_str(), p["file"].get<std::string>().c_str());
  if (!settings.near_field_distances_m.empty()) {
    std::string verdict;
    if (far_field_distance.distance_m) verdict = format_number(*far_field_distance.distance_m) + " m";
    else if (far_field_distance.farthest == sim::PlaneVerdict::Fails)
      verdict = "beyond the distances asked for (the farthest plane deviates by more than 1 %)";
    else
      verdict = "undecided (too few photons to tell at the farthest plane; about " +
                format_number(far_field_distance.photons_to_tell, 2) + " would)";
    std::printf("  far-field distance: %s\n", verdict.c_str());
  }
  {
    const sim::NextEventSummary n = sim->next_event();
    if (n.mode != sim::NextEventMode::Off)
      std::printf("  next-event estimation %s (%s; %.0f %% of the pilot's escaping light leaves after a connected "
                  "event)%s\n",
                  n.enabled ? "on" : "off", sim::to_string(n.mode), 100.0 * n.pilot_covered_share,
                  n.enabled ? (": " + format_number(static_cast<double>(n.connections), 3) + " connections, " +
                               format_number(n.booked_lm, 6) + " lm booked for " + format_number(n.covered_lm, 6) +
                               " lm of escapes")
                                  .c_str()
                            : "");
  }
  for (const auto& img : luminance.images) {
    const nlohmann::json& g = img["cie232"];
    std::printf("  luminance image C%s G%s: max %s cd/m2, %s cd; CIE 232: %s\n",
                format_number(img["c_deg"].get<double>()).c_str(), format_number(img["gamma_deg"].get<double>()).c_str(),
                format_number(img["max_cd_m2"].get<double>(), 4).c_str(),
                format_number(img["intensity_cd"].get<double>(), 4).c_str(),
                g["defined"].get<bool>()
                    ? ("k2 " + format_number(g["k2"].get<double>(), 3) + ", delta UGR " +
                       format_fixed(g["delta_ugr"].get<double>(), 1) + ": " + img["file"].get<std::string>())
                          .c_str()
                    : ("not defined (" + g["why_undefined"].get<std::string>() + ")").c_str());
  }
  if (l.escaped.photons == 0 || !(l.escaped.flux_lm > 0.0))
    print_warning(model + ": no light leaves the model: all " + std::to_string(l.emitted.photons) +
                  " photons were absorbed or cut off (is the emitter sealed in?); the files hold zero "
                  "intensity");
  if (std::isfinite(run.estimated_rms_error_pct))
    std::printf("  estimated RMS candela error %.3g %% of the peak%s\n", run.estimated_rms_error_pct,
                run.stopped_by == StopReason::TargetError ? " (stopped at the target error)" : "");
  if (!outputs->symmetry_reason.empty()) {
    if (symmetry)
      std::printf("  %s\n", outputs->symmetry_reason.c_str());
    else  // the reasoning is long: stderr (and the report) only
      std::fprintf(stderr, "%s: simulate: %s\n", kProgramName, outputs->symmetry_reason.c_str());
  }
  for (const WrittenFile& f : outputs->files) {
    if (std::isfinite(f.flux_lm) && std::isfinite(f.flux_difference))
      std::printf("  wrote %s: %.6g lm read back (%s of the escaped flux)%s\n", f.path.c_str(), f.flux_lm,
                  signed_percent(f.flux_difference).c_str(), f.clean() ? "" : ", NOT CLEAN");
    else if (std::isfinite(f.flux_lm))  // no escaped flux to compare with
      std::printf("  wrote %s: %.6g lm read back%s\n", f.path.c_str(), f.flux_lm, f.clean() ? "" : ", NOT CLEAN");
    else
      std::printf("  wrote %s%s\n", f.path.c_str(), f.clean() ? "" : ", NOT CLEAN");
  }
  std::printf("  wrote %s\n", report_path.c_str());
  if (preview)
    std::printf("  preview: %s and %s\n", preview->exr_path().c_str(), preview->png_path().c_str());

  if (!failures.empty()) {
    for (const Error& e : failures) print_error(e);
    print_error("simulate: " + std::to_string(failures.size()) + " output" +
                (failures.size() == 1 ? "" : "s") + " failed after tracing; " + report_path +
                " lists what was written");
    (void)energy_exit_code(model, energy);  // its failures are printed too
    return kExitFailure;
  }
  if (const int code = energy_exit_code(model, energy); code != kExitOk) return code;
  if (l.cutoff.flux_lm > 0.01 * l.emitted.flux_lm)
    print_warning(model + ": " + std::to_string(percent(l.cutoff.flux_lm, l.emitted.flux_lm)) +
                  " % of the flux was cut off by the bounce limit (--max-bounces " +
                  std::to_string(max_bounces) + "): light trapped in the model is missing");
  return kExitOk;
}

}  // namespace gonio::cli
