#include "tools/cli/simulate_command.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "gonio/version.h"
#include "photometry/format.h"
#include "tools/cli/input_options.h"

namespace gonio::cli {
namespace {

double percent(double part, double whole) { return whole > 0.0 ? 100.0 * part / whole : 0.0; }

std::string signed_percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.3f %%", 100.0 * fraction);
  return buf;
}

// The run's speed, ledger, LOR, near field and estimate (stdout).
void print_run_figures(const app::SimulatePlan& plan, const app::ProgressiveOutcome& run, const app::RunFiles& files) {
  const sim::SimulationStats st = run.simulation.stats();
  const sim::Ledger l = run.simulation.ledger();
  const std::string& model = plan.model;
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
  std::printf("  light output ratio %.4f (escaped / emitted)\n", files.energy.lor);
  if (files.report.contains("near_field")) {
    for (const auto& p : files.report["near_field"])
      std::printf("  near field at %s m: %s lx on the axis, the far field predicts %s lx; largest deviation %s %% "
                  "(E_far >= 10 %% of its maximum): %s\n",
                  format_number(p["distance_m"].get<double>()).c_str(),
                  format_number(p["on_axis_lx"].get<double>()).c_str(),
                  format_number(p["far_field_on_axis_lx"].get<double>()).c_str(),
                  format_number(p["max_deviation_pct"].get<double>()).c_str(), p["file"].get<std::string>().c_str());
  }
  if (files.far_field_distance) {
    const sim::FarFieldDistance& d = *files.far_field_distance;
    std::string verdict;
    if (d.distance_m)
      verdict = format_number(*d.distance_m) + " m";
    else if (d.farthest == sim::PlaneVerdict::Fails)
      verdict = "beyond the distances asked for (the farthest plane deviates by more than 1 %)";
    else
      verdict = "undecided (too few photons to tell at the farthest plane; about " +
                format_number(d.photons_to_tell, 2) + " would)";
    std::printf("  far-field distance: %s\n", verdict.c_str());
  }
  const sim::NextEventSummary n = run.simulation.next_event();
  if (n.mode != sim::NextEventMode::Off)
    std::printf("  next-event estimation %s (%s; %.0f %% of the pilot's escaping light leaves after a connected "
                "event)%s\n",
                n.enabled ? "on" : "off", sim::to_string(n.mode), 100.0 * n.pilot_covered_share,
                n.enabled ? (": " + format_number(static_cast<double>(n.connections), 3) + " connections, " +
                             format_number(n.booked_lm, 6) + " lm booked for " + format_number(n.covered_lm, 6) +
                             " lm of escapes")
                                .c_str()
                          : "");
  if (files.report.contains("luminance_images"))
    for (const auto& img : files.report["luminance_images"]) {
      const nlohmann::json& g = img["cie232"];
      std::printf("  luminance image C%s G%s: max %s cd/m2, %s cd; CIE 232: %s\n",
                  format_number(img["c_deg"].get<double>()).c_str(),
                  format_number(img["gamma_deg"].get<double>()).c_str(),
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
                run.stopped_by == app::StopReason::TargetError ? " (stopped at the target error)" : "");
}

// Every file written, with its flux read back (stdout).
void print_written(const app::SimulatePlan& plan, const app::RunFiles& files) {
  const app::OutputResult& outputs = files.outputs;
  if (!outputs.symmetry_reason.empty()) {
    if (plan.symmetry)
      std::printf("  %s\n", outputs.symmetry_reason.c_str());
    else  // the reasoning is long: stderr (and the report) only
      std::fprintf(stderr, "%s: simulate: %s\n", kProgramName, outputs.symmetry_reason.c_str());
  }
  for (const app::WrittenFile& f : outputs.files) {
    if (std::isfinite(f.flux_lm) && std::isfinite(f.flux_difference))
      std::printf("  wrote %s: %.6g lm read back (%s of the escaped flux)%s\n", f.path.c_str(), f.flux_lm,
                  signed_percent(f.flux_difference).c_str(), f.clean() ? "" : ", NOT CLEAN");
    else if (std::isfinite(f.flux_lm))  // no escaped flux to compare with
      std::printf("  wrote %s: %.6g lm read back%s\n", f.path.c_str(), f.flux_lm, f.clean() ? "" : ", NOT CLEAN");
    else
      std::printf("  wrote %s%s\n", f.path.c_str(), f.clean() ? "" : ", NOT CLEAN");
  }
  if (files.ray_file)
    std::printf("  wrote %s: %zu rays, %s lm (the escaped flux)\n", files.ray_file->path.c_str(),
                files.ray_file->rays, format_number(files.ray_file->flux_lm).c_str());
  std::printf("  wrote %s\n", files.report_path.c_str());
  if (files.preview.size() == 2)
    std::printf("  preview: %s and %s\n", files.preview[0].c_str(), files.preview[1].c_str());
}

}  // namespace

void add_simulate_options(ArgParser& p, app::SimulateOptions* o) {
  // The defaults shown are the command's own: watch sets other ones first.
  p.option("photons", &o->photons, app::kPhotonsBounds.min, app::kPhotonsBounds.max, "N",
           "photons per iteration (default " + std::to_string(o->photons) + ")");
  p.option("iterations", &o->iterations, app::kIterationsBounds.min, app::kIterationsBounds.max, "K",
           "iterations (default " + std::to_string(o->iterations) + "): K·N photons in all");
  p.option("seed", &o->seed, app::kSeedBounds.min, app::kSeedBounds.max, "S", "random seed (default 1)");
  p.choice("sampler", &o->sampler, {"sobol", "random"},
           "where photons' numbers come from: sobol (default: Owen-scrambled Sobol' points in four "
           "independent scrambles keyed by the seed, whose spread gives the error estimate) or random "
           "(pseudo-random); either gives the same bytes for any threads or split");
  p.choice("next-event", &o->next_event, {"auto", "on", "off"},
           "next-event estimation for the far field: at every diffuse or glossy surface a photon meets,\n"
           "M connection rays book what it sends out of the luminaire directly (docs/luminance-and-\n"
           "glare.md); auto (default): M per surface and side chosen from a pilot of the first photons\n"
           "by what the connections buy, on where they pay (the LED array sample: 0.3x the time to 1 %\n"
           "error; the bell: off); not with guided emission");
  p.option("connections", &o->connections, app::kConnectionsBounds.min, app::kConnectionsBounds.max, "M",
           "next-event connections per surface vertex (default 16)");
  p.option("luminance-image", &o->luminance_images, "C:G,...|ugr",
           "luminance images of the luminaire seen from these directions (C and gamma in degrees; ugr:\n"
           "CIE 232's views, gamma 65 and 50 in C0 and C90), orthographic, 1.2 mm pixels, as\n"
           "STEM.luminance-C<C>-G<G>.exr (L in cd/m2; x, y in spectral runs) and .png, with CIE\n"
           "232:2019's glare-source figures and the UGR correction in report.json (up to 16 views)");
  p.option("threads", &o->threads, app::kThreadsBounds.min, app::kThreadsBounds.max, "T", "threads (default 0: every core)");
  p.option("max-bounces", &o->max_bounces, app::kMaxBouncesBounds.min, app::kMaxBouncesBounds.max, "B",
           "surface interactions before a photon is cut off (default 100)");
  p.option("face-size", &o->face_size, app::kFaceSizeBounds.min, app::kFaceSizeBounds.max, "F",
           "cube-map texels per face edge (default: two texels per grid step, 128 for 5 x 2.5 deg, at\n"
           "most 1024: a 0.1 deg step gets one texel per step; 2048 gives two at 4x the memory)");
  p.option("c-step", &o->c_step, app::kGridStepBounds.min, app::kGridStepBounds.max, "DEG",
           "C-plane spacing of the IES/LDT grid (default 5; divides 360)");
  p.option("gamma-step", &o->gamma_step, app::kGammaStepBounds.min, app::kGammaStepBounds.max, "DEG",
           "gamma spacing of the IES/LDT grid (default 2.5; divides 180; down to 0.1, the cube map\n"
           "following, see --face-size)");
  p.option("gamma-angles", &o->gamma_angles, "LIST",
           "the grid's gamma angles instead of a step, 0 to 180, ascending: numbers and ranges\n"
           "FROM:STEP:TO, e.g. 0:0.1:5,6:1:90,92.5:2.5:180 for a narrow beam (gaps down to 0.1)");
  p.option("c-angles", &o->c_angles, "LIST",
           "the grid's C-planes instead of a step, in [0, 360) (360 repeats 0), as --gamma-angles;\n"
           "with --symmetry C0-C180, C90-C270 or quadrant its range alone, mirrored (0:15:90)");
  p.option("grid-like", &o->grid_like, "FILE",
           "the grid of a measured Type C file (IES, LDT, TM-33, GLDF): its C-planes and gamma\n"
           "angles, so the simulated files share its angles (gamma extended to 0-180 where it\n"
           "covers less, said on stderr)");
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
  p.option("tm25-rays", &o->tm25_rays, app::kTm25RaysBounds.min, app::kTm25RaysBounds.max, "N",
           "with --format tm25: the escapes of the run's first N photons are the ray file's rays\n"
           "(default 1000000); their fluxes add up to the escaped flux");
  p.option("near-field", &o->near_field, "D1,D2,...",
           "near-field photometry: the illuminance on planes D metres below the luminaire's centre\n"
           "(perpendicular to the nadir, 4D square, 41 x 41 pixels) from every escaping photon's\n"
           "path, against the far field's prediction, as STEM.near-field-Dm.exr, with near_field and\n"
           "far_field_distance_m in report.json (up to 16 distances, each in (0, 1e4])");
  p.choice("ies-version", &o->ies_version, {"2002", "2019"}, "IES LM-63 version (default 2019)");
  p.option("name", &o->stem, "STEM",
           "file names DIR/STEM.* (default: the model's file name without extension, NAME for NAME.design.toml)");
  p.option("min-lor", &o->min_lor, app::kFractionBounds.min, app::kFractionBounds.max, "X",
           "fail when the light output ratio escaped/emitted is under X (default 0: never)");
  p.option("flux-tolerance", &o->flux_tolerance, app::kFractionBounds.min, app::kFractionBounds.max, "X",
           "fail when a written file's flux differs from the escaped flux by more than X "
           "(a fraction; default 0.005 = 0.5 %)");
  p.option("target-error", &o->target_error_pct, app::kTargetErrorBounds.min, app::kTargetErrorBounds.max, "PCT",
           "stop once the estimated RMS candela error (relative to the peak; under --sampler sobol from "
           "the spread of its four replicates, under random from photon counts) is at or under PCT "
           "percent (default 0: run every iteration)");
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
  p.option("cache-limit", &o->cache_limit_mb, app::kCacheLimitMbBounds.min, app::kCacheLimitMbBounds.max, "MB",
           "after the run, remove the cache's least recently used entries while they hold more than "
           "MB megabytes (MiB), down to nine tenths of it; other files in the folder are left alone "
           "(default 1024; 0: no limit)");
  add_model_input_options(p, &o->model_input);
  add_preview_options(p, &o->preview);
}

void print_usage_error(const std::string& command, const ArgParser& p, const std::string& message) {
  print_error(command + ": " + message);
  std::fprintf(stderr, "%s\n", p.usage().c_str());
}

std::optional<app::SimulatePlan> plan_or_usage(const std::string& command, const std::string& model,
                                               const app::SimulateOptions& options, const ArgParser& p) {
  // A step and a list (or --grid-like) for the same axis: which one was meant?
  for (const auto& [step, lists] : {std::pair<const char*, const char*>{"gamma-step", "gamma-angles"},
                                    std::pair<const char*, const char*>{"c-step", "c-angles"}}) {
    for (const char* other : {lists, "grid-like"}) {
      if (p.given(step) && p.given(other)) {
        print_usage_error(command, p, std::string("--") + step + " and --" + other + " exclude each other");
        return std::nullopt;
      }
    }
  }
  Result<app::SimulatePlan> plan = app::plan_simulation(model, options);
  if (plan.ok()) {
    if (!plan.value().grid_note.empty())
      std::fprintf(stderr, "%s: %s: --grid-like %s: added to its angles: %s\n", kProgramName, command.c_str(),
                   options.grid_like->c_str(), plan.value().grid_note.c_str());
    return std::move(plan.value());
  }
  print_usage_error(command, p, plan.error().message);
  return std::nullopt;
}

int print_run_files(const app::SimulatePlan& plan, const app::ProgressiveOutcome& run, const app::RunFiles& files) {
  if (files.report_error) {
    for (const Error& e : files.failures) print_error(e);
    print_error(*files.report_error);
    for (const std::string& path : files.written)
      print_error("simulate: written before the report failed: " + path);
    return kExitFailure;
  }
  print_run_figures(plan, run, files);
  print_written(plan, files);
  if (!files.failures.empty()) {
    for (const Error& e : files.failures) print_error(e);
    print_error("simulate: " + std::to_string(files.failures.size()) + " output" +
                (files.failures.size() == 1 ? "" : "s") + " failed after tracing; " + files.report_path +
                " lists what was written");
    (void)app::energy_exit_code(plan.model, files.energy);  // its failures are printed too
    return kExitFailure;
  }
  if (const int code = app::energy_exit_code(plan.model, files.energy); code != kExitOk) return code;
  const sim::Ledger l = run.simulation.ledger();
  if (l.cutoff.flux_lm > 0.01 * l.emitted.flux_lm)
    print_warning(plan.model + ": " + std::to_string(percent(l.cutoff.flux_lm, l.emitted.flux_lm)) +
                  " % of the flux was cut off by the bounce limit (--max-bounces " +
                  std::to_string(plan.progressive.simulation.max_bounces) + "): light trapped in the model is missing");
  return kExitOk;
}

}  // namespace gonio::cli
