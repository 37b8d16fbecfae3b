#include "tools/run/model_input.h"

#include <chrono>
#include <utility>
#include <vector>

#include "design/design_file.h"
#include "design/design_scene.h"
#include "io/model/cad.h"
#include "io/model/gltf.h"
#include "io/model/gltf_files.h"
#include "io/model/model_check.h"
#include "io/outputs/report.h"
#include "tools/run/console.h"

namespace gonio::app {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

Result<io::CadTessellation> cad_tessellation(const ModelInputOptions& options) {
  const io::CadTessellation base = io::tessellation_for_grid(options.gamma_step_deg);
  return options.tessellation.empty() ? Result<io::CadTessellation>(base)
                                      : io::parse_tessellation(options.tessellation, base);
}

nlohmann::json tessellation_report(const io::CadTessellation& t) {
  return {{"angular_deflection_deg", t.angular_deflection_deg},
          {"chordal_relative", t.chordal_relative},
          {"chordal_min_mm", t.chordal_min_m * 1e3},
          {"chordal_mm", t.chordal_m > 0.0 ? nlohmann::json(t.chordal_m * 1e3) : nlohmann::json()},
          {"exact_normals", t.exact_normals}};
}

nlohmann::json per_part_report(const io::CadLoadInfo& info) {
  nlohmann::json parts = nlohmann::json::array();
  for (const io::CadLoadInfo::Part& p : info.per_part)
    parts.push_back({{"name", p.name},
                     {"triangles", p.triangles},
                     {"placements", p.placements},
                     {"size_mm", p.size_m * 1e3},
                     {"chordal_deflection_mm", p.chordal_m * 1e3}});
  return parts;
}

// report.json's "cad": what the model was read as and meshed to.
nlohmann::json cad_report(const io::CadLoadInfo& info) {
  return {{"format", info.format},
          {"file_unit", info.file_unit},
          {"parts_file", info.parts_file.empty() ? nlohmann::json() : nlohmann::json(info.parts_file)},
          {"tessellation", tessellation_report(info.tessellation)},
          {"parts", info.parts},
          {"placements", info.placements},
          {"triangles_unique", info.unique_triangles},
          {"triangles_placed", info.placed_triangles},
          {"from_cache", info.from_cache},
          {"tessellate_s", info.tessellate_s},
          {"per_part", per_part_report(info)}};
}

// report.json's "design_file": a design file (or one in memory) as read:
// its parts by kind, its variables' values, and the parts' meshes with the
// cad section's keys.
nlohmann::json design_file_report(const design::Design& d, const io::CadLoadInfo& info) {
  nlohmann::json kinds = nlohmann::json::object();
  for (const char* key : {"reflectors", "lenses", "troughs", "covers", "parts", "emitters"}) {
    const io::TomlNode* a = d.document.get(key);
    kinds[key] = a && a->is_array() ? a->array.size() : std::size_t{0};
  }
  nlohmann::json variables = nlohmann::json::object();
  for (const design::Variable& v : d.variables) variables[v.name] = v.value;
  return {{"file", d.path},
          {"length_unit", info.file_unit},
          {"kinds", std::move(kinds)},
          {"variables", std::move(variables)},
          {"tessellation", tessellation_report(info.tessellation)},
          {"parts", info.parts},
          {"placements", info.placements},
          {"triangles_unique", info.unique_triangles},
          {"triangles_placed", info.placed_triangles},
          {"tessellate_s", info.tessellate_s},
          {"per_part", per_part_report(info)}};
}

}  // namespace

Status check_model_input(const ModelInputOptions& options, const std::vector<std::string>& models) {
  if (Result<io::CadTessellation> t = cad_tessellation(options); !t.ok()) return t.error();
  if (options.parts_file.empty() && options.tessellation.empty()) return Ok{};
  for (const std::string& m : models)
    if (io::is_cad_path(m) || (options.parts_file.empty() && design::is_design_path(m))) return Ok{};
  return make_error(std::string(options.parts_file.empty() ? "--tessellation" : "--parts") +
                    " applies to CAD models (.step, .stp, .p21, .iges, .igs); a glTF model says its materials "
                    "and is meshed already");
}

std::vector<std::string> model_files(const std::string& model, const ModelInputOptions& options) {
  if (design::is_design_path(model)) return design::design_files(model);
  if (io::is_cad_path(model)) return io::cad_files(model, options.parts_file);
  auto files = io::gltf_files(model);
  return files.ok() ? files.value() : std::vector<std::string>{model};
}

ModelLoad load_model(const std::string& model, const ModelInputOptions& options, ModelInputTimes* times) {
  ModelLoad out;
  ModelInputTimes t;
  auto start = std::chrono::steady_clock::now();
  Result<sim::SceneDesc> scene = Error{};
  if (options.build_scene) {
    scene = options.build_scene(&out.findings);
  } else if (options.design || design::is_design_path(model)) {
    // A design file (or one in memory): its parts tessellated as CAD parts
    // are, to the same rule.
    io::CadLoadOptions load;
    load.allow_outside_paths = options.allow_outside_paths;
    Result<io::CadTessellation> tessellation = cad_tessellation(options);
    if (tessellation.ok()) {
      load.tessellation = *tessellation;
      io::CadLoadInfo info;
      Result<design::Design> read = options.design ? Result<design::Design>(*options.design)
                                                   : design::read_design_file(model);
      scene = read.ok() ? design::design_scene(*read, load, &out.findings, &info)
                        : Result<sim::SceneDesc>(read.error());
      if (scene.ok()) t.design_file = design_file_report(*read, info);
    } else {
      scene = tessellation.error();
    }
  } else if (io::is_cad_path(model)) {
    io::CadLoadOptions load;
    load.parts_file = options.parts_file;
    load.cache_dir = options.cache_dir;
    load.instancing = !options.no_instancing;
    load.allow_outside_paths = options.allow_outside_paths;
    Result<io::CadTessellation> tessellation = cad_tessellation(options);
    if (tessellation.ok()) {
      load.tessellation = *tessellation;
      io::CadLoadInfo info;
      scene = io::load_cad(model, load, &out.findings, &info);
      if (scene.ok()) t.cad = cad_report(info);
    } else {
      scene = tessellation.error();
    }
  } else {
    io::GltfLoadOptions load;
    load.allow_outside_paths = options.allow_outside_paths;
    load.instancing = !options.no_instancing;
    scene = io::load_gltf(model, &out.findings, load);
  }
  t.load_s = seconds_since(start);
  t.max_rss_after_load_bytes = io::peak_memory_bytes();
  if (!scene.ok()) {
    out.error = scene.error();
    if (times) *times = t;
    return out;
  }
  start = std::chrono::steady_clock::now();
  io::ModelCheckOptions check_options;
  check_options.cache_dir = options.cache_dir;
  io::ModelCheckStats stats;
  const std::vector<Finding> checks = io::check_model(scene.value(), check_options, &stats);
  out.findings.insert(out.findings.end(), checks.begin(), checks.end());
  t.check_s = seconds_since(start);
  t.meshes = stats.meshes;
  t.meshes_from_cache = stats.meshes_from_cache;
  t.max_rss_after_checks_bytes = io::peak_memory_bytes();
  if (times) *times = t;
  for (const Finding& f : out.findings)
    if (f.severity == Severity::Error) out.has_errors = true;
  out.scene = std::move(scene.value());
  return out;
}

void tell_model_findings(const std::string& model, const std::vector<Finding>& findings, const MessageSink& sink) {
  for (const Finding& f : findings) {
    const std::string where = f.where.file.empty() ? model : to_string(f.where);
    if (f.severity == Severity::Error)
      tell(sink, Severity::Error, where + ": " + f.message);
    else if (f.severity == Severity::Warning)
      tell(sink, Severity::Warning, "warning: " + where + ": " + f.message);
  }
}

std::optional<sim::SceneDesc> load_checked_model(const std::string& model, const std::string& not_done,
                                                 const ModelInputOptions& options, ModelInputTimes* times,
                                                 const MessageSink& sink, std::vector<Finding>* findings,
                                                 std::optional<Error>* failure) {
  ModelLoad loaded = load_model(model, options, times);
  tell_model_findings(model, loaded.findings, sink);
  if (findings) *findings = loaded.findings;
  if (loaded.error) {
    tell(sink, *loaded.error);
    if (failure) *failure = *loaded.error;
    return std::nullopt;
  }
  if (loaded.has_errors) {
    tell(sink, Severity::Error, model + ": the model has errors (above); nothing was " + not_done);
    if (failure)
      for (const Finding& f : loaded.findings)
        if (f.severity == Severity::Error && !*failure) {
          Error e{f.where, f.message + " [" + f.code + "]; nothing was " + not_done};
          if (e.where.file.empty()) e.where.file = model;
          *failure = std::move(e);
        }
    return std::nullopt;
  }
  return std::move(loaded.scene);
}

}  // namespace gonio::app
