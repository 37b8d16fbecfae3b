#include "design/trough.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "design/design_scene.h"
#include "design/part_mesh.h"
#include "photometry/error_at.h"
#include "photometry/format.h"

namespace gonio::design {

Result<Trough> read_trough(const io::TomlNode& t, const std::string& path, double unit_m) {
  const std::string what = "[[troughs]] at line " + std::to_string(t.line);
  Trough out;
  out.line = t.line;
  // The trough's own keys; the rest is a reflector's (name, material, profile and its keys).
  io::TomlNode profile_part = t;
  std::erase_if(profile_part.table, [](const io::TomlMember& m) {
    return m.first == "length" || m.first == "symmetric" || m.first == "caps";
  });
  Result<Reflector> r = read_profile_part(profile_part, path, unit_m, "troughs");
  if (!r.ok()) return r.error();
  out.name = r->name;
  out.material = r->material;
  out.profile = r->profile;
  const io::TomlNode* length = t.get("length");
  if (!length) return make_error(path, t.line, what + ": 'length' is missing (the trough's extent along Y)");
  const std::optional<double> l = length->number();
  if (!l || !std::isfinite(*l) || !(*l > 0.0))
    return make_error(path, length->line, what + ": 'length' must be a number > 0");
  out.length = *l * unit_m;
  if (const io::TomlNode* s = t.get("symmetric")) {
    if (s->type != io::TomlNode::Type::Boolean) return make_error(path, s->line, what + ": 'symmetric' must be true or false");
    out.symmetric = s->boolean;
  }
  if (const io::TomlNode* c = t.get("caps")) {
    if (!c->is_string() || c->string.empty())
      return make_error(path, c->line, what + ": 'caps' must be the name of the end caps' material");
    out.caps = c->string;
    out.caps_line = c->line;
  }
  return out;
}

Result<TroughMesh> tessellate_trough(const Trough& trough, const io::CadTessellation& tess, std::size_t max_triangles) {
  Result<ProfileCurve> curve = ProfileCurve::make(trough.profile);
  if (!curve.ok()) return curve.error();
  const std::vector<ProfileSample> fine = sample_profile(*curve);
  double rho_max = 0.0, z_min = INFINITY, z_max = -INFINITY;
  for (const ProfileSample& s : fine) {
    rho_max = std::max(rho_max, s.rho);
    z_min = std::min(z_min, s.z);
    z_max = std::max(z_max, s.z);
  }
  TroughMesh out;
  const double width = trough.symmetric ? 2.0 * rho_max : rho_max;
  out.size_m = std::sqrt(width * width + trough.length * trough.length + (z_max - z_min) * (z_max - z_min));
  out.chordal_m = tess.chordal_m > 0.0 ? tess.chordal_m : std::max(tess.chordal_relative * out.size_m, tess.chordal_min_m);
  const double delta = tess.angular_deflection_deg * std::numbers::pi / 180.0;
  const std::vector<std::size_t> rows = profile_rows(fine, delta, out.chordal_m);
  const int halves = trough.symmetric ? 2 : 1;
  const double triangles = 2.0 * halves * static_cast<double>(rows.size()) * (trough.caps.empty() ? 1.0 : 2.0);
  if (triangles > static_cast<double>(max_triangles))
    return make_error("meshed to an angular deflection of " + format_number(tess.angular_deflection_deg) +
                      "° it would take " + format_number(triangles, 3) + " triangles, more than " +
                      std::to_string(max_triangles) + ": coarsen the tessellation");

  // The reflector: per half, two vertices (y = ∓L/2) per row, the exact normal (±n_ρ, 0, n_z).
  const double side = normal_side(fine);
  const double y0 = -0.5 * trough.length, y1 = 0.5 * trough.length;
  for (int h = 0; h < halves; ++h) {
    const double sx = h == 0 ? 1.0 : -1.0;
    const auto first = static_cast<std::uint32_t>(out.reflector.positions.size());
    for (std::size_t row : rows) {
      const ProfileSample& s = fine[row];
      const double len = std::hypot(s.drho, s.dz);
      const Vec3 n{sx * side * s.dz / len, 0.0, -side * s.drho / len};
      add_vertex(out.reflector, Vec3{sx * s.rho, y0, s.z}, n);
      add_vertex(out.reflector, Vec3{sx * s.rho, y1, s.z}, n);
    }
    for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
      const std::uint32_t a = first + static_cast<std::uint32_t>(2 * i);
      add_triangle(out.reflector, a, a + 1, a + 3);
      add_triangle(out.reflector, a, a + 3, a + 2);
    }
  }
  if (!trough.caps.empty()) {
    // Strips between consecutive rows, from the profile to its mirror image (or to x = 0).
    io::CadSurface caps;
    for (const double y : {y0, y1}) {
      const Vec3 n{0.0, y < 0.0 ? 1.0 : -1.0, 0.0};  // into the trough
      const auto first = static_cast<std::uint32_t>(caps.positions.size());
      for (std::size_t row : rows) {
        const ProfileSample& s = fine[row];
        add_vertex(caps, Vec3{s.rho, y, s.z}, n);
        add_vertex(caps, Vec3{trough.symmetric ? -s.rho : 0.0, y, s.z}, n);
      }
      for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
        const std::uint32_t a = first + static_cast<std::uint32_t>(2 * i);
        add_triangle(caps, a, a + 1, a + 3);
        add_triangle(caps, a, a + 3, a + 2);
      }
    }
    out.caps = std::move(caps);
  }
  return out;
}

double distance_to_trough(const Trough& trough, const Vec3& p) {
  Result<ProfileCurve> curve = ProfileCurve::make(trough.profile);
  if (!curve.ok()) return INFINITY;
  const double x = trough.symmetric ? std::abs(p.x) : p.x;
  const double across = distance_to_profile(*curve, x, p.z);
  const double beyond = std::max(0.0, std::abs(p.y) - 0.5 * trough.length);
  return std::hypot(across, beyond);
}

}  // namespace gonio::design
