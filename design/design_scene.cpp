#include "design/design_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>

#include "design/table_reader.h"
#include "io/model/parts_file.h"
#include "io/support/text.h"
#include "photometry/error_at.h"
#include "photometry/format.h"

namespace gonio::design {
namespace {

using io::TomlNode;
namespace fs = std::filesystem;

constexpr std::size_t kMaxPartTriangles = 16'000'000;  // as a glTF scene's (io::kMaxTriangles)

class PartsReader : public TableReader {
 public:
  using TableReader::TableReader;

  // `table`: the array of tables it sits in, as messages name it.
  Result<Reflector> reflector(const TomlNode& t, const std::string& table = "reflectors") const;
};

Result<Reflector> PartsReader::reflector(const TomlNode& t, const std::string& table) const {
  const std::string what = "[[" + table + "]] at line " + std::to_string(t.line);
  Reflector r;
  r.line = t.line;
  Result<std::string> name = string(t, "name", what);
  if (!name.ok()) return name.error();
  r.name = *name;
  if (r.name.empty() || r.name.find_first_of("*?[]/\\") != std::string::npos)
    return make_error(path_, t.get("name")->line, what + ": 'name' must be non-empty, without * ? [ ] / \\");
  Result<std::string> material = string(t, "material", what);
  if (!material.ok()) return material.error();
  r.material = *material;
  Result<std::string> kind = string(t, "profile", what);
  if (!kind.ok()) return kind.error();
  const int profile_line = t.get("profile")->line;
  if (*kind == "conic") {
    if (Status s = keys(t, {"name", "material", "profile", "radius", "conic", "aspheric", "vertex", "aperture"}, what);
        !s.ok())
      return s.error();
    ConicProfile c;
    Result<std::optional<double>> radius = number(t, "radius", what);
    if (!radius.ok()) return radius.error();
    Result<std::optional<double>> conic = number(t, "conic", what);
    if (!conic.ok()) return conic.error();
    Result<std::optional<double>> vertex = number(t, "vertex", what);
    if (!vertex.ok()) return vertex.error();
    Result<std::vector<double>> aspheric = numbers(t, "aspheric", what, false);
    if (!aspheric.ok()) return aspheric.error();
    Result<std::vector<double>> aperture = numbers(t, "aperture", what, true);
    if (!aperture.ok()) return aperture.error();
    if (aperture->size() != 2)
      return make_error(path_, t.get("aperture")->line, what + ": 'aperture' must be [inner, outer], ρ from the axis");
    c.radius = radius->value_or(0.0) * unit_;
    c.conic = conic->value_or(0.0);
    c.vertex = vertex->value_or(0.0) * unit_;
    c.inner = (*aperture)[0] * unit_;
    c.outer = (*aperture)[1] * unit_;
    // a_{2i} multiplies ρ^{2i}: in metres, a·unit^(1−2i).
    for (std::size_t i = 0; i < aspheric->size(); ++i)
      c.aspheric.push_back((*aspheric)[i] * std::pow(unit_, 1.0 - 2.0 * static_cast<double>(i + 2)));
    r.profile = c;
  } else if (*kind == "polar") {
    if (Status s = keys(t, {"name", "material", "profile", "theta_deg", "r"}, what); !s.ok()) return s.error();
    Result<PolarProfile> p = polar(t, what);
    if (!p.ok()) return p.error();
    r.profile = *p;
  } else if (*kind == "bspline") {
    if (Status s = keys(t, {"name", "material", "profile", "degree", "points"}, what); !s.ok()) return s.error();
    BSplineProfile b;
    Result<int> degree = this->degree(t, what, 3);
    if (!degree.ok()) return degree.error();
    b.degree = *degree;
    if (Status st = points(t, what, b); !st.ok()) return st.error();
    r.profile = b;
  } else {
    return make_error(path_, profile_line,
                      what + ": profile " + io::shown(*kind) + " is not one Gonio knows (conic, polar, bspline)");
  }
  Result<ProfileCurve> curve = ProfileCurve::make(r.profile);
  if (!curve.ok()) return make_error(path_, profile_line, what + " (" + r.name + "): " + curve.error().message);
  return r;
}

// A reflector with its facets, where it has them (design/facets.h).
Result<Reflector> read_faceted_reflector(const PartsReader& reader, const TomlNode& t, const std::string& path,
                                         double unit_m) {
  const TomlNode* facets = t.get("facets");
  if (!facets) return reader.reflector(t);
  TomlNode smooth = t;
  std::erase_if(smooth.table, [](const io::TomlMember& m) { return m.first == "facets"; });
  Result<Reflector> r = reader.reflector(smooth);
  if (!r.ok()) return r;
  Result<Facets> f = read_facets(*facets, path, "[[reflectors]] at line " + std::to_string(t.line), unit_m);
  if (!f.ok()) return f.error();
  r->facets = *f;
  return r;
}

// The line of the part already named `name` (reflectors, troughs), or 0.
int line_of_name(const DesignParts& parts, const std::string& name) {
  for (const Reflector& r : parts.reflectors)
    if (r.name == name) return r.line;
  for (const Trough& t : parts.troughs)
    if (t.name == name || (!t.caps.empty() && t.name + " caps" == name)) return t.line;
  for (const Cover& c : parts.covers)
    if (c.name == name) return c.line;
  for (const FixedPart& f : parts.fixed_parts)
    if (f.name == name) return f.line;
  for (const Lens& l : parts.lenses)
    if (l.name == name) return l.line;
  return 0;
}

// The part kinds beside the reflectors: [[troughs]] (design/trough.h).
Status read_other_parts(const TomlNode& resolved, const std::string& path, DesignParts& out) {
  if (const TomlNode* r = resolved.get("troughs")) {
    if (!r->is_array_of_tables()) return make_error(path, r->line, "'troughs' must be an array of tables ([[troughs]])");
    for (const TomlNode& t : r->array) {
      Result<Trough> one = read_trough(t, path, out.unit_m);
      if (!one.ok()) return one.error();
      for (const std::string& name : {one->name, one->name + " caps"})
        if (const int other = line_of_name(out, name))
          return make_error(path, t.line, "[[troughs]] at line " + std::to_string(t.line) + ": the name " + io::shown(name) +
                                              " is taken by the part at line " + std::to_string(other));
      out.troughs.push_back(std::move(*one));
    }
  }
  if (const TomlNode* r = resolved.get("covers")) {
    if (!r->is_array_of_tables()) return make_error(path, r->line, "'covers' must be an array of tables ([[covers]])");
    for (const TomlNode& t : r->array) {
      Result<Cover> one = read_cover(t, path, out.unit_m);
      if (!one.ok()) return one.error();
      if (const int other = line_of_name(out, one->name))
        return make_error(path, t.line, "[[covers]] at line " + std::to_string(t.line) + ": the name " + io::shown(one->name) +
                                            " is taken by the part at line " + std::to_string(other));
      out.covers.push_back(std::move(*one));
    }
  }
  if (const TomlNode* r = resolved.get("parts"); r && r->is_array())
    for (const TomlNode& t : r->array) {
      if (!is_fixed_part(t)) continue;  // a rule of the sidecar's
      Result<FixedPart> one = read_fixed_part(t, path, out.unit_m);
      if (!one.ok()) return one.error();
      if (const int other = line_of_name(out, one->name))
        return make_error(path, t.line, "[[parts]] at line " + std::to_string(t.line) + ": the name " + io::shown(one->name) +
                                            " is taken by the part at line " + std::to_string(other));
      out.fixed_parts.push_back(std::move(*one));
    }
  return Ok{};
}

// One part of the design placed once where the file puts it, named `name`,
// given `material` by a rule.
void add_design_part(io::CadModel& model, io::PartsFile& sidecar, const std::string& name, const std::string& material,
                     int line, io::CadSurface surface, double size_m, double chordal_m) {
  io::CadPart part;
  part.name = name;
  part.size_m = size_m;
  part.chordal_m = chordal_m;
  part.surfaces.push_back(std::move(surface));
  io::CadPlacement placement;
  placement.part = static_cast<std::uint32_t>(model.parts.size());
  placement.path = name;
  model.parts.push_back(std::move(part));
  model.placements.push_back(std::move(placement));
  io::PartsRule rule;
  rule.match = name;
  rule.material = material;
  rule.line = line;
  sidecar.rules.push_back(std::move(rule));
}

// The troughs tessellated into `model`, each an emitter's distance from its surface checked.
Status add_troughs(const DesignParts& parts, const std::string& path, const io::CadTessellation& tess,
                   io::PartsFile& sidecar, io::CadModel& model) {
  for (const Trough& t : parts.troughs) {
    const std::string what = "[[troughs]] at line " + std::to_string(t.line) + " (" + t.name + ")";
    for (const auto& [material, line] : {std::pair{t.material, t.line}, std::pair{t.caps, t.caps_line}})
      if (!material.empty() && !sidecar.material(material))
        return make_error(path, line, what + ": material " + io::shown(material) + " is not defined ([materials." + material + "])");
    Result<TroughMesh> mesh = tessellate_trough(t, tess, kMaxPartTriangles);
    if (!mesh.ok()) return make_error(path, t.line, what + ": " + mesh.error().message);
    for (const io::PartsEmitter& e : sidecar.emitters) {
      if (!e.at.empty() || !e.position) continue;
      const double d = distance_to_trough(t, *e.position * parts.unit_m);
      if (d <= mesh->chordal_m)
        return make_error(path, t.line, what + ": the profile passes through the emitter " + io::shown(e.name) + " (line " +
                                            std::to_string(e.line) + "; " + format_number(d * 1e3) +
                                            " mm from it, within the chordal deflection " + format_number(mesh->chordal_m * 1e3) + " mm)");
    }
    add_design_part(model, sidecar, t.name, t.material, t.line, std::move(mesh->reflector), mesh->size_m, mesh->chordal_m);
    if (mesh->caps)
      add_design_part(model, sidecar, t.name + " caps", t.caps, t.caps_line, std::move(*mesh->caps), mesh->size_m,
                      mesh->chordal_m);
  }
  return Ok{};
}

// The covers meshed into `model`: solids of their thickness where their
// material is a volume's, sheets otherwise (design/cover.h).
Status add_covers(const DesignParts& parts, const std::string& path, const io::CadTessellation& tess,
                  io::PartsFile& sidecar, io::CadModel& model) {
  for (const Cover& c : parts.covers) {
    const std::string what = "[[covers]] at line " + std::to_string(c.line) + " (" + c.name + ")";
    const io::PartsMaterial* material = sidecar.material(c.material);
    if (!material)
      return make_error(path, c.line, what + ": material " + io::shown(c.material) + " is not defined ([materials." + c.material + "])");
    double preset_thickness = 0.0;
    Result<bool> volume = is_volume_material(*material, path, &preset_thickness);
    if (!volume.ok()) return volume.error();
    double thickness = 0.0;
    if (*volume) {
      thickness = c.thickness.value_or(preset_thickness);
      if (!(thickness > 0.0))
        return make_error(path, c.line, what + ": material " + io::shown(c.material) +
                                            " is a volume (a dielectric or a medium): give the cover a 'thickness'");
    } else if (c.thickness) {
      return make_error(path, c.thickness_line, what + ": material " + io::shown(c.material) +
                                                    " is a thin sheet's (one surface): a 'thickness' would mean nothing");
    }
    Result<CoverMesh> mesh = tessellate_cover(c, thickness, tess, kMaxPartTriangles);
    if (!mesh.ok()) return make_error(path, c.line, what + ": " + mesh.error().message);
    for (const io::PartsEmitter& e : sidecar.emitters)
      if (e.at.empty() && e.position && cover_holds(c, thickness, mesh->chordal_m, *e.position * parts.unit_m))
        return make_error(path, c.line, what + ": the emitter " + io::shown(e.name) + " (line " + std::to_string(e.line) +
                                            ") lies " + (thickness > 0.0 ? "inside the cover's solid" : "on the cover"));
    add_design_part(model, sidecar, c.name, c.material, c.line, std::move(mesh->surface), mesh->size_m, mesh->chordal_m);
  }
  return Ok{};
}

// [[lenses]] (design/lens.h), their names unique among all parts.
Status read_lenses(const TomlNode& resolved, const std::string& path, DesignParts& out) {
  const TomlNode* l = resolved.get("lenses");
  if (!l) return Ok{};
  if (!l->is_array_of_tables()) return make_error(path, l->line, "'lenses' must be an array of tables ([[lenses]])");
  for (const TomlNode& t : l->array) {
    Result<Lens> one = read_lens(t, path, out.unit_m);
    if (!one.ok()) return one.error();
    if (const int other = line_of_name(out, one->name))
      return make_error(path, t.line, "[[lenses]] at line " + std::to_string(t.line) + ": the name " + io::shown(one->name) +
                                          " is taken by the part at line " + std::to_string(other));
    out.lenses.push_back(std::move(*one));
  }
  return Ok{};
}

// A lens as a placed part with its material's rule; an emitter on its
// surfaces or inside its glass is an error.
Status add_lens(const Lens& lens, const std::string& path, const io::CadLoadOptions& options, double unit_m,
                io::PartsFile& sidecar, io::CadModel& model) {
  const std::string what = "[[lenses]] at line " + std::to_string(lens.line) + " (" + lens.name + ")";
  if (!sidecar.material(lens.material))
    return make_error(path, lens.line, what + ": material " + io::shown(lens.material) + " is not defined ([materials." +
                                           lens.material + "])");
  Result<io::CadPart> part = lens_part(lens, options.tessellation, kMaxPartTriangles);
  if (!part.ok()) return make_error(path, lens.line, what + ": " + part.error().message);
  for (const io::PartsEmitter& e : sidecar.emitters) {
    if (!e.at.empty() || !e.position) continue;
    const std::string problem = lens_emitter_problem(lens, *e.position * unit_m, part->chordal_m);
    if (!problem.empty())
      return make_error(path, lens.line, what + ": emitter " + io::shown(e.name) + " (line " + std::to_string(e.line) +
                                             "): " + problem);
  }
  io::CadPlacement placement;
  placement.part = static_cast<std::uint32_t>(model.parts.size());
  placement.path = lens.name;
  model.parts.push_back(std::move(*part));
  model.placements.push_back(std::move(placement));
  io::PartsRule rule;
  rule.match = lens.name;
  rule.material = lens.material;
  rule.line = lens.line;
  sidecar.rules.push_back(std::move(rule));
  return Ok{};
}

}  // namespace

Result<Reflector> read_profile_part(const TomlNode& t, const std::string& path, double unit_m, const std::string& table) {
  return PartsReader(path, unit_m).reflector(t, table);
}

const std::vector<std::string>& design_root_keys() {
  static const std::vector<std::string> keys = {"length_unit", "materials", "emitters", "reflectors", "lenses",
                                                "troughs",     "covers",    "parts",    "merit",      "tolerances"};
  return keys;
}

Result<DesignParts> read_design_parts(const TomlNode& resolved, const std::string& path) {
  DesignParts out;
  if (const TomlNode* u = resolved.get("length_unit")) {
    const std::optional<double> m = u->is_string() ? io::length_unit_m(u->string) : std::nullopt;
    if (!m) return make_error(path, u->line, "length_unit must be a unit Gonio knows (mm, cm, m, in, ft, µm)");
    out.unit_m = *m;
  }
  PartsReader reader(path, out.unit_m);
  if (const TomlNode* r = resolved.get("reflectors")) {
    if (!r->is_array_of_tables()) return make_error(path, r->line, "'reflectors' must be an array of tables ([[reflectors]])");
    for (const TomlNode& t : r->array) {
      Result<Reflector> one = read_faceted_reflector(reader, t, path, out.unit_m);
      if (!one.ok()) return one.error();
      for (const Reflector& other : out.reflectors)
        if (other.name == one->name)
          return make_error(path, t.line, "[[reflectors]] at line " + std::to_string(t.line) + ": the name " +
                                              io::shown(one->name) + " is taken by the reflector at line " +
                                              std::to_string(other.line));
      out.reflectors.push_back(std::move(*one));
    }
  }
  if (Status s = read_lenses(resolved, path, out); !s.ok()) return s.error();
  if (Status s = read_other_parts(resolved, path, out); !s.ok()) return s.error();
  if (out.reflectors.empty() && out.lenses.empty() && out.troughs.empty() && out.covers.empty() && out.fixed_parts.empty())
    return make_error(path, 0, "the design has no parts: add [[reflectors]], [[lenses]], [[troughs]], [[covers]] or [[parts]]");
  return out;
}

Result<sim::SceneDesc> design_scene(const Design& design, const io::CadLoadOptions& options,
                                    std::vector<Finding>* findings, io::CadLoadInfo* info) {
  const auto start = std::chrono::steady_clock::now();
  const TomlNode resolved = resolved_document(design);
  Result<io::PartsFile> sidecar =
      io::parse_parts_tree(sidecar_tree(resolved), design.path, design_root_keys(), "the design file");
  if (!sidecar.ok()) return sidecar.error();
  Result<DesignParts> parts = read_design_parts(resolved, design.path);
  if (!parts.ok()) return parts.error();
  sidecar->length_unit_m = parts->unit_m;

  io::CadModel model;
  model.format = "Gonio design";
  model.file_unit = "m";
  model.file_unit_m = 1.0;
  model.tessellation = options.tessellation;
  for (const Reflector& r : parts->reflectors) {
    if (!sidecar->material(r.material))
      return make_error(design.path, r.line, "[[reflectors]] at line " + std::to_string(r.line) + ": material " +
                                                 io::shown(r.material) + " is not defined ([materials." + r.material + "])");
    Result<ProfileCurve> curve = ProfileCurve::make(r.profile);
    if (!curve.ok()) return make_error(design.path, r.line, curve.error().message);
    io::CadPart part;
    part.name = r.name;
    Result<io::CadSurface> meshed =
        r.facets ? revolve_faceted(*curve, *r.facets, options.tessellation, kMaxPartTriangles, &part.size_m, &part.chordal_m)
                 : revolve(*curve, options.tessellation, kMaxPartTriangles, &part.size_m, &part.chordal_m);
    if (!meshed.ok())  // at the facet entry's line where it names one (a radius too small)
      return make_error(design.path, meshed.error().where.line > 0 ? meshed.error().where.line : r.line,
                        "[[reflectors]] at line " + std::to_string(r.line) + " (" + r.name + "): " + meshed.error().message);
    io::CadSurface surface = std::move(*meshed);
    // An emitter on the profile (within the chordal deflection) would sit on the mesh's either side.
    for (const io::PartsEmitter& e : sidecar->emitters) {
      if (!e.at.empty() || !e.position) continue;
      const Vec3 p = *e.position * parts->unit_m;
      const double d = distance_to_profile(*curve, std::hypot(p.x, p.y), p.z);
      if (d <= part.chordal_m)
        return make_error(design.path, r.line,
                          "[[reflectors]] at line " + std::to_string(r.line) + " (" + r.name + "): the profile passes through the emitter " +
                              io::shown(e.name) + " (line " + std::to_string(e.line) + "; " + format_number(d * 1e3) +
                              " mm from it, within the chordal deflection " + format_number(part.chordal_m * 1e3) + " mm)");
    }
    part.surfaces.push_back(std::move(surface));
    io::CadPlacement placement;
    placement.part = static_cast<std::uint32_t>(model.parts.size());
    placement.path = r.name;
    model.parts.push_back(std::move(part));
    model.placements.push_back(std::move(placement));
    io::PartsRule rule;
    rule.match = r.name;
    rule.material = r.material;
    rule.line = r.line;
    sidecar->rules.push_back(std::move(rule));
  }
  for (const Lens& lens : parts->lenses)
    if (Status s = add_lens(lens, design.path, options, parts->unit_m, *sidecar, model); !s.ok()) return s.error();
  if (Status s = add_troughs(*parts, design.path, options.tessellation, *sidecar, model); !s.ok()) return s.error();
  if (Status s = add_covers(*parts, design.path, options.tessellation, *sidecar, model); !s.ok()) return s.error();
  for (const FixedPart& f : parts->fixed_parts)
    if (Status s = add_fixed_part(f, design.path, options, *sidecar, model, findings); !s.ok()) return s.error();
  const double tessellate_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Result<sim::SceneDesc> scene = io::cad_scene(model, *sidecar, design.path, options, findings, info);
  if (scene.ok() && info) {
    info->format = model.format;
    info->file_unit = parts->unit_m == 1e-3 ? "mm" : format_number(parts->unit_m) + " m";
    info->tessellation = options.tessellation;
    info->parts = model.parts.size();
    info->placements = model.placements.size();
    info->unique_triangles = model.unique_triangle_count();
    info->placed_triangles = model.placed_triangle_count();
    info->from_cache = false;
    info->tessellate_s = tessellate_s;
  }
  return scene;
}

Result<sim::SceneDesc> load_design(const std::string& path, const io::CadLoadOptions& options,
                                   std::vector<Finding>* findings, io::CadLoadInfo* info) {
  Result<Design> design = read_design_file(path);
  if (!design.ok()) return design.error();
  return design_scene(*design, options, findings, info);
}

std::vector<std::string> design_files(const std::string& path) {
  std::vector<std::string> files = {path};
  Result<Design> design = read_design_file(path);
  if (!design.ok()) return files;
  const TomlNode resolved = resolved_document(*design);
  Result<io::PartsFile> sidecar = io::parse_parts_tree(sidecar_tree(resolved), path, design_root_keys(), "the design file");
  if (!sidecar.ok()) return files;
  const fs::path dir = fs::path(path).parent_path();
  if (Result<DesignParts> parts = read_design_parts(resolved, path); parts.ok())
    for (const FixedPart& f : parts->fixed_parts) {
      const std::string file = (dir / f.file).lexically_normal().string();
      if (std::find(files.begin(), files.end(), file) == files.end()) files.push_back(file);
    }
  for (const io::PartsEmitter& e : sidecar->emitters)
    for (const std::string* reference : {&e.profile, &e.ray_file}) {
      if (reference->empty()) continue;
      const std::string file = (dir / *reference).lexically_normal().string();
      if (std::find(files.begin(), files.end(), file) == files.end()) files.push_back(file);
    }
  return files;
}

}  // namespace gonio::design
