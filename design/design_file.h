// Design files: parametric optical parts that Gonio reads as a model
// (`gonio simulate lamp.design.toml`), that `gonio design` writes, and whose
// numbers an optimiser or a tolerance analysis sets by name. docs/design.md
// has the format; in short:
//
//   length_unit = "mm"                 # as the CAD sidecar's (io/model/parts_file.h)
//
//   [materials.mirror]                 # the sidecar's materials: extras.gonio's keys,
//   reflectance = 0.95                 #   presets of the material library
//
//   [[emitters]]                       # the sidecar's emitters: profile, flux_lm,
//   name = "LED"                       #   position, nadir, c0, ray_file, spectrum
//   position = [0, 0, 0]
//   profile = "led.ies"
//
//   [[reflectors]]                     # a reflector of revolution about the Z axis
//   name = "reflector"
//   material = "mirror"
//   profile = "conic"                  # z(ρ) = vertex − sag(ρ), ρ over `aperture`
//   radius = 20                        # R at the vertex (c = 1/R)
//   conic = -1                         # κ (−1 a paraboloid)
//   aspheric = [0, 0]                  # a4, a6, …: sag += a4·ρ⁴ + a6·ρ⁶ + …
//   vertex = 10                        # the vertex's height on the axis
//   aperture = [4, 30]                 # ρ from the axis: inner and outer edge
//
//   [[reflectors]]
//   name = "polar"
//   material = "mirror"
//   profile = "polar"                  # r(θ) about the origin, θ from the nadir (−Z)
//   theta_deg = [60, 90, 120, 150, 180]
//   r = [{ value = 20, min = 15, max = 30 }, 21, 22, 23, 24]
//
//   [[reflectors]]
//   name = "spline"
//   material = "mirror"
//   profile = "bspline"                # a clamped B-spline through control points
//   degree = 3                         # 1 … 5 (default 3)
//   points = [[4, 10], [15, 8], [25, 2], [30, -5]]   # (ρ, z), ρ ≥ 0
//
// Other kinds of part, each in its own header: [[troughs]] (design/trough.h),
// [[covers]] (design/cover.h), [[parts]] with a file (design/fixed_part.h),
// and a reflector's `facets` (design/facets.h).
//
// The frame is the luminaire's photometric frame: zenith +Z, C0 +X, so the
// nadir (γ = 0) is −Z; every reflector turns about the Z axis.
//
// Any number may be a variable, `{ value = …, min = …, max = … }` (bounds
// optional, `name = "…"` optional: its name is otherwise the key's path,
// "reflectors[0].r[2]"). A design keeps its document with the variables in
// place, so that setting one and building the scene again is all an
// optimiser does (set_variable, design_scene), and writing it back keeps them.
//
// Errors name the file and line: TOML syntax, unknown keys, wrong types, a
// variable outside its bounds, a profile that crosses itself or passes
// through an emitter, a conic undefined over its aperture.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"

namespace gonio::design {

// Whether `path` names a design file: it ends with ".design.toml" (any case).
bool is_design_path(const std::string& path);

// A model file's name without its extension, ".design.toml" counting as one
// (any case): "lamp" for a/lamp.design.toml, "x" for x.gltf, "x.v2" for
// x.v2.step; what the outputs are named after (STEM.ies, STEM.ldt, …).
std::string model_stem(const std::string& path);

// A named number of the design.
struct Variable {
  std::string name;
  double value = 0.0;
  std::optional<double> min, max;
  int line = 0;
  // Where it sits in the document: keys of tables and indices of arrays.
  struct Step {
    std::string key;  // empty: an array index
    std::size_t index = 0;
  };
  std::vector<Step> path;
};

struct Design {
  std::string path;           // the file, as named in messages
  io::TomlNode document;      // as read, variables in place (tables with `value`)
  std::vector<Variable> variables;

  const Variable* variable(const std::string& name) const;
};

// Parses design text (`name` names it in messages), finding its variables
// and checking them against their bounds; the parts are checked when the
// scene is built (design_scene, design/design_scene.h).
Result<Design> parse_design(std::string_view text, const std::string& name);

// Reads and parses the design file at `path` (at most 16 MiB).
Result<Design> read_design_file(const std::string& path);

// Sets a variable's value, in `variables` and in the document. Errors: no
// such variable, a value outside its bounds or not finite.
Status set_variable(Design& design, const std::string& name, double value);

// The document with every variable replaced by its value (the line kept).
io::TomlNode resolved_document(const Design& design);

// The design as TOML text (keys in the document's order, variables inline
// as `{ value = …, min = …, max = … }`); `header`: comment lines written
// first (each given without '#').
std::string write_design(const io::TomlNode& document, const std::vector<std::string>& header = {});

// Builders for a document made in code (gonio design).
io::TomlNode toml_string(std::string value);
io::TomlNode toml_number(double value);
io::TomlNode toml_variable(double value, std::optional<double> min, std::optional<double> max);
io::TomlNode toml_array(std::vector<io::TomlNode> items);
io::TomlNode toml_table();
// Adds (or replaces) key in a table.
void toml_set(io::TomlNode& table, const std::string& key, io::TomlNode value);

}  // namespace gonio::design
