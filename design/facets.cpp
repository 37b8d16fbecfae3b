#include "design/facets.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

#include "design/part_mesh.h"
#include "io/support/text.h"
#include "photometry/error_at.h"
#include "photometry/format.h"

namespace gonio::design {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kMaxFacets = 100000;


// Curved facets (kind = "curved"): per facet a grid of sub-rows and
// sub-columns on the exact facet, from the output's needs.
Result<io::CadSurface> revolve_curved(const FacetSurface& surface, const ProfileCurve& curve, const Facets& facets,
                                      double delta, double chordal, double rho_max, std::size_t max_triangles) {
  // Along the profile: the facet's arc in sub-rows (δ/4 of turn, the chordal
  // deflection), or the smooth rule's rows where smooth that way.
  auto steps_for = [&](double turn, double radius, double per) {
    if (!std::isfinite(radius) || turn == 0.0) return 1;
    const double a = std::abs(turn), r = std::abs(radius);
    double n = std::ceil(a / per);
    if (chordal < r) n = std::max(n, std::ceil(a / (2.0 * std::acos(1.0 - chordal / r))));
    return static_cast<int>(std::clamp(n, 1.0, 4096.0));
  };
  std::vector<std::vector<double>> rows_u(static_cast<std::size_t>(surface.bands()));
  if (facets.theta == 0) {
    const std::vector<ProfileSample> fine = sample_profile(curve);
    for (std::size_t k : profile_rows(fine, delta, chordal))
      rows_u[0].push_back((fine[k].t - curve.t0()) / (curve.t1() - curve.t0()));
    rows_u[0].front() = 0.0;
    rows_u[0].back() = 1.0;
  } else {
    for (int i = 0; i < surface.bands(); ++i) {
      double r0 = 0.0, z0 = 0.0, d0 = 0.0, e0 = 0.0, r1 = 0.0, z1 = 0.0, d1 = 0.0, e1 = 0.0;
      surface.meridian(i, 0.0, r0, z0, d0, e0);
      surface.meridian(i, 1.0, r1, z1, d1, e1);
      const double turn = std::atan2(e1, d1) - std::atan2(e0, d0);
      const int n = steps_for(std::remainder(turn, 2.0 * kPi), facets.radius_theta, delta / 4.0);
      for (int k = 0; k <= n; ++k) rows_u[static_cast<std::size_t>(i)].push_back(static_cast<double>(k) / n);
    }
  }
  // Around: the sector's arc in sub-columns (δ of turn, the chordal
  // deflection), or the smooth rule's steps where smooth that way.
  int sectors = 0, columns = 1;
  if (facets.azimuth > 0) {
    sectors = facets.azimuth;
    const double half = rho_max * std::sin(kPi / facets.azimuth);
    const double r = std::abs(facets.radius_azimuth);
    columns = steps_for(std::isfinite(r) ? 2.0 * std::asin(std::min(1.0, half / r)) : 0.0, facets.radius_azimuth, delta);
  } else {
    sectors = static_cast<int>(azimuth_segments(rho_max, delta, chordal));
  }
  double cells = 0.0;
  for (const std::vector<double>& r : rows_u) cells += static_cast<double>(r.size() - 1);
  cells *= static_cast<double>(sectors) * columns;
  if (2.0 * cells > static_cast<double>(max_triangles))
    return make_error("the facets would take " + format_number(2.0 * cells, 3) + " triangles, more than " +
                      std::to_string(max_triangles));
  io::CadSurface out;
  for (int i = 0; i < surface.bands(); ++i) {
    const std::vector<double>& us = rows_u[static_cast<std::size_t>(i)];
    for (std::size_t r = 0; r + 1 < us.size(); ++r)
      for (int j = 0; j < sectors; ++j) {
        // The sector's patch and its v range (smooth around: a segment of a quarter turn).
        int patch = j;
        double v0 = 0.0, v1 = 1.0;
        if (facets.azimuth == 0) {
          const double turn = static_cast<double>(j) / sectors * surface.sectors();
          patch = std::min(surface.sectors() - 1, static_cast<int>(turn));
          v0 = turn - patch;
          v1 = static_cast<double>(j + 1) / sectors * surface.sectors() - patch;
        }
        for (int c = 0; c < columns; ++c) {
          const double va = v0 + (v1 - v0) * c / columns, vb = v0 + (v1 - v0) * (c + 1) / columns;
          std::uint32_t idx[4];
          const std::pair<double, double> corners[4] = {{us[r], va}, {us[r], vb}, {us[r + 1], vb}, {us[r + 1], va}};
          for (int k = 0; k < 4; ++k) {
            Vec3 p, n;
            surface.eval(i, patch, corners[k].first, corners[k].second, p, n);
            idx[k] = add_vertex(out, p, n);
          }
          add_triangle(out, idx[0], idx[1], idx[2]);
          add_triangle(out, idx[0], idx[2], idx[3]);
        }
      }
  }
  return out;
}

}  // namespace

Result<Facets> read_facets(const io::TomlNode& t, const std::string& path, const std::string& what, double unit_m) {
  const std::string where = what + ": facets";
  if (!t.is_table()) return make_error(path, t.line, where + " must be a table { theta = N, azimuth = M, kind = \"flat\" }");
  if (Status s = io::check_keys(t, {"theta", "azimuth", "kind", "radius_theta", "radius_azimuth"}, where, path); !s.ok())
    return s.error();
  Facets f;
  f.line = t.line;
  for (auto [key, out] : {std::pair{"theta", &f.theta}, std::pair{"azimuth", &f.azimuth}}) {
    const io::TomlNode* n = t.get(key);
    if (!n) continue;
    const std::optional<double> v = n->number();
    const int least = std::string(key) == "azimuth" ? 3 : 1;
    if (!v || *v != std::trunc(*v) || (*v != 0.0 && (*v < least || *v > kMaxFacets)))
      return make_error(path, n->line, where + ": '" + key + "' must be 0 (smooth) or a whole number " + std::to_string(least) +
                                           " … " + std::to_string(kMaxFacets));
    *out = static_cast<int>(*v);
  }
  if (const io::TomlNode* k = t.get("kind")) {
    if (!k->is_string() || (k->string != "flat" && k->string != "curved"))
      return make_error(path, k->line, where + ": kind " + (k->is_string() ? io::shown(k->string) : std::string("(not a string)")) +
                                           " is not one Gonio makes (flat, curved)");
    f.curved = k->string == "curved";
  }
  if (f.theta == 0 && f.azimuth == 0) return make_error(path, t.line, where + ": give 'theta' or 'azimuth' (or both) facets");
  for (auto [key, out, count, line] :
       {std::tuple{"radius_theta", &f.radius_theta, f.theta, &f.radius_theta_line},
        std::tuple{"radius_azimuth", &f.radius_azimuth, f.azimuth, &f.radius_azimuth_line}}) {
    const io::TomlNode* n = t.get(key);
    if (!n) continue;
    *line = n->line;
    if (!f.curved) return make_error(path, n->line, where + ": '" + key + "' bends curved facets: add kind = \"curved\"");
    if (count == 0)
      return make_error(path, n->line, where + ": '" + key + "' without " + (std::string(key) == "radius_theta" ? "'theta'" : "'azimuth'") +
                                           " facets (smooth that way) bends nothing");
    const std::optional<double> v = n->number();
    if (!v || std::isnan(*v) || *v == 0.0)
      return make_error(path, n->line, where + ": '" + key + "' must be a signed radius (> 0 concave, < 0 convex seen from the lit side; inf: flat)");
    *out = *v * unit_m;
  }
  if (f.curved && std::isinf(f.radius_theta) && std::isinf(f.radius_azimuth) && !t.get("radius_theta") &&
      !t.get("radius_azimuth"))
    return make_error(path, t.line, where + ": curved facets need 'radius_theta' or 'radius_azimuth'");
  return f;
}

Result<FacetSurface> FacetSurface::make(const ProfileCurve& curve, const Facets& facets) {
  FacetSurface s;
  s.curve_ = &curve;
  s.facets_ = facets;
  s.side_ = normal_side(sample_profile(curve));
  s.bands_ = facets.theta > 0 ? facets.theta : 1;
  s.sectors_ = facets.azimuth > 0 ? facets.azimuth : 4;
  if (facets.theta > 0) {
    for (int i = 0; i <= facets.theta; ++i) {
      const double t = curve.t0() + (curve.t1() - curve.t0()) * i / facets.theta;
      double rho = 0.0, z = 0.0, dr = 0.0, dz = 0.0;
      curve.eval(t, rho, z, dr, dz);
      s.row_t_.push_back(t);
      s.row_rho_.push_back(rho);
      s.row_z_.push_back(z);
    }
    if (std::isfinite(facets.radius_theta)) {
      const double R = facets.radius_theta, r = std::abs(R), sign = R > 0.0 ? 1.0 : -1.0;
      for (int i = 0; i < facets.theta; ++i) {
        const double ar = s.row_rho_[i], az = s.row_z_[i], br = s.row_rho_[i + 1], bz = s.row_z_[i + 1];
        const double c = std::hypot(br - ar, bz - az);
        if (2.0 * r < c)
          return make_error({}, facets.radius_theta_line,
                            "facets (line " + std::to_string(facets.radius_theta_line) + "): radius_theta " +
                                format_number(R * 1e3) + " mm is smaller than half of facet " + std::to_string(i + 1) +
                                "'s chord (" + format_number(0.5 * c * 1e3) + " mm)");
        // The chord's normal toward the lit side, the centre on it (R > 0) or behind it.
        const double nr = s.side_ * (bz - az) / c, nz = -s.side_ * (br - ar) / c;
        s.mr_.push_back(0.5 * (ar + br));
        s.mz_.push_back(0.5 * (az + bz));
        s.tr_.push_back((br - ar) / c);
        s.tz_.push_back((bz - az) / c);
        s.dr_.push_back(-sign * nr);
        s.dz_.push_back(-sign * nz);
        s.alpha_.push_back(std::asin(std::min(1.0, 0.5 * c / r)));
      }
    }
  }
  if (facets.azimuth > 0 && std::isfinite(facets.radius_azimuth)) {
    double rho_max = 0.0;
    for (const ProfileSample& p : sample_profile(curve)) rho_max = std::max(rho_max, p.rho);
    for (double r : s.row_rho_) rho_max = std::max(rho_max, r);
    const double half_chord = rho_max * std::sin(kPi / facets.azimuth);
    if (std::abs(facets.radius_azimuth) < half_chord)
      return make_error({}, facets.radius_azimuth_line,
                        "facets (line " + std::to_string(facets.radius_azimuth_line) + "): radius_azimuth " +
                            format_number(facets.radius_azimuth * 1e3) + " mm is smaller than half of the widest sector's chord (" +
                            format_number(half_chord * 1e3) + " mm)");
  }
  return s;
}

void FacetSurface::meridian(int i, double u, double& rho, double& z, double& drho, double& dz) const {
  const auto k = static_cast<std::size_t>(i);
  if (facets_.theta == 0) {  // the exact profile, one band
    const double span = curve_->t1() - curve_->t0();
    curve_->eval(curve_->t0() + span * u, rho, z, drho, dz);
    drho *= span;
    dz *= span;
  } else if (!alpha_.empty()) {  // the arc, from the chord's middle (no cancellation where |R| is large)
    // ψ from −α (row i) to α (row i + 1): M + R·sin ψ·t + R·(cos ψ − cos α)·(−d), cos ψ − cos α = 2·sin((α + ψ)/2)·sin((α − ψ)/2).
    const double r = std::abs(facets_.radius_theta), a = alpha_[k], psi = -a + 2.0 * a * u;
    const double along = r * std::sin(psi), out = 2.0 * r * std::sin(0.5 * (a + psi)) * std::sin(0.5 * (a - psi));
    rho = mr_[k] + along * tr_[k] + out * dr_[k];
    z = mz_[k] + along * tz_[k] + out * dz_[k];
    drho = 2.0 * a * r * (std::cos(psi) * tr_[k] - std::sin(psi) * dr_[k]);
    dz = 2.0 * a * r * (std::cos(psi) * tz_[k] - std::sin(psi) * dz_[k]);
    if (u == 0.0) rho = row_rho_[k], z = row_z_[k];  // the rows exactly
    if (u == 1.0) rho = row_rho_[k + 1], z = row_z_[k + 1];
  } else {  // the chord
    drho = row_rho_[k + 1] - row_rho_[k];
    dz = row_z_[k + 1] - row_z_[k];
    rho = row_rho_[k] + u * drho;
    z = row_z_[k] + u * dz;
    if (u == 1.0) rho = row_rho_[k + 1], z = row_z_[k + 1];
  }
}

void FacetSurface::eval(int i, int j, double u, double v, Vec3& p, Vec3& n) const {
  double rho = 0.0, z = 0.0, dr = 0.0, dz = 0.0;
  meridian(i, u, rho, z, dr, dz);
  const double step = 2.0 * kPi / sectors_;
  if (facets_.azimuth == 0) {  // smooth around: a surface of revolution
    const double psi = step * (j + v);
    const double len = std::hypot(dr, dz), nr = side_ * dz / len, nz = -side_ * dr / len;
    p = Vec3{rho * std::cos(psi), rho * std::sin(psi), z};
    n = Vec3{nr * std::cos(psi), nr * std::sin(psi), nz};
    return;
  }
  const double h = 0.5 * step, mid = step * (j + 0.5);
  const Vec3 out{std::cos(mid), std::sin(mid), 0.0}, across{-std::sin(mid), std::cos(mid), 0.0}, up{0.0, 0.0, 1.0};
  const double s = 2.0 * v - 1.0;
  // The flat (ruled) facet: the chord at every point of the meridian, its normal in the mid-plane.
  auto flat_normal = [&](double drho, double dzz) {
    const double nr = side_ * dzz, nz = -side_ * drho * std::cos(h), len = std::hypot(nr, nz);
    return out * (nr / len) + up * (nz / len);
  };
  auto point = [&](double uu, double ss) {
    double r = 0.0, zz = 0.0, a = 0.0, b = 0.0;
    meridian(i, uu, r, zz, a, b);
    const double half = r * std::sin(h), x = ss * half;
    Vec3 q = out * (r * std::cos(h)) + across * x + up * zz;
    if (std::isfinite(facets_.radius_azimuth)) {
      const double R = std::abs(facets_.radius_azimuth);
      // √(R² − x²) − √(R² − half²), without cancellation where R is large.
      const double bulge = (half - x) * (half + x) /
                           (std::sqrt(std::max(0.0, R * R - x * x)) + std::sqrt(std::max(0.0, R * R - half * half)));
      q = q - flat_normal(a, b) * ((facets_.radius_azimuth > 0.0 ? 1.0 : -1.0) * bulge);
    }
    return q;
  };
  p = point(u, s);
  const Vec3 flat = flat_normal(dr, dz);
  if (!std::isfinite(facets_.radius_azimuth) && alpha_.empty()) {
    n = flat;
    return;
  }
  // The exact surface's normal: ∂p/∂u × ∂p/∂s by central differences (one-sided at the ends).
  const double e = 1e-6;
  const double u0 = std::max(0.0, u - e), u1 = std::min(1.0, u + e), s0 = std::max(-1.0, s - e), s1 = std::min(1.0, s + e);
  const Vec3 du = (point(u1, s) - point(u0, s)) * (1.0 / (u1 - u0));
  const Vec3 ds = (point(u, s1) - point(u, s0)) * (1.0 / (s1 - s0));
  Vec3 c = cross(du, ds);
  const double len = length(c);
  if (!(len > 1e-30)) {
    n = flat;
    return;
  }
  c = c * (1.0 / len);
  n = dot(c, flat) < 0.0 ? c * -1.0 : c;
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

  if (facets.curved) {
    Result<FacetSurface> surface = FacetSurface::make(curve, facets);
    if (!surface.ok()) return surface.error();
    return revolve_curved(*surface, curve, facets, delta, chordal, rho_max, max_triangles);
  }
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
