#include "tools/model_input.h"

#include <utility>
#include <vector>

#include "io/gltf.h"
#include "io/model_check.h"
#include "tools/cli.h"

namespace gonio::cli {

ModelLoad load_model(const std::string& model) {
  ModelLoad out;
  Result<sim::SceneDesc> scene = io::load_gltf(model, &out.findings);
  if (!scene.ok()) {
    out.error = scene.error();
    return out;
  }
  const std::vector<Finding> checks = io::check_model(scene.value());
  out.findings.insert(out.findings.end(), checks.begin(), checks.end());
  for (const Finding& f : out.findings)
    if (f.severity == Severity::Error) out.has_errors = true;
  out.scene = std::move(scene.value());
  return out;
}

std::optional<sim::SceneDesc> load_checked_model(const std::string& model, const std::string& not_done) {
  ModelLoad loaded = load_model(model);
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
