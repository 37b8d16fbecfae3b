#include "io/model/cad.h"

#include <signal.h>
#include <string.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <set>

#include "io/model/gltf.h"
#include "io/model/gltf_files.h"
#include "io/materials/bsdf_file.h"
#include "io/model/gltf_material.h"
#include "io/model/material_extras.h"
#include "io/model/parts_file.h"
#include "io/photometric/photometric_file.h"
#include "io/photometric/tm25.h"
#include "io/support/cache_folder.h"
#include "io/support/content_hash.h"
#include "io/support/file_io.h"
#include "io/support/process.h"
#include "io/support/text.h"
#include "photometry/error_at.h"
#include "photometry/flux.h"
#include "photometry/format.h"

#ifndef GONIO_CAD_HELPER_BUILD_PATH
#define GONIO_CAD_HELPER_BUILD_PATH ""
#endif
#ifndef GONIO_OCCT_VERSION
#define GONIO_OCCT_VERSION ""
#endif

namespace gonio::io {
namespace {

namespace fs = std::filesystem;

constexpr const char* kHelperName = "gonio-cad";

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

Result<std::string> find_helper(const std::string& model) {
  std::string tried;
  for (const std::string& p : beside_executable(kHelperName, GONIO_CAD_HELPER_BUILD_PATH)) {
    std::error_code ec;
    if (fs::is_regular_file(p, ec)) return p;
    tried += (tried.empty() ? "" : ", ") + p;
  }
  return make_error(model, std::string("the CAD reader ") + kHelperName + " (OpenCASCADE) is missing; looked for " +
                               tried);
}

// The helper program: the options' one, else the one that comes with gonio.
Result<std::string> helper_for(const std::string& path, const CadLoadOptions& options) {
  if (!options.helper.empty()) return options.helper;
  return find_helper(path);
}

std::uint64_t cache_key(std::string_view bytes, const CadTessellation& t) {
  ContentHash h;
  h.text("gonio-cad");
  h.value(kCadModelFormat);
  h.value(kCadReaderRevision);
  h.text(GONIO_OCCT_VERSION);  // another OpenCASCADE may mesh otherwise
  h.value(t.angular_deflection_deg);
  h.value(t.chordal_relative);
  h.value(t.chordal_min_m);
  h.value(t.chordal_m);
  h.value(t.exact_normals);
  h.bytes(bytes.data(), bytes.size());
  return h.digest();
}

bool same_tessellation(const CadTessellation& a, const CadTessellation& b) {
  return a.angular_deflection_deg == b.angular_deflection_deg && a.chordal_relative == b.chordal_relative &&
         a.chordal_min_m == b.chordal_min_m && a.chordal_m == b.chordal_m && a.exact_normals == b.exact_normals;
}

std::string colour_text(const sim::Vec3f& c) {
  auto byte = [](float v) { return static_cast<int>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  char out[8];
  std::snprintf(out, sizeof out, "#%02x%02x%02x", byte(c.x), byte(c.y), byte(c.z));
  return out;
}

bool colour_matches(const Vec3& rule, const sim::Vec3f& c) {
  auto byte = [](double v) { return std::lround(std::clamp(v, 0.0, 1.0) * 255.0); };
  return byte(rule.x) == byte(static_cast<double>(c.x)) && byte(rule.y) == byte(static_cast<double>(c.y)) &&
         byte(rule.z) == byte(static_cast<double>(c.z));
}

std::string last_component(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// Whether a glob names this placement: a pattern with '/' against the
// whole path, one without against the last component and the product.
bool names_placement(const std::string& pattern, const std::string& path, const std::string& product) {
  if (pattern.find('/') != std::string::npos) return glob_match(pattern, path);
  return glob_match(pattern, last_component(path)) || (!product.empty() && glob_match(pattern, product));
}

// One surface of one placement, as the rules see it.
struct SurfaceFacts {
  const std::string* path;
  const std::string* product;
  std::optional<sim::Vec3f> colour;
  std::vector<std::string> layers;
};

bool rule_matches(const PartsRule& r, const SurfaceFacts& f) {
  if (!r.match.empty() && !names_placement(r.match, *f.path, *f.product)) return false;
  if (r.colour && !(f.colour && colour_matches(*r.colour, *f.colour))) return false;
  if (!r.layer.empty() &&
      std::none_of(f.layers.begin(), f.layers.end(), [&](const std::string& l) { return glob_match(r.layer, l); }))
    return false;
  return true;
}

double world_area(const sim::Mesh& mesh, const sim::Affine* to_world) {
  double area = 0.0;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    Vec3 p[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = sim::to_double(mesh.positions[mesh.indices[t + static_cast<std::size_t>(k)]]);
      if (to_world) p[k] = to_world->point(p[k]);
    }
    area += 0.5 * length(cross(p[1] - p[0], p[2] - p[0]));
  }
  return area;
}

class SceneBuilder {
 public:
  SceneBuilder(const CadModel& model, std::string model_path, const CadLoadOptions& options,
               std::vector<Finding>& findings, const PartsFile* given = nullptr)
      : model_(model), model_path_(std::move(model_path)), options_(options), findings_(findings), given_(given) {}

  Result<sim::SceneDesc> build(CadLoadInfo* info);

 private:
  Error fail(std::string message) const { return make_error(model_path_, std::move(message)); }
  Error fail_sidecar(int line, std::string message) const;
  Status read_sidecar();
  Status add_materials();
  Status assign();
  Status add_geometry();
  Status add_point_emitter(const PartsEmitter& e);
  Result<std::string> sidecar_file(const std::string& reference, const std::string& what) const;

  const CadModel& model_;
  std::string model_path_;
  const CadLoadOptions& options_;
  std::vector<Finding>& findings_;
  const PartsFile* given_;  // the sidecar, read already (a design file's); null: read it
  PartsFile parts_;
  bool has_sidecar_ = false;
  double unit_m_ = 0.001;  // metres per unit of the sidecar's coordinates
  sim::SceneDesc scene_;
  std::map<std::string, std::uint32_t> material_ids_;
  std::vector<double> luminance_;                  // per scene material [cd/m²]
  std::vector<sim::EmitterSpectrum> emitted_;      // per scene material
  // material_of_[placement][surface]: the scene material.
  std::vector<std::vector<std::uint32_t>> material_of_;
};

Error SceneBuilder::fail_sidecar(int line, std::string message) const {
  return make_error(parts_.path, line, std::move(message));
}

Status SceneBuilder::read_sidecar() {
  if (given_) {
    parts_ = *given_;
    has_sidecar_ = true;
    return Ok{};
  }
  const std::string path = options_.parts_file.empty() ? default_parts_path(model_path_) : options_.parts_file;
  std::error_code ec;
  if (options_.parts_file.empty() && !fs::exists(path, ec)) {
    parts_.path = path;
    return Ok{};
  }
  Result<PartsFile> p = read_parts_file(path);
  if (!p.ok()) return p.error();
  parts_ = std::move(*p);
  has_sidecar_ = true;
  return Ok{};
}

Status SceneBuilder::add_materials() {
  for (const PartsMaterial& m : parts_.materials) {
    const std::string what = "material '" + m.name + "'";
    const SourceLoc where{parts_.path, m.line, 0};
    Result<MaterialExtras> read = read_material_extras(m.extras, where, what, findings_);
    if (!read.ok()) return read.error();
    MaterialExtras& x = *read;
    if (!x.has_lobe_weights() && !x.has_datasheet() && !x.luminance_cd_m2 && !x.preset && !x.bsdf_file &&
        !x.abg_reflect && !x.abg_transmit)
      return fail_sidecar(m.line, what + ": says neither how it scatters (lobe weights kd, ks, mirror, dielectric, "
                                 "diffuse_transmit, datasheet values reflectance, transmittance, a preset, abg "
                                 "or a bsdf_file) nor what it emits (luminance_cd_m2)");
    // A measured BSDF beside the sidecar, as its profiles and ray files are.
    std::shared_ptr<const sim::TabulatedBsdf> table;
    if (x.bsdf_file) {
      Result<std::string> bsdf_path = sidecar_file(*x.bsdf_file, what + " bsdf_file");
      if (!bsdf_path.ok()) return bsdf_path.error();
      Result<std::shared_ptr<const sim::TabulatedBsdf>> t = read_bsdf_file(*bsdf_path, findings_);
      if (!t.ok()) return Error{t.error().where, what + ": bsdf_file: " + t.error().message};
      table = std::move(*t);
    }
    // No glTF factors behind a sidecar material: a black, non-metallic
    // surface without a specular coat, which the extras then define.
    GltfMaterial base;
    base.name = m.name;
    base.base_color = {0.0, 0.0, 0.0};
    base.metallic = 0.0;
    base.specular = 0.0;
    Result<sim::Material> mapped = map_material(base, x, where, what, findings_, std::move(table));
    if (!mapped.ok()) return mapped.error();
    material_ids_[m.name] = static_cast<std::uint32_t>(scene_.materials.size());
    scene_.materials.push_back(std::move(*mapped));
    luminance_.push_back(x.luminance_cd_m2.value_or(0.0));
    emitted_.push_back(std::move(x.spectrum));
  }
  return Ok{};
}

Status SceneBuilder::assign() {
  struct Uncovered {
    std::string path;
    std::string detail;
  };
  std::vector<Uncovered> uncovered;
  std::vector<char> rule_used(parts_.rules.size(), 0);
  material_of_.resize(model_.placements.size());
  for (std::size_t pi = 0; pi < model_.placements.size(); ++pi) {
    const CadPlacement& pl = model_.placements[pi];
    const CadPart& part = model_.parts[pl.part];
    SurfaceFacts facts{&pl.path, &part.name, std::nullopt, pl.layers};
    facts.layers.insert(facts.layers.end(), part.layers.begin(), part.layers.end());
    for (std::size_t si = 0; si < part.surfaces.size(); ++si) {
      const CadSurface& s = part.surfaces[si];
      facts.colour = s.colour ? s.colour : pl.colour ? pl.colour : part.colour;
      std::optional<std::uint32_t> id;
      for (std::size_t r = 0; r < parts_.rules.size() && !id; ++r)
        if (rule_matches(parts_.rules[r], facts)) {
          id = material_ids_.at(parts_.rules[r].material);
          rule_used[r] = 1;
        }
      if (!id && !parts_.default_material.empty()) id = material_ids_.at(parts_.default_material);
      if (!id) {
        std::string detail;
        if (!part.name.empty() && part.name != last_component(pl.path)) detail += "part " + shown(part.name);
        if (facts.colour) detail += (detail.empty() ? "" : ", ") + std::string("colour ") + colour_text(*facts.colour);
        for (const std::string& l : facts.layers) detail += (detail.empty() ? "" : ", ") + std::string("layer ") + shown(l);
        if (uncovered.empty() || uncovered.back().path != pl.path || uncovered.back().detail != detail)
          uncovered.push_back({pl.path, detail});
        id = 0;
      }
      material_of_[pi].push_back(*id);
    }
  }
  for (std::size_t r = 0; r < parts_.rules.size(); ++r)
    if (!rule_used[r])
      findings_.push_back({Severity::Warning, "cad-rule-unused",
                           "[[parts]] rule at line " + std::to_string(parts_.rules[r].line) +
                               " covers no surface of the model",
                           {parts_.path, parts_.rules[r].line, 0}});
  if (uncovered.empty()) return Ok{};
  std::string list;
  const std::size_t shown_max = 40;
  for (std::size_t i = 0; i < uncovered.size() && i < shown_max; ++i)
    list += "\n  " + uncovered[i].path + (uncovered[i].detail.empty() ? "" : " (" + uncovered[i].detail + ")");
  if (uncovered.size() > shown_max) list += "\n  … and " + std::to_string(uncovered.size() - shown_max) + " more";
  const std::string why =
      has_sidecar_ ? "no [[parts]] rule of " + parts_.path + " covers them and it names no default_material"
                   : "there is no sidecar " + parts_.path + " (or --parts FILE) to say what they are made of";
  return fail(std::to_string(uncovered.size()) + " part placement(s) have no material: " + why + ":" + list);
}

Status SceneBuilder::add_geometry() {
  for (std::size_t part_index = 0; part_index < model_.parts.size(); ++part_index) {
    const CadPart& part = model_.parts[part_index];
    // Placements of this part, grouped by the materials their surfaces take.
    std::map<std::vector<std::uint32_t>, std::vector<std::size_t>> groups;
    for (std::size_t pi = 0; pi < model_.placements.size(); ++pi)
      if (model_.placements[pi].part == part_index) groups[material_of_[pi]].push_back(pi);
    for (const auto& [materials, placements] : groups) {
      const bool instanced = options_.instancing && placements.size() > 1;
      for (std::size_t si = 0; si < part.surfaces.size(); ++si) {
        const CadSurface& s = part.surfaces[si];
        if (s.indices.empty()) continue;
        sim::Mesh mesh;
        mesh.positions = s.positions;
        mesh.normals = s.normals;
        mesh.indices = s.indices;
        mesh.material = materials[si];
        const std::string suffix = part.surfaces.size() > 1 ? "/" + std::to_string(si) : std::string();
        const bool emits = luminance_[mesh.material] > 0.0;
        if (instanced) {
          mesh.instanced = true;
          mesh.name = (part.name.empty() ? last_component(model_.placements[placements.front()].path) : part.name) + suffix;
          const auto mesh_id = static_cast<std::uint32_t>(scene_.meshes.size());
          for (std::size_t pi : placements) {
            const CadPlacement& pl = model_.placements[pi];
            if (std::abs(pl.to_world.determinant()) < 1e-30) {
              findings_.push_back({Severity::Warning, "cad-singular-placement",
                                   "'" + pl.path + "': its placement is singular; left out", {model_path_}});
              continue;
            }
            const auto instance_id = static_cast<std::uint32_t>(scene_.instances.size());
            scene_.instances.push_back({mesh_id, pl.to_world, pl.path + suffix});
            if (emits) {
              sim::Emitter e;
              e.kind = sim::Emitter::Kind::Area;
              e.name = pl.path + suffix;
              e.mesh = mesh_id;
              e.instance = instance_id;
              e.flux_lm = std::numbers::pi * luminance_[mesh.material] * world_area(mesh, &pl.to_world);
              e.spectrum = emitted_[mesh.material];
              scene_.emitters.push_back(std::move(e));
            }
          }
          scene_.meshes.push_back(std::move(mesh));
        } else {
          for (std::size_t pi : placements) {
            const CadPlacement& pl = model_.placements[pi];
            sim::Mesh world = mesh;
            world.name = pl.path + suffix;
            sim::transform(world, pl.to_world);
            if (emits) {
              sim::Emitter e;
              e.kind = sim::Emitter::Kind::Area;
              e.name = world.name;
              e.mesh = static_cast<std::uint32_t>(scene_.meshes.size());
              e.flux_lm = std::numbers::pi * luminance_[world.material] * world_area(world, nullptr);
              e.spectrum = emitted_[world.material];
              scene_.emitters.push_back(std::move(e));
            }
            scene_.meshes.push_back(std::move(world));
          }
        }
      }
    }
  }
  return Ok{};
}

Result<std::string> SceneBuilder::sidecar_file(const std::string& reference, const std::string& what) const {
  const std::string dir = fs::absolute(fs::path(parts_.path)).parent_path().lexically_normal().string();
  if (!options_.allow_outside_paths)
    if (std::optional<std::string> why = outside_the_folder(dir, reference))
      return fail_sidecar(0, outside_message(what + " " + shown(reference), *why));
  return (fs::path(dir) / reference).string();
}

Status SceneBuilder::add_point_emitter(const PartsEmitter& e) {
  const std::string what = "[[emitters]] at line " + std::to_string(e.line);
  // Where: every placement `at` names, or the file's frame.
  std::vector<const CadPlacement*> at;
  if (!e.at.empty()) {
    for (const CadPlacement& pl : model_.placements)
      if (names_placement(e.at, pl.path, model_.parts[pl.part].name)) at.push_back(&pl);
    if (at.empty()) return fail_sidecar(e.line, what + ": 'at' = " + shown(e.at) + " names no part of the model");
  } else {
    at.push_back(nullptr);
  }

  std::shared_ptr<const photometry::Distribution> profile;
  double profile_flux = 0.0;
  std::optional<Tm25RaySet> rays;
  if (!e.profile.empty()) {
    Result<std::string> file = sidecar_file(e.profile, what + ": profile");
    if (!file.ok()) return file.error();
    Result<PhotometricFile> read = read_photometric_file(*file);
    if (!read.ok()) return fail_sidecar(e.line, what + ": " + to_string(read.error()));
    findings_.insert(findings_.end(), read->findings.begin(), read->findings.end());
    if (Status valid = photometry::validate(read->distribution); !valid.ok())
      return fail_sidecar(e.line, what + ": invalid light profile " + *file + ": " + valid.error().message);
    profile_flux = photometry::total_flux_lm(read->distribution);
    if (!(std::isfinite(profile_flux) && profile_flux > 0.0))
      return fail_sidecar(e.line, what + ": the profile " + *file + " emits no flux");
    profile = std::make_shared<const photometry::Distribution>(std::move(read->distribution));
  }
  if (!e.ray_file.empty()) {
    Result<std::string> file = sidecar_file(e.ray_file, what + ": ray_file");
    if (!file.ok()) return file.error();
    Result<Tm25RaySet> set = read_tm25_file(*file);
    if (!set.ok()) return fail_sidecar(e.line, what + ": " + to_string(set.error()));
    findings_.insert(findings_.end(), set->findings.begin(), set->findings.end());
    if (!e.flux_lm && !set->has_luminous_flux())
      return fail_sidecar(e.line, what + ": the rays carry radiant flux only and the file does not state both "
                                         "total fluxes; give flux_lm");
    rays = std::move(*set);
  }
  Result<sim::EmitterSpectrum> spectrum = e.spectrum.is_null()
                                              ? Result<sim::EmitterSpectrum>(sim::EmitterSpectrum{})
                                              : read_emitter_spectrum(e.spectrum, {parts_.path, e.line, 0}, what);
  if (!spectrum.ok()) return spectrum.error();

  for (const CadPlacement* pl : at) {
    // The emitter's frame → world [m]: the part's axes, or the file's.
    sim::Affine place = pl ? pl->to_world : sim::Affine{};
    const Vec3 offset = e.position.value_or(Vec3{}) * unit_m_;
    const Vec3 origin = place.point(offset);
    auto direction = [&](const Vec3& local) { return normalize(place.linear(local)); };
    Vec3 nadir, c0;
    if (pl) {
      nadir = direction(e.nadir.value_or(Vec3{0, 0, -1}));
      c0 = direction(e.c0.value_or(Vec3{1, 0, 0}));
    } else {
      nadir = e.nadir ? normalize(*e.nadir) : scene_.frame.up * -1.0;
      c0 = e.c0 ? normalize(*e.c0) : scene_.frame.c0;
    }
    if (!(std::isfinite(nadir.x) && std::isfinite(c0.x)) || length(cross(nadir, c0)) < 1e-3)
      return fail_sidecar(e.line, what + ": nadir and c0 are parallel (or collapsed by the part's placement)");
    const std::string name = e.name + (pl && at.size() > 1 ? " @ " + pl->path : std::string());
    sim::Emitter out;
    out.name = name;
    out.spectrum = *spectrum;
    if (rays) {
      auto set = std::make_shared<sim::RaySet>();
      const std::size_t n = rays->ray_count();
      const sim::Affine to_world = place * sim::translation(offset);
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3 d = to_world.linear(rays->direction(i));
        const double len = length(d);
        if (!(len > 0.0)) return fail_sidecar(e.line, what + ": the part's placement collapses the rays' directions");
        set->position_m.push_back(sim::to_float(to_world.point(rays->position_mm(i) * 1e-3)));
        set->direction.push_back(sim::to_float(d / len));
        set->flux_lm.push_back(static_cast<float>(rays->has_luminous_flux() ? rays->luminous_flux_lm(i)
                                                                            : rays->radiant_flux_w(i)));
      }
      out.kind = sim::Emitter::Kind::RaySet;
      out.position = origin;
      out.flux_lm = e.flux_lm ? *e.flux_lm : rays->total_luminous_flux_lm();
      out.rays = std::move(set);
    } else {
      out.kind = sim::Emitter::Kind::Point;
      out.position = origin;
      out.frame = photometry::make_frame(nadir * -1.0, c0);
      out.profile = profile;
      out.flux_lm = e.flux_lm ? *e.flux_lm : profile_flux;
    }
    scene_.emitters.push_back(std::move(out));
  }
  return Ok{};
}

Result<sim::SceneDesc> SceneBuilder::build(CadLoadInfo* info) {
  scene_.name = fs::path(model_path_).filename().string();
  for (const Finding& f : model_.findings) findings_.push_back(f);
  if (Status s = read_sidecar(); !s.ok()) return s.error();

  std::optional<double> file_unit = length_unit_m(model_.file_unit);
  if (!file_unit) {
    findings_.push_back({Severity::Warning, "cad-unknown-unit",
                         "the file's length unit " + shown(model_.file_unit) +
                             " is not one Gonio knows: the sidecar's coordinates are read as millimetres "
                             "(set length_unit there)",
                         {model_path_}});
    file_unit = 0.001;
  }
  unit_m_ = parts_.length_unit_m.value_or(*file_unit);
  scene_.frame = photometry::make_frame(parts_.frame_up.value_or(Vec3{0, 0, 1}), parts_.frame_c0.value_or(Vec3{1, 0, 0}));

  if (Status s = add_materials(); !s.ok()) return s.error();
  if (Status s = assign(); !s.ok()) return s.error();
  if (Status s = add_geometry(); !s.ok()) return s.error();
  for (const PartsEmitter& e : parts_.emitters)
    if (Status s = add_point_emitter(e); !s.ok()) return s.error();
  if (scene_.emitters.empty())
    return has_sidecar_ ? fail_sidecar(0, "no emitter: add [[emitters]], or a material with luminance_cd_m2")
                        : fail("no emitter (and no sidecar " + parts_.path + ")");
  if (scene_.unique_triangle_count() > kMaxTriangles)
    return fail("more than " + std::to_string(kMaxTriangles) + " triangles: coarsen the tessellation");

  if (info) {
    info->parts_file = has_sidecar_ ? parts_.path : std::string();
    info->per_part.clear();
    for (const CadPart& p : model_.parts) info->per_part.push_back({p.name, p.triangle_count(), 0, p.size_m, p.chordal_m});
    for (const CadPlacement& p : model_.placements) ++info->per_part[p.part].placements;
  }
  return std::move(scene_);
}

}  // namespace

bool is_cad_path(const std::string& path) {
  const std::string ext = lower(fs::path(path).extension().string());
  return ext == ".step" || ext == ".stp" || ext == ".p21" || ext == ".iges" || ext == ".igs";
}

bool cad_supported() {
#ifdef GONIO_WITH_OCCT
  return true;
#else
  return false;
#endif
}

CadTessellation tessellation_for_grid(double gamma_step_deg) {
  CadTessellation t;
  t.angular_deflection_deg = std::clamp(kDeflectionPerGammaStep * gamma_step_deg, 0.05, 20.0);
  return t;
}

Result<CadTessellation> parse_tessellation(const std::string& text, CadTessellation base) {
  auto number = [](const std::string& s, double& out) {
    char* end = nullptr;
    out = std::strtod(s.c_str(), &end);
    return !s.empty() && end == s.c_str() + s.size() && std::isfinite(out);
  };
  const std::size_t comma = text.find(',');
  double deg = 0.0, mm = 0.0;
  if (!number(text.substr(0, comma), deg) || !(deg > 0.0 && deg <= 90.0) ||
      (comma != std::string::npos && (!number(text.substr(comma + 1), mm) || !(mm > 0.0))))
    return make_error("--tessellation " + shown(text) +
                      ": give the angular deflection in degrees (0 < DEG ≤ 90), optionally ',MM', an absolute "
                      "chordal deflection in millimetres (> 0)");
  base.angular_deflection_deg = deg;
  if (comma != std::string::npos) base.chordal_m = mm * 1e-3;
  return base;
}

std::string default_parts_path(const std::string& model) {
  const fs::path p(model);
  return (p.parent_path() / (p.stem().string() + ".gonio.toml")).string();
}

std::vector<std::string> cad_files(const std::string& model, const std::string& parts_file) {
  std::vector<std::string> files = {model, parts_file.empty() ? default_parts_path(model) : parts_file};
  Result<PartsFile> parts = read_parts_file(files[1]);
  if (!parts.ok()) return files;
  const fs::path dir = fs::path(files[1]).parent_path();
  for (const PartsEmitter& e : parts->emitters)
    for (const std::string* reference : {&e.profile, &e.ray_file}) {
      if (reference->empty()) continue;
      const std::string path = (dir / *reference).lexically_normal().string();
      if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
    }
  return files;
}

Result<CadModel> tessellate_cad(const std::string& path, const CadLoadOptions& options, CadLoadInfo* info) {
  const auto start = std::chrono::steady_clock::now();
  if (!cad_supported() && options.helper.empty())
    return make_error(path, "this gonio was built without OpenCASCADE (GONIO_OCCT off or not found), so it "
                            "cannot read STEP or IGES models; export the model as glTF (.glb), or build with "
                            "libocct-data-exchange-dev installed");
  Result<std::string> bytes = read_file(path, kMaxFileBytes);
  if (!bytes.ok()) return bytes.error();
  if (bytes->empty()) return make_error(path, "empty file");
  const std::uint64_t key = cache_key(*bytes, options.tessellation);
  const std::string entry =
      options.cache_dir.empty() ? std::string() : (fs::path(options.cache_dir) / cache_entry_name(CacheEntry::CadModel, key)).string();

  auto done = [&](CadModel m, bool cached) -> Result<CadModel> {
    if (info) {
      info->format = m.format;
      info->file_unit = m.file_unit;
      info->tessellation = m.tessellation;
      info->parts = m.parts.size();
      info->placements = m.placements.size();
      info->unique_triangles = m.unique_triangle_count();
      info->placed_triangles = m.placed_triangle_count();
      info->from_cache = cached;
      info->tessellate_s = seconds_since(start);
    }
    return m;
  };

  std::error_code ec;
  if (!entry.empty() && fs::is_regular_file(entry, ec)) {
    Result<std::string> cached = read_file(entry, std::size_t{4} << 30);
    if (cached.ok()) {
      Result<CadModel> m = parse_cad_model(*cached, entry);
      if (m.ok() && same_tessellation(m->tessellation, options.tessellation)) {
        mark_cache_entry_used(entry);
        return done(std::move(*m), true);
      }
    }
  }

  Result<std::string> helper = helper_for(path, options);
  if (!helper.ok()) return helper.error();
  ScratchDir scratch("gonio-cad");
  if (scratch.path().empty()) return make_error(path, "cannot create a scratch folder for the CAD reader");
  const std::string out = (scratch.path() / "model.bin").string();
  const std::string err = (scratch.path() / "error.txt").string();
  const CadTessellation& t = options.tessellation;
  const std::vector<std::string> argv = {*helper,
                                         fs::absolute(path).string(),
                                         out,
                                         err,
                                         format_number(t.angular_deflection_deg, 17),
                                         format_number(t.chordal_relative, 17),
                                         format_number(t.chordal_min_m, 17),
                                         format_number(t.chordal_m, 17),
                                         t.exact_normals ? "1" : "0"};
  Result<ProcessOutput> run = run_program(argv, options.time_limit, std::size_t{1} << 20,
                                          "the CAD reader that comes with gonio");
  if (!run.ok()) {
    if (run.error().message.find("did not finish") != std::string::npos)
      return make_error(path, "OpenCASCADE did not finish reading and meshing the model within " +
                                  std::to_string(options.time_limit.count()) +
                                  " s (stopped); a damaged file, or a model that needs a coarser --tessellation");
    return make_error(path, run.error().message);
  }
  if (run->signal != 0) {
    const char* name = ::sigabbrev_np(run->signal);
    return make_error(path, "OpenCASCADE crashed reading the model (signal " + std::to_string(run->signal) +
                                (name ? std::string(", SIG") + name : std::string()) +
                                "), which a malformed file can make it do; nothing was read");
  }
  if (run->exit_code != 0) {
    Result<std::string> message = read_file(err, std::size_t{1} << 20);
    std::string text = message.ok() ? *message : std::string();
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    if (text.empty()) text = "the CAD reader failed (exit " + std::to_string(run->exit_code) + "): " + last_lines(run->err, 400);
    return make_error(path, text);
  }
  Result<std::string> produced = read_file(out, std::size_t{4} << 30);
  if (!produced.ok()) return make_error(path, "the CAD reader wrote no model: " + produced.error().message);
  Result<CadModel> m = parse_cad_model(*produced, out);
  if (!m.ok()) return make_error(path, to_string(m.error()));
  for (Finding& f : m->findings)
    if (f.where.file.empty() || f.where.file == fs::absolute(path).string()) f.where.file = path;
  if (!entry.empty()) {
    // The cache is a saving, not a duty: a folder that cannot be written is no error.
    if (make_directories(options.cache_dir).ok()) (void)write_file_atomic(entry, *produced);
  }
  return done(std::move(*m), false);
}

Result<sim::SceneDesc> cad_scene(const CadModel& model, const std::string& model_path, const CadLoadOptions& options,
                                 std::vector<Finding>* findings, CadLoadInfo* info) {
  std::vector<Finding> local;
  SceneBuilder builder(model, model_path, options, findings ? *findings : local);
  return builder.build(info);
}

Result<sim::SceneDesc> cad_scene(const CadModel& model, const PartsFile& parts, const std::string& model_path,
                                 const CadLoadOptions& options, std::vector<Finding>* findings, CadLoadInfo* info) {
  std::vector<Finding> local;
  SceneBuilder builder(model, model_path, options, findings ? *findings : local, &parts);
  return builder.build(info);
}

Result<sim::SceneDesc> load_cad(const std::string& path, const CadLoadOptions& options,
                                std::vector<Finding>* findings, CadLoadInfo* info) {
  Result<CadModel> model = tessellate_cad(path, options, info);
  if (!model.ok()) return model.error();
  return cad_scene(*model, path, options, findings, info);
}

Result<double> export_step(const StepExport& request, const std::string& path, const CadLoadOptions& options) {
  if (!cad_supported() && options.helper.empty())
    return make_error(path, "this gonio was built without OpenCASCADE (GONIO_OCCT off or not found), so it "
                            "cannot write STEP; the glTF export is there");
  Result<std::string> helper = helper_for(path, options);
  if (!helper.ok()) return helper.error();
  ScratchDir scratch("gonio-cad");
  if (scratch.path().empty()) return make_error(path, "cannot create a scratch folder for the STEP writer");
  const std::string in = (scratch.path() / "request.txt").string();
  const std::string out = (scratch.path() / "model.step").string();
  const std::string err = (scratch.path() / "error.txt").string();
  if (Status s = write_file_atomic(in, serialize_step_export(request)); !s.ok()) return s.error();
  Result<ProcessOutput> run = run_program({*helper, "--write-step", in, out, err}, options.time_limit,
                                          std::size_t{1} << 20, "the CAD helper that comes with gonio");
  if (!run.ok()) return make_error(path, run.error().message);
  if (run->signal != 0)
    return make_error(path, "OpenCASCADE crashed writing STEP (signal " + std::to_string(run->signal) + ")");
  if (run->exit_code != 0) {
    Result<std::string> message = read_file(err, std::size_t{1} << 20);
    std::string text = message.ok() ? *message : std::string();
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    if (text.empty()) text = "the STEP writer failed (exit " + std::to_string(run->exit_code) + "): " + last_lines(run->err, 400);
    return make_error(path, text);
  }
  Result<std::string> produced = read_file(out, std::size_t{4} << 30);
  if (!produced.ok()) return make_error(path, "the STEP writer wrote nothing: " + produced.error().message);
  char* end = nullptr;
  const double deviation = std::strtod(run->out.c_str(), &end);
  if (end == run->out.c_str()) return make_error(path, "the STEP writer did not say how close its curves are");
  if (Status s = write_file_atomic(path, *produced); !s.ok()) return s.error();
  return deviation;
}

}  // namespace gonio::io
