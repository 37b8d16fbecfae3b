#include "design/design_export.h"

#include <cmath>
#include <filesystem>
#include <map>

#include "design/design_scene.h"
#include "design/parts_export.h"
#include "design/revolved.h"
#include "io/model/cad.h"
#include "io/model/gltf_writer.h"
#include "io/model/parts_file.h"
#include "io/model/step_export.h"
#include "io/support/file_io.h"
#include "io/support/text.h"

namespace gonio::design {
namespace {

// A lens as one glTF mesh (its three surfaces, exact normals, glTF's Y-up)
// with its material's keys as extras.gonio.
Status add_lens_gltf(io::GltfWriter& w, const Lens& lens, const io::PartsFile& sidecar, const std::string& path,
                     const io::CadTessellation& tessellation, std::map<std::string, int>& materials) {
  const io::PartsMaterial* m = sidecar.material(lens.material);
  if (!m) return make_error(path, "material " + lens.material + " is not defined");
  if (!materials.count(lens.material))
    materials[lens.material] =
        w.material({{"name", lens.material},
                    {"pbrMetallicRoughness",
                     {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
                    {"extras", {{"gonio", m->extras}}}});
  Result<io::CadPart> part = lens_part(lens, tessellation, std::size_t{16'000'000});
  if (!part.ok()) return make_error(path, lens.name + ": " + part.error().message);
  sim::Mesh mesh;
  for (const io::CadSurface& s : part->surfaces) {
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (const sim::Vec3f& p : s.positions) mesh.positions.push_back({p.x, p.z, -p.y});
    for (const sim::Vec3f& n : s.normals) mesh.normals.push_back({n.x, n.z, -n.y});
    for (std::uint32_t i : s.indices) mesh.indices.push_back(base + i);
  }
  const int index = w.mesh(mesh, materials[lens.material], lens.name);
  w.node({{"name", lens.name}, {"mesh", index}});
  return Ok{};
}

// A lens for STEP: its closed meridian, inner (axis to rim), side, outer
// (rim to axis), each curve sampled at kStepProfileSamples points.
io::StepRevolvedPart lens_step_part(const Lens& lens) {
  const LensCurves c = lens_curves_mm(lens, kStepProfileSamples);
  io::StepRevolvedPart part;
  part.name = lens.name;
  for (std::size_t k = 0; k < c.rho.size(); ++k) {
    const bool reversed = k + 1 == c.rho.size();  // the outer surface, back to the axis
    const std::size_t m = c.rho[k].size();
    if (k > 0) part.curves.push_back(part.rho.size() - 1);
    else part.curves.push_back(0);
    for (std::size_t i = k > 0 ? 1 : 0; i < m; ++i) {
      const std::size_t j = reversed ? m - 1 - i : i;
      part.rho.push_back(c.rho[k][j]);
      part.z.push_back(c.z[k][j]);
    }
  }
  part.rho.back() = 0.0;  // on the axis, as the first point
  if (lens.position != Vec3{0.0, 0.0, 0.0} || lens.rotate_deg != Vec3{0.0, 0.0, 0.0}) {
    const sim::Affine place = lens_transform(lens);  // the helper turns and moves the solid [mm]
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) part.place.push_back(place.m[i][j]);
      part.place.push_back(place.offset[i] * 1e3);
    }
  }
  return part;
}

}  // namespace

Status write_design_gltf(const Design& design, const std::string& gltf_path, const io::CadTessellation& tessellation) {
  const io::TomlNode resolved = resolved_document(design);
  Result<io::PartsFile> sidecar = io::parse_parts_tree(sidecar_tree(resolved), design.path, design_root_keys(), "the design file");
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
    Result<io::CadSurface> meshed = r.facets ? revolve_faceted(*curve, *r.facets, tessellation, std::size_t{16'000'000})
                                             : revolve(*curve, tessellation, std::size_t{16'000'000});
    if (!meshed.ok()) {
      Error e = make_error(design.path, r.name + ": " + meshed.error().message);
      e.where.line = meshed.error().where.line;  // the facet entry's (a radius too small), or none
      return e;
    }
    const io::CadSurface& s = *meshed;
    sim::Mesh mesh;
    // Z-up (the design) to glTF's Y-up: (x, y, z) → (x, z, −y).
    for (const sim::Vec3f& p : s.positions) mesh.positions.push_back({p.x, p.z, -p.y});
    for (const sim::Vec3f& n : s.normals) mesh.normals.push_back({n.x, n.z, -n.y});
    mesh.indices = s.indices;
    const int index = w.mesh(mesh, materials[r.material], r.name);
    w.node({{"name", r.name}, {"mesh", index}});
  }
  for (const Lens& lens : parts->lenses)
    if (Status s = add_lens_gltf(w, lens, *sidecar, design.path, tessellation, materials); !s.ok()) return s;
  // The other part kinds (troughs, covers, fixed parts): design/parts_export.h.
  auto material_index = [&](const std::string& name) -> Result<int> {
    const io::PartsMaterial* m = sidecar->material(name);
    if (!m) return make_error(design.path, "material " + name + " is not defined");
    if (!materials.count(name))
      materials[name] = w.material({{"name", name},
                                    {"pbrMetallicRoughness",
                                     {{"baseColorFactor", {0.9, 0.9, 0.9, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.05}}},
                                    {"doubleSided", true},
                                    {"extras", {{"gonio", m->extras}}}});
    return materials[name];
  };
  if (Status s = write_other_parts_gltf(design, *parts, tessellation, w, material_index); !s.ok()) return s;
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

Result<StepExportInfo> write_design_step(const Design& design, const std::string& step_path, double tolerance_mm,
                                         const std::string& helper) {
  namespace fs = std::filesystem;
  const io::TomlNode resolved = resolved_document(design);
  Result<io::PartsFile> sidecar = io::parse_parts_tree(sidecar_tree(resolved), design.path, design_root_keys(), "the design file");
  if (!sidecar.ok()) return sidecar.error();
  Result<DesignParts> parts = read_design_parts(resolved, design.path);
  if (!parts.ok()) return parts.error();
  if (Status s = step_export_supported(design, *parts); !s.ok()) return s.error();
  if (parts->reflectors.empty() && parts->lenses.empty() && parts->troughs.empty() && parts->covers.empty() &&
      parts->fixed_parts.empty())
    return make_error(design.path, "the design has no parts to write as STEP");

  io::StepExport request;
  request.tolerance_mm = tolerance_mm;
  request.product = std::filesystem::path(step_path).stem().string();
  io::TomlNode rules = toml_array({});
  add_design_rules_to_step(resolved, rules);  // first, as in the simulation
  for (const Reflector& r : parts->reflectors) {
    Result<ProfileCurve> curve = ProfileCurve::make(r.profile);
    if (!curve.ok()) return make_error(design.path, r.name + ": " + curve.error().message);
    io::StepRevolvedPart part;
    part.name = r.name;
    if (r.facets) {
      Result<io::StepRevolvedPart> faceted = faceted_step_part(r, *curve);
      if (!faceted.ok()) {
        Error e = faceted.error();
        e.where = SourceLoc{design.path, e.where.line > 0 ? e.where.line : r.line, 0};
        e.message = "[[reflectors]] at line " + std::to_string(r.line) + " (" + r.name + "): " + e.message;
        return e;
      }
      part = std::move(*faceted);
    }
    for (int i = 0; i < kStepProfileSamples && part.faces.empty() && part.patches.empty(); ++i) {
      const double t = curve->t0() + (curve->t1() - curve->t0()) * i / (kStepProfileSamples - 1);
      double rho = 0.0, z = 0.0, drho = 0.0, dz = 0.0;
      curve->eval(t, rho, z, drho, dz);
      part.rho.push_back(std::max(0.0, rho) * 1e3);
      part.z.push_back(z * 1e3);
    }
    request.parts.push_back(std::move(part));
    io::TomlNode rule = toml_table();
    toml_set(rule, "match", toml_string(r.name));  // names hold no glob characters
    toml_set(rule, "material", toml_string(r.material));
    rules.array.push_back(std::move(rule));
  }
  for (const Lens& lens : parts->lenses) {
    request.parts.push_back(lens_step_part(lens));
    io::TomlNode rule = toml_table();
    toml_set(rule, "match", toml_string(lens.name));
    toml_set(rule, "material", toml_string(lens.material));
    rules.array.push_back(std::move(rule));
  }
  if (Status s = add_troughs_to_step(design, *parts, kStepProfileSamples, request, rules); !s.ok()) return s.error();
  if (Status s = add_covers_to_step(design, *parts, *sidecar, request, rules); !s.ok()) return s.error();
  if (Status s = add_fixed_parts_to_step(design, *parts, *sidecar, request, rules); !s.ok()) return s.error();
  if (const fs::path folder = fs::path(step_path).parent_path(); !folder.empty())
    if (Status s = io::make_directories(folder.string()); !s.ok()) return s.error();
  io::CadLoadOptions options;
  options.helper = helper;
  Result<double> deviation = io::export_step(request, step_path, options);
  if (!deviation.ok()) return deviation.error();

  // The sidecar: the design's own sidecar vocabulary, its parts as rules.
  io::TomlNode doc = toml_table();
  std::map<std::string, std::string> copied;  // target: source
  const fs::path design_dir = fs::absolute(design.path).parent_path();
  const fs::path step_dir = fs::absolute(step_path).parent_path();
  for (const auto& [key, value] : resolved.table) {
    if (key == "reflectors" || key == "lenses" || key == "troughs" || key == "covers") continue;
    io::TomlNode copy = value;
    // The emitters' files: copied beside the STEP where they are elsewhere
    // (a sidecar's paths stay in its folder, as glTF's uris do), by name.
    if (key == "emitters" && copy.is_array())
      for (io::TomlNode& e : copy.array)
        for (const char* file_key : {"profile", "ray_file"}) {
          io::TomlNode* f = e.get(file_key);
          if (!f || !f->is_string() || f->string.empty()) continue;
          const fs::path source = (design_dir / f->string).lexically_normal();
          const fs::path target = step_dir / source.filename();
          std::error_code ec;
          if (!fs::equivalent(source, target, ec)) {
            if (copied.count(target.string()) && copied[target.string()] != source.string())
              return make_error(design.path, "two emitters' files are named " + io::shown(source.filename().string()) +
                                                 "; the STEP's folder can hold one");
            Result<std::string> bytes = io::read_file(source.string(), std::size_t{1} << 30);
            if (!bytes.ok()) return make_error(design.path, "emitter file " + to_string(bytes.error()));
            if (Status s = io::write_file_atomic(target.string(), *bytes); !s.ok()) return s.error();
            copied[target.string()] = source.string();
          }
          f->string = source.filename().string();
        }
    toml_set(doc, key, std::move(copy));
  }
  toml_set(doc, "parts", std::move(rules));
  StepExportInfo info;
  info.sidecar = io::default_parts_path(step_path);
  info.max_deviation_mm = *deviation;
  info.parts = request.parts.size();
  const std::string text =
      write_design(doc, {"The sidecar of " + fs::path(step_path).filename().string() + ", written by gonio from " +
                             fs::path(design.path).filename().string() + " (docs/design.md)."});
  if (Status s = io::write_file_atomic(info.sidecar, text); !s.ok()) return s.error();
  return info;
}

}  // namespace gonio::design
