// Gonio's material library: named presets an engineer picks by name
// (glTF extras.gonio.preset, and the CAD sidecar's material names), each
// with the datasheet values it stands for and where they come from
// (docs/materials.md lists them). Where no maker's figure was found, the
// preset says "assumed" and why.
//
// Volume presets (opal and satin sheet) are scattering media for closed
// parts of the stated thickness: their (μs, μa) were fitted once to the
// datasheet values with sim::fit_volume (sim/bsdfs/slab.h) and are stored
// here; tests/sim/bsdfs/library_test.cpp traces the stored media again and
// checks that they give the datasheet values back.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sim/scene.h"

namespace gonio::sim {

struct MaterialPreset {
  std::string name;       // the name to use, e.g. "opal PC 3 mm"
  std::string datasheet;  // the values it stands for, in words
  std::string source;     // where they come from (or "assumed: ...")
  Material material;      // named `name`
  // Volume presets: the datasheet values the medium was fitted to (0 where
  // not used) and the thickness of the sheet [m].
  double transmittance = 0.0, haze = 0.0, half_value_deg = 0.0, thickness_m = 0.0;
};

const std::vector<MaterialPreset>& material_library();
// The preset of that name (exact, case-sensitive); nullptr if none.
const MaterialPreset* find_preset(std::string_view name);

}  // namespace gonio::sim
