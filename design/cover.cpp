#include "design/cover.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "design/part_mesh.h"
#include "design/revolved.h"
#include "io/model/gltf_material.h"
#include "io/model/material_extras.h"
#include "io/support/text.h"
#include "photometry/error_at.h"
#include "photometry/format.h"
#include "sim/bsdfs/library.h"

namespace gonio::design {
namespace {

constexpr double kPi = std::numbers::pi;

// Points on a circle of radius r: as many as the angular deflection and the
// chordal one ask, at least 8.
std::size_t circle_segments(double r, const io::CadTessellation& tess, double chordal) {
  const double delta = tess.angular_deflection_deg * kPi / 180.0;
  std::size_t n = static_cast<std::size_t>(std::ceil(2.0 * kPi / delta));
  if (r > chordal) n = std::max(n, static_cast<std::size_t>(std::ceil(kPi / std::acos(1.0 - chordal / r))));
  return std::max<std::size_t>(n, 8);
}

// A flat polygon (its corners in order) as a fan about its centroid, normal n.
void add_polygon(io::CadSurface& s, const std::vector<Vec3>& corners, const Vec3& n) {
  Vec3 c{};
  for (const Vec3& p : corners) c = c + p;
  c = c * (1.0 / static_cast<double>(corners.size()));
  const std::uint32_t centre = add_vertex(s, c, n);
  const auto first = static_cast<std::uint32_t>(s.positions.size());
  for (const Vec3& p : corners) add_vertex(s, p, n);
  const auto k = static_cast<std::uint32_t>(corners.size());
  for (std::uint32_t i = 0; i < k; ++i) add_triangle(s, centre, first + i, first + (i + 1) % k);
}

// The band between two equal polygons (top[i] above bottom[i]), normals
// from `normal(i)`; closed around.
template <typename Normal>
void add_band(io::CadSurface& s, const std::vector<Vec3>& top, const std::vector<Vec3>& bottom, Normal normal,
              bool smooth) {
  const std::size_t k = top.size();
  for (std::size_t i = 0; i < k; ++i) {
    const std::size_t j = (i + 1) % k;
    // Smooth (a cylinder): the exact normal at each vertex; flat (a box): the face's, normal(i).
    const Vec3 ni = normal(i), nj = smooth ? normal(j) : ni;
    const std::uint32_t a = add_vertex(s, top[i], ni), b = add_vertex(s, top[j], nj), c = add_vertex(s, bottom[j], nj),
                        d = add_vertex(s, bottom[i], ni);
    add_triangle(s, a, b, c);
    add_triangle(s, a, c, d);
  }
}

// The last row of a surface of revolution (revolved.h): its trailing
// vertices at the last vertex's height.
std::vector<Vec3> rim_of(const io::CadSurface& s) {
  std::vector<Vec3> rim;
  const float z = s.positions.back().z;
  for (std::size_t i = s.positions.size(); i-- > 0 && s.positions[i].z == z;) rim.push_back(sim::to_double(s.positions[i]));
  std::reverse(rim.begin(), rim.end());
  return rim;
}

// Orients a surface of revolution so that its normals point away from
// `centre` (outward true) or toward it.
void orient(io::CadSurface& s, const Vec3& centre, bool outward) {
  const std::size_t i = s.positions.size() / 2;
  const double d = dot(sim::to_double(s.normals[i]), sim::to_double(s.positions[i]) - centre);
  if ((d > 0.0) != outward) flip(s);
}

}  // namespace

Result<Cover> read_cover(const io::TomlNode& t, const std::string& path, double unit_m) {
  const std::string what = "[[covers]] at line " + std::to_string(t.line);
  if (Status s = io::check_keys(t, {"name", "material", "shape", "size", "diameter", "height", "thickness", "sag"}, what, path);
      !s.ok())
    return s.error();
  Cover c;
  c.line = t.line;
  auto text = [&](const char* key) -> Result<std::string> {
    const io::TomlNode* n = t.get(key);
    if (!n) return make_error(path, t.line, what + ": '" + key + "' is missing");
    if (!n->is_string() || n->string.empty()) return make_error(path, n->line, what + ": '" + key + "' must be a non-empty string");
    return n->string;
  };
  auto length = [&](const char* key, bool positive) -> Result<std::optional<double>> {
    const io::TomlNode* n = t.get(key);
    if (!n) return std::optional<double>();
    const std::optional<double> v = n->number();
    if (!v || !std::isfinite(*v) || (positive && !(*v > 0.0)))
      return make_error(path, n->line, what + ": '" + key + "' must be a " + (positive ? "number > 0" : "finite number"));
    return std::optional<double>(*v * unit_m);
  };
  Result<std::string> name = text("name");
  if (!name.ok()) return name.error();
  c.name = *name;
  if (c.name.find_first_of("*?[]/\\") != std::string::npos)
    return make_error(path, t.get("name")->line, what + ": 'name' must be without * ? [ ] / \\");
  Result<std::string> material = text("material");
  if (!material.ok()) return material.error();
  c.material = *material;
  Result<std::string> shape = text("shape");
  if (!shape.ok()) return shape.error();
  const int shape_line = t.get("shape")->line;
  if (*shape == "plate")
    c.shape = Cover::Shape::Plate;
  else if (*shape == "dome")
    c.shape = Cover::Shape::Dome;
  else
    return make_error(path, shape_line, what + ": shape " + io::shown(*shape) + " is not one Gonio knows (plate, dome)");
  Result<std::optional<double>> height = length("height", false);
  if (!height.ok()) return height.error();
  if (!*height) return make_error(path, t.line, what + ": 'height' is missing (z of the face toward the luminaire)");
  c.height = **height;
  Result<std::optional<double>> thickness = length("thickness", true);
  if (!thickness.ok()) return thickness.error();
  c.thickness = *thickness;
  if (const io::TomlNode* n = t.get("thickness")) c.thickness_line = n->line;
  Result<std::optional<double>> diameter = length("diameter", true);
  if (!diameter.ok()) return diameter.error();
  c.diameter = *diameter;
  if (const io::TomlNode* size = t.get("size")) {
    if (c.shape == Cover::Shape::Dome) return make_error(path, size->line, what + ": a dome takes 'diameter', not 'size'");
    if (c.diameter) return make_error(path, size->line, what + ": give 'size' (a rectangle) or 'diameter' (a disc), not both");
    const bool ok = size->is_array() && size->array.size() == 2 && size->array[0].number() && size->array[1].number() &&
                    *size->array[0].number() > 0.0 && *size->array[1].number() > 0.0 &&
                    std::isfinite(*size->array[0].number()) && std::isfinite(*size->array[1].number());
    if (!ok) return make_error(path, size->line, what + ": 'size' must be [x, y], two numbers > 0");
    c.width = *size->array[0].number() * unit_m;
    c.depth = *size->array[1].number() * unit_m;
  } else if (!c.diameter) {
    return make_error(path, t.line, what + (c.shape == Cover::Shape::Dome ? ": 'diameter' is missing (the dome's base)"
                                                                           : ": give 'size' (a rectangle) or 'diameter' (a disc)"));
  }
  const io::TomlNode* sag = t.get("sag");
  if (c.shape == Cover::Shape::Plate) {
    if (sag) return make_error(path, sag->line, what + ": a plate has no 'sag' (shape = \"dome\" has)");
  } else {
    if (!sag) return make_error(path, t.line, what + ": 'sag' is missing (the dome's depth below its base)");
    Result<std::optional<double>> s = length("sag", false);
    if (!s.ok()) return s.error();
    c.sag = **s;
    if (!(std::abs(c.sag) > 0.0 && std::abs(c.sag) < 0.5 * *c.diameter))
      return make_error(path, sag->line, what + ": 'sag' must be non-zero and smaller in size than the base's radius (" +
                                             format_number(0.5 * *c.diameter / unit_m) +
                                             "): a dome of a hemisphere or more is not a spherical cap Gonio makes");
  }
  return c;
}

Result<bool> is_volume_material(const io::PartsMaterial& material, const std::string& path, double* thickness_m) {
  std::vector<Finding> findings;
  const SourceLoc where{path, material.line, 0};
  const std::string what = "material " + io::shown(material.name);
  Result<io::MaterialExtras> x = io::read_material_extras(material.extras, where, what, findings);
  if (!x.ok()) return x.error();
  if (x->preset)
    if (const sim::MaterialPreset* p = sim::find_preset(*x->preset); p && thickness_m) *thickness_m = p->thickness_m;
  if (x->bsdf_file) return false;  // a measured BSDF: a surface's
  Result<sim::Material> m = io::map_material(io::GltfMaterial{}, *x, where, what, findings);
  if (!m.ok()) return m.error();
  return m->dielectric > 0.0 || m->scattering_per_m > 0.0 || m->attenuation_per_m > 0.0;
}

Result<CoverMesh> tessellate_cover(const Cover& cover, double thickness, const io::CadTessellation& tess,
                                   std::size_t max_triangles) {
  CoverMesh out;
  out.solid = thickness > 0.0;
  const double h = cover.height;
  const double t = thickness;
  const double extent = cover.diameter ? *cover.diameter : std::hypot(*cover.width, *cover.depth);
  out.size_m = std::hypot(extent, std::max(t, std::abs(cover.sag)));
  out.chordal_m = tess.chordal_m > 0.0 ? tess.chordal_m : std::max(tess.chordal_relative * out.size_m, tess.chordal_min_m);
  io::CadSurface& s = out.surface;
  const Vec3 up{0, 0, 1}, down{0, 0, -1};
  if (cover.shape == Cover::Shape::Plate) {
    std::vector<Vec3> outline;  // counter-clockwise seen from +Z
    std::vector<Vec3> radial;
    if (cover.width) {
      const double x = 0.5 * *cover.width, y = 0.5 * *cover.depth;
      outline = {{x, -y, 0}, {x, y, 0}, {-x, y, 0}, {-x, -y, 0}};
    } else {
      const double r = 0.5 * *cover.diameter;
      const std::size_t n = circle_segments(r, tess, out.chordal_m);
      if (4.0 * static_cast<double>(n) > static_cast<double>(max_triangles))
        return make_error("meshed to the tessellation it would take more than " + std::to_string(max_triangles) +
                          " triangles: coarsen the tessellation");
      for (std::size_t i = 0; i < n; ++i) {
        const double psi = 2.0 * kPi * static_cast<double>(i) / static_cast<double>(n);
        outline.push_back({r * std::cos(psi), r * std::sin(psi), 0});
        radial.push_back({std::cos(psi), std::sin(psi), 0});
      }
    }
    auto at = [&](double z) {
      std::vector<Vec3> p = outline;
      for (Vec3& v : p) v.z = z;
      return p;
    };
    if (!out.solid) {
      add_polygon(s, at(h), h <= 0.0 ? up : down);  // facing the luminaire
      return out;
    }
    const std::vector<Vec3> top = at(h), bottom = at(h - t);
    add_polygon(s, top, up);
    add_polygon(s, bottom, down);
    if (!radial.empty()) {
      add_band(s, top, bottom, [&](std::size_t i) { return radial[i]; }, true);
    } else {
      add_band(s, top, bottom, [&](std::size_t i) {
        const Vec3 e = outline[(i + 1) % outline.size()] - outline[i];
        return normalize(Vec3{e.y, -e.x, 0.0});  // outward of a counter-clockwise outline
      }, false);
    }
    return out;
  }

  // The dome, built bulging down (s > 0) and mirrored about its base's plane where it bulges up.
  const double a = 0.5 * *cover.diameter, sg = std::abs(cover.sag);
  const double radius = (a * a + sg * sg) / (2.0 * sg);
  const Vec3 centre{0, 0, h - sg + radius};
  Result<ProfileCurve> outer = ProfileCurve::make(ConicProfile{-radius, 0.0, {}, h - sg, 0.0, a});
  if (!outer.ok()) return outer.error();
  Result<io::CadSurface> outer_mesh = revolve(*outer, tess, max_triangles);
  if (!outer_mesh.ok()) return outer_mesh.error();
  if (!out.solid) {
    s = std::move(*outer_mesh);
  } else {
    if (!(t < sg))
      return make_error("the dome's thickness " + format_number(t * 1e3) + " mm is not less than its sag " +
                        format_number(sg * 1e3) + " mm: its inner surface would not reach its base");
    const double inner_r = radius - t;
    const double rho_in = std::sqrt(inner_r * inner_r - (radius - sg) * (radius - sg));
    Result<ProfileCurve> inner = ProfileCurve::make(ConicProfile{-inner_r, 0.0, {}, h - sg + t, 0.0, rho_in});
    if (!inner.ok()) return inner.error();
    Result<io::CadSurface> inner_mesh = revolve(*inner, tess, max_triangles);
    if (!inner_mesh.ok()) return inner_mesh.error();
    orient(*outer_mesh, centre, true);
    orient(*inner_mesh, centre, false);
    // The flat ring at the base between the two rims, normal up (out of the solid below it).
    const std::vector<Vec3> ro = rim_of(*outer_mesh), ri = rim_of(*inner_mesh);
    io::CadSurface ring;
    std::vector<std::uint32_t> o, in;
    for (const Vec3& p : ro) o.push_back(add_vertex(ring, p, up));
    for (const Vec3& p : ri) in.push_back(add_vertex(ring, p, up));
    const std::size_t no = o.size(), ni = in.size();
    for (std::size_t i = 0, j = 0; i < no || j < ni;) {
      const double next_o = static_cast<double>(i + 1) / static_cast<double>(no);
      const double next_i = static_cast<double>(j + 1) / static_cast<double>(ni);
      if (j == ni || (i < no && next_o <= next_i)) {
        add_triangle(ring, o[i], o[(i + 1) % no], in[j % ni]);
        ++i;
      } else {
        add_triangle(ring, o[i % no], in[(j + 1) % ni], in[j]);
        ++j;
      }
    }
    s = std::move(*outer_mesh);
    append(s, *inner_mesh);
    append(s, ring);
  }
  if (cover.sag < 0.0) {  // mirrored about z = h
    for (sim::Vec3f& p : s.positions) p.z = static_cast<float>(2.0 * h - static_cast<double>(p.z));
    for (sim::Vec3f& n : s.normals) n.z = -n.z;
    for (std::size_t i = 0; i + 2 < s.indices.size(); i += 3) std::swap(s.indices[i + 1], s.indices[i + 2]);
  }
  if (!out.solid) {  // a sheet faces the luminaire (the origin)
    const std::size_t i = s.positions.size() / 2;
    if (dot(sim::to_double(s.normals[i]), sim::to_double(s.positions[i])) > 0.0) flip(s);
  }
  return out;
}

bool cover_holds(const Cover& cover, double thickness, double chordal, const Vec3& p) {
  const double h = cover.height, t = std::max(thickness, 0.0), e = thickness > 0.0 ? 0.0 : chordal;
  if (cover.shape == Cover::Shape::Plate) {
    const bool across = cover.width ? std::abs(p.x) <= 0.5 * *cover.width + e && std::abs(p.y) <= 0.5 * *cover.depth + e
                                    : std::hypot(p.x, p.y) <= 0.5 * *cover.diameter + e;
    return across && p.z >= h - t - e && p.z <= h + e;
  }
  // The dome, bulging down: between its spheres, below its base (mirrored where it bulges up).
  const double a = 0.5 * *cover.diameter, sg = std::abs(cover.sag);
  const double radius = (a * a + sg * sg) / (2.0 * sg);
  const double z = cover.sag < 0.0 ? 2.0 * h - p.z : p.z;
  const double r = length(Vec3{p.x, p.y, z - (h - sg + radius)});
  return z <= h + e && r <= radius + e && r >= radius - t - e;
}

}  // namespace gonio::design
