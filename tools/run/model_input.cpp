#include "tools/run/model_input.h"

#include <chrono>
#include <utility>
#include <vector>

#include "io/model/gltf.h"
#include "io/model/model_check.h"
#include "io/outputs/report.h"
#include "tools/run/console.h"

namespace gonio::cli {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

ModelLoad load_model(const std::string& model, const ModelInputOptions& options, ModelInputTimes* times) {
  ModelLoad out;
  ModelInputTimes t;
  auto start = std::chrono::steady_clock::now();
  io::GltfLoadOptions load;
  load.allow_outside_paths = options.allow_outside_paths;
  load.instancing = !options.no_instancing;
  Result<sim::SceneDesc> scene = io::load_gltf(model, &out.findings, load);
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

std::optional<sim::SceneDesc> load_checked_model(const std::string& model, const std::string& not_done,
                                                 const ModelInputOptions& options, ModelInputTimes* times) {
  ModelLoad loaded = load_model(model, options, times);
  for (const Finding& f : loaded.findings) {
    const std::string where = f.where.file.empty() ? model : to_string(f.where);
    if (f.severity == Severity::Error)
      print_error(where + ": " + f.message);
    else if (f.severity == Severity::Warning)
      print_warning(where + ": " + f.message);
  }
  if (loaded.error) {
    print_error(*loaded.error);
    return std::nullopt;
  }
  if (loaded.has_errors) {
    print_error(model + ": the model has errors (above); nothing was " + not_done);
    return std::nullopt;
  }
  return std::move(loaded.scene);
}

}  // namespace gonio::cli
