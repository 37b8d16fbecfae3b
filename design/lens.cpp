#include "design/lens.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <tuple>

#include "design/table_reader.h"
#include "sim/scene.h"
#include "io/support/text.h"
#include "photometry/error_at.h"
#include "photometry/format.h"

namespace gonio::design {
namespace {

using io::TomlNode;


std::string mm(double m) { return format_number(m * 1e3, 4); }

// Reads the numbers of one [[lenses]] table and its surface tables.
class LensReader : public TableReader {
 public:
  LensReader(const std::string& path, double unit_m) : TableReader(path, unit_m) {}
  // A surface: `vertex_z` its vertex's height (conic and B-spline), `aperture` the conic's rim.
  Result<Profile> surface(const TomlNode& t, const std::string& what, std::optional<double> vertex_z,
                          std::optional<double> aperture, const char* vertex_needs) const {
    if (!t.is_table()) return make_error(path_, t.line, what + " must be a table, e.g. { profile = \"conic\", radius = 20 }");
    const TomlNode* kind = t.get("profile");
    if (!kind || !kind->is_string()) return make_error(path_, t.line, what + ": 'profile' (conic, bspline, polar) is missing");
    auto need_vertex = [&]() -> Status {
      if (!vertex_z) return make_error(path_, t.line, what + ": a " + kind->string + " surface needs the lens's " + vertex_needs);
      return Ok{};
    };
    if (kind->string == "conic") {
      if (Status s = io::check_keys(t, {"profile", "radius", "conic", "aspheric"}, what, path_); !s.ok()) return s.error();
      if (Status s = need_vertex(); !s.ok()) return s.error();
      if (!aperture) return make_error(path_, t.line, what + ": a conic surface needs the lens's 'aperture' (its rim's ρ)");
      ConicProfile c;
      Result<std::optional<double>> radius = number(t, "radius", what);
      if (!radius.ok()) return radius.error();
      Result<std::optional<double>> conic = number(t, "conic", what);
      if (!conic.ok()) return conic.error();
      Result<std::vector<double>> aspheric = numbers(t, "aspheric", what, false);
      if (!aspheric.ok()) return aspheric.error();
      c.radius = radius->value_or(0.0) * unit_;
      c.conic = conic->value_or(0.0);
      c.vertex = *vertex_z;
      c.inner = 0.0;
      c.outer = *aperture;
      for (std::size_t i = 0; i < aspheric->size(); ++i)
        c.aspheric.push_back((*aspheric)[i] * std::pow(unit_, 1.0 - 2.0 * static_cast<double>(i + 2)));
      return Profile(c);
    }
    if (kind->string == "bspline") {
      if (Status s = io::check_keys(t, {"profile", "degree", "points"}, what, path_); !s.ok()) return s.error();
      if (Status s = need_vertex(); !s.ok()) return s.error();
      BSplineProfile b;
      Result<int> deg = degree(t, what, 3);
      if (!deg.ok()) return deg.error();
      b.degree = *deg;
      if (Status s = points(t, what, b); !s.ok()) return s.error();
      if (b.rho.empty() || b.rho[0] != 0.0 || b.z[0] != 0.0)
        return make_error(path_, t.get("points")->line,
                          what + ": the first point must be the vertex, [0, 0] (points are relative to the surface's vertex)");
      for (double& z : b.z) z += *vertex_z;
      return Profile(b);
    }
    if (kind->string == "polar") {
      if (Status s = io::check_keys(t, {"profile", "theta_deg", "r"}, what, path_); !s.ok()) return s.error();
      Result<PolarProfile> polar_table = polar(t, what);
      if (!polar_table.ok()) return polar_table.error();
      const PolarProfile& p = *polar_table;
      if (p.theta.empty() || p.theta[0] != 0.0)
        return make_error(path_, t.get("theta_deg")->line,
                          what + ": a lens's polar surface starts on the axis below the source: theta_deg[0] must be 0");
      return Profile(p);
    }
    return make_error(path_, kind->line,
                      what + ": profile " + io::shown(kind->string) + " is not one a lens surface takes (conic, bspline, polar)");
  }
};

void point_at(const ProfileCurve& c, double t, double& rho, double& z) {
  double dr = 0, dz = 0;
  c.eval(t, rho, z, dr, dz);
}

double signed_area(const std::vector<std::pair<double, double>>& poly) {
  double a = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& p = poly[i];
    const auto& q = poly[(i + 1) % poly.size()];
    a += p.first * q.second - q.first * p.second;
  }
  return 0.5 * a;
}

bool inside_polygon(const std::vector<std::pair<double, double>>& poly, double x, double y) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto& a = poly[i];
    const auto& b = poly[j];
    if ((a.second > y) != (b.second > y) && x < (b.first - a.first) * (y - a.second) / (b.second - a.second) + a.first)
      in = !in;
  }
  return in;
}

// The curves of a checked lens (read_lens made them once already).
struct Curves {
  ProfileCurve inner, outer;
  std::optional<ProfileCurve> side;
};
Curves curves_of(const Lens& lens) {
  Curves c{*ProfileCurve::make(lens.inner), *ProfileCurve::make(lens.outer), std::nullopt};
  if (lens.has_side) c.side = *ProfileCurve::make(lens.side);
  return c;
}

}  // namespace

Result<Lens> read_lens(const TomlNode& t, const std::string& path, double unit) {
  const std::string what = "[[lenses]] at line " + std::to_string(t.line);
  if (Status s = io::check_keys(t, {"name", "material", "vertex", "thickness", "aperture", "inner", "outer", "side",
                                    "position", "rotate_deg"},
                                what, path);
      !s.ok())
    return s.error();
  Lens lens;
  lens.line = t.line;
  for (auto [key, out] : {std::pair{"name", &lens.name}, std::pair{"material", &lens.material}}) {
    const TomlNode* n = t.get(key);
    if (!n) return make_error(path, t.line, what + ": '" + key + "' is missing");
    if (!n->is_string()) return make_error(path, n->line, what + ": '" + key + "' must be a string");
    *out = n->string;
  }
  if (lens.name.empty() || lens.name.find_first_of("*?[]/\\") != std::string::npos)
    return make_error(path, t.get("name")->line, what + ": 'name' must be non-empty, without * ? [ ] / \\");
  const std::string named = what + " (" + lens.name + ")";
  LensReader r(path, unit);
  Result<std::optional<double>> vertex = r.number(t, "vertex", named);
  if (!vertex.ok()) return vertex.error();
  Result<std::optional<double>> thickness = r.number(t, "thickness", named);
  if (!thickness.ok()) return thickness.error();
  Result<std::optional<double>> aperture = r.number(t, "aperture", named);
  if (!aperture.ok()) return aperture.error();
  if (*aperture && !(**aperture > 0.0))
    return make_error(path, t.get("aperture")->line, named + ": 'aperture' (the rims' ρ) must be > 0");
  std::optional<double> v, a, v_out;
  if (vertex->has_value()) v = vertex->value() * unit;
  if (aperture->has_value()) a = aperture->value() * unit;
  if (vertex->has_value() && thickness->has_value()) v_out = (vertex->value() - thickness->value()) * unit;
  for (auto [key, out, scale] : {std::tuple{"position", &lens.position, unit}, std::tuple{"rotate_deg", &lens.rotate_deg, 1.0}}) {
    const TomlNode* n = t.get(key);
    if (!n) continue;
    const std::optional<std::array<double, 3>> xyz = n->three_numbers();
    if (!xyz) return make_error(path, n->line, named + ": '" + key + "' must be an array of three finite numbers");
    *out = Vec3{(*xyz)[0], (*xyz)[1], (*xyz)[2]} * scale;
  }
  for (const char* key : {"inner", "outer"})
    if (!t.get(key)) return make_error(path, t.line, named + ": '" + key + "' (a surface table) is missing");
  Result<Profile> inner = r.surface(*t.get("inner"), named + ": inner", v, a, "'vertex'");
  if (!inner.ok()) return inner.error();
  Result<Profile> outer = r.surface(*t.get("outer"), named + ": outer", v_out, a, "'vertex' and 'thickness'");
  if (!outer.ok()) return outer.error();
  lens.inner = *inner;
  lens.outer = *outer;
  Result<ProfileCurve> ci = ProfileCurve::make(lens.inner);
  if (!ci.ok()) return make_error(path, t.get("inner")->line, named + ": inner: " + ci.error().message);
  Result<ProfileCurve> co = ProfileCurve::make(lens.outer);
  if (!co.ok()) return make_error(path, t.get("outer")->line, named + ": outer: " + co.error().message);
  double ri = 0, zi = 0, ro = 0, zo = 0;
  for (auto [curve, key] : {std::pair{&*ci, "inner"}, std::pair{&*co, "outer"}}) {
    double rho = 0, z = 0;
    point_at(*curve, curve->t0(), rho, z);
    if (std::abs(rho) > 1e-12)
      return make_error(path, t.get(key)->line, named + ": " + key + ": the surface must start on the axis (ρ = 0), not at ρ = " +
                                                    mm(rho) + " mm");
  }
  point_at(*ci, ci->t1(), ri, zi);
  point_at(*co, co->t1(), ro, zo);
  if (!(ri > 0.0) || !(ro > 0.0)) return make_error(path, t.line, named + ": a surface's rim lies on the axis");

  // The side: from the inner rim to the outer rim.
  BSplineProfile side;
  side.degree = 1;
  if (const TomlNode* s = t.get("side")) {
    const std::string sw = named + ": side";
    if (!s->is_table()) return make_error(path, s->line, sw + " must be a table { profile = \"bspline\", points = [...] }");
    if (Status st = io::check_keys(*s, {"profile", "degree", "points"}, sw, path); !st.ok()) return st.error();
    const TomlNode* kind = s->get("profile");
    if (!kind || !kind->is_string() || kind->string != "bspline")
      return make_error(path, kind ? kind->line : s->line, sw + ": 'profile' must be \"bspline\" (the rims are its end points)");
    BSplineProfile between;
    if (Status st = r.points(*s, sw, between); !st.ok()) return st.error();
    side.rho.push_back(ri);
    side.z.push_back(zi);
    side.rho.insert(side.rho.end(), between.rho.begin(), between.rho.end());
    side.z.insert(side.z.end(), between.z.begin(), between.z.end());
    side.rho.push_back(ro);
    side.z.push_back(zo);
    Result<int> deg = r.degree(*s, sw, std::min<int>(3, static_cast<int>(side.rho.size()) - 1));
    if (!deg.ok()) return deg.error();
    side.degree = *deg;
    Result<ProfileCurve> cs = ProfileCurve::make(side);
    if (!cs.ok()) return make_error(path, s->line, sw + ": " + cs.error().message);
  } else {
    side.rho = {ri, ro};
    side.z = {zi, zo};
    lens.has_side = std::hypot(ri - ro, zi - zo) > 1e-9;
  }
  lens.side = side;

  // Thinner than zero: the meridian crosses itself, or winds the wrong way.
  const std::vector<std::pair<double, double>> poly = lens_meridian(lens, 1024);
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // neighbours across the closing segment
      const auto& p0 = poly[i];
      const auto& p1 = poly[i + 1];
      const auto& q0 = poly[j];
      const auto& q1 = poly[(j + 1) % n];
      if (segments_cross(p0.first, p0.second, p1.first, p1.second, q0.first, q0.second, q1.first, q1.second))
        return make_error(path, t.line, named + ": the lens is thinner than zero near (ρ, z) = (" + mm(q0.first) + ", " +
                                            mm(q0.second) + ") mm: its surfaces cross");
    }
  double zi0 = 0, zo0 = 0, dummy = 0;
  point_at(*ci, ci->t0(), dummy, zi0);
  point_at(*co, co->t0(), dummy, zo0);
  if (!(zi0 > zo0) || !(signed_area(poly) < 0.0))
    return make_error(path, t.line, named + ": the lens is thinner than zero on the axis (inner vertex at z = " + mm(zi0) +
                                        " mm, outer at " + mm(zo0) +
                                        " mm): the inner surface, facing the source, lies above the outer one");
  return lens;
}

std::vector<std::pair<double, double>> lens_meridian(const Lens& lens, std::size_t samples) {
  const Curves c = curves_of(lens);
  std::vector<std::pair<double, double>> out;
  auto add = [&](const ProfileCurve& curve, bool reversed, bool skip_first) {
    for (std::size_t k = skip_first ? 1 : 0; k < samples; ++k) {
      const double u = static_cast<double>(reversed ? samples - 1 - k : k) / static_cast<double>(samples - 1);
      double rho = 0, z = 0;
      point_at(curve, curve.t0() + (curve.t1() - curve.t0()) * u, rho, z);
      out.emplace_back(rho, z);
    }
  };
  add(c.inner, false, false);
  if (c.side) add(*c.side, false, true);
  add(c.outer, true, true);
  return out;
}

Result<io::CadPart> lens_part(const Lens& lens, const io::CadTessellation& t, std::size_t max_triangles) {
  const Curves c = curves_of(lens);
  // One size and chordal deflection for the solid, and one azimuth count.
  double rho_max = 0.0, z_min = INFINITY, z_max = -INFINITY;
  for (const auto& [rho, z] : lens_meridian(lens, 1024)) {
    rho_max = std::max(rho_max, rho);
    z_min = std::min(z_min, z);
    z_max = std::max(z_max, z);
  }
  const auto [size, chordal] = revolved_extent(rho_max, z_min, z_max, t);
  io::CadTessellation fixed = t;
  fixed.chordal_m = chordal;
  const double delta = t.angular_deflection_deg * std::numbers::pi / 180.0;
  const std::size_t segments = azimuth_segments(rho_max, delta, fixed.chordal_m);

  io::CadPart part;
  part.name = lens.name;
  part.size_m = size;
  part.chordal_m = fixed.chordal_m;
  part.solids = 1;
  // The meridian runs clockwise in (ρ, z) (inner, side, outer reversed):
  // outward is −(dz, −dρ) along inner and side, +(dz, −dρ) along outer.
  struct One {
    const ProfileCurve* curve;
    int side;
  };
  std::vector<One> surfaces = {{&c.inner, -1}};
  if (c.side) surfaces.push_back({&*c.side, -1});
  surfaces.push_back({&c.outer, +1});
  std::size_t budget = max_triangles;
  for (const One& s : surfaces) {
    RevolveOptions extra;
    extra.normal_side = s.side;
    extra.segments = segments;
    Result<io::CadSurface> m = revolve(*s.curve, fixed, budget, nullptr, nullptr, extra);
    if (!m.ok()) return m.error();
    budget -= std::min(budget, m->indices.size() / 3);
    part.surfaces.push_back(std::move(*m));
  }
  // The rims share their positions (a closed solid to the bit): the inner
  // surface's last ring is the side's first, the side's last the outer's last.
  auto ring = [&](io::CadSurface& s, bool last) {
    return last ? s.positions.begin() + static_cast<std::ptrdiff_t>(s.positions.size() - segments) : s.positions.begin();
  };
  io::CadSurface& inner = part.surfaces.front();
  io::CadSurface& outer = part.surfaces.back();
  if (c.side) {
    io::CadSurface& side = part.surfaces[1];
    std::copy_n(ring(inner, true), segments, ring(side, false));
    std::copy_n(ring(side, true), segments, ring(outer, true));
  } else {
    std::copy_n(ring(inner, true), segments, ring(outer, true));
  }
  part.faces = static_cast<std::uint32_t>(part.surfaces.size());
  // One surface, so that the solid is one mesh (the model checks ask each
  // refractive mesh to be closed on its own); vertices stay per surface,
  // each with its surface's normal, the rims' positions shared.
  io::CadSurface solid;
  for (const io::CadSurface& s : part.surfaces) {
    const auto base = static_cast<std::uint32_t>(solid.positions.size());
    solid.positions.insert(solid.positions.end(), s.positions.begin(), s.positions.end());
    solid.normals.insert(solid.normals.end(), s.normals.begin(), s.normals.end());
    for (std::uint32_t i : s.indices) solid.indices.push_back(base + i);
  }
  part.surfaces.assign(1, std::move(solid));
  // Placed: positions and normals turned (a rotation: normals as positions' directions) and moved.
  const sim::Affine place = lens_transform(lens);
  if (lens.position != Vec3{0.0, 0.0, 0.0} || lens.rotate_deg != Vec3{0.0, 0.0, 0.0})
    for (io::CadSurface& s : part.surfaces) {
      for (sim::Vec3f& v : s.positions) v = sim::to_float(place.point(sim::to_double(v)));
      for (sim::Vec3f& n : s.normals) n = sim::to_float(normalize(place.linear(sim::to_double(n))));
    }
  return part;
}

sim::Affine lens_transform(const Lens& lens) {
  constexpr double kDeg = std::numbers::pi / 180.0;
  const sim::Affine turn = sim::rotation(Vec3{0, 0, 1}, lens.rotate_deg.z * kDeg) *
                           sim::rotation(Vec3{0, 1, 0}, lens.rotate_deg.y * kDeg) *
                           sim::rotation(Vec3{1, 0, 0}, lens.rotate_deg.x * kDeg);
  return sim::translation(lens.position) * turn;
}

std::string lens_emitter_problem(const Lens& lens, const Vec3& world, double chordal_m) {
  // Into the lens's own frame: p = Rᵀ·(world − position).
  const sim::Affine place = lens_transform(lens);
  const Vec3 w = world - place.offset;
  const Vec3 p{place.m[0][0] * w.x + place.m[1][0] * w.y + place.m[2][0] * w.z,
               place.m[0][1] * w.x + place.m[1][1] * w.y + place.m[2][1] * w.z,
               place.m[0][2] * w.x + place.m[1][2] * w.y + place.m[2][2] * w.z};
  const Curves c = curves_of(lens);
  const double rho = std::hypot(p.x, p.y);
  double d = std::min(distance_to_profile(c.inner, rho, p.z), distance_to_profile(c.outer, rho, p.z));
  if (c.side) d = std::min(d, distance_to_profile(*c.side, rho, p.z));
  if (d <= chordal_m)
    return "a surface passes through the emitter (" + mm(d) + " mm from it, within the chordal deflection " +
           mm(chordal_m) + " mm)";
  if (inside_polygon(lens_meridian(lens, 1024), rho, p.z))
    return "the emitter lies inside the glass (photons start in air: give the source a cavity, e.g. an inner "
           "surface that is a sphere about it)";
  return {};
}

LensCurves lens_curves_mm(const Lens& lens, int samples) {
  const Curves c = curves_of(lens);
  LensCurves out;
  std::vector<const ProfileCurve*> list = {&c.inner};
  if (c.side) list.push_back(&*c.side);
  list.push_back(&c.outer);
  for (const ProfileCurve* curve : list) {
    std::vector<double> rho, z;
    for (int i = 0; i < samples; ++i) {
      double r = 0, zz = 0;
      point_at(*curve, curve->t0() + (curve->t1() - curve->t0()) * i / (samples - 1), r, zz);
      rho.push_back(std::max(0.0, r) * 1e3);
      z.push_back(zz * 1e3);
    }
    out.rho.push_back(std::move(rho));
    out.z.push_back(std::move(z));
  }
  return out;
}

}  // namespace gonio::design
