// A glTF 2.0 writer for models Gonio makes (the samples, the benchmark
// models, design files' parts: design/): a document with one binary buffer,
// written field by field with nlohmann::json — independent of the loader
// (io/model/gltf.h) that reads it back.
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "sim/scene.h"

namespace gonio::io {

// A glTF 2.0 document with one binary buffer, written field by field.
class GltfWriter {
 public:
  using json = nlohmann::json;

  explicit GltfWriter(const std::string& generator = "Gonio sample generator") {
    doc_["asset"] = {{"version", "2.0"}, {"generator", generator}};
    doc_["scene"] = 0;
    doc_["scenes"] = json::array({json{{"nodes", json::array()}}});
    doc_["nodes"] = json::array();
  }

  json& doc() { return doc_; }

  void use(const std::string& extension) {
    json& used = doc_["extensionsUsed"];
    if (std::find(used.begin(), used.end(), extension) == used.end()) used.push_back(extension);
  }

  int material(json m) { return push("materials", std::move(m)); }

  // A mesh with one triangle primitive: positions (with the min/max glTF
  // requires), shading normals and tangents where the shape has them.
  int mesh(const sim::Mesh& m, int material, const std::string& name) {
    json attributes = {{"POSITION", vec3(m.positions, true)}};
    if (!m.normals.empty()) attributes["NORMAL"] = vec3(m.normals, false);
    if (!m.tangents.empty()) attributes["TANGENT"] = tangents(m.tangents);
    json primitive = {{"attributes", attributes},
                      {"indices", indices(m.indices)},
                      {"material", material},
                      {"mode", 4}};
    return push("meshes", json{{"name", name}, {"primitives", json::array({primitive})}});
  }

  int node(json n) {
    const int i = push("nodes", std::move(n));
    doc_["scenes"][0]["nodes"].push_back(i);
    return i;
  }

  int khr_light(json light) {
    use("KHR_lights_punctual");
    json& lights = doc_["extensions"]["KHR_lights_punctual"]["lights"];
    lights.push_back(std::move(light));
    return static_cast<int>(lights.size() - 1);
  }

  int ies_light(json light) {
    use("EXT_lights_ies");
    json& lights = doc_["extensions"]["EXT_lights_ies"]["lights"];
    lights.push_back(std::move(light));
    return static_cast<int>(lights.size() - 1);
  }

  // The .gltf text, its buffer stored in `bin_name`; `bin` receives the bytes.
  std::string finish(const std::string& bin_name, std::string& bin) {
    doc_["buffers"] = json::array({json{{"uri", bin_name}, {"byteLength", bin_.size()}}});
    bin = bin_;
    return doc_.dump(1) + "\n";
  }

  // A float VEC3 accessor without bounds (e.g. EXT_mesh_gpu_instancing's
  // TRANSLATION).
  int vec3(const std::vector<sim::Vec3f>& v) { return vec3(v, false); }

 private:
  int push(const char* key, json value) {
    json& array = doc_[key];
    if (array.is_null()) array = json::array();
    array.push_back(std::move(value));
    return static_cast<int>(array.size() - 1);
  }

  int view(const void* data, std::size_t bytes, int target) {
    while (bin_.size() % 4) bin_.push_back('\0');
    const std::size_t offset = bin_.size();
    bin_.append(static_cast<const char*>(data), bytes);
    return push("bufferViews",
                json{{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}, {"target", target}});
  }

  // glTF binary data is little-endian, as x86-64 and AArch64 store floats.
  int vec3(const std::vector<sim::Vec3f>& v, bool bounds) {
    std::vector<float> flat;
    flat.reserve(3 * v.size());
    std::array<float, 3> lo{v[0].x, v[0].y, v[0].z}, hi = lo;
    for (const sim::Vec3f& p : v) {
      flat.insert(flat.end(), {p.x, p.y, p.z});
      lo = {std::min(lo[0], p.x), std::min(lo[1], p.y), std::min(lo[2], p.z)};
      hi = {std::max(hi[0], p.x), std::max(hi[1], p.y), std::max(hi[2], p.z)};
    }
    json a = {{"bufferView", view(flat.data(), flat.size() * 4, 34962)},
              {"componentType", 5126},
              {"count", v.size()},
              {"type", "VEC3"}};
    if (bounds) {
      a["min"] = {lo[0], lo[1], lo[2]};
      a["max"] = {hi[0], hi[1], hi[2]};
    }
    return push("accessors", std::move(a));
  }

  int tangents(const std::vector<sim::Vec3f>& v) {
    std::vector<float> flat;
    flat.reserve(4 * v.size());
    for (const sim::Vec3f& t : v) flat.insert(flat.end(), {t.x, t.y, t.z, 1.0f});
    return push("accessors", json{{"bufferView", view(flat.data(), flat.size() * 4, 34962)},
                                  {"componentType", 5126},
                                  {"count", v.size()},
                                  {"type", "VEC4"}});
  }

  int indices(const std::vector<std::uint32_t>& idx) {
    return push("accessors", json{{"bufferView", view(idx.data(), idx.size() * 4, 34963)},
                                  {"componentType", 5125},
                                  {"count", idx.size()},
                                  {"type", "SCALAR"}});
  }

  json doc_;
  std::string bin_;
};

}  // namespace gonio::io
