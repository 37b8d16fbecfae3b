#include "design/design_export.h"

#include <cmath>
#include <filesystem>
#include <map>

#include "design/design_scene.h"
#include "design/revolved.h"
#include "io/model/gltf_writer.h"
#include "io/model/parts_file.h"
#include "io/support/file_io.h"

namespace gonio::design {

Status write_design_gltf(const Design& design, const std::string& gltf_path, const io::CadTessellation& tessellation) {
  const io::TomlNode resolved = resolved_document(design);
  Result<io::PartsFile> sidecar = io::parse_parts_tree(resolved, design.path, design_root_keys(), "the design file");
  if (!sidecar.ok()) return sidecar.error();
  Result<DesignParts> parts = read_design_parts(resolved, design.path);
  if (!parts.ok()) return parts.error();

  io::GltfWriter w("Gonio design (gonio design)");
  std::map<std::string, int> materials;
  for (const Reflector& r : parts->reflectors) {
    const io::PartsMaterial* m = sidecar->material(r.material);
    if (!m) return make_error(design.path, "material " + r.material + " is not defined");
    if (!materials.count(r.material))
      materials[r.material] =
          w.material({{"name", r.material},
                      {"pbrMetallicRoughness",
                       {{"baseColorFactor", {0.9, 0.9, 0.9, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.05}}},
                      {"doubleSided", true},
                      {"extras", {{"gonio", m->extras}}}});
    Result<ProfileCurve> curve = ProfileCurve::make(r.profile);
    if (!curve.ok()) return make_error(design.path, curve.error().message);
    Result<io::CadSurface> meshed = revolve(*curve, tessellation, std::size_t{16'000'000});
    if (!meshed.ok()) return make_error(design.path, r.name + ": " + meshed.error().message);
    const io::CadSurface& s = *meshed;
    sim::Mesh mesh;
    // Z-up (the design) to glTF's Y-up: (x, y, z) → (x, z, −y).
    for (const sim::Vec3f& p : s.positions) mesh.positions.push_back({p.x, p.z, -p.y});
    for (const sim::Vec3f& n : s.normals) mesh.normals.push_back({n.x, n.z, -n.y});
    mesh.indices = s.indices;
    const int index = w.mesh(mesh, materials[r.material], r.name);
    w.node({{"name", r.name}, {"mesh", index}});
  }
  // Emitters with a profile in the design's frame: EXT_lights_ies lights,
  // their γ = 0 (the node's −Z) turned to glTF's −Y as the samples do.
  for (const io::PartsEmitter& e : sidecar->emitters) {
    if (e.profile.empty() || !e.at.empty() || e.nadir || e.c0 || !e.spectrum.is_null()) continue;
    const int light = w.ies_light({{"name", e.name}, {"uri", e.profile}});
    const Vec3 p = e.position.value_or(Vec3{}) * parts->unit_m;
    nlohmann::json node = {{"name", e.name},
                           {"translation", {p.x, p.z, -p.y}},
                           {"rotation", {-std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)}},
                           {"extensions", {{"EXT_lights_ies", {{"light", light}}}}}};
    if (e.flux_lm) node["extras"] = {{"gonio", {{"flux_lm", *e.flux_lm}}}};
    w.node(std::move(node));
  }
  const std::filesystem::path path(gltf_path);
  const std::string bin_name = path.stem().string() + ".bin";
  std::string bin;
  const std::string text = w.finish(bin_name, bin);
  if (Status s = io::write_file_atomic((path.parent_path() / bin_name).string(), bin); !s.ok()) return s;
  return io::write_file_atomic(gltf_path, text);
}

}  // namespace gonio::design
