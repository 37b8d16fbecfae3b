// A design's parts written for CAD and viewers: glTF 2.0 (io/model/gltf_writer.h),
// one mesh per part with its exact normals, in glTF's Y-up frame (the design's
// nadir −Z becomes glTF's −Y, Gonio's default for glTF luminaires), each
// material's design-file keys as extras.gonio so that Gonio reads the same
// materials back. Emitters are not written (glTF's lights cannot say a
// measured profile's flux as the design does): the design file stays the
// luminaire's description.
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
