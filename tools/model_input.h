// How subcommands read luminaire models (glTF 2.0): load, then the model
// checks (closed refractive volumes, degenerate and self-intersecting
// faces); errors stop the command, warnings are printed.
#pragma once

#include <optional>
#include <string>

#include "sim/scene.h"
#include "tools/cli.h"

namespace gonio::cli {

// How a model may be read: what every command that loads one offers.
struct ModelInputOptions {
  bool allow_outside_paths = false;  // --allow-outside-paths (io::GltfLoadOptions)
};

// Registers --allow-outside-paths on a subcommand that loads models.
void add_model_input_options(ArgParser& parser, ModelInputOptions* options);

// Loads and checks `model`, printing every warning and error to stderr with
// the file and the part of the model. Returns nothing where the model cannot
// be loaded or has errors; then the last message says "nothing was
// `not_done`" (e.g. "simulated").
std::optional<sim::SceneDesc> load_checked_model(const std::string& model, const std::string& not_done,
                                                 const ModelInputOptions& options);

}  // namespace gonio::cli
