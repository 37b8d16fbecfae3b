#include "tools/run/simulation_run.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "design/design_file.h"
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
#include "sim/detectors/colour_over_angle.h"
#include "sim/detectors/resample.h"
#include "sim/simulation.h"
#include "sim/detectors/symmetry.h"
#include "sim/emitters/ray_set_emitter.h"
#include "tools/run/console.h"
#include "tools/run/distributed_run.h"
#include "tools/run/json_figures.h"
#include "tools/run/resampler_cache.h"

namespace gonio::app {
namespace {

// STEM.tm25ray (--format tm25): the escapes the simulation kept
// (SimulationSettings::capture_escaped_photons), each moved along its
// direction to where it leaves the luminaire's bounding sphere (centre: the
// middle of the bounding box of every placed vertex and emitter; radius: half
// its diagonal; a start outside the sphere stays where it is), in the
// photometric frame with the ray file's axes of tools/run/ray_file_far_field.h
// (+x C0, −y C90, +z the nadir; millimetres from the centre). Each ray's
// luminous flux is its photon's share of the run's escaped flux (power
// units), so the rays add up to the escaped flux.
Result<RayFileWritten> write_ray_file(const std::string& path, const sim::Simulation& simulation,
                                      double escaped_lm, const std::string& date) {
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
  h.light_source = design::model_stem(scene.name);
  h.ray_file_creator = std::string("Gonio ") + kVersion;
  h.model_creator = h.ray_file_creator;
  h.equipment = "Gonio photon tracer (simulation)";
  h.additional_info = "escaping photons of the run's first " +
                      std::to_string(simulation.settings().capture_escaped_photons) + " of " +
                      std::to_string(simulation.stats().photons) +
                      " photons, started where they leave the luminaire's bounding sphere (radius " +
                      format_number(radius * 1000.0) + " mm about its centre); +x C0, -y C90, +z nadir";
  if (Status s = io::write_tm25_file(path, set); !s.ok()) return s.error();
  return RayFileWritten{path, set.ray_count(), set.header.luminous_flux_lm};
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

// report.json's "far_field_distance" (sim/detectors/near_field.h): the distance, the
// farthest plane's verdict, and the photometric centre the planes hang from.
nlohmann::json far_field_distance_json(const sim::Simulation& sim, const sim::FarFieldDistance& d) {
  const Vec3 centre = sim.scene().frame.to_local(sim.near_field_planes()->centre);
  const auto optional_number = [](const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
  };
  return {{"distance_m", optional_number(d.distance_m)},
          {"farthest", sim::to_string(d.farthest)},
          {"nearer_plane_m", optional_number(d.nearer_plane_m)},
          {"photons_to_tell", std::isfinite(d.photons_to_tell) ? nlohmann::json(d.photons_to_tell)
                                                               : nlohmann::json(nullptr)},
          {"photometric_centre_m", {centre.x, centre.y, centre.z}}};
}

// report.json's "next_event" (sim/tracer/next_event.h): the mode, the pilot's
// verdict, and with the estimator on what it booked.
nlohmann::json next_event_json(const sim::Simulation& sim, const sim::FarField& far_field, const sim::Ledger& ledger) {
  const sim::NextEventSummary n = sim.next_event();
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
  return ne;
}

// What the files record and are made of, from the plan and the run.
// `colour`: the run's X and Z (empty: a grey run), kept alive by the caller.
OutputRequest output_request(const SimulatePlan& plan, const sim::Simulation& sim, const sim::FarField& far_field,
                             const sim::ColourFarField& colour) {
  const sim::SimulationSettings& settings = plan.progressive.simulation;
  OutputRequest request = table_request(sim, plan.model, plan.grid, plan.symmetry, plan.model_input.cache_dir);
  request.directory = plan.out_dir;
  request.stem = plan.stem;
  request.formats = plan.formats;
  request.ies_version = plan.ies_version;
  if (!colour.empty()) request.colour = &colour;
  // Spectral runs (sim/tracer/spectral.h): the luminaire's colour and its colour
  // over angle on the output grid (sim/detectors/colour_over_angle.h), for
  // report.json and the datasheet.
  if (sim.tracer().spectral()) {
    const sim::Resampler own =
        cached_resampler(settings.face_size, sim.scene().frame, plan.grid, plan.model_input.cache_dir);
    request.colour_report = colour_json(sim::colour_over_angle(own, far_field, colour));
  }
  return request;
}

// report.json's settings, speed and setup (io::SimulationReport) and the
// run's own figures: how it stopped, its estimate, preview and far field.
nlohmann::json run_json(const SimulatePlan& plan, const ProgressiveOutcome& run, const ModelInputTimes& input_times,
                        const PreviewOutput* preview, std::chrono::steady_clock::time_point start) {
  const sim::SimulationSettings& settings = plan.progressive.simulation;
  const sim::Simulation& sim = run.simulation;
  const sim::SimulationStats st = sim.stats();
  io::SimulationReport report;
  report.program_version = kVersion;
  report.model = plan.model;
  report.photons_per_iteration = settings.photons_per_iteration;
  report.iterations = settings.iterations;
  report.seed = settings.seed;
  report.threads = st.threads;
  report.max_bounces = settings.max_bounces;
  report.face_size = settings.face_size;
  report.robust_embree = settings.robust_embree;
  report.bvh_quality = sim::to_string(sim.tracer().settings().embree.quality);
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
  report.setup.instances = sim.scene().instances.size();
  report.setup.triangles_unique = sim.scene().unique_triangle_count();
  report.setup.triangles_placed = sim.scene().placed_triangle_count();
  report.setup.max_rss_after_load_bytes = input_times.max_rss_after_load_bytes;
  report.setup.max_rss_after_checks_bytes = input_times.max_rss_after_checks_bytes;
  report.max_rss_bytes = io::peak_memory_bytes();
  report.ledger = sim.ledger();
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
  return json;
}

// Spectral runs: the colour figures and the colour-over-angle chart beside
// the intensity diagram (STEM-colour.svg); returns the chart's path, or
// empty where it failed (added to `failures`).
std::string write_colour_chart(const SimulatePlan& plan, const nlohmann::json& colour_report, nlohmann::json& json,
                               std::vector<Error>& failures) {
  json.update(colour_report);
  const std::vector<io::ColourCurve> curves = io::colour_curves(json["colour_over_angle"]);
  const std::string chart_path = (std::filesystem::path(plan.out_dir) / (plan.stem + "-colour.svg")).string();
  const nlohmann::json& dmax = json["colour_over_angle"]["delta_uv_max"];
  Result<io::Figure> chart = io::colour_over_angle_chart(curves, plan.model + ": colour over angle",
                                                         dmax.is_number() ? dmax.get<double>() : photometry::kNaN);
  Status chart_status = chart.ok() ? io::write_figure(chart_path, *chart) : Status(chart.error());
  if (!chart_status.ok()) {
    failures.push_back(chart_status.error());
    return {};
  }
  json["colour_over_angle"]["chart"] = std::filesystem::path(chart_path).filename().string();
  return chart_path;
}

// report.json's "cache": the cache folder kept to its limit, now that this
// run has used and written its entries (each marked used, so they go last).
nlohmann::json trimmed_cache_json(const SimulatePlan& plan) {
  const std::string& dir = plan.model_input.cache_dir;
  if (dir.empty()) return nullptr;
  const io::CacheTrim trim = io::trim_cache(dir, plan.cache_limit_bytes);
  return {{"dir", dir},
          {"limit_bytes", plan.cache_limit_bytes},
          {"entries", trim.entries},
          {"bytes", trim.bytes},
          {"removed_entries", trim.removed_entries},
          {"removed_bytes", trim.removed_bytes}};
}

}  // namespace

RunFiles write_run_files(const SimulatePlan& plan, const ProgressiveOutcome& run, const ModelInputTimes& input_times,
                         const PreviewOutput* preview, std::chrono::steady_clock::time_point start,
                         const nlohmann::json& ranks_report, std::vector<Error> failures,
                         const sim::Resampler* resampler) {
  const sim::SimulationSettings& settings = plan.progressive.simulation;
  const sim::Simulation& sim = run.simulation;
  const sim::FarField far_field = sim.far_field();
  const sim::Ledger ledger = sim.ledger();
  RunFiles files;
  files.report_path = (std::filesystem::path(plan.out_dir) / "report.json").string();

  const sim::ColourFarField colour = sim.colour_far_field();
  OutputRequest request = output_request(plan, sim, far_field, colour);
  request.resampler = resampler;  // the estimate's, where the run built one (not twice)
  std::vector<std::string> near_field_files;
  nlohmann::json near_field_list, far_field_distance;
  request.near_field = nlohmann::json::object();  // report keys the datasheet reads too
  if (!settings.near_field_distances_m.empty()) {
    const std::vector<sim::NearFieldPlane> planes = sim.near_field();
    near_field_list = write_near_field(plan.out_dir, plan.stem, planes, &near_field_files, &failures);
    files.far_field_distance = sim::far_field_distance(planes);
    far_field_distance = far_field_distance_json(sim, *files.far_field_distance);
    request.near_field["near_field"] = near_field_list;
    request.near_field["far_field_distance_m"] = far_field_distance["distance_m"];
    request.near_field["far_field_distance"] = far_field_distance;
  }
  // Luminance images and CIE 232's figures (io/outputs/luminance_images.h).
  io::LuminanceOutputs luminance;
  if (!settings.luminance.views.empty()) {
    luminance = io::write_luminance_images(plan.out_dir, plan.stem, sim.luminance_images(), request.opening->opening,
                                           settings.luminance.cone_deg);
    failures.insert(failures.end(), luminance.failures.begin(), luminance.failures.end());
    request.near_field["luminance_images"] = luminance.images;
    request.near_field["cie232"] = luminance.cie232;
  }
  Result<OutputResult> written = write_outputs(far_field, sim.scene(), ledger, request);
  if (!written.ok()) failures.push_back(written.error());
  if (plan.tm25) {
    const std::string ray_path = (std::filesystem::path(plan.out_dir) / (plan.stem + ".tm25ray")).string();
    Result<RayFileWritten> rays = write_ray_file(ray_path, sim, ledger.escaped.flux_lm, request.run.issue_date);
    if (rays.ok())
      files.ray_file = rays.value();
    else
      failures.push_back(rays.error());
  }
  if (written.ok()) files.outputs = std::move(written.value());
  const OutputResult& outputs = files.outputs;
  for (const FailedFile& f : outputs.failed) failures.push_back(f.error);

  nlohmann::json json = run_json(plan, run, input_times, preview, start);
  json["far_field"] = {{"face_size", settings.face_size},
                       {"texels", far_field.texel_count()},
                       {"flux_lm", far_field.total_flux_lm()}};
  for (const WrittenFile& f : outputs.files)
    if (f.format == OutputFormat::Exr) json["far_field"]["file"] = std::filesystem::path(f.path).filename().string();
  json["outputs"] = to_json(outputs, plan.grid, ledger.escaped.flux_lm);
  std::string colour_chart_path;
  if (request.colour_report.is_object())
    colour_chart_path = write_colour_chart(plan, request.colour_report, json, failures);
  if (!ranks_report.is_null()) json["mpi"] = ranks_report;
  if (!input_times.cad.is_null()) json["cad"] = input_times.cad;  // a CAD model: how it was meshed
  if (!input_times.design_file.is_null()) json["design_file"] = input_times.design_file;  // a design file
  if (!settings.near_field_distances_m.empty()) {
    json["near_field"] = near_field_list;
    json["far_field_distance_m"] = far_field_distance["distance_m"];
    json["far_field_distance"] = far_field_distance;
    json["far_field_distance_method"] =
        "planes at D below the photometric centre (the power-weighted mean of the points where escaping light "
        "heading down leaves); each compared on 21 x 21 cells of 4D/21 where E_far >= 10 % of the plane's "
        "largest cell: a plane passes when every cell has |E - E_far| / E_far + 1.645 sigma <= 1 % (95 %, "
        "one-sided), fails when one has |E - E_far| / E_far - z sigma > 1 % (z: Sidak for the cells at 95 %), "
        "else is undecided; sigma = sqrt(photons in only one of the cell's two tallies) / photons in E_far; the "
        "distance is the smallest asked for from which that plane and every farther one pass";
  }
  json["next_event"] = next_event_json(sim, far_field, ledger);
  if (!settings.luminance.views.empty()) {
    json["luminance_images"] = luminance.images;
    json["cie232"] = luminance.cie232;
  }
  json["cache"] = trimmed_cache_json(plan);
  // Every file this run left in DIR besides report.json, and what failed.
  for (const WrittenFile& f : outputs.files) files.written.push_back(f.path);
  if (!colour_chart_path.empty()) files.written.push_back(colour_chart_path);
  for (const std::string& path : near_field_files) files.written.push_back(path);
  for (const std::string& path : luminance.written) files.written.push_back(path);
  if (preview)
    for (const std::string& path : {preview->exr_path(), preview->png_path()}) {
      files.preview.push_back(path);
      if (std::filesystem::is_regular_file(path)) files.written.push_back(path);
    }
  json["written"] = files.written;
  json["output_failures"] = nlohmann::json::array();
  for (const Error& e : failures) json["output_failures"].push_back(to_string(e));

  // The energy checks, each with what it found.
  files.energy = check_energy(ledger, outputs.files, plan.min_lor, plan.flux_tolerance);
  json["energy"] = files.energy.json;
  if (Status s = io::write_json(files.report_path, json); !s.ok()) files.report_error = s.error();
  files.report = std::move(json);
  files.failures = std::move(failures);
  return files;
}

}  // namespace gonio::app
