#include "tools/model_input.h"

#include <utility>
#include <vector>

#include "io/gltf.h"
#include "io/model_check.h"
#include "tools/cli.h"

namespace gonio::cli {

void add_model_input_options(ArgParser& parser, ModelInputOptions* options) {
  parser.flag("allow-outside-paths", &options->allow_outside_paths,
              "let the model's uris (buffers, images, light profiles) name files outside its folder "
              "(absolute paths, '..', symbolic links leading out); refused by default");
}

std::optional<sim::SceneDesc> load_checked_model(const std::string& model, const std::string& not_done,
                                                 const ModelInputOptions& options) {
  std::vector<Finding> findings;
  io::GltfLoadOptions load;
  load.allow_outside_paths = options.allow_outside_paths;
  Result<sim::SceneDesc> scene = io::load_gltf(model, &findings, load);
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
