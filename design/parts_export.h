// Export of the design's part kinds beside the reflectors of revolution
// (design/trough.h, design/cover.h, design/fixed_part.h; design_export.h
// calls it): into the design's glTF, each as the simulation meshes it —
// the same tessellation, positions and exact normals, the fixed parts as
// placed — turned into glTF's Y-up frame as the reflectors are.
#pragma once

#include <functional>
#include <string>

#include "design/design_file.h"
#include "design/design_scene.h"
#include "io/model/cad_model.h"
#include "io/model/gltf_writer.h"
#include "io/model/parts_file.h"
#include "io/model/step_export.h"
#include "photometry/diagnostics.h"

namespace gonio::design {

// Adds a mesh and node per part other than the reflectors of `parts` to
// `w`; `material` gives the glTF material index of a design material's name.
Status write_other_parts_gltf(const Design& design, const DesignParts& parts, const io::CadTessellation& tessellation,
                              io::GltfWriter& w, const std::function<Result<int>(const std::string&)>& material);

// Ok where the design has nothing the STEP export does not write yet;
// else the error naming the first such part's line (every kind is written
// now: kept for the kinds to come).
Status step_export_supported(const Design& design, const DesignParts& parts);

// The troughs as extruded parts of the STEP request (io/model/step_export.h):
// the profile sampled at `samples` equal steps of its parameter [mm], a
// symmetric trough's mirror image joined to it where the profile starts on
// the axis (one face), else its own part "NAME mirrored"; with a sidecar
// rule (match, material) per part added to `rules`. Caps: the part "NAME
// caps", two plane faces at y = ±length/2 through the same samples.
Status add_troughs_to_step(const Design& design, const DesignParts& parts, int samples, io::StepExport& request,
                           io::TomlNode& rules);

// A faceted reflector as one part. Flat both ways (facets.theta,
// facets.azimuth > 0): plane faces through the facets' corners on the exact
// surface [mm], the rows and sectors of design/facets.h. Else (facets one
// way only, or curved): a B-spline patch per facet (design/facets.h's
// FacetSurface, smooth around: four quarter turns per band), fitted by the
// helper within the export's tolerance of a grid of points on the exact
// facet. Errors (no file): a radius too small for a facet, at the radius's
// line.
Result<io::StepRevolvedPart> faceted_step_part(const Reflector& r, const ProfileCurve& curve);

// The covers as parts of the STEP request: OpenCASCADE's primitives (a box,
// a cylinder, a dome turned from its meridian), solids of their thickness
// where their material is a volume's, one face otherwise (design/cover.h),
// named by their names, with a sidecar rule each.
Status add_covers_to_step(const Design& design, const DesignParts& parts, const io::PartsFile& sidecar,
                          io::StepExport& request, io::TomlNode& rules);

// The design's own sidecar rules ([[parts]] tables without `file`, from
// `resolved`) into the STEP's sidecar `rules`, to be added before any part's
// rule: in the simulation they come first (the first rule that matches a
// surface wins, so one may give a reflector another material).
void add_design_rules_to_step(const io::TomlNode& resolved, io::TomlNode& rules);

// The fixed parts (design/fixed_part.h) as parts of the STEP request: a STEP
// or IGES file's shapes placed by the helper as position, rotate_deg and
// scale place them (OpenCASCADE's own shapes, each "NAME/<its name>"); a
// glTF file's triangles, placed as the simulation places them, as plane
// faces sewn into one part per mesh, named as the design names its
// placements ("NAME/<mesh>"). `rules` gets the rule "NAME/*" of a part's
// material (the design's own rules: add_design_rules_to_step). Errors name the part's
// line: a file outside the design's folder, a glTF part of more than
// kMaxFixedPartStepTriangles triangles (OpenCASCADE sews each as a face).
// kMaxStepPartFaces: the most faces the STEP export writes for one part
// (a fixed part's triangles, a faceted reflector's facets).
constexpr std::size_t kMaxStepPartFaces = 20000;
constexpr std::size_t kMaxFixedPartStepTriangles = kMaxStepPartFaces;
Status add_fixed_parts_to_step(const Design& design, const DesignParts& parts, const io::PartsFile& sidecar,
                               io::StepExport& request, io::TomlNode& rules);

}  // namespace gonio::design
