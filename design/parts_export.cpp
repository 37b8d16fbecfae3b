#include "design/parts_export.h"

#include <algorithm>
#include <cmath>

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
  for (const Trough& t : parts.troughs)
    if (!t.caps.empty()) return refuse("[[troughs]] (its caps)", t.line);
  if (!parts.fixed_parts.empty()) return refuse("[[parts]]", parts.fixed_parts.front().line);
  for (const Reflector& r : parts.reflectors)
    if (r.facets) return refuse("[[reflectors]]", r.line);
  return Ok{};
}

Status add_troughs_to_step(const Design& design, const DesignParts& parts, int samples, io::StepExport& request,
                           io::TomlNode& rules) {
  for (const Trough& t : parts.troughs) {
    Result<ProfileCurve> curve = ProfileCurve::make(t.profile);
    if (!curve.ok()) return make_error(design.path, t.name + ": " + curve.error().message);
    io::StepRevolvedPart half;
    half.name = t.name;
    half.extrude_mm = t.length * 1e3;
    for (int i = 0; i < samples; ++i) {
      const double u = curve->t0() + (curve->t1() - curve->t0()) * i / (samples - 1);
      double rho = 0.0, z = 0.0, drho = 0.0, dz = 0.0;
      curve->eval(u, rho, z, drho, dz);
      half.rho.push_back(rho * 1e3);
      half.z.push_back(z * 1e3);
    }
    std::vector<io::StepRevolvedPart> out;
    if (t.symmetric && std::abs(half.rho.front()) <= 1e-9) {
      io::StepRevolvedPart whole = half;  // −x … 0 … +x, one curve
      whole.rho.clear();
      whole.z.clear();
      for (std::size_t i = half.rho.size(); i-- > 1;) {
        whole.rho.push_back(-half.rho[i]);
        whole.z.push_back(half.z[i]);
      }
      whole.rho.insert(whole.rho.end(), half.rho.begin(), half.rho.end());
      whole.z.insert(whole.z.end(), half.z.begin(), half.z.end());
      out.push_back(std::move(whole));
    } else {
      out.push_back(half);
      if (t.symmetric) {
        io::StepRevolvedPart mirrored = half;
        mirrored.name = t.name + " mirrored";
        for (double& x : mirrored.rho) x = -x;
        out.push_back(std::move(mirrored));
      }
    }
    for (io::StepRevolvedPart& p : out) {
      io::TomlNode rule = toml_table();
      toml_set(rule, "match", toml_string(p.name));
      toml_set(rule, "material", toml_string(t.material));
      rules.array.push_back(std::move(rule));
      request.parts.push_back(std::move(p));
    }
  }
  return Ok{};
}

Status add_covers_to_step(const Design& design, const DesignParts& parts, const io::PartsFile& sidecar,
                          io::StepExport& request, io::TomlNode& rules) {
  for (const Cover& c : parts.covers) {
    const io::PartsMaterial* material = sidecar.material(c.material);
    if (!material) return make_error(design.path, "material " + c.material + " is not defined");
    double preset = 0.0;
    Result<bool> volume = is_volume_material(*material, design.path, &preset);
    if (!volume.ok()) return volume.error();
    io::StepRevolvedPart p;
    p.name = c.name;
    p.cover = c.shape == Cover::Shape::Dome ? "dome" : c.width ? "box" : "disc";
    p.cover_a = (c.width ? *c.width : *c.diameter) * 1e3;
    p.cover_b = (c.shape == Cover::Shape::Dome ? c.sag : c.depth.value_or(0.0)) * 1e3;
    p.cover_t = *volume ? c.thickness.value_or(preset) * 1e3 : 0.0;
    p.cover_z = c.height * 1e3;
    io::TomlNode rule = toml_table();
    toml_set(rule, "match", toml_string(p.name));
    toml_set(rule, "material", toml_string(c.material));
    rules.array.push_back(std::move(rule));
    request.parts.push_back(std::move(p));
  }
  return Ok{};
}

}  // namespace gonio::design
