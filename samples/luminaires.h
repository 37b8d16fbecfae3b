// The sample luminaires (samples/<name>/README.md describes each): built from
// the mesh builders (sim/shapes.h) and written as glTF 2.0 with
// nlohmann::json directly — an independent writer for the loader to be
// tested against. Everything is deterministic: the same bytes on every run.
#pragma once

#include <string>
#include <vector>

#include "photometry/diagnostics.h"
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

// Writes every sample to <dir>/<name>/<file> atomically, creating folders.
Status write_samples(const std::string& dir);

}  // namespace gonio::samples
