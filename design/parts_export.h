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
#include "photometry/diagnostics.h"

namespace gonio::design {

// Adds a mesh and node per part other than the reflectors of `parts` to
// `w`; `material` gives the glTF material index of a design material's name.
Status write_other_parts_gltf(const Design& design, const DesignParts& parts, const io::CadTessellation& tessellation,
                              io::GltfWriter& w, const std::function<Result<int>(const std::string&)>& material);

// Ok where the design has nothing the STEP export does not write yet;
// else the error naming the first such part's line (troughs, covers and
// fixed parts go to glTF only so far).
Status step_export_supported(const Design& design, const DesignParts& parts);

}  // namespace gonio::design
