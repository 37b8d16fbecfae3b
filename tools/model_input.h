// How subcommands read luminaire models (glTF 2.0): load, then the model
// checks (closed refractive volumes, degenerate and self-intersecting
// faces); errors stop the command, warnings are printed.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/scene.h"

namespace gonio::cli {

// A model loaded and checked, nothing printed: the scene unless `error`;
// `findings` of the reader and the checks; `has_errors` when one of them is
// an error (the scene must not be simulated).
struct ModelLoad {
  std::optional<sim::SceneDesc> scene;
  std::optional<Error> error;
  std::vector<Finding> findings;
  bool has_errors = false;
};
ModelLoad load_model(const std::string& model);

// Loads and checks `model`, printing every warning and error to stderr with
// the file and the part of the model. Returns nothing where the model cannot
// be loaded or has errors; then the last message says "nothing was
// `not_done`" (e.g. "simulated").
std::optional<sim::SceneDesc> load_checked_model(const std::string& model, const std::string& not_done);

}  // namespace gonio::cli
