// Fixed parts of a design file (design/design_file.h): a housing, a board,
// any part drawn in CAD, read from a glTF or STEP file by Gonio's own model
// loaders (io/model/gltf.h, io/model/cad.h) and placed in the design:
//
//   [[parts]]
//   name = "housing"
//   file = "housing.gltf"              # .gltf/.glb, or .step/.stp/.iges, beside the design file
//   position = [0, 0, 20]              # [length_unit]: where the file's origin goes
//   rotate_deg = [0, 0, 90]            # about X, then Y, then Z (the design's axes), about that origin
//   scale = 1                          # uniform, > 0 (default 1)
//   material = "black"                 # every surface of the file (optional: see below)
//
//   [[parts]]                          # a [[parts]] table without `file` is a rule of
//   match = "housing/Reflector*"       #   the CAD sidecar (io/model/parts_file.h): the
//   material = "mirror"                #   first rule that matches a surface wins
//
// Each of the file's meshes (glTF) or placements (STEP) becomes a placement
// of the design named "NAME/<its name or assembly path>", so sidecar rules
// choose among them; the part's own `material`, where given, is the rule
// "NAME/*" after the file's rules. The file's frame: a glTF file's own
// photometric frame (Y up by default, its extras), turned into the design's
// (Z up, C0 +X); a STEP file's axes are the design's, as for a STEP
// luminaire. Units: glTF's metres, STEP's own (converted by the reader);
// the design's length_unit applies to `position` alone. The file's lights
// and glTF materials are not used: the design's [[emitters]] and materials
// are (a finding says so where the file has lights).
#pragma once

#include <string>
#include <vector>

#include "io/model/cad.h"
#include "io/model/parts_file.h"
#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"
#include "sim/affine.h"

namespace gonio::design {

struct FixedPart {
  std::string name;
  std::string file;          // as written, relative to the design file
  std::string material;      // empty: the sidecar rules alone
  Vec3 position;             // [m]
  Vec3 rotate_deg;
  double scale = 1.0;
  int line = 0, file_line = 0;
};

// Whether a [[parts]] table is a fixed part (it has `file`) rather than a rule.
bool is_fixed_part(const io::TomlNode& table);

// The document with the fixed parts left out of [[parts]] (the rules stay):
// what the sidecar's reader (io::parse_parts_tree) takes.
io::TomlNode sidecar_tree(const io::TomlNode& resolved);

// A fixed part's table (variables resolved). Errors name `path` and the
// line: unknown keys, a missing name or file, a file of a kind Gonio does
// not read, a scale not > 0.
Result<FixedPart> read_fixed_part(const io::TomlNode& t, const std::string& path, double unit_m);

// The map from the file's frame (after the glTF frame's turn) to the design's.
sim::Affine fixed_part_transform(const FixedPart& part);

// Reads the part's file (found beside `design_path`; outside its folder
// only with options.allow_outside_paths) and adds its surfaces to `model`,
// placed, with the rule for `material` in `sidecar`. Errors name the design
// file and the part's line, with the loader's message.
Status add_fixed_part(const FixedPart& part, const std::string& design_path, const io::CadLoadOptions& options,
                      io::PartsFile& sidecar, io::CadModel& model, std::vector<Finding>* findings);

}  // namespace gonio::design
