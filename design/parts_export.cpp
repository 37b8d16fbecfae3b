#include "design/parts_export.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <cctype>
#include <filesystem>
#include <optional>

#include "design/facets.h"
#include "design/fixed_part.h"
#include "io/model/gltf_files.h"
#include "io/support/text.h"
#include "photometry/error_at.h"
#include "photometry/format.h"
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
    // Reflectors and lenses are written by write_design_gltf itself.
    const bool reflector = std::any_of(parts.reflectors.begin(), parts.reflectors.end(),
                                       [&](const Reflector& r) { return r.name == m.name; });
    const bool lens =
        std::any_of(parts.lenses.begin(), parts.lenses.end(), [&](const Lens& l) { return l.name == m.name; });
    if (reflector || lens || m.material >= flat.materials.size()) continue;
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

Status step_export_supported(const Design&, const DesignParts&) {
  // Every kind is written now (fixed parts, facets one way only and curved
  // facets since issue 40's second round); a kind to come that the STEP
  // export cannot write refuses here, naming its line.
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
    if (!t.caps.empty()) {
      // The caps close the cross-section between the two halves (or the
      // profile and x = 0): the profile's samples out, their mirror images
      // (or x = 0) back, one plane face at each end.
      // Every 5th sample, 401 a half (a chord's sagitta L²/8R: 0.14 µm on
      // the tests' 80 mm parabolic trough): a polygon of all 2001 took
      // OpenCASCADE minutes to sew and mesh.
      std::vector<double> x, z;
      const std::size_t stride = 5, last = half.rho.size() - 1;
      for (std::size_t i = 0;; i = std::min(i + stride, last)) {
        x.push_back(half.rho[i]);
        z.push_back(half.z[i]);
        if (i == last) break;
      }
      const std::size_t out_count = x.size();
      if (t.symmetric) {
        for (std::size_t i = out_count; i-- > 0;) {
          x.push_back(-x[i]);
          z.push_back(z[i]);
        }
      } else {  // along x = 0: its two ends
        x.insert(x.end(), {0.0, 0.0});
        z.insert(z.end(), {half.z.back(), half.z.front()});
      }
      io::StepRevolvedPart caps;
      caps.name = t.name + " caps";
      for (const double y : {-0.5 * half.extrude_mm, 0.5 * half.extrude_mm}) {
        caps.faces.push_back(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) caps.corners.insert(caps.corners.end(), {x[i], y, z[i]});
      }
      io::TomlNode rule = toml_table();
      toml_set(rule, "match", toml_string(caps.name));
      toml_set(rule, "material", toml_string(t.caps));
      rules.array.push_back(std::move(rule));
      request.parts.push_back(std::move(caps));
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

Result<io::StepRevolvedPart> faceted_step_part(const Reflector& r, const ProfileCurve& curve) {
  io::StepRevolvedPart part;
  part.name = r.name;
  const int n = r.facets->theta, m = r.facets->azimuth;
  // A face per facet (smooth around: four quarter turns a band), each sewn
  // by OpenCASCADE: bounded as a fixed part's triangles are.
  const double faces = static_cast<double>(n > 0 ? n : 1) * static_cast<double>(m > 0 ? m : 4);
  if (faces > static_cast<double>(kMaxStepPartFaces))
    return make_error("facets (line " + std::to_string(r.facets->line) + "): " + format_number(faces, 10) +
                      " faces, more than the " + std::to_string(kMaxStepPartFaces) +
                      " the STEP export writes for one part (OpenCASCADE sews each as a face)");
  if (r.facets->curved || n == 0 || m == 0) {
    Result<FacetSurface> surface = FacetSurface::make(curve, *r.facets);
    if (!surface.ok()) return surface.error();
    // Points along: the whole profile (smooth that way), an arc, or a chord;
    // around: a quarter turn (smooth), an arc across the sector, or its chord.
    const std::size_t nu = n == 0 ? 201 : std::isfinite(r.facets->radius_theta) ? 9 : 5;
    const std::size_t nv = m == 0 ? 17 : std::isfinite(r.facets->radius_azimuth) ? 9 : 5;
    for (int i = 0; i < surface->bands(); ++i)
      for (int j = 0; j < surface->sectors(); ++j) {
        part.patches.insert(part.patches.end(), {nu, nv});
        for (std::size_t a = 0; a < nu; ++a)
          for (std::size_t b = 0; b < nv; ++b) {
            Vec3 p, normal;
            surface->eval(i, j, static_cast<double>(a) / static_cast<double>(nu - 1),
                          static_cast<double>(b) / static_cast<double>(nv - 1), p, normal);
            part.patch_points.insert(part.patch_points.end(), {p.x * 1e3, p.y * 1e3, p.z * 1e3});
          }
      }
    return part;
  }
  std::vector<double> rho, z;
  for (int i = 0; i <= n; ++i) {  // the rows of design/facets.cpp: equal steps of t
    double rr = 0.0, zz = 0.0, dr = 0.0, dz = 0.0;
    curve.eval(curve.t0() + (curve.t1() - curve.t0()) * i / n, rr, zz, dr, dz);
    rho.push_back(std::max(0.0, rr) * 1e3);
    z.push_back(zz * 1e3);
  }
  const double step = 2.0 * std::numbers::pi / m;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double p0 = step * j, p1 = step * (j + 1);
      const auto ii = static_cast<std::size_t>(i);
      part.faces.push_back(4);
      for (const auto& [row, psi] : {std::pair{ii, p0}, std::pair{ii, p1}, std::pair{ii + 1, p1}, std::pair{ii + 1, p0}})
        part.corners.insert(part.corners.end(), {rho[row] * std::cos(psi), rho[row] * std::sin(psi), z[row]});
    }
  return part;
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

void add_design_rules_to_step(const io::TomlNode& resolved, io::TomlNode& rules) {
  if (const io::TomlNode* table = resolved.get("parts"); table && table->is_array())
    for (const io::TomlNode& t : table->array)
      if (!is_fixed_part(t)) rules.array.push_back(t);
}

Status add_fixed_parts_to_step(const Design& design, const DesignParts& parts, const io::PartsFile& sidecar,
                               io::StepExport& request, io::TomlNode& rules) {
  if (parts.fixed_parts.empty()) return Ok{};
  namespace fs = std::filesystem;
  const std::string dir = fs::absolute(fs::path(design.path)).parent_path().lexically_normal().string();
  for (const FixedPart& f : parts.fixed_parts) {
    const std::string what = "[[parts]] at line " + std::to_string(f.line) + " (" + f.name + ")";
    auto fail = [&](int line, const std::string& message) { return make_error(design.path, line, what + ": " + message); };
    if (std::optional<std::string> why = io::outside_the_folder(dir, f.file))
      return fail(f.file_line, io::outside_message("file " + io::shown(f.file), *why));
    const std::string ext = fs::path(f.file).extension().string();
    std::string lower;
    for (char c : ext) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower != ".gltf" && lower != ".glb") {
      io::StepRevolvedPart p;
      p.name = f.name;
      p.file = (fs::path(dir) / f.file).lexically_normal().string();
      const sim::Affine place = fixed_part_transform(f);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) p.place.push_back(place.m[i][j]);
        p.place.push_back(place.offset[i] * 1e3);
      }
      request.parts.push_back(std::move(p));
    } else {
      // The simulation's own placement of the glTF's meshes.
      io::CadModel model;
      io::PartsFile scratch = sidecar;
      if (Status s = add_fixed_part(f, design.path, io::CadLoadOptions{}, scratch, model, nullptr); !s.ok())
        return s.error();
      std::size_t triangles = 0;
      for (const io::CadPlacement& pl : model.placements)
        for (const io::CadSurface& surface : model.parts[pl.part].surfaces) triangles += surface.indices.size() / 3;
      if (triangles > kMaxFixedPartStepTriangles)
        return fail(f.file_line, "the glTF holds " + std::to_string(triangles) + " triangles, more than the " +
                                     std::to_string(kMaxFixedPartStepTriangles) +
                                     " the STEP export writes as faces (export the part from its CAD source instead)");
      for (const io::CadPlacement& pl : model.placements) {
        io::StepRevolvedPart p;
        p.name = pl.path;
        for (const io::CadSurface& surface : model.parts[pl.part].surfaces)
          for (std::size_t t = 0; t + 2 < surface.indices.size(); t += 3) {
            p.faces.push_back(3);
            for (int k = 0; k < 3; ++k) {
              const Vec3 v = pl.to_world.point(sim::to_double(surface.positions[surface.indices[t + static_cast<std::size_t>(k)]]));
              p.corners.insert(p.corners.end(), {v.x * 1e3, v.y * 1e3, v.z * 1e3});
            }
          }
        if (!p.faces.empty()) request.parts.push_back(std::move(p));
      }
    }
  }
  for (const FixedPart& f : parts.fixed_parts) {
    if (f.material.empty()) continue;
    io::TomlNode rule = toml_table();
    toml_set(rule, "match", toml_string(f.name + "/*"));
    toml_set(rule, "material", toml_string(f.material));
    rules.array.push_back(std::move(rule));
  }
  return Ok{};
}

}  // namespace gonio::design
