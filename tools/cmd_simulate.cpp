// gonio simulate: traces a luminaire model into its far field.
//
//   gonio simulate MODEL [--photons N] [--iterations K] [--seed S]
//                  [--threads T] [--max-bounces B] [--face-size F]
//                  [--preview [filter options]] --out DIR
//
// Writes DIR/farfield.exr (the far field as an OpenEXR cube map: Y in cd,
// flux in lm, photons per texel) and DIR/report.json (settings, speed and
// the energy ledger). With --preview, DIR/preview.exr and DIR/preview.png
// are replaced after every iteration (tools/preview_output.h). Progress goes
// to stderr when it is a terminal.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include "gonio/version.h"
#include "io/exr.h"
#include "io/file_io.h"
#include "io/gltf.h"
#include "io/model_check.h"
#include "io/report.h"
#include "sim/simulation.h"
#include "tools/cli.h"
#include "tools/commands.h"
#include "tools/preview_output.h"

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

}  // namespace

int run_simulate(const Args& args) {
  const auto start = std::chrono::steady_clock::now();
  std::string model, out_dir;
  long long photons = 1'000'000, iterations = 10, seed = 1, threads = 0, max_bounces = 100;
  long long face_size = sim::CubeMapGrid::face_size_for_step(2.5);
  ArgParser p("simulate", "MODEL --out DIR [options]",
              "Traces photons through a luminaire model (glTF 2.0: .gltf or .glb) and writes\n"
              "its far field, DIR/farfield.exr (OpenEXR cube map: Y = intensity in cd, flux in\n"
              "lm and photon count per texel), and DIR/report.json (settings, speed, and the\n"
              "energy ledger: emitted = escaped + absorbed + cut off, per emitter, mesh and\n"
              "material). The same seed gives the same files whatever the thread count.");
  p.positional("MODEL", &model, "the luminaire model (.gltf or .glb)");
  p.option("out", &out_dir, "DIR", "output directory (created if missing)");
  p.option("photons", &photons, 1, 4'294'967'295LL, "N", "photons per iteration (default 1000000)");
  p.option("iterations", &iterations, 1, 1'000'000, "K", "iterations (default 10): K·N photons in all");
  p.option("seed", &seed, 0, 9'223'372'036'854'775'807LL, "S", "random seed (default 1)");
  p.option("threads", &threads, 0, 4096, "T", "threads (default 0: every core)");
  p.option("max-bounces", &max_bounces, 0, 1'000'000, "B",
           "surface interactions before a photon is cut off (default 100)");
  p.option("face-size", &face_size, 1, 4096, "F",
           "cube-map texels per face edge (default 128: enough for a 2.5° grid)");
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
  if (out_dir.empty()) {
    print_error("simulate: --out DIR is required");
    std::fprintf(stderr, "%s\n", p.usage().c_str());
    return kExitUsage;
  }

  // Load, then check the geometry (closed refractive volumes, degenerate
  // and self-intersecting faces): errors stop the run, warnings are printed.
  std::vector<Finding> findings;
  Result<sim::SceneDesc> scene = io::load_gltf(model, &findings);
  if (scene.ok()) {
    const std::vector<Finding> checks = io::check_model(scene.value());
    findings.insert(findings.end(), checks.begin(), checks.end());
  }
  bool model_errors = false;
  for (const Finding& f : findings) {
    const std::string where = f.where.file.empty() ? model : to_string(f.where);
    if (f.severity == Severity::Error) {
      print_error(where + ": " + f.message);
      model_errors = true;
    } else if (f.severity == Severity::Warning) {
      print_warning(where + ": " + f.message);
    }
  }
  if (!scene.ok()) {
    print_error(scene.error());
    return kExitFailure;
  }
  if (model_errors) {
    print_error(model + ": the model has errors (above); nothing was simulated");
    return kExitFailure;
  }

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

  if (!preview_status.ok()) {
    print_error(preview_status.error());
    return kExitFailure;
  }
  const std::string exr_path = (std::filesystem::path(out_dir) / "farfield.exr").string();
  const std::string report_path = (std::filesystem::path(out_dir) / "report.json").string();
  const sim::FarField far_field = sim->far_field();
  Result<io::ExrImage> image = io::far_field_image(far_field);
  if (!image.ok()) {
    print_error(exr_path + ": " + image.error().message);
    return kExitFailure;
  }
  if (Status s = io::write_exr(exr_path, image.value()); !s.ok()) {
    print_error(s.error());
    return kExitFailure;
  }

  const sim::SimulationStats st = sim->stats();
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
  json["far_field"] = {{"file", "farfield.exr"},
                       {"face_size", settings.face_size},
                       {"texels", far_field.texel_count()},
                       {"flux_lm", far_field.total_flux_lm()}};
  if (Status s = io::write_json(report_path, json); !s.ok()) {
    print_error(s.error());
    return kExitFailure;
  }

  const sim::Ledger& l = report.ledger;
  std::printf("%s: %llu photons in %d iteration%s, %sphotons/s, %srays/s, %d thread%s\n",
              model.c_str(), static_cast<unsigned long long>(st.photons), st.iterations_done,
              st.iterations_done == 1 ? "" : "s", format_rate(st.photons_per_s()).c_str(),
              format_rate(st.rays_per_s()).c_str(), st.threads, st.threads == 1 ? "" : "s");
  std::printf("  emitted %.6g lm: escaped %.6g lm (%.2f %%), absorbed %.6g lm (%.2f %%), cut off %.6g lm (%.2f %%)\n",
              l.emitted.flux_lm, l.escaped.flux_lm, percent(l.escaped.flux_lm, l.emitted.flux_lm),
              l.absorbed.flux_lm, percent(l.absorbed.flux_lm, l.emitted.flux_lm), l.cutoff.flux_lm,
              percent(l.cutoff.flux_lm, l.emitted.flux_lm));
  if (l.glossy_gain_events > 0)
    std::printf("  glossy lobe weights above 1 added %.6g lm (%.3f %% of the emitted flux)\n",
                l.glossy_gain_lm, percent(l.glossy_gain_lm, l.emitted.flux_lm));
  std::printf("  wrote %s and %s\n", exr_path.c_str(), report_path.c_str());
  if (preview)
    std::printf("  preview: %s and %s\n", preview->exr_path().c_str(), preview->png_path().c_str());

  // The books must close: anything else is a bug, and the files say so too.
  if (!l.photons_close() || std::abs(l.flux_imbalance_lm()) > 1e-9 * l.emitted.flux_lm) {
    print_error(model + ": energy check failed: emitted " + std::to_string(l.emitted.photons) +
                " photons, accounted for " +
                std::to_string(l.escaped.photons + l.absorbed.photons + l.cutoff.photons));
    return kExitFailure;
  }
  if (l.cutoff.flux_lm > 0.01 * l.emitted.flux_lm)
    print_warning(model + ": " + std::to_string(percent(l.cutoff.flux_lm, l.emitted.flux_lm)) +
                  " % of the flux was cut off by the bounce limit (--max-bounces " +
                  std::to_string(max_bounces) + "): light trapped in the model is missing");
  return kExitOk;
}

}  // namespace gonio::cli
