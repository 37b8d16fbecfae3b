#include "design/facets.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "design/part_mesh.h"
#include "io/support/text.h"
#include "photometry/format.h"

namespace gonio::design {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kMaxFacets = 100000;

Error fail(const std::string& file, int line, std::string message) {
  return Error{{file, line, 0}, std::move(message)};
}

}  // namespace

Result<Facets> read_facets(const io::TomlNode& t, const std::string& path, const std::string& what) {
  const std::string where = what + ": facets";
  if (!t.is_table()) return fail(path, t.line, where + " must be a table { theta = N, azimuth = M, kind = \"flat\" }");
  if (Status s = io::check_keys(t, {"theta", "azimuth", "kind"}, where, path); !s.ok()) return s.error();
  Facets f;
  for (auto [key, out] : {std::pair{"theta", &f.theta}, std::pair{"azimuth", &f.azimuth}}) {
    const io::TomlNode* n = t.get(key);
    if (!n) continue;
    const std::optional<double> v = n->number();
    const int least = std::string(key) == "azimuth" ? 3 : 1;
    if (!v || *v != std::trunc(*v) || (*v != 0.0 && (*v < least || *v > kMaxFacets)))
      return fail(path, n->line, where + ": '" + key + "' must be 0 (smooth) or a whole number " + std::to_string(least) +
                                     " … " + std::to_string(kMaxFacets));
    *out = static_cast<int>(*v);
  }
  if (const io::TomlNode* k = t.get("kind")) {
    if (!k->is_string() || k->string != "flat")
      return fail(path, k->line, where + ": kind " + (k->is_string() ? io::shown(k->string) : std::string("(not a string)")) +
                                     " is not one Gonio makes yet (flat)");
  }
  if (f.theta == 0 && f.azimuth == 0) return fail(path, t.line, where + ": give 'theta' or 'azimuth' (or both) facets");
  return f;
}

Result<io::CadSurface> revolve_faceted(const ProfileCurve& curve, const Facets& facets, const io::CadTessellation& tess,
                                       std::size_t max_triangles, double* size_out, double* chordal_out) {
  const std::vector<ProfileSample> fine = sample_profile(curve);
  double rho_max = 0.0, z_min = INFINITY, z_max = -INFINITY;
  for (const ProfileSample& s : fine) {
    rho_max = std::max(rho_max, s.rho);
    z_min = std::min(z_min, s.z);
    z_max = std::max(z_max, s.z);
  }
  const auto [size, chordal] = revolved_extent(rho_max, z_min, z_max, tess);
  const double delta = tess.angular_deflection_deg * kPi / 180.0;
  const double side = normal_side(fine);
  if (size_out) *size_out = size;
  if (chordal_out) *chordal_out = chordal;

  // Rows: N + 1 at equal steps of t, or the smooth rule's.
  std::vector<ProfileSample> rows;
  if (facets.theta > 0) {
    for (int i = 0; i <= facets.theta; ++i) {
      ProfileSample s;
      s.t = curve.t0() + (curve.t1() - curve.t0()) * i / facets.theta;
      curve.eval(s.t, s.rho, s.z, s.drho, s.dz);
      rows.push_back(s);
    }
  } else {
    for (std::size_t k : profile_rows(fine, delta, chordal)) rows.push_back(fine[k]);
  }
  const std::size_t segments =
      facets.azimuth > 0 ? static_cast<std::size_t>(facets.azimuth) : azimuth_segments(rho_max, delta, chordal);
  if (2.0 * static_cast<double>(rows.size()) * static_cast<double>(segments) > static_cast<double>(max_triangles))
    return make_error("the facets would take " + format_number(2.0 * static_cast<double>(rows.size() * segments), 3) +
                      " triangles, more than " + std::to_string(max_triangles));

  // The normal in the meridian half plane (n_ρ, n_z) of band i (between rows i and i + 1) at row r,
  // for a sector of half angle h (0: smooth around).
  auto meridian_normal = [&](std::size_t i, std::size_t r, double h) {
    double dr = rows[r].drho, dz = rows[r].dz;
    if (facets.theta > 0) {  // the chord of the band
      dr = rows[i + 1].rho - rows[i].rho;
      dz = rows[i + 1].z - rows[i].z;
    }
    const double c = std::cos(h);
    const double nr = side * dz, nz = -side * dr * c;
    const double len = std::hypot(nr, nz);
    return std::pair{nr / len, nz / len};
  };
  const double step = 2.0 * kPi / static_cast<double>(segments);
  io::CadSurface out;
  auto point = [&](std::size_t r, double psi) {
    return Vec3{rows[r].rho * std::cos(psi), rows[r].rho * std::sin(psi), rows[r].z};
  };
  for (std::size_t i = 0; i + 1 < rows.size(); ++i)
    for (std::size_t j = 0; j < segments; ++j) {
      const double p0 = step * static_cast<double>(j), p1 = step * static_cast<double>(j + 1);
      const Vec3 a = point(i, p0), b = point(i, p1), c = point(i + 1, p1), d = point(i + 1, p0);
      std::uint32_t va, vb, vc, vd;
      if (facets.azimuth > 0) {
        // Flat across the sector: the normal in its mid-plane, at each row (one normal where flat along too).
        const double mid = 0.5 * (p0 + p1), h = 0.5 * step;
        const auto [nr0, nz0] = meridian_normal(i, i, h);
        const auto [nr1, nz1] = meridian_normal(i, i + 1, h);
        const Vec3 n0{nr0 * std::cos(mid), nr0 * std::sin(mid), nz0}, n1{nr1 * std::cos(mid), nr1 * std::sin(mid), nz1};
        va = add_vertex(out, a, n0);
        vb = add_vertex(out, b, n0);
        vc = add_vertex(out, c, n1);
        vd = add_vertex(out, d, n1);
      } else {
        // A cone band (flat along, smooth around): its normal at each azimuth.
        const auto [nr, nz] = meridian_normal(i, i, 0.0);
        const Vec3 n0{nr * std::cos(p0), nr * std::sin(p0), nz}, n1{nr * std::cos(p1), nr * std::sin(p1), nz};
        va = add_vertex(out, a, n0);
        vb = add_vertex(out, b, n1);
        vc = add_vertex(out, c, n1);
        vd = add_vertex(out, d, n0);
      }
      add_triangle(out, va, vb, vc);
      add_triangle(out, va, vc, vd);
    }
  return out;
}

}  // namespace gonio::design
