// A design's parts written for CAD and viewers: glTF 2.0 (io/model/gltf_writer.h),
// one mesh per part with its exact normals, in glTF's Y-up frame (the design's
// nadir −Z becomes glTF's −Y, Gonio's default for glTF luminaires), each
// material's design-file keys as extras.gonio so that Gonio reads the same
// materials back. Emitters with a profile in the design's own frame (no
// `at`, `nadir`, `c0` or spectrum) become EXT_lights_ies lights naming the
// same profile file (so the glTF beside the design file is a luminaire Gonio
// simulates), `flux_lm` as the node's extras.gonio.flux_lm; others (ray
// files, isotropic, turned or coloured emitters) are left out: the design
// file stays the luminaire's description.
#pragma once

#include <string>

#include "design/design_file.h"
#include "io/model/cad_model.h"
#include "photometry/diagnostics.h"

namespace gonio::design {

// Writes `gltf_path` and its buffer beside it (the same name, .bin), each by
// an atomic write. `tessellation`: as for a run (io::CadTessellation).
Status write_design_gltf(const Design& design, const std::string& gltf_path, const io::CadTessellation& tessellation);

// STEP export (through the helper gonio-cad, io/model/cad.h's export_step):
// each reflector a face of revolution about Z whose meridian is a B-spline
// within `tolerance_mm` of the exact profile sampled at kStepProfileSamples
// points (equal steps of the profile's parameter), named by the part's name,
// in millimetres; and beside it the sidecar that makes it a luminaire for
// `gonio simulate NAME.step`: `<folder>/<stem>.gonio.toml` (io::default_parts_path)
// with the design's length_unit, materials and emitters and a [[parts]] rule
// per part giving its material; the emitters' profile and ray files are
// copied beside the STEP where they are elsewhere (a sidecar's files stay in
// its folder), and named by their file names. All by atomic writes; the
// STEP's folder is made where missing.
// Troughs and covers go into the same STEP and sidecar (design/parts_export.h);
// a design with fixed parts, facets or troughs' caps is refused, naming the
// part's line.
inline constexpr int kStepProfileSamples = 2001;
inline constexpr double kStepToleranceMm = 1e-3;
struct StepExportInfo {
  std::string sidecar;            // the sidecar written
  double max_deviation_mm = 0.0;  // the B-splines' largest distance from the samples
  std::size_t parts = 0;
};
Result<StepExportInfo> write_design_step(const Design& design, const std::string& step_path,
                                         double tolerance_mm = kStepToleranceMm, const std::string& helper = {});

}  // namespace gonio::design
