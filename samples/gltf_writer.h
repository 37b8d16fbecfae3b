// The samples' glTF writing (internal to gonio_samples_lib): the writer is
// io/model/gltf_writer.h, shared with design files' parts.
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "io/model/gltf_writer.h"
#include "samples/luminaires.h"
#include "sim/scene.h"

namespace gonio::samples {

using GltfWriter = io::GltfWriter;

// The sample `name`: name.gltf, its buffer name.bin, and `extra` files.
inline Sample finish(const std::string& name, GltfWriter& w, std::vector<SampleFile> extra = {}) {
  Sample s;
  s.name = name;
  s.model = name + ".gltf";
  std::string bin;
  const std::string text = w.finish(name + ".bin", bin);
  s.files.push_back({s.model, text});
  s.files.push_back({name + ".bin", bin});
  for (SampleFile& f : extra) s.files.push_back(std::move(f));
  return s;
}

inline nlohmann::json pbr(double base, double metallic, double roughness) {
  return {{"baseColorFactor", {base, base, base, 1.0}},
          {"metallicFactor", metallic},
          {"roughnessFactor", roughness}};
}

// Quaternion (x, y, z, w) of a right-handed turn about +X: −90° turns a
// light's −Z (where KHR spots and EXT_lights_ies profiles point) to −Y.
inline nlohmann::json about_x(double angle_rad) {
  return {std::sin(angle_rad / 2), 0.0, 0.0, std::cos(angle_rad / 2)};
}

}  // namespace gonio::samples
