#include "tools/model_input.h"

#include <utility>
#include <vector>

#include "io/gltf.h"
#include "io/model_check.h"
#include "tools/cli.h"

namespace gonio::cli {

std::optional<sim::SceneDesc> load_checked_model(const std::string& model, const std::string& not_done) {
  std::vector<Finding> findings;
  Result<sim::SceneDesc> scene = io::load_gltf(model, &findings);
  if (scene.ok()) {
    const std::vector<Finding> checks = io::check_model(scene.value());
    findings.insert(findings.end(), checks.begin(), checks.end());
  }
  bool errors = false;
  for (const Finding& f : findings) {
    const std::string where = f.where.file.empty() ? model : to_string(f.where);
    if (f.severity == Severity::Error) {
      print_error(where + ": " + f.message);
      errors = true;
    } else if (f.severity == Severity::Warning) {
      print_warning(where + ": " + f.message);
    }
  }
  if (!scene.ok()) {
    print_error(scene.error());
    return std::nullopt;
  }
  if (errors) {
    print_error(model + ": the model has errors (above); nothing was " + not_done);
    return std::nullopt;
  }
  return std::move(scene.value());
}

}  // namespace gonio::cli
