#include "design/fixed_part.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "io/model/gltf.h"
#include "io/model/gltf_files.h"
#include "io/support/text.h"
#include "photometry/error_at.h"
#include "photometry/format.h"

namespace gonio::design {
namespace {

namespace fs = std::filesystem;

std::string extension(const std::string& file) {
  std::string e = fs::path(file).extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

bool is_gltf(const std::string& file) {
  const std::string e = extension(file);
  return e == ".gltf" || e == ".glb";
}

}  // namespace

bool is_fixed_part(const io::TomlNode& table) { return table.is_table() && table.get("file") != nullptr; }

io::TomlNode sidecar_tree(const io::TomlNode& resolved) {
  io::TomlNode out = resolved;
  if (io::TomlNode* parts = out.get("parts"); parts && parts->is_array()) {
    std::erase_if(parts->array, [](const io::TomlNode& t) { return is_fixed_part(t); });
    if (parts->array.empty()) std::erase_if(out.table, [](const io::TomlMember& m) { return m.first == "parts"; });
  }
  return out;
}

Result<FixedPart> read_fixed_part(const io::TomlNode& t, const std::string& path, double unit_m) {
  const std::string what = "[[parts]] at line " + std::to_string(t.line);
  if (Status s = io::check_keys(t, {"name", "file", "position", "rotate_deg", "scale", "material"}, what, path); !s.ok())
    return s.error();
  FixedPart p;
  p.line = t.line;
  for (auto [key, out] : {std::pair{"name", &p.name}, std::pair{"file", &p.file}, std::pair{"material", &p.material}}) {
    const io::TomlNode* n = t.get(key);
    if (!n) {
      if (std::string(key) == "material") continue;
      return make_error(path, t.line, what + ": '" + key + "' is missing");
    }
    if (!n->is_string() || n->string.empty()) return make_error(path, n->line, what + ": '" + key + "' must be a non-empty string");
    *out = n->string;
  }
  p.file_line = t.get("file")->line;
  if (p.name.find_first_of("*?[]/\\") != std::string::npos)
    return make_error(path, t.get("name")->line, what + ": 'name' must be without * ? [ ] / \\");
  if (!is_gltf(p.file) && !io::is_cad_path(p.file))
    return make_error(path, p.file_line, what + ": file " + io::shown(p.file) +
                                             " is not a model Gonio reads as a part (.gltf, .glb, .step, .stp, .iges, .igs)");
  for (auto [key, out, scale] : {std::tuple{"position", &p.position, unit_m}, std::tuple{"rotate_deg", &p.rotate_deg, 1.0}}) {
    const io::TomlNode* n = t.get(key);
    if (!n) continue;
    const std::optional<std::array<double, 3>> v = n->three_numbers();
    if (!v) return make_error(path, n->line, what + ": '" + key + "' must be an array of three finite numbers");
    *out = Vec3{(*v)[0], (*v)[1], (*v)[2]} * scale;
  }
  if (const io::TomlNode* n = t.get("scale")) {
    const std::optional<double> s = n->number();
    if (!s || !std::isfinite(*s) || !(*s > 0.0)) return make_error(path, n->line, what + ": 'scale' must be a number > 0");
    p.scale = *s;
  }
  return p;
}

sim::Affine fixed_part_transform(const FixedPart& part) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  const sim::Affine turn = sim::rotation(Vec3{0, 0, 1}, part.rotate_deg.z * kDeg) *
                           sim::rotation(Vec3{0, 1, 0}, part.rotate_deg.y * kDeg) *
                           sim::rotation(Vec3{1, 0, 0}, part.rotate_deg.x * kDeg);
  return sim::translation(part.position) * turn * sim::scaling(part.scale, part.scale, part.scale);
}

Status add_fixed_part(const FixedPart& part, const std::string& design_path, const io::CadLoadOptions& options,
                      io::PartsFile& sidecar, io::CadModel& model, std::vector<Finding>* findings) {
  const std::string what = "[[parts]] at line " + std::to_string(part.line) + " (" + part.name + ")";
  const std::string dir = fs::absolute(fs::path(design_path)).parent_path().lexically_normal().string();
  if (!options.allow_outside_paths)
    if (std::optional<std::string> why = io::outside_the_folder(dir, part.file))
      return make_error(design_path, part.file_line, what + ": " + io::outside_message("file " + io::shown(part.file), *why));
  const std::string file = (fs::path(dir) / part.file).string();
  const sim::Affine place = fixed_part_transform(part);
  const auto first_part = static_cast<std::uint32_t>(model.parts.size());
  if (is_gltf(part.file)) {
    io::GltfLoadOptions o;
    o.allow_outside_paths = options.allow_outside_paths;
    o.require_emitters = false;
    std::vector<Finding> local;
    Result<sim::SceneDesc> scene = io::load_gltf(file, findings ? findings : &local, o);
    if (!scene.ok()) return make_error(design_path, part.file_line, what + ": " + to_string(scene.error()));
    if (!scene->emitters.empty() && findings)
      findings->push_back(Finding{Severity::Info, "fixed-part-lights",
                                  what + ": the lights of " + io::shown(part.file) +
                                      " are not used; the design's [[emitters]] are",
                                  {design_path, part.line, 0}});
    // The file's photometric frame onto the design's: rows C0, C90, up.
    sim::Affine frame;
    const Vec3 rows[3] = {scene->frame.c0, scene->frame.c90, scene->frame.up};
    for (int i = 0; i < 3; ++i) {
      frame.m[i][0] = rows[i].x;
      frame.m[i][1] = rows[i].y;
      frame.m[i][2] = rows[i].z;
    }
    const sim::Affine to_design = place * frame;
    for (std::size_t k = 0; k < scene->meshes.size(); ++k) {
      const sim::Mesh& m = scene->meshes[k];
      io::CadPart p;
      p.name = m.name;
      io::CadSurface s;
      s.positions = m.positions;
      s.normals = m.normals;
      s.indices = m.indices;
      p.surfaces.push_back(std::move(s));
      const auto index = static_cast<std::uint32_t>(model.parts.size());
      model.parts.push_back(std::move(p));
      if (!m.instanced) {
        io::CadPlacement pl;
        pl.part = index;
        pl.to_world = to_design;
        pl.path = part.name + "/" + (m.name.empty() ? "mesh" + std::to_string(k) : m.name);
        model.placements.push_back(std::move(pl));
      }
    }
    for (const sim::Instance& i : scene->instances) {
      io::CadPlacement pl;
      pl.part = first_part + i.mesh;
      pl.to_world = to_design * i.to_world;
      pl.path = part.name + "/" + i.name;
      model.placements.push_back(std::move(pl));
    }
  } else {
    io::CadLoadOptions o = options;
    Result<io::CadModel> cad = io::tessellate_cad(file, o);
    if (!cad.ok()) return make_error(design_path, part.file_line, what + ": " + to_string(cad.error()));
    for (io::CadPart& p : cad->parts) model.parts.push_back(std::move(p));
    for (io::CadPlacement& pl : cad->placements) {
      pl.part += first_part;
      pl.to_world = place * pl.to_world;
      pl.path = part.name + "/" + pl.path;
      model.placements.push_back(std::move(pl));
    }
    if (findings)
      for (Finding& f : cad->findings) findings->push_back(std::move(f));
  }
  if (!part.material.empty()) {
    if (!sidecar.material(part.material))
      return make_error(design_path, part.line, what + ": material " + io::shown(part.material) + " is not defined ([materials." +
                                                    part.material + "])");
    io::PartsRule rule;
    rule.match = part.name + "/*";
    rule.material = part.material;
    rule.line = part.line;
    sidecar.rules.push_back(std::move(rule));
  }
  return Ok{};
}

}  // namespace gonio::design
