#include "samples/large_models.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "samples/gltf_writer.h"
#include "sim/shapes.h"

namespace gonio::samples {
namespace {

using nlohmann::json;
constexpr double kPi = std::numbers::pi;

// Rings for a lathe of 2·rings segments and ≈ 4·rings² triangles.
int rings_for(std::size_t triangles) {
  return std::max(4, static_cast<int>(std::lround(std::sqrt(static_cast<double>(triangles) / 4.0))));
}

void point_lamp(GltfWriter& w, double y_m) {
  const int lamp = w.khr_light({{"name", "lamp"}, {"type", "point"}, {"intensity", 1000.0 / (4.0 * kPi)}});
  w.node({{"name", "lamp"}, {"translation", {0.0, y_m, 0.0}},
          {"extensions", {{"KHR_lights_punctual", {{"light", lamp}}}}}});
}

int glass(GltfWriter& w, const char* name, double ior) {
  for (const char* e : {"KHR_materials_transmission", "KHR_materials_ior"}) w.use(e);
  return w.material({{"name", name},
                     {"pbrMetallicRoughness", pbr(1.0, 0.0, 0.0)},
                     {"extensions",
                      {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                       {"KHR_materials_ior", {{"ior", ior}}}}}});
}

Sample faceted_reflector(std::size_t triangles, const std::string& name) {
  GltfWriter w;
  const int aluminium = w.material({{"name", "polished aluminium"}, {"pbrMetallicRoughness", pbr(0.9, 1.0, 0.0)}});
  const int rings = rings_for(triangles);
  // Focus at the origin, f = 20 mm, aperture Ø 200 mm, a 20 mm hole for the
  // lamp; flat facets: no shading normals.
  sim::Mesh reflector = sim::paraboloid(0.020, 0.100, 0.010, rings, 2 * rings);
  reflector.normals.clear();
  reflector.tangents.clear();
  w.node({{"name", "reflector"}, {"mesh", w.mesh(reflector, aluminium, "reflector")}});
  point_lamp(w, 0.0);
  return finish(name, w);
}

Sample lens_array(std::size_t triangles, const std::string& name) {
  GltfWriter w;
  const int pmma = glass(w, "PMMA", 1.49);
  // One lens: a sphere Ø 8 mm squashed to 3.2 mm, 32 × 16 facets, placed
  // on a square grid by EXT_mesh_gpu_instancing (one node, one translation
  // per copy), as CAD exporters write arrays.
  sim::Mesh lens = sim::sphere(0.004, 32, 16);
  sim::transform(lens, sim::scaling(1.0, 0.4, 1.0));
  const int mesh = w.mesh(lens, pmma, "lens");
  const std::size_t copies = std::max<std::size_t>(1, triangles / lens.triangle_count());
  const auto side = static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(copies))));
  const double pitch = 0.010;  // [m]
  const double half = 0.5 * pitch * static_cast<double>(side - 1);
  std::vector<sim::Vec3f> offsets;
  offsets.reserve(copies);
  for (std::size_t k = 0; k < copies; ++k)
    offsets.push_back({static_cast<float>(pitch * static_cast<double>(k % side) - half), 0.0f,
                       static_cast<float>(pitch * static_cast<double>(k / side) - half)});
  w.use("EXT_mesh_gpu_instancing");
  w.node({{"name", "lenses"},
          {"mesh", mesh},
          {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", w.vec3(offsets)}}}}}}}});
  point_lamp(w, 0.010);
  return finish(name, w);
}

Sample glass_part(std::size_t triangles, const std::string& name) {
  GltfWriter w;
  const int crown = glass(w, "crown glass", 1.52);
  const int rings = rings_for(triangles);
  w.node({{"name", "glass"}, {"mesh", w.mesh(sim::sphere(0.050, 2 * rings, rings), crown, "glass")}});
  point_lamp(w, 0.0);
  return finish(name, w);
}

}  // namespace

std::string large_model_name(LargeModel kind) {
  switch (kind) {
    case LargeModel::FacetedReflector: return "faceted-reflector";
    case LargeModel::LensArray: return "lens-array";
    case LargeModel::GlassPart: return "glass-part";
  }
  return "";
}

Sample large_model(LargeModel kind, std::size_t triangles) {
  const std::string name = large_model_name(kind) + "-" + std::to_string(triangles);
  switch (kind) {
    case LargeModel::FacetedReflector: return faceted_reflector(triangles, name);
    case LargeModel::LensArray: return lens_array(triangles, name);
    case LargeModel::GlassPart: return glass_part(triangles, name);
  }
  return {};
}

}  // namespace gonio::samples
