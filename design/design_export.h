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

}  // namespace gonio::design
