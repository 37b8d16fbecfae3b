// GLDF (Global Lighting Data Format) containers and the L3D geometry inside
// them.
//
// A .gldf is a ZIP archive (io/support/zip.h) with product.xml at its root and its
// files in folders named by the first part of their content type: ldc/ for
// photometries (ldc/eulumdat, ldc/ies, ldc/iesxml), geo/ for geometry
// (geo/l3d). An .l3d is itself a ZIP archive: structure.xml at its root and
// each OBJ model in a folder named by its geometry id.
//
// Reading (gonio info|check|convert on a .gldf): product.xml's
// GeneralDefinitions/Photometries, each Photometry's
// PhotometryFileReference resolved through Files/File to an archive entry
// (the content type's folder, else the archive root). Errors name the
// archive and, for product.xml, the line: a hostile or corrupt archive
// (io/support/zip.h), no product.xml, malformed XML, a photometry that refers to an
// unknown file id or to a file the archive lacks. Photometries given by URL
// are a "gldf-url-not-fetched" warning; nothing is fetched.
//
// Writing (gonio convert FILE out.gldf; gonio simulate --format gldf):
// product.xml valid against GLDF 1.0.0-rc.3 with the header (manufacturer,
// format version, creating application, creation time, a unique id), the
// photometries' files, their descriptive photometry (LOR, efficacy, DFF,
// half- and tenth-peak divergence as far as they are defined), one
// changeable light emitter on the first photometry, the geometry where
// there is one, and one product with one variant.
//
// L3D coordinates: metres, right-handed, Z up; the luminaire's photometric
// frame maps onto it as X = C0, Y = C90, Z = zenith, so a light-emitting
// object facing −Z emits towards the nadir with its C0 plane along X.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/support/zip.h"
#include "photometry/diagnostics.h"
#include "photometry/distribution.h"
#include "photometry/vec3.h"
#include "sim/scene.h"

namespace gonio::io {

// ------------------------------------------------------------------ reading

struct GldfPhotometry {
  std::string id;            // the Photometry's id in product.xml
  std::string entry;         // its file in the archive, e.g. "ldc/bell.ldt"
  std::string content_type;  // "ldc/eulumdat", "ldc/ies" or "ldc/iesxml"
  std::string bytes;         // the file's contents
  int line = 0;              // product.xml line of the <Photometry>
};

struct GldfFile {
  std::string product_name;  // ProductMetaData/Name (the first locale); empty if none
  std::string manufacturer;  // Header/Manufacturer
  std::vector<GldfPhotometry> photometries;
  std::vector<std::string> entries;  // every file in the archive, in archive order
  std::vector<Finding> findings;     // warnings, with product.xml lines
};

inline constexpr std::size_t kMaxGldfBytes = std::size_t{256} << 20;  // the archive itself

Result<GldfFile> parse_gldf(std::string_view bytes, const std::string& name);

// ------------------------------------------------------------------ writing

// A light-emitting object: a rectangle in L3D's frame facing −Z.
struct L3dEmitter {
  std::string name;        // partName: a letter, then letters and digits
  Vec3 position_m;
  double size_x_m = 0.0;   // along X (C0)
  double size_y_m = 0.0;   // along Y (C90)
};

// An instanced mesh's OBJ, written once however often it is placed (an L3D
// GeometryFileDefinition).
struct L3dDefinition {
  std::string id;   // geometry id and OBJ folder: a letter, then letters and digits
  std::string obj;  // Wavefront OBJ, metres, in the luminaire frame's axes, one object
};

// One placement of a definition (an L3D Geometry part): a point q of its OBJ
// lies at position_m + R·q, R a rotation about one axis of L3D's frame
// (right-handed, counter-clockwise seen from that axis's tip) by the one
// non-zero component of rotation_deg, or none.
struct L3dPart {
  std::string name;         // partName: a letter, then letters and digits
  std::string geometry_id;  // an L3dDefinition's id
  Vec3 position_m;
  Vec3 rotation_deg;
};

struct L3dGeometry {
  std::string id = "luminaire";  // the body's geometry id and OBJ folder
  std::string obj;               // the body: Wavefront OBJ, metres, L3D frame, one object
  std::vector<L3dDefinition> definitions;  // instanced meshes
  std::vector<L3dPart> parts;              // their placements
  std::vector<L3dEmitter> emitters;
};

// The model's triangles in L3D's frame (the luminaire's photometric frame:
// X = C0, Y = C90, Z = zenith, about the world origin), and one
// light-emitting object where the emitters are: a rectangle over their
// extent seen from above (points: the emitters' positions; areas: their
// meshes' vertices as placed; at least 1 mm a side), at their mean height,
// on the body. One object, because a GLDF emitter's photometry is the whole
// luminaire's: several objects referring to it would multiply its flux.
// `gonio simulate` replaces that rectangle by the luminous opening its LDT
// and IES carry (where the light leaves the model, seen from above:
// tools/run/simulation_outputs.h, simulated_opening()).
//
// World meshes go into the body's OBJ. An instanced mesh is written once
// per scale it is placed at (an OBJ scaled and turned into the luminaire
// frame's axes) and each instance becomes a part, so the archive grows with
// the unique geometry, not with the copies. L3D places a part by a position
// and Euler angles whose order (ZXY) the format leaves open to reading as
// intrinsic or extrinsic; Gonio therefore writes parts only for placements
// that are a uniform scale, a rotation about at most one axis of L3D's frame
// and a translation (arrays, rings about the luminaire's axis), which read
// the same either way. Any other instance (mirrored, sheared, non-uniformly
// scaled, turned about a skew axis) is flattened into the body, as is the
// first instance when the body would otherwise hold no triangle.
L3dGeometry l3d_from_scene(const sim::SceneDesc& scene);

// The .l3d archive: structure.xml, the body's OBJ in folder `id` and each
// definition's in a folder of its id.
Result<std::string> write_l3d(const L3dGeometry& geometry, const std::string& created_with,
                              std::int64_t created_unix);

struct GldfPhotometryOut {
  std::string file_name;     // inside ldc/, e.g. "bell.ldt"
  std::string content_type;  // "ldc/eulumdat", "ldc/ies" or "ldc/iesxml"
  std::string bytes;
  photometry::Distribution distribution;  // for the descriptive photometry
};

struct GldfProduct {
  std::string name;          // product and variant name
  std::string manufacturer;  // "not stated" when empty
  std::string description;
  std::vector<GldfPhotometryOut> photometries;  // at least one; the first is the emitter's
  std::optional<L3dGeometry> geometry;
  std::int64_t created_unix = 0;  // GldfCreationTimeCode and the entries' times
};

// product.xml on its own (what the schema test validates).
std::string gldf_product_xml(const GldfProduct& product);

// The .gldf archive bytes: product.xml, ldc/<files>, geo/<id>.l3d.
Result<std::string> write_gldf(const GldfProduct& product);

}  // namespace gonio::io
