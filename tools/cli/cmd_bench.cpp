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
// For each model: a cached reference run (tools/bench/bench_reference.h), the
// series (tools/bench/bench_series.h), and DIR/series.csv, DIR/bench.json and the
// charts (tools/bench/bench_report.h); with several models each gets DIR/<name>/.
// --page writes a Markdown page over all of them (scripts/results.sh makes
// docs/results.md this way).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <thread>

#include "gonio/tracer_revision.h"
#include "gonio/version.h"
#include "io/support/content_hash.h"
#include "io/support/file_io.h"
#include "io/outputs/report.h"
#include "photometry/format.h"
#include "sim/cube_map.h"
#include "sim/resample.h"
#include "tools/bench/bench_reference.h"
#include "tools/bench/bench_report.h"
#include "tools/bench/bench_series.h"
#include "tools/cli/cli.h"
#include "tools/cli/input_options.h"
#include "tools/cli/commands.h"
#include "tools/run/distributed_run.h"
#include "tools/run/model_input.h"
#include "tools/run/scene_hash.h"

namespace gonio::cli {
namespace {

namespace fs = std::filesystem;

std::string first_line_of(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) {
        std::size_t b = colon + 1;
        while (b < line.size() && line[b] == ' ') ++b;
        return line.substr(b);
      }
    }
  return "";
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  double a = 0, b = 0, c = 0;
  if (!(in >> a >> b >> c)) return "unknown";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f, %.2f, %.2f", a, b, c);
  return buf;
}

void print_summary(const BenchOutcome& o) {
  const Reference& r = o.reference;
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
  for (const SeriesResult& s : o.series) {
    if (s.points.empty()) continue;
    std::printf("  %-28s %12s %12s %16s %14s %12s %8s\n", s.spec.label.c_str(),
                format_value(s.time_to_target_s, 3).c_str(), format_value(s.photons_to_target, 3).c_str(),
                format_value(s.time_to_cube_target_s, 3).c_str(),
                format_value(s.points.back().table.rms_pct, 3).c_str(),
                format_value(s.points.back().cube.rmse, 3).c_str(), format_value(s.table_slope, 3).c_str());
  }
  std::printf("  wrote %s/{series.csv,bench.json,candela-time,cubemap-time,photons,psnr-snr}\n",
              o.directory.c_str());
}

}  // namespace

int run_bench(const Args& args) {
  std::vector<std::string> models;
  std::string out_dir, page;
  long long photons = 1LL << 25, first = 1LL << 14, steps = 2, reference_photons = 0, seed = 1;
  long long reference_seed = -1, threads = 0, max_bounces = 100, face_size = 0;
  long long emission_face_size = 32;
  double c_step = 5.0, gamma_step = 2.5, target = 1.0, cube_target = 0.1, min_acceptance = 1.0 / 16.0;
  bool importance = false, no_png = false;
  std::string sampler_name = "both";
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
  p.positional_list("MODEL", &models, 1, "luminaire models (.gltf, .glb, .step, .stp, .iges or .igs)");
  p.option("out", &out_dir, "DIR", "output directory (created if missing)");
  p.option("photons", &photons, 1, 1LL << 36, "N", "photons of each series in all (default 33554432 = 2^25)");
  p.option("first", &first, 1, 4'294'967'295LL, "N", "photons of the first iteration (default 16384)");
  p.option("steps", &steps, 1, 16, "K", "iterations per doubling of the photons (default 2)");
  p.option("reference", &reference_photons, 2, 1LL << 39, "N",
           "photons of the reference run (default 16 x --photons: its noise is 1/4 of the last raw error)");
  p.option("seed", &seed, 0, 9'223'372'036'854'775'806LL, "S", "seed of the series (default 1)");
  p.option("reference-seed", &reference_seed, 0, 9'223'372'036'854'775'807LL, "S",
           "seed of the reference (default: series seed + 1; must differ)");
  p.option("threads", &threads, 0, 4096, "T", "threads (default 0: every core)");
  p.option("max-bounces", &max_bounces, 0, 1'000'000, "B", "bounce limit (default 100)");
  p.option("c-step", &c_step, sim::kMinGridStepDeg, sim::kMaxGridStepDeg, "DEG", "C-plane step of the table (default 5)");
  p.option("gamma-step", &gamma_step, sim::kMinGridStepDeg, sim::kMaxGridStepDeg, "DEG", "gamma step of the table (default 2.5)");
  p.option("face-size", &face_size, 1, 1024, "F", "cube-map texels per face edge (default: what the grid needs, 128)");
  p.option("target", &target, 1e-3, 100.0, "PCT", "RMS candela error to time [% of peak] (default 1)");
  p.option("cube-target", &cube_target, 1e-4, 100.0, "E", "cube-map RMSE to time (default 0.1)");
  p.flag("importance", &importance, "add importance-guided emission (thesis 5.4.1), raw and adaptive");
  p.choice("sampler", &sampler_name, {"random", "sobol", "both"},
           "sampler of the series (sim/sampler.h): random, sobol, or both (default: the pseudo-random\n"
           "series and Sobol' raw and adaptive, charted against each other); the reference is\n"
           "pseudo-random either way (its noise is taken out as Poisson noise)");
  p.option("emission-face-size", &emission_face_size, 1, 1024, "E",
           "guided emission: emission grid texels per face edge (default 32)");
  p.option("min-acceptance", &min_acceptance, 1e-4, 1.0, "A",
           "guided emission: smallest acceptance, photon power <= 1/A (default 1/16)");
  p.option("page", &page, "FILE", "also write a Markdown results page over all models");
  p.flag("no-png", &no_png, "write the charts as SVG only");
  ModelInputOptions model_options;
  add_model_input_options(p, &model_options);
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run) return ArgParser::exit_code(outcome);
  auto usage_error = [&](const std::string& message) {
    print_error("bench: " + message);
    std::fprintf(stderr, "%s\n", p.usage().c_str());
    return kExitUsage;
  };
  if (out_dir.empty()) return usage_error("--out DIR is required");
  if (first > photons) return usage_error("--first must not exceed --photons");
  if (reference_seed < 0) reference_seed = seed + 1;
  if (reference_seed == seed) return usage_error("the reference needs a seed of its own (--reference-seed)");
  if (reference_photons == 0) {
    if (photons > (1LL << 39) / 16) return usage_error("--photons too large for the default reference; give --reference");
    reference_photons = 16 * photons;
  }
  const sim::CGammaGrid grid{c_step, gamma_step};
  if (Status s = sim::validate(grid); !s.ok()) return usage_error(s.error().message);
  model_options.gamma_step_deg = gamma_step;
  if (Status s = check_model_input(model_options, models); !s.ok()) return usage_error(s.error().message);
  if (face_size == 0) face_size = sim::face_size_for(grid);
  if (!p.given("importance") && (p.given("emission-face-size") || p.given("min-acceptance")))
    return usage_error("--emission-face-size and --min-acceptance need --importance");
  std::set<std::string> stems;
  for (const std::string& m : models)
    if (!stems.insert(fs::path(m).stem().string()).second)
      return usage_error("two models named '" + fs::path(m).stem().string() + "': give them separate runs");

  BenchSettings settings;
  settings.photons = static_cast<std::uint64_t>(photons);
  settings.first_photons = static_cast<std::uint64_t>(first);
  settings.steps_per_doubling = static_cast<int>(steps);
  settings.seed = static_cast<std::uint64_t>(seed);
  settings.threads = static_cast<int>(threads);
  settings.max_bounces = static_cast<int>(max_bounces);
  settings.face_size = static_cast<int>(face_size);
  settings.importance = importance;
  settings.sampler = sampler_name == "sobol" ? sim::SamplerKind::Sobol : sim::SamplerKind::Random;
  settings.compare_samplers = sampler_name == "both";
  settings.importance_settings.emission_face_size = static_cast<int>(emission_face_size);
  settings.importance_settings.min_acceptance = min_acceptance;
  settings.target_pct = target;
  settings.cube_target = cube_target;
  char grid_text[64];
  std::snprintf(grid_text, sizeof grid_text, "%g° × %g°", c_step, gamma_step);

  // Under mpirun/srun the reference runs are shared by the ranks
  // (tools/run/distributed_run.h); rank 0 alone runs the series and writes.
  std::optional<sim::Ranks> ranks = join_job("bench");
  if (!ranks) return kExitFailure;
  const bool lead = ranks->rank() == 0;
  // A failure on one rank (rank 0's writes) while the others go on to the
  // next model's reference: end them all (they would wait for it for ever).
  auto job_failed = [&]() -> int {
    if (ranks->distributed()) ranks->abort(kExitFailure);
    return kExitFailure;
  };
  const std::string load_before = load_average();
  const bool show_progress = lead && stderr_is_terminal();
  std::vector<BenchOutcome> outcomes;
  for (const std::string& model : models) {
    std::optional<sim::SceneDesc> scene = load_checked_model(model, "benchmarked", model_options);
    Result<std::string> bytes = scene ? io::read_file(model, std::size_t{1} << 31)
                                      : Result<std::string>(Error{{}, "not read"});
    if (scene && !bytes.ok()) print_error(bytes.error());
    BenchOutcome o;
    o.model = model;
    o.name = fs::path(model).stem().string();
    o.directory = models.size() == 1 ? out_dir : (fs::path(out_dir) / o.name).string();
    o.settings = settings;
    o.grid = grid_text;
    bool ready = bytes.ok();
    if (ready && lead) {
      if (Status s = io::make_directories(o.directory); !s.ok()) {
        print_error(s.error());
        ready = false;
      }
    }
    ReferenceKey key;
    if (ready) {
      key.program_version = kVersion;
      key.tracer_revision = kTracerRevision;
      key.model_hash = io::content_hash_hex(bytes.value());
      key.scene_hash = scene_hash(scene.value());
      key.seed = static_cast<std::uint64_t>(reference_seed);
      key.photons = static_cast<std::uint64_t>(reference_photons);
      key.face_size = settings.face_size;
      key.max_bounces = settings.max_bounces;
      key.robust_embree = true;
    }
    // Every rank ready, with the same model and reference settings, or none traces.
    std::optional<std::string> fingerprint;
    if (ready) fingerprint = ranks->distributed() ? io::content_hash_hex(key.to_json().dump()) : std::string();
    if (!ranks_agree(*ranks, fingerprint, "bench")) return kExitFailure;
    const auto resampler = std::make_shared<const sim::Resampler>(settings.face_size, scene->frame, grid);

    auto reference = load_or_make_reference(
        o.directory, key, scene.value(), settings.threads, resampler,
        [&](std::uint64_t done, std::uint64_t total) {
          if (!show_progress) return;
          std::fprintf(stderr, "\r%s: bench %s: reference %.0f %%   ", kProgramName, o.name.c_str(),
                       100.0 * static_cast<double>(done) / static_cast<double>(total));
          if (done == total) std::fputc('\n', stderr);
          std::fflush(stderr);
        },
        &ranks.value());
    if (!reference.ok()) {
      Error e = reference.error();
      if (e.where.file.empty()) e.where.file = model;
      print_error(e);
      return job_failed();  // e.g. rank 0 could not write it: the others went on
    }
    if (!lead) continue;  // the series measure one process: rank 0's
    auto judge = sim::ConvergenceReference::create(reference->far_field, resampler);
    if (!judge.ok()) {
      print_error(model + ": " + judge.error().message);
      return job_failed();
    }
    auto series = run_series(scene.value(), settings, default_series(importance, settings.sampler, settings.compare_samplers), judge.value(),
                             [&](const BenchProgress& pr) {
                               if (!show_progress) return;
                               std::fprintf(stderr, "\r%s: bench %s: %s run, iteration %d/%d   ", kProgramName,
                                            o.name.c_str(), pr.run, pr.iteration, pr.iterations);
                               if (pr.iteration == pr.iterations) std::fputc('\n', stderr);
                               std::fflush(stderr);
                             });
    if (!series.ok()) {
      Error e = series.error();
      if (e.where.file.empty()) e.where.file = model;
      print_error(e);
      return job_failed();
    }
    o.series = std::move(series.value());
    o.reference = std::move(reference.value());
    o.reference.far_field = sim::FarField(1);  // not needed any more
    o.smallest_raw_error_pct = std::numeric_limits<double>::quiet_NaN();
    for (const SeriesResult& s : o.series)
      if (s.spec.name == "raw" && !s.points.empty()) o.smallest_raw_error_pct = s.points.back().table.rms_pct;

    const std::string dir = o.directory;
    if (Status s = io::write_file_atomic((fs::path(dir) / "series.csv").string(), series_csv(o.series)); !s.ok()) {
      print_error(s.error());
      return job_failed();
    }
    nlohmann::json j = bench_json(o);
    j["program"] = {{"name", kProgramName}, {"version", kVersion}};
    if (Status s = io::write_json((fs::path(dir) / "bench.json").string(), j); !s.ok()) {
      print_error(s.error());
      return job_failed();
    }
    if (Status s = write_charts(o, !no_png); !s.ok()) {
      print_error(s.error());
      return job_failed();
    }
    print_summary(o);
    outcomes.push_back(std::move(o));
  }

  if (!page.empty() && lead) {
    std::string command = "gonio bench";
    for (const std::string& a : args) command += " " + a;
    std::string cpu = first_line_of("/proc/cpuinfo", "model name");
    char machine[512];
    std::snprintf(machine, sizeof machine,
                  "Machine: %s, %u hardware threads, %d threads used; load average %s at the start and "
                  "%s at the end (1, 5, 15 min); finished %s; gonio %s.",
                  cpu.empty() ? "unknown CPU" : cpu.c_str(), std::thread::hardware_concurrency(),
                  settings.threads > 0 ? settings.threads
                                       : static_cast<int>(std::thread::hardware_concurrency()),
                  load_before.c_str(), load_average().c_str(), format_utc(std::time(nullptr), "%Y-%m-%d %H:%M UTC").c_str(), kVersion);
    if (Status s = io::make_directories(fs::absolute(page).parent_path().string()); !s.ok()) {
      print_error(s.error());
      return kExitFailure;
    }
    if (Status s = io::write_file_atomic(page, results_page(outcomes, page, machine, command)); !s.ok()) {
      print_error(s.error());
      return kExitFailure;
    }
    std::printf("wrote %s\n", page.c_str());
  }
  return kExitOk;
}

}  // namespace gonio::cli
