// glTF 2.0 luminaire models (.gltf with external or data-URI buffers, .glb)
// into the simulation's scene description (sim/scene.h).
//
// Files: the model, its buffers and profiles are read whole, each at most
// kMaxFileBytes; URIs are data URIs or paths relative to the model's folder
// (never the working directory) that stay inside it (GltfLoadOptions). Textures are not used: external image files are opened by the
// parser but never decoded, and a missing or broken image is only a warning.
//
// Geometry
// - Every triangle primitive of the nodes of the default scene (`scene`), or
//   of every root node when the file names no default scene, with node
//   transforms (TRS or matrix, any depth) applied: positions in world space,
//   metres, times `extras.gonio.unit_m` (below). Shading normals (NORMAL) and
//   tangents (TANGENT) are transformed too. A node with a mirroring transform
//   (negative determinant) has its triangles' winding reversed, as glTF
//   requires, so counter-clockwise always means front.
// - Instancing: a mesh placed by more than one node of the scene, and the
//   mesh of a node with EXT_mesh_gpu_instancing (TRANSLATION, ROTATION,
//   SCALE float accessors; the node places one copy per element, none of
//   its own), is read once: each primitive becomes one instanced sim::Mesh
//   in the glTF mesh's own frame, named "<mesh>/<primitive>", and each
//   placement a sim::Instance (node name, "[i]" appended for the extension's
//   copies) with the full world transform. Emissive primitives emit from
//   every instance (one area emitter each). A copy with a singular
//   transform is left out (warning). GltfLoadOptions::instancing = false
//   flattens every copy instead. A mesh placed once is world geometry named
//   "<node>/<mesh>/<primitive>".
// - Triangle strips and fans are converted to triangles with glTF's vertex
//   order rules (strip triangles with a repeated index, the usual stitching,
//   are dropped). Points and lines are an error naming node, mesh and
//   primitive. Sparse accessors are applied. Each primitive keeps only the
//   vertices its triangles use. Positions, normals and tangents
//   must be float accessors (KHR_mesh_quantization, Draco and meshopt
//   compression are refused with an error).
// - Errors (file and model part named): unreadable or truncated files, bad
//   JSON, missing or short buffers, accessors reaching past their buffer
//   views, indices out of range, non-finite vertices or transforms, cycles
//   in the node graph, more than kMaxTriangles unique triangles or
//   kMaxInstances placements, files larger than
//   kMaxFileBytes, no emitter.
//
// Emitters (one sim::Emitter each; several per model are fine)
// - EXT_lights_ies: a point with a measured profile read from the light's
//   `uri` (relative to the model, or a data URI) or `bufferView` (mimeType
//   "application/x-ies-lm-63"). A `.ldt` uri, or the mimeType
//   "application/x-eulumdat", is read as EULUMDAT. The node's `multiplier`
//   scales the flux; its `color` is ignored (photometry is luminous) with an
//   info finding. Orientation as the extension defines it: the profile's
//   (0°, 0°) is the node's −Z, C0 its +X, C90 its +Y (see io/model/gltf_lights.h);
//   Types B and A use photometry/angles.h's frames about the same axes (Type
//   A, optional in the extension, with a warning). Scale is removed; a
//   mirroring node transform cannot mirror a profile (warning). TILT data in
//   a profile is not applied (info). Each profile is read once and shared by
//   every node that uses it; the reader's own warnings are passed on.
// - KHR_lights_punctual: point lights are isotropic, Φ = 4πI; spot lights get
//   a rotational Type C profile with the extension's smooth falloff and its
//   exact flux (io/model/gltf_lights.h). Directional lights are not parts of a
//   luminaire: ignored with a warning. `range` and `color` are ignored. A
//   spot light must carry its `spot` object: tinygltf 2.7 refuses one
//   without it (the extension would default the cones).
// - Emissive materials (emissiveFactor × KHR_materials_emissive_strength
//   read as luminance L in cd/m², or extras.gonio.luminance_cd_m2): every
//   emissive primitive is a Lambertian area emitter with Φ = π·L·A, from the
//   front side, or both sides (2π·L·A) when the material is doubleSided.
//
// Flux of an emitter [lm], the first that applies:
//   1. the node's  "extras": {"gonio": {"flux_lm": Φ}}  — the flux of the
//      light on that node, or the total of the node's emissive primitives
//      (split in proportion to their π·L·A);
//   2. the light's "extras": {"gonio": {"flux_lm": Φ}}  (KHR light, or an
//      EXT_lights_ies profile entry) — times the node's multiplier;
//   3. what the file says photometrically: 4πI, the spot's closed form, the
//      profile's integrated flux times the multiplier, π·L·A.
//
// Model-level extras, on the default scene, else on `asset`:
//   "extras": {"gonio": {
//     "frame": {"up": [x, y, z], "c0": [x, y, z]},  // luminaire's photometric
//              // frame in glTF world coordinates (before unit_m); default:
//              // up +Y, C0 +X, so nadir −Y and C90 −Z (photometry/frame.h)
//     "unit_m": 0.001                               // metres per model unit
//   }}
// Materials: io/model/gltf_material.h (mapping and `extras.gonio` of materials).
//
// Unknown keys inside any `extras.gonio` are warnings (a typo must not pass
// silently); `extras` outside `gonio` belong to others and are left alone.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/scene.h"

namespace gonio::io {

inline constexpr std::size_t kMaxFileBytes = std::size_t{512} << 20;  // model, buffer or profile
inline constexpr std::size_t kMaxTriangles = 16'000'000;              // whole scene, unique
inline constexpr std::size_t kMaxInstances = 16'000'000;              // placements of instanced meshes

struct GltfLoadOptions {
  // Whether file references (buffer, image and light-profile uris, and an IES
  // profile's TILT=<file>) may leave the model's folder. By default an
  // absolute path, a `..` that climbs out of the folder, or a symbolic link
  // resolving outside it is an error naming the model and the uri, before
  // the file is opened (`--allow-outside-paths` on the command line).
  bool allow_outside_paths = false;
  // Whether a mesh placed more than once (by several nodes, or by
  // EXT_mesh_gpu_instancing) is kept once and placed by instances
  // (sim::Instance); false flattens every copy into world geometry
  // (sim::flattened), as Gonio did before instancing.
  bool instancing = true;
  // Whether a model without an emitter is an error ("nothing would shine");
  // false for a part placed in a design file (design/fixed_part.h), whose
  // light comes from the design.
  bool require_emitters = true;
};

// Loads a .gltf or .glb luminaire model. Findings (warnings, notes about what
// was ignored or assumed) are appended to `findings` when it is not null;
// anything that makes the model unusable is the returned Error, naming the
// file and the part of the model (node, mesh, primitive, accessor, light).
Result<sim::SceneDesc> load_gltf(const std::string& path, std::vector<Finding>* findings,
                                 const GltfLoadOptions& options = {});

}  // namespace gonio::io
