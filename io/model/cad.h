// CAD luminaire models (STEP AP203/AP214/AP242, IGES) into the simulation's
// scene description (sim/scene.h): the same sim::SceneDesc a glTF model
// gives (io/model/gltf.h), so that checks, instancing, spectra, near field,
// MPI and the live page take it unchanged.
//
// 1. Tessellation (io/model/step.h), in the helper program gonio-cad run as
//    a child process with a time limit (CadLoadOptions::time_limit): a crash,
//    hang or runaway of OpenCASCADE on a hostile file is an error naming the
//    file, never gonio's end. The helper is looked for next to the running
//    executable, in ../lib/gonio/, then where the build wrote it.
// 2. Cache: the tessellation is kept in the cache folder as
//    cad-<hash>.bin (io/support/cache_folder.h) under the XXH3 of the file's
//    bytes, the tessellation settings, kCadModelFormat, kCadReaderRevision
//    and OpenCASCADE's version (another may mesh otherwise), so an unchanged
//    model with unchanged settings is not read by OpenCASCADE again. A
//    damaged entry is ignored and replaced.
// 3. The sidecar (io/model/parts_file.h): `lamp.gonio.toml` beside
//    `lamp.step` (the model's name without its extension, then .gonio.toml),
//    or CadLoadOptions::parts_file. Each surface (a part's faces of one
//    colour) of each placement takes the material of the first rule that
//    matches its assembly path, colour (the faces', else the component's,
//    else the part's) and layers; one that no rule covers takes
//    default_material, and without one every such part is listed in one
//    error. No sidecar: the same error, naming the file it looked for.
// 4. Scene: metres (the file's unit converted), the photometric frame of
//    the sidecar (default: zenith +Z, C0 +X, so nadir −Z and C90 +Y: CAD's
//    Z-up convention), a part placed more than once an instanced mesh (one
//    sim::Instance per placement, named by its assembly path) unless
//    `instancing` is off or its placements take different materials; a part
//    placed once world geometry named by its path. Shading normals from the
//    exact surface (CadTessellation::exact_normals).
//
// Errors name the model (entity #n or part) or the sidecar (line).
#pragma once

#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

#include "io/model/cad_model.h"
#include "io/model/step_export.h"
#include "photometry/diagnostics.h"
#include "sim/scene.h"

namespace gonio::io {

// Whether `path` names a CAD model by its extension (.step, .stp, .p21,
// .iges, .igs; any case).
bool is_cad_path(const std::string& path);

// Whether this build reads CAD models (built with OpenCASCADE, GONIO_OCCT).
bool cad_supported();

// The sidecar a model takes by default: "<folder>/<stem>.gonio.toml".
std::string default_parts_path(const std::string& model);

// The files a CAD model is read from: the model, its sidecar (CadLoadOptions'
// parts_file, else default_parts_path; listed whether or not it exists, so
// that one written later is noticed), then each profile and ray file the
// sidecar names, resolved against its folder, once each. `gonio watch`
// watches these. A sidecar that cannot be read adds no further files.
std::vector<std::string> cad_files(const std::string& model, const std::string& parts_file = {});

// How finely a run on a C-γ grid of `gamma_step_deg` needs its CAD parts
// meshed: the angular deflection kDeflectionPerGammaStep × the step (the
// default 2.5° grid: 2°), with exact-surface normals; docs/cad.md has the
// measurements behind the factor. Clamped to [0.05°, 20°].
inline constexpr double kDeflectionPerGammaStep = 0.8;
CadTessellation tessellation_for_grid(double gamma_step_deg);

// `--tessellation DEG` (the angular deflection) or `DEG,MM` (also an
// absolute chordal deflection in millimetres for every part, which turns
// the angular refinement off), over `base`. Errors name the option.
Result<CadTessellation> parse_tessellation(const std::string& text, CadTessellation base);

struct CadLoadOptions {
  std::string parts_file;                       // empty: default_parts_path(model)
  CadTessellation tessellation;
  std::string cache_dir;                        // empty: no cache
  bool instancing = true;                       // false: every placement world geometry
  bool allow_outside_paths = false;             // sidecar's profile and ray-file paths (as glTF's uris)
  std::chrono::seconds time_limit{900};         // for the helper
  std::string helper;                           // the gonio-cad program; empty: found as above
};

// What loading did, for reports (report.json's "model" section).
struct CadLoadInfo {
  std::string format;                           // "STEP", "IGES"
  std::string file_unit;                        // as the file names it
  std::string parts_file;                       // the sidecar read
  CadTessellation tessellation;
  std::size_t parts = 0, placements = 0;
  std::size_t unique_triangles = 0, placed_triangles = 0;
  bool from_cache = false;
  double tessellate_s = 0.0;                    // the helper's run, or reading the cache entry [s]
  struct Part {
    std::string name;
    std::size_t triangles = 0, placements = 0;
    double size_m = 0.0, chordal_m = 0.0;
  };
  std::vector<Part> per_part;
};

// The tessellated model only (steps 1 and 2).
Result<CadModel> tessellate_cad(const std::string& path, const CadLoadOptions& options, CadLoadInfo* info = nullptr);

// Steps 3 and 4 on a tessellated model: `model_path` names the model in
// messages and finds the default sidecar.
Result<sim::SceneDesc> cad_scene(const CadModel& model, const std::string& model_path, const CadLoadOptions& options,
                                 std::vector<Finding>* findings, CadLoadInfo* info = nullptr);

// Steps 3 and 4 with the sidecar given, read already (a design file's parts
// and its sidecar vocabulary, design/design_file.h): `model_path` names the
// model in messages; profiles and ray files are found beside parts.path.
struct PartsFile;
Result<sim::SceneDesc> cad_scene(const CadModel& model, const PartsFile& parts, const std::string& model_path,
                                 const CadLoadOptions& options, std::vector<Finding>* findings,
                                 CadLoadInfo* info = nullptr);

// All of it. Findings (the reader's and the sidecar's warnings) are appended
// to `findings` when it is not null.
Result<sim::SceneDesc> load_cad(const std::string& path, const CadLoadOptions& options,
                                std::vector<Finding>* findings, CadLoadInfo* info = nullptr);

// Writes `request` as a STEP file at `path` (an atomic write) through the
// helper gonio-cad (its --write-step mode; io/model/step.h's write_step_file),
// with options.helper and options.time_limit as for reading. Returns the
// largest distance of a profile point from its B-spline [mm] (≤ the
// request's tolerance). Errors name `path`.
Result<double> export_step(const StepExport& request, const std::string& path, const CadLoadOptions& options = {});

}  // namespace gonio::io
