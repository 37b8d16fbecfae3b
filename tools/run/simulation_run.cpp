#include "tools/run/simulation_run.h"

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
#include "tools/run/console.h"
#include "tools/run/distributed_run.h"
#include "tools/run/json_figures.h"
#include "tools/run/resampler_cache.h"

namespace gonio::cli {
namespace {

double percent(double part, double whole) { return whole > 0.0 ? 100.0 * part / whole : 0.0; }

std::string signed_percent(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.3f %%", 100.0 * fraction);
  return buf;
}

// STEM.tm25ray (--format tm25): the escapes the simulation kept
// (SimulationSettings::capture_escaped_photons), each moved along its
// direction to where it leaves the luminaire's bounding sphere (centre: the
// middle of the bounding box of every placed vertex and emitter; radius: half
// its diagonal; a start outside the sphere stays where it is), in the
// photometric frame with the ray file's axes of tools/run/ray_file_far_field.h
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
                    {"max_deviation_bound_pct", p.max_deviation_bound_pct},
                    {"min_photons_per_pixel", p.min_photons}});
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

  OutputRequest request = table_request(*sim, model, grid, symmetry, plan.model_input.cache_dir);
  request.directory = out_dir;
  request.stem = plan.stem;
  request.formats = plan.formats;
  request.ies_version = plan.ies_version;
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
  std::optional<double> far_field_distance;
  if (!settings.near_field_distances_m.empty()) {
    const std::vector<sim::NearFieldPlane> planes = sim->near_field();
    near_field_list = write_near_field(out_dir, plan.stem, planes, &near_field_files, &failures);
    far_field_distance = sim::far_field_distance_m(planes);
    request.near_field = {{"near_field", near_field_list},
                          {"far_field_distance_m", far_field_distance ? nlohmann::json(*far_field_distance)
                                                                      : nlohmann::json(nullptr)}};
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
    json["far_field_distance_m"] = far_field_distance ? nlohmann::json(*far_field_distance) : nlohmann::json(nullptr);
    json["far_field_distance_method"] =
        "the smallest distance asked for from which that plane and every farther one asked for have "
        "|E - E_far| / E_far + 2 sigma <= 1 % in every pixel with E_far >= 10 % of the plane's maximum; "
        "sigma = sqrt(photons landing in only one of the pixel's two tallies) / photons in E_far";
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
  if (!settings.near_field_distances_m.empty())
    std::printf("  far-field distance: %s\n", far_field_distance ? (format_number(*far_field_distance) + " m").c_str()
                                                                 : "beyond the distances asked for");
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
