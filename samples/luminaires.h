// The sample luminaires (samples/<name>/README.md describes each): built from
// the mesh builders (sim/shapes.h) and written as glTF 2.0 with
// nlohmann::json directly — an independent writer for the loader to be
// tested against. Everything is deterministic: the same bytes on every run.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/scene.h"
#include "sim/shapes.h"

namespace gonio::samples {

struct SampleFile {
  std::string name;   // file name inside the sample's folder
  std::string bytes;  // contents
};

struct Sample {
  std::string name;               // folder name: bell, downlight, spotlight, led-array
  std::string model;              // the .gltf file among `files`
  std::vector<SampleFile> files;  // the .gltf, its .bin and any profiles
};

// The four samples: bell, downlight, spotlight, led-array.
std::vector<Sample> make_samples();

// The bell's shade: its lathe profile, walked from the rim (Ø 400 mm at
// y = −250 mm) up to the top opening, so that its front faces outwards.
std::vector<sim::ProfilePoint> bell_shade_profile();

// The bell with a volume diffuser (the materials study's (b), issue 32; the
// next-event study's "bell-volume"): `bell`, the bell sample as loaded, with
// its shade (the mesh whose name holds "shade") replaced by a closed shell of
// the library's "opal PMMA 3 mm" — the shade's profile and the same profile
// offset inwards by the preset's thickness, one closed lathe of 96 segments.
// Empty where `bell` has no shade mesh.
std::optional<sim::SceneDesc> bell_with_volume_shade(const sim::SceneDesc& bell);

// Writes every sample to <dir>/<name>/<file> atomically, creating folders.
Status write_samples(const std::string& dir);

}  // namespace gonio::samples
