// gonio simulate: traces a luminaire model into its far field and writes the
// files light-planning programs and renderers read.
//
//   gonio simulate MODEL --out DIR [--photons N] [--iterations K] [--seed S]
//                  [--threads T] [--max-bounces B] [--face-size F]
//                  [--c-step DEG] [--gamma-step DEG] [--symmetry S]
//                  [--format LIST] [--ies-version 2002|2019] [--name STEM]
//                  [--min-lor X] [--flux-tolerance X]
//                  [--preview [filter options]]
//
// Writes DIR/STEM.ies, STEM.ldt, farfield.exr (cube), farfield-latlong.exr, STEM.svg (the
// intensity diagram; tools/simulation_outputs.h) and DIR/report.json
// (settings, speed, the energy ledger, and each file read back: its flux and
// its check findings). With --preview, DIR/preview.exr and DIR/preview.png
// are replaced after every iteration (tools/preview_output.h). Progress goes
// to stderr when it is a terminal.
//
// report.json adds to io/report.h's fields: "outputs" {grid, symmetry
// {chosen, reason, tests [{symmetry, chi_square, degrees_of_freedom,
// p_value, groups, rejected, detectable_deviation}]}, escaped_lm, files [{path, format, flux_lm,
// flux_difference, clean, findings, writer_notes}], failed [{path, format,
// error}]} and "energy"
// {photons_close, flux_imbalance_lm, lor, min_lor, flux_tolerance,
// files [{path, flux_ok, clean}], passed, failures [text]}.
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

#include "gonio/version.h"
#include "io/exr.h"
#include "io/file_io.h"
#include "io/report.h"
#include "sim/resample.h"
#include "sim/simulation.h"
#include "sim/symmetry.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/model_input.h"
#include "tools/preview_output.h"
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

std::string today_utc() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[16];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", &tm);
  return buf;
}

std::string signed_percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.3f %%", 100.0 * fraction);
  return buf;
}

int usage_error(const ArgParser& p, const std::string& message) {
  print_error("simulate: " + message);
  std::fprintf(stderr, "%s\n", p.usage().c_str());
  return kExitUsage;
}

}  // namespace

int run_simulate(const Args& args) {
  const auto start = std::chrono::steady_clock::now();
  std::string model, out_dir;
  long long photons = 1'000'000, iterations = 10, seed = 1, threads = 0, max_bounces = 100;
  long long face_size = 0;
  double c_step = 5.0, gamma_step = 2.5, min_lor = 0.0, flux_tolerance = 0.005;
  std::string symmetry_name = "auto", format_list = "all", ies_version = "2019", stem;
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
  p.option("out", &out_dir, "DIR", "output directory (created if missing)");
  p.option("photons", &photons, 1, 4'294'967'295LL, "N", "photons per iteration (default 1000000)");
  p.option("iterations", &iterations, 1, 1'000'000, "K", "iterations (default 10): K·N photons in all");
  p.option("seed", &seed, 0, 9'223'372'036'854'775'807LL, "S", "random seed (default 1)");
  p.option("threads", &threads, 0, 4096, "T", "threads (default 0: every core)");
  p.option("max-bounces", &max_bounces, 0, 1'000'000, "B",
           "surface interactions before a photon is cut off (default 100)");
  p.option("face-size", &face_size, 1, 4096, "F",
           "cube-map texels per face edge (default: two texels per grid step, 128 for 5 x 2.5 deg)");
  p.option("c-step", &c_step, sim::kMinGridStepDeg, sim::kMaxGridStepDeg, "DEG",
           "C-plane spacing of the IES/LDT grid (default 5; divides 360)");
  p.option("gamma-step", &gamma_step, sim::kMinGridStepDeg, sim::kMaxGridStepDeg, "DEG",
           "gamma spacing of the IES/LDT grid (default 2.5; divides 180)");
  p.option("symmetry", &symmetry_name, "S",
           "auto (default: a chi-square test per symmetry on the photon counts), none, C0-C180, "
           "C90-C270, quadrant or rotational");
  p.option("format", &format_list, "LIST",
           "files to write, comma-separated: ies, ldt, exr, latlong, plot, or all (default)");
  p.choice("ies-version", &ies_version, {"2002", "2019"}, "IES LM-63 version (default 2019)");
  p.option("name", &stem, "STEM", "file names DIR/STEM.* (default: the model's file name without extension)");
  p.option("min-lor", &min_lor, 0.0, 1.0, "X",
           "fail when the light output ratio escaped/emitted is under X (default 0: never)");
  p.option("flux-tolerance", &flux_tolerance, 0.0, 1.0, "X",
           "fail when a written file's flux differs from the escaped flux by more than X "
           "(a fraction; default 0.005 = 0.5 %)");
  ModelInputOptions model_options;
  add_model_input_options(p, &model_options);
  PreviewOptions preview_options;
  add_preview_options(p, &preview_options);
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run)
    return ArgParser::exit_code(outcome);
  const Result<sim::PreviewFilterParams> preview_params_result = preview_params(preview_options, p);
  if (!preview_params_result.ok()) {
    print_error("simulate: " + preview_params_result.error().message);
    std::fprintf(stderr, "%s\n", p.usage().c_str());
    return kExitUsage;
  }
  if (out_dir.empty()) return usage_error(p, "--out DIR is required");
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
  Result<std::vector<OutputFormat>> formats = parse_formats(format_list);
  if (!formats.ok()) return usage_error(p, formats.error().message);
  if (stem.empty()) stem = std::filesystem::path(model).stem().string();
  if (stem.empty() || stem.find_first_of("/\\") != std::string::npos || stem == "." || stem == "..")
    return usage_error(p, "--name: '" + stem + "' is not a plain file name");
  if (!p.given("face-size")) face_size = sim::face_size_for(grid);

  // Load, then check the geometry: errors stop the run, warnings are printed.
  std::optional<sim::SceneDesc> scene = load_checked_model(model, "simulated", model_options);
  if (!scene) return kExitFailure;

  sim::SimulationSettings settings;
  settings.photons_per_iteration = static_cast<std::uint64_t>(photons);
  settings.iterations = static_cast<int>(iterations);
  settings.seed = static_cast<std::uint64_t>(seed);
  settings.threads = static_cast<int>(threads);
  settings.max_bounces = static_cast<int>(max_bounces);
  settings.face_size = static_cast<int>(face_size);

  // The output directory is made before tracing so that previews can land in it.
  if (Status s = io::make_directories(out_dir); !s.ok()) {
    print_error(s.error());
    return kExitFailure;
  }
  std::optional<PreviewOutput> preview;
  if (preview_options.enabled)
    preview.emplace(out_dir, settings.face_size, preview_params_result.value());
  Status preview_status = Ok{};

  const bool show_progress = stderr_is_terminal();
  auto progress = [&](const sim::SimulationProgress& pr, const sim::Simulation& simulation) {
    if (preview && preview_status.ok()) preview_status = preview->write(simulation.far_field());
    if (!show_progress) return;
    std::fprintf(stderr, "\r%s: simulate: iteration %d/%d, %sphotons/s, %s left   ", kProgramName,
                 pr.iteration, pr.iterations, format_rate(pr.photons_per_s).c_str(),
                 format_duration(pr.remaining_s).c_str());
    if (pr.iteration == pr.iterations) std::fputc('\n', stderr);
    std::fflush(stderr);
  };
  Result<sim::Simulation> sim = sim::simulate(scene.value(), settings, progress);
  if (!sim.ok()) {
    Error e = sim.error();
    if (e.where.file.empty()) e.where.file = model;
    print_error(e);
    return kExitFailure;
  }

  // From here on a failure loses nothing: every file that can be written is,
  // report.json lists them with each failure, and the exit code is 1.
  std::vector<Error> failures;
  if (!preview_status.ok()) failures.push_back(preview_status.error());
  const std::string report_path = (std::filesystem::path(out_dir) / "report.json").string();
  const sim::FarField far_field = sim->far_field();
  const sim::SimulationStats st = sim->stats();
  const sim::Ledger ledger = sim->ledger();

  OutputRequest request;
  request.directory = out_dir;
  request.stem = stem;
  request.formats = formats.value();
  request.grid = grid;
  request.symmetry = symmetry;
  request.ies_version = ies_version == "2002" ? io::IesVersion::LM63_2002 : io::IesVersion::LM63_2019;
  request.run.program_version = kVersion;
  request.run.model = model;
  request.run.photons = st.photons;
  request.run.seed = settings.seed;
  request.run.max_bounces = settings.max_bounces;
  request.run.issue_date = today_utc();
  Result<OutputResult> written = write_outputs(far_field, sim->scene(), ledger, request);
  if (!written.ok()) failures.push_back(written.error());
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
  report.iterations_done = st.iterations_done;
  report.photons = st.photons;
  report.rays = st.rays;
  report.trace_s = st.trace_s;
  report.setup_s = st.setup_s;
  report.ledger = sim->ledger();
  report.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json json = io::to_json(report);
  if (preview) {
    const sim::PreviewStats& ps = preview->stats();
    json["preview"] = {{"exr", "preview.exr"},
                       {"png", "preview.png"},
                       {"filter", describe(preview_params_result.value(), settings.face_size)},
                       {"flux_lm", ps.preview_flux_lm}};
  }
  json["far_field"] = {{"face_size", settings.face_size},
                       {"texels", far_field.texel_count()},
                       {"flux_lm", far_field.total_flux_lm()}};
  for (const WrittenFile& f : outputs->files)
    if (f.format == OutputFormat::Exr) json["far_field"]["file"] = std::filesystem::path(f.path).filename().string();
  json["outputs"] = to_json(*outputs, grid, ledger.escaped.flux_lm);
  // Every file this run left in DIR besides report.json, and what failed.
  nlohmann::json written_paths = nlohmann::json::array();
  for (const WrittenFile& f : outputs->files) written_paths.push_back(f.path);
  if (preview)
    for (const std::string& path : {preview->exr_path(), preview->png_path()})
      if (std::filesystem::is_regular_file(path)) written_paths.push_back(path);
  json["written"] = written_paths;
  json["output_failures"] = nlohmann::json::array();
  for (const Error& e : failures) json["output_failures"].push_back(to_string(e));

  // The energy checks, each with what it found.
  const sim::Ledger& l = ledger;
  const EnergyCheck energy = check_energy(l, outputs->files, min_lor, flux_tolerance);
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
              model.c_str(), static_cast<unsigned long long>(st.photons), st.iterations_done,
              st.iterations_done == 1 ? "" : "s", format_rate(st.photons_per_s()).c_str(),
              format_rate(st.rays_per_s()).c_str(), st.threads, st.threads == 1 ? "" : "s");
  std::printf("  emitted %.6g lm: escaped %.6g lm (%.2f %%), absorbed %.6g lm (%.2f %%), cut off %.6g lm (%.2f %%)\n",
              l.emitted.flux_lm, l.escaped.flux_lm, percent(l.escaped.flux_lm, l.emitted.flux_lm),
              l.absorbed.flux_lm, percent(l.absorbed.flux_lm, l.emitted.flux_lm), l.cutoff.flux_lm,
              percent(l.cutoff.flux_lm, l.emitted.flux_lm));
  std::printf("  light output ratio %.4f (escaped / emitted)\n", lor);
  if (l.escaped.photons == 0 || !(l.escaped.flux_lm > 0.0))
    print_warning(model + ": no light leaves the model: all " + std::to_string(l.emitted.photons) +
                  " photons were absorbed or cut off (is the emitter sealed in?); the files hold zero "
                  "intensity");
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
