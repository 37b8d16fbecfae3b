// A design file's parts and emitters as the simulation's scene: each part
// tessellated (design/revolved.h) into a io::CadModel part placed once, named
// by its `name`, and the file's sidecar vocabulary ([materials], [[emitters]],
// length_unit; io/model/parts_file.h) applied by the CAD loader's scene
// builder (io::cad_scene), so that materials, the material library, profiles,
// ray files and spectra are read exactly as a CAD sidecar's.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "design/design_file.h"
#include "design/lens.h"
#include "design/cover.h"
#include "design/facets.h"
#include "design/fixed_part.h"
#include "design/revolved.h"
#include "design/trough.h"
#include "io/model/cad.h"
#include "photometry/diagnostics.h"
#include "sim/scene.h"

namespace gonio::design {

// A reflector of revolution as the file gives it (lengths in metres).
struct Reflector {
  std::string name;
  std::string material;
  Profile profile;
  std::optional<Facets> facets;  // design/facets.h; none: smooth
  int line = 0;
};

// The parts of a resolved document (resolved_document), checked: unknown
// keys, types, names, the profiles' own errors, each naming the line.
struct DesignParts {
  double unit_m = 1e-3;  // metres per unit of the file's lengths
  std::vector<Reflector> reflectors;
  std::vector<Lens> lenses;  // design/lens.h
  std::vector<Trough> troughs;              // design/trough.h
  std::vector<Cover> covers;                // design/cover.h
  std::vector<FixedPart> fixed_parts;       // design/fixed_part.h ([[parts]] with a file)
};
Result<DesignParts> read_design_parts(const io::TomlNode& resolved, const std::string& path);

// A table with a reflector's keys (name, material, profile and the
// profile's keys) read as a reflector, `table` naming its array in messages
// ("[[troughs]] at line 12: …"); the other kinds of profile part
// (design/trough.h) read their profile with it.
Result<Reflector> read_profile_part(const io::TomlNode& t, const std::string& path, double unit_m,
                                    const std::string& table);

// The root keys a design file may hold.
const std::vector<std::string>& design_root_keys();

// The scene of `design` at its variables' current values. `options`: the
// tessellation, and allow_outside_paths for the emitters' files (its
// parts_file, cache and helper are not used). Errors name the design file
// and line; a profile that passes within the chordal deflection of an
// emitter placed by `position` is an error naming both.
Result<sim::SceneDesc> design_scene(const Design& design, const io::CadLoadOptions& options,
                                    std::vector<Finding>* findings, io::CadLoadInfo* info = nullptr);

// Reads the design file at `path` and builds its scene.
Result<sim::SceneDesc> load_design(const std::string& path, const io::CadLoadOptions& options,
                                   std::vector<Finding>* findings, io::CadLoadInfo* info = nullptr);

// The files a design is read from: the file, then each profile and ray file
// its emitters name (resolved against its folder, once each). `gonio watch`
// watches these.
std::vector<std::string> design_files(const std::string& path);

}  // namespace gonio::design
