#include "design/parts_export.h"

#include <algorithm>

#include "sim/scene.h"

namespace gonio::design {

Status write_other_parts_gltf(const Design& design, const DesignParts& parts, const io::CadTessellation& tessellation,
                              io::GltfWriter& w, const std::function<Result<int>(const std::string&)>& material) {
  if (parts.troughs.empty() && parts.covers.empty() && parts.fixed_parts.empty()) return Ok{};
  io::CadLoadOptions options;
  options.tessellation = tessellation;
  std::vector<Finding> findings;
  Result<sim::SceneDesc> scene = design_scene(design, options, &findings);
  if (!scene.ok()) return scene.error();
  const sim::SceneDesc flat = sim::flattened(*scene);
  for (const sim::Mesh& m : flat.meshes) {
    const bool reflector = std::any_of(parts.reflectors.begin(), parts.reflectors.end(),
                                       [&](const Reflector& r) { return r.name == m.name; });
    if (reflector || m.material >= flat.materials.size()) continue;
    Result<int> index = material(flat.materials[m.material].name);
    if (!index.ok()) return index.error();
    sim::Mesh out;
    // Z-up (the design) to glTF's Y-up: (x, y, z) → (x, z, −y).
    for (const sim::Vec3f& p : m.positions) out.positions.push_back({p.x, p.z, -p.y});
    for (const sim::Vec3f& n : m.normals) out.normals.push_back({n.x, n.z, -n.y});
    out.indices = m.indices;
    const int mesh = w.mesh(out, *index, m.name);
    w.node({{"name", m.name}, {"mesh", mesh}});
  }
  return Ok{};
}

Status step_export_supported(const Design& design, const DesignParts& parts) {
  auto refuse = [&](const char* kind, int line) {
    return Error{{design.path, line, 0}, std::string(kind) + " at line " + std::to_string(line) +
                                             ": STEP export of this kind is not built yet (the glTF export writes it)"};
  };
  if (!parts.troughs.empty()) return refuse("[[troughs]]", parts.troughs.front().line);
  if (!parts.covers.empty()) return refuse("[[covers]]", parts.covers.front().line);
  if (!parts.fixed_parts.empty()) return refuse("[[parts]]", parts.fixed_parts.front().line);
  for (const Reflector& r : parts.reflectors)
    if (r.facets) return refuse("[[reflectors]]", r.line);
  return Ok{};
}

}  // namespace gonio::design
