// The CAD sidecar: a TOML file beside a STEP or IGES model (lamp.gonio.toml
// beside lamp.step, or `--parts FILE`) that says what the model's parts are
// made of and where its light comes from. toml++ reads it into the plain
// tree of io/model/toml_tree.h; this header is its plain-data form,
// and io/model/cad.h applies it to the tessellated model. docs/cad.md has
// the format with a full example:
//
//   length_unit = "mm"            # unit of the coordinates below; default: the model file's
//   default_material = "black"    # for parts no rule covers; without it they are an error
//
//   [frame]                       # the luminaire's photometric frame, in the file's axes
//   up = [0, 0, 1]                # zenith (γ = 180°); default +Z (nadir −Z)
//   c0 = [1, 0, 0]                # C0; default +X (so C90 is +Y)
//
//   [materials.reflector]         # a material: the keys of glTF's extras.gonio
//   reflectance = 0.95            #   (io/model/gltf_material.h)
//
//   [[parts]]                     # rules, the first that matches a surface wins
//   match = "Reflector*"          # glob on the assembly path (see below)
//   colour = "#c0c0c0"            # or [r, g, b] in 0..1: the CAD colour (sRGB)
//   layer = "OPTICS"              # a layer of the part or of a component above it
//   material = "reflector"
//
//   [[emitters]]                  # a point emitter (or a ray set)
//   name = "LED"
//   at = "LED*"                   # at every placement of these parts, in their axes
//   position = [0, 0, 0.5]        # the point: in the part's axes (with `at`) or the file's
//   nadir = [0, 0, -1]            # γ = 0 (default: the part's −Z, or the frame's nadir)
//   c0 = [1, 0, 0]                # C0 (default: the part's +X, or the frame's C0)
//   profile = "led.ies"           # IES, LDT, TM-33 or GLDF beside the sidecar; absent: isotropic
//   ray_file = "led.tm25ray"      # instead of a profile: an IES TM-25 ray set in the part's axes
//   flux_lm = 1200                # the emitter's flux (default: the profile's or ray file's)
//   spectrum = { blackbody_k = 4000 }   # as extras.gonio.spectrum
//
// Patterns are globs (fnmatch: *, ?, [...]), blind to the case of ASCII
// letters ("led*" matches "LED1"). A pattern with a '/' is matched
// against the whole assembly path ("Lamp/Optic/Lens[2]", '*' crossing '/'),
// one without against the path's last component and against the part's
// product name. A rule with several conditions needs all of them.
// Materials with luminance_cd_m2 emit from their surfaces (Lambertian,
// Φ = π·L·A), as glTF's emissive materials do.
//
// Errors name the file and line: TOML syntax, unknown keys (a typo must not
// pass silently; unknown keys inside a material are warnings, as in glTF), a
// value of the wrong type, a rule or emitter naming a material or nothing.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"
#include "photometry/vec3.h"

namespace gonio::io {

// Which surfaces a rule covers; every condition given must hold.
struct PartsRule {
  std::string match;                 // glob; empty: any
  std::optional<Vec3> colour;        // sRGB in [0, 1]; matches a colour within half an 8-bit step
  std::string layer;                 // glob on layer names; empty: any
  std::string material;              // a name of PartsFile::materials
  int line = 0;
};

struct PartsEmitter {
  std::string name;
  int line = 0;
  std::string at;                    // glob of parts: at each placement; empty: in the file's frame
  std::optional<Vec3> position;      // [length_unit]: in the part's axes (at) or the file's
  std::optional<Vec3> nadir, c0;     // directions, likewise
  std::string profile;               // path relative to the sidecar; empty: none
  std::string ray_file;              // likewise
  std::optional<double> flux_lm;     // [lm]
  nlohmann::json spectrum;           // {"spectrum": ...} as extras.gonio has it; null: none
};

struct PartsMaterial {
  std::string name;
  nlohmann::json extras;             // the table as extras.gonio JSON
  int line = 0;
};

struct PartsFile {
  std::string path;                  // the sidecar, as named in messages
  std::optional<double> length_unit_m;  // metres per unit of its coordinates; none: the model's
  std::string default_material;      // empty: none
  std::optional<Vec3> frame_up, frame_c0;
  std::vector<PartsMaterial> materials;
  std::vector<PartsRule> rules;
  std::vector<PartsEmitter> emitters;

  const PartsMaterial* material(const std::string& name) const {
    for (const PartsMaterial& m : materials)
      if (m.name == name) return &m;
    return nullptr;
  }
};

// Parses sidecar text; `name` is the file named in messages.
Result<PartsFile> parse_parts_file(std::string_view text, const std::string& name);

// The sidecar's vocabulary in another TOML document (a design file,
// design/design_file.h): `root` may hold the keys `root_keys` (others are
// errors naming the line, `what` first: "the design file: unknown key …");
// those the sidecar knows (length_unit, default_material, frame, materials,
// parts, emitters) are read as in a sidecar, the caller reads the rest.
Result<PartsFile> parse_parts_tree(const TomlNode& root, const std::string& name,
                                   const std::vector<std::string>& root_keys, const std::string& what);

// Reads and parses the sidecar at `path` (at most 16 MiB).
Result<PartsFile> read_parts_file(const std::string& path);

// Metres per unit for a length unit's name as STEP, IGES and people write
// it ("mm", "millimetre", "MM", "inch", "in", "m", "metre", "cm", "ft",
// "foot", "µm", "micrometre"; case-insensitive); nothing for other names.
std::optional<double> length_unit_m(std::string_view name);

// fnmatch(3) of `pattern` against `text`, '*' crossing '/', blind to the
// case of ASCII letters (FNM_CASEFOLD): exporters change the case of names
// (Creo and IGES write capitals), and CAD on Windows treats names case-blind.
bool glob_match(const std::string& pattern, const std::string& text);

}  // namespace gonio::io
