// How subcommands read luminaire models (glTF 2.0, and STEP or IGES with
// their sidecar: io/model/cad.h): load, then the model checks (closed
// refractive volumes, degenerate and self-intersecting faces); errors stop
// the command, warnings are printed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "photometry/diagnostics.h"
#include "sim/scene.h"
#include "tools/run/console.h"

namespace gonio::design {
struct Design;
}

namespace gonio::app {

// How a model may be read: what every command that loads one offers.
struct ModelInputOptions {
  bool allow_outside_paths = false;  // --allow-outside-paths (io::GltfLoadOptions)
  bool no_instancing = false;        // --no-instancing: flatten meshes placed more than once
  // The cache folder: the model checks' results (io/model/model_check.h), CAD
  // models' tessellations (io/model/cad.h), and for the commands that write
  // files, the outputs' resamplers (tools/run/resampler_cache.h); empty: no cache.
  std::string cache_dir;
  // CAD models only (io::is_cad_path):
  std::string parts_file;       // --parts FILE; empty: the sidecar beside the model
  std::string tessellation;     // --tessellation DEG[,MM]; empty: from the grid
  double gamma_step_deg = 2.5;  // the output grid's γ step, which the default tessellation follows
  // A design held in memory (the Python module's gonio.Design): the model is
  // built from it, at its variables' current values, and the model's name
  // only names it in messages and outputs; no file is read for it.
  std::shared_ptr<const design::Design> design;
  // A model built in memory (the Python module's gonio.Model: meshes from
  // arrays, the sidecar's materials and emitters): called in place of
  // reading a file, its findings appended to the load's; the model's name
  // only names it.
  std::function<Result<sim::SceneDesc>(std::vector<Finding>*)> build_scene;
};

// Whether the options suit these models: --tessellation parses (a CAD model
// is meshed to io::parse_tessellation of it over io::tessellation_for_grid of
// the γ step), and --parts or --tessellation come with at least one CAD
// model. Errors name the option.
Status check_model_input(const ModelInputOptions& options, const std::vector<std::string>& models);

// The files a model is read from, the model first: a glTF model's buffers,
// images and profiles (io::gltf_files); a CAD model's sidecar (whether or not
// it exists yet) and the sidecar's profiles and ray files (io::cad_files).
// `gonio watch` starts again when one of them changes. Just the model where
// it cannot be read now.
std::vector<std::string> model_files(const std::string& model, const ModelInputOptions& options = {});

// What loading took.
struct ModelInputTimes {
  double load_s = 0.0;   // reading the glTF model [s]
  double check_s = 0.0;  // the model checks, or finding them in the cache [s]
  std::size_t meshes = 0;
  std::size_t meshes_from_cache = 0;
  std::uint64_t max_rss_after_load_bytes = 0;    // the memory high-water mark then
  std::uint64_t max_rss_after_checks_bytes = 0;  // (io::peak_memory_bytes)
  // A CAD model's report.json section "cad" (cad_report in model_input.cpp):
  // format, unit, sidecar, the tessellation asked for and its triangles per
  // part, whether it came from the cache; null for glTF.
  nlohmann::json cad;
  // A design file's report.json section "design_file" (design_file_report in
  // model_input.cpp), in place of "cad": the file, its parts by kind, its
  // variables' values, the tessellation and triangles per part; null otherwise.
  nlohmann::json design_file;
};

// A model loaded and checked, nothing printed: the scene unless `error`;
// `findings` of the reader and the checks; `has_errors` when one of them is
// an error (the scene must not be simulated).
struct ModelLoad {
  std::optional<sim::SceneDesc> scene;
  std::optional<Error> error;
  std::vector<Finding> findings;
  bool has_errors = false;
};
ModelLoad load_model(const std::string& model, const ModelInputOptions& options = {},
                     ModelInputTimes* times = nullptr);

// Tells the warnings and errors among a model's findings ("warning: WHERE:
// message", "WHERE: message"; WHERE the finding's place, else the model).
void tell_model_findings(const std::string& model, const std::vector<Finding>& findings,
                         const MessageSink& sink = {});

// Loads and checks `model`, telling every warning and error (tools/run/console.h;
// by default printed to stderr) with the file and the part of the model. Returns
// nothing where the model cannot be loaded or has errors; then the last
// message says "nothing was `not_done`" (e.g. "simulated"). `findings`: all of
// them, the notes too. `failure`: where it returns nothing, the error that
// stopped it as a value (the loader's, or the model's first error finding,
// "MESSAGE [CODE]; nothing was NOT_DONE"), for a front end that raises it.
std::optional<sim::SceneDesc> load_checked_model(const std::string& model, const std::string& not_done,
                                                 const ModelInputOptions& options = {},
                                                 ModelInputTimes* times = nullptr, const MessageSink& sink = {},
                                                 std::vector<Finding>* findings = nullptr,
                                                 std::optional<Error>* failure = nullptr);

}  // namespace gonio::app
