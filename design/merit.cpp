#include "design/merit.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <array>
#include <limits>
#include <tuple>

#include "io/support/text.h"
#include "photometry/beam.h"
#include "photometry/bug_rating.h"
#include "photometry/ugr.h"
#include "photometry/error_at.h"
#include "photometry/format.h"
#include "photometry/frame.h"

namespace gonio::design {
namespace {

using io::TomlNode;
constexpr double kDeg = std::numbers::pi / 180.0;

// Whether `step` divides `range` into a whole number of steps.
bool divides(double step, double range) {
  const double n = range / step;
  return step > 0.0 && std::abs(n - std::round(n)) < 1e-9 * n && std::round(n) >= 1.0;
}

// The basis function of node j on a line of nodes x_k = k·h (tent or cell),
// at x (the line's ends clamp nothing: the sphere's ends are γ = 0 and 180).
double basis(double x, double node, double h, bool smooth) {
  const double d = std::abs(x - node);
  if (smooth) return std::max(0.0, 1.0 - d / h);
  return d <= 0.5 * h ? 1.0 : 0.0;
}

// ∫ f(γ)·basis_j(γ)·sin γ dγ over [0, π] on the node's support, by the
// midpoint rule on `n` pieces; f in candela, or 1 for the solid angle.
template <typename F>
double gamma_integral(double node, double h, bool smooth, F&& f, int n = 64) {
  const double lo = std::max(0.0, node - (smooth ? h : 0.5 * h));
  const double hi = std::min(std::numbers::pi, node + (smooth ? h : 0.5 * h));
  const double dx = (hi - lo) / n;
  double sum = 0.0;
  for (int k = 0; k < n; ++k) {
    const double x = lo + (k + 0.5) * dx;
    sum += f(x) * basis(x, node, h, smooth) * std::sin(x) * dx;
  }
  return sum;
}


// A number of a limit's table: absent stays as it is; else within [lo, hi].
// The [merit] ugr table's cell: `room = [X, Y]` [H], one of CIE 190's 19
// rooms; `reflectances = [ceiling, walls, floor]` [%], one of its five
// sets; `view = "crosswise" | "endwise"`. Errors name the key's line and
// list what the table has.
Status read_ugr_cell(const TomlNode& n, const std::string& path, MeritSpec::Ugr* x) {
  const auto numbers = [](const TomlNode& a, std::size_t count) {
    std::vector<double> out;
    if (!a.is_array() || a.array.size() != count) return out;
    for (const TomlNode& e : a.array) {
      const std::optional<double> v = e.number();
      if (!v || !std::isfinite(*v)) return std::vector<double>{};
      out.push_back(*v);
    }
    return out;
  };
  if (const TomlNode* room = n.get("room")) {
    const std::vector<double> v = numbers(*room, 2);
    const std::vector<std::array<double, 2>> rooms = photometry::ugr_room_sizes();
    bool found = false;
    std::string list;
    for (const std::array<double, 2>& r : rooms) {
      list += (list.empty() ? "" : ", ") + std::string("[") + format_number(r[0]) + ", " + format_number(r[1]) + "]";
      if (v.size() == 2 && r[0] == v[0] && r[1] == v[1]) found = true;
    }
    if (!found)
      return make_error(path, room->line ? room->line : n.line,
                        "[merit]: 'ugr.room' must be one of CIE 190's rooms [X, Y] in H (X across the line of sight, Y "
                        "along it): " + list);
    x->x_h = v[0];
    x->y_h = v[1];
  }
  if (const TomlNode* refl = n.get("reflectances")) {
    const std::vector<double> v = numbers(*refl, 3);
    bool found = false;
    std::string list;
    for (std::size_t k = 0; k < photometry::kUgrReflectances.size(); ++k) {
      const std::array<double, 3>& r = photometry::kUgrReflectances[k];
      list += (list.empty() ? "" : ", ") + std::string("[") + format_number(100.0 * r[0]) + ", " +
              format_number(100.0 * r[1]) + ", " + format_number(100.0 * r[2]) + "]";
      if (v.size() == 3 && std::abs(v[0] - 100.0 * r[0]) < 1e-9 && std::abs(v[1] - 100.0 * r[1]) < 1e-9 &&
          std::abs(v[2] - 100.0 * r[2]) < 1e-9) {
        found = true;
        x->reflectance_set = k;
      }
    }
    if (!found)
      return make_error(path, refl->line ? refl->line : n.line,
                        "[merit]: 'ugr.reflectances' must be one of CIE 190's sets [ceiling, walls, floor] in %: " + list);
  }
  if (const TomlNode* view = n.get("view")) {
    if (view->is_string() && view->string == "crosswise") {
      x->view = 1;
    } else if (view->is_string() && view->string == "endwise") {
      x->view = 2;
    } else {
      return make_error(path, view->line ? view->line : n.line,
                        "[merit]: 'ugr.view' must be \"crosswise\" or \"endwise\" (without it: the larger of the two)");
    }
  }
  return Ok{};
}

Status table_number(const TomlNode& t, const char* table, const char* key, double lo, double hi,
                    const std::string& path, std::optional<double>* out) {
  const TomlNode* n = t.get(key);
  if (!n) return Ok{};
  const std::optional<double> v = n->number();
  if (!v || !std::isfinite(*v) || *v < lo || *v > hi)
    return make_error(path, n->line ? n->line : t.line,
                      std::string("[merit]: '") + table + "." + key + "' must be a number in [" + format_number(lo) + ", " +
                          format_number(hi) + "]");
  *out = *v;
  return Ok{};
}

// The limits' tables: max_cd_above, ugr, bug, size (merit.h).
Status read_merit_limits(const TomlNode& m, const std::string& path, MeritSpec& spec) {
  const auto table_of = [&](const char* key) -> Result<const TomlNode*> {
    const TomlNode* t = m.get(key);
    if (!t) return static_cast<const TomlNode*>(nullptr);
    if (!t->is_table())
      return make_error(path, t->line, std::string("[merit]: '") + key + "' must be a table ({ … })");
    return t;
  };
  std::optional<double> v;
  {
    Result<const TomlNode*> t = table_of("max_cd_above");
    if (!t.ok()) return t.error();
    if (*t) {
      const TomlNode& n = **t;
      if (Status s = io::check_keys(n, {"gamma", "to", "limit", "weight"}, "[merit] max_cd_above", path); !s.ok())
        return s;
      MeritSpec::MaxCdAbove x;
      x.line = n.line;
      if (!n.get("gamma")) return make_error(path, n.line, "[merit]: 'max_cd_above' needs 'gamma' (the cut-off angle [deg])");
      if (Status s = table_number(n, "max_cd_above", "gamma", 0.0, 180.0, path, &(v = std::nullopt)); !s.ok()) return s;
      x.gamma_deg = *v;
      if (Status s = table_number(n, "max_cd_above", "to", 0.0, 180.0, path, &(v = std::nullopt)); !s.ok()) return s;
      if (v) x.to_deg = *v;
      if (!(x.to_deg > x.gamma_deg))
        return make_error(path, n.line, "[merit]: 'max_cd_above' needs gamma < to (the range of γ it looks at)");
      if (Status s = table_number(n, "max_cd_above", "limit", 1e-12, 1e12, path, &x.limit_cd); !s.ok()) return s;
      if (Status s = table_number(n, "max_cd_above", "weight", 0.0, 1e6, path, &(v = std::nullopt)); !s.ok()) return s;
      if (v) x.weight = *v;
      spec.max_cd_above = x;
    }
  }
  {
    Result<const TomlNode*> t = table_of("ugr");
    if (!t.ok()) return t.error();
    if (*t) {
      const TomlNode& n = **t;
      if (Status s = io::check_keys(n, {"limit", "weight", "room", "reflectances", "view"}, "[merit] ugr", path);
          !s.ok())
        return s;
      MeritSpec::Ugr x;
      x.line = n.line;
      if (Status s = read_ugr_cell(n, path, &x); !s.ok()) return s;
      if (Status s = table_number(n, "ugr", "limit", 0.0, 60.0, path, &x.limit); !s.ok()) return s;
      if (Status s = table_number(n, "ugr", "weight", 0.0, 1e6, path, &(v = std::nullopt)); !s.ok()) return s;
      if (v) x.weight = *v;
      spec.ugr = x;
    }
  }
  {
    Result<const TomlNode*> t = table_of("bug");
    if (!t.ok()) return t.error();
    if (*t) {
      const TomlNode& n = **t;
      if (Status s = io::check_keys(n, {"b", "u", "g", "table", "weight"}, "[merit] bug", path); !s.ok()) return s;
      MeritSpec::Bug x;
      x.line = n.line;
      for (auto [key, out] : {std::pair{"b", &x.b}, std::pair{"u", &x.u}, std::pair{"g", &x.g}}) {
        const TomlNode* k = n.get(key);
        if (!k) continue;
        if (k->type != TomlNode::Type::Integer || k->integer < 0 || k->integer > 4)
          return make_error(path, k->line ? k->line : n.line,
                            std::string("[merit]: 'bug.") + key + "' must be a class 0 … 4 (the largest allowed; 5 is no limit)");
        *out = static_cast<int>(k->integer);
      }
      if (x.b < 0 && x.u < 0 && x.g < 0)
        return make_error(path, n.line, "[merit]: 'bug' limits nothing: give b, u or g (the largest class allowed)");
      if (const TomlNode* k = n.get("table")) {
        if (!k->is_string() || (k->string != "asymmetric" && k->string != "symmetric"))
          return make_error(path, k->line ? k->line : n.line,
                            "[merit]: 'bug.table' must be \"asymmetric\" (IES Types I–IV) or \"symmetric\" (Types V, VS)");
        x.symmetric = k->string == "symmetric";
      }
      if (Status s = table_number(n, "bug", "weight", 0.0, 1e6, path, &(v = std::nullopt)); !s.ok()) return s;
      if (v) x.weight = *v;
      spec.bug = x;
    }
  }
  {
    Result<const TomlNode*> t = table_of("size");
    if (!t.ok()) return t.error();
    if (*t) {
      const TomlNode& n = **t;
      if (Status s = io::check_keys(n, {"radius", "height", "weight"}, "[merit] size", path); !s.ok()) return s;
      MeritSpec::Size x;
      x.line = n.line;
      if (Status s = table_number(n, "size", "radius", 1e-6, 1e9, path, &x.radius_mm); !s.ok()) return s;
      if (Status s = table_number(n, "size", "height", 1e-6, 1e9, path, &x.height_mm); !s.ok()) return s;
      if (!x.radius_mm && !x.height_mm)
        return make_error(path, n.line, "[merit]: 'size' limits nothing: give radius or height [mm]");
      if (Status s = table_number(n, "size", "weight", 0.0, 1e6, path, &(v = std::nullopt)); !s.ok()) return s;
      if (v) x.weight = *v;
      spec.size = x;
    }
  }
  return Ok{};
}

// The BUG zones a spec limits, with each zone's lumens and limit.
struct BugZoneLimit {
  const char* name;
  double photometry::BugZones::*zone;
  double limit;
};
std::vector<BugZoneLimit> bug_zone_limits(const MeritSpec::Bug& b) {
  const photometry::BugLimits& l = photometry::bug_limits_lm();
  using Z = photometry::BugZones;
  std::vector<BugZoneLimit> out;
  if (b.b >= 0) {
    const auto n = static_cast<std::size_t>(b.b);
    out.push_back({"bug BL", &Z::bl, l.bl[n]});
    out.push_back({"bug BM", &Z::bm, l.bm[n]});
    out.push_back({"bug BH", &Z::bh, l.bh[n]});
  }
  if (b.u >= 0) {
    const auto n = static_cast<std::size_t>(b.u);
    out.push_back({"bug UL", &Z::ul, l.ul[n]});
    out.push_back({"bug UH", &Z::uh, l.uh[n]});
  }
  if (b.g >= 0) {
    const auto n = static_cast<std::size_t>(b.g);
    out.push_back({"bug FVH", &Z::fvh, l.fvh[n]});
    out.push_back({"bug BVH", &Z::bvh, l.bvh[n]});
    out.push_back({"bug FH", &Z::fh, l.fh[n]});
    out.push_back({"bug BH (glare)", &Z::bh, b.symmetric ? l.bh_glare_symmetric[n] : l.bh_glare[n]});
  }
  return out;
}

// A limit's value: (value − limit) / limit, per unit where the limit is 0.
MeritLimitValue limit_value(std::string name, double value, double limit) {
  return {std::move(name), value, limit, (value - limit) / (limit > 0.0 ? limit : 1.0)};
}

}  // namespace

Result<MeritSpec> read_merit(const io::TomlNode& resolved, const std::string& path) {
  MeritSpec spec;
  const TomlNode* m = resolved.get("merit");
  if (!m) return spec;
  if (!m->is_table()) return make_error(path, m->line, "'merit' must be a table ([merit])");
  spec.line = m->line;
  static const std::vector<std::string> known = {"target",    "c_step",          "gamma_step", "normalize",
                                                 "smooth",    "photons_per_bin", "candela",    "gamma_weights",
                                                 "lor",       "beam",       "field",      "max_cd_above", "ugr", "bug", "size"};
  for (const auto& [key, v] : m->table)
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      return make_error(path, v.line, "[merit]: unknown key " + io::shown(key) + " (known: " + list + ")");
    }
  const auto number = [&](const char* key, double& out, double lo, double hi) -> Status {
    const TomlNode* n = m->get(key);
    if (!n) return Ok{};
    const std::optional<double> v = n->number();
    if (!v || !std::isfinite(*v) || *v < lo || *v > hi)
      return make_error(path, n->line,
                        std::string("[merit]: '") + key + "' must be a number in [" + format_number(lo) + ", " +
                            format_number(hi) + "]");
    out = *v;
    return Ok{};
  };
  for (auto [key, out, lo, hi] : {std::tuple{"c_step", &spec.c_step_deg, 1.0, 360.0},
                                  std::tuple{"gamma_step", &spec.gamma_step_deg, 0.5, 90.0},
                                  std::tuple{"photons_per_bin", &spec.photons_per_bin, 40.0, 1e6},
                                  std::tuple{"candela", &spec.candela_weight, 0.0, 1e6},
                                  std::tuple{"lor", &spec.lor_weight, 0.0, 1e6},
                                  std::tuple{"beam", &spec.beam_weight, 0.0, 1e6},
                                  std::tuple{"field", &spec.field_weight, 0.0, 1e6}})
    if (Status s = number(key, *out, lo, hi); !s.ok()) return s.error();
  if (const TomlNode* n = m->get("beam")) spec.beam_line = n->line;
  if (const TomlNode* n = m->get("field")) spec.field_line = n->line;
  if (!divides(spec.c_step_deg, 360.0))
    return make_error(path, m->get("c_step")->line, "[merit]: c_step must divide 360");
  if (!divides(spec.gamma_step_deg, 180.0))
    return make_error(path, m->get("gamma_step")->line, "[merit]: gamma_step must divide 180");
  if (const TomlNode* t = m->get("target")) {
    if (!t->is_string() || t->string.empty()) return make_error(path, t->line, "[merit]: 'target' must be a file name");
    const std::filesystem::path p(t->string);
    spec.target = p.is_absolute() ? p.string() : (std::filesystem::path(path).parent_path() / p).string();
  }
  if (const TomlNode* n = m->get("normalize")) {
    if (!n->is_string() || (n->string != "flux" && n->string != "absolute"))
      return make_error(path, n->line, "[merit]: 'normalize' must be \"flux\" or \"absolute\"");
    spec.absolute = n->string == "absolute";
  }
  if (const TomlNode* n = m->get("smooth")) {
    if (n->type != TomlNode::Type::Boolean) return make_error(path, n->line, "[merit]: 'smooth' must be true or false");
    spec.smooth = n->boolean;
  }
  if (const TomlNode* n = m->get("gamma_weights")) {
    if (!n->is_array()) return make_error(path, n->line, "[merit]: 'gamma_weights' must be an array of [from, to, weight]");
    for (const TomlNode& row : n->array) {
      const int line = row.line ? row.line : n->line;
      if (!row.is_array() || row.array.size() != 3)
        return make_error(path, line, "[merit]: each of 'gamma_weights' must be [from, to, weight]");
      std::optional<double> v[3];
      for (int k = 0; k < 3; ++k) v[k] = row.array[static_cast<std::size_t>(k)].number();
      if (!v[0] || !v[1] || !v[2] || !(*v[0] >= 0.0 && *v[0] < *v[1] && *v[1] <= 180.0) || !(*v[2] >= 0.0) ||
          !std::isfinite(*v[2]))
        return make_error(path, line, "[merit]: 'gamma_weights' rows need 0 ≤ from < to ≤ 180 and a weight ≥ 0");
      spec.gamma_weights.push_back({*v[0], *v[1], *v[2]});
    }
  }
  if (Status s = read_merit_limits(*m, path, spec); !s.ok()) return s.error();
  return spec;
}

MeritGrid merit_grid(const MeritSpec& spec) {
  MeritGrid g;
  g.smooth = spec.smooth;
  const int nc = static_cast<int>(std::round(360.0 / spec.c_step_deg));
  const int ng = static_cast<int>(std::round(180.0 / spec.gamma_step_deg));
  for (int i = 0; i < nc; ++i) g.c_deg.push_back(i * spec.c_step_deg);
  for (int j = 0; j <= ng; ++j) g.gamma_deg.push_back(j * spec.gamma_step_deg);
  const double dc = 2.0 * std::numbers::pi / nc, h = spec.gamma_step_deg * kDeg;
  std::vector<double> per_gamma;
  for (double gamma : g.gamma_deg)
    per_gamma.push_back(dc * gamma_integral(gamma * kDeg, h, g.smooth, [](double) { return 1.0; }));
  for (int i = 0; i < nc; ++i) g.solid_angle_sr.insert(g.solid_angle_sr.end(), per_gamma.begin(), per_gamma.end());
  return g;
}

std::vector<double> bin_photons(const MeritGrid& grid, const std::vector<MeritPhoton>& photons) {
  const std::size_t nc = grid.c_deg.size(), ng = grid.gamma_deg.size();
  std::vector<double> flux(grid.size(), 0.0);
  const double dc = 360.0 / static_cast<double>(nc), dg = 180.0 / static_cast<double>(ng - 1);
  for (const MeritPhoton& p : photons) {
    const photometry::CGamma a = photometry::c_gamma_from_direction(p.direction);
    const double u = a.gamma_rad / kDeg / dg, v = a.c_rad / kDeg / dc;
    if (grid.smooth) {
      const double j0 = std::clamp(std::floor(u), 0.0, static_cast<double>(ng - 2));
      const double f = std::clamp(u - j0, 0.0, 1.0);
      const double i0 = std::floor(v), gfrac = v - i0;
      const std::size_t ia = static_cast<std::size_t>(i0) % nc, ib = (ia + 1) % nc;
      const std::size_t ja = static_cast<std::size_t>(j0), jb = ja + 1;
      flux[ia * ng + ja] += p.flux_lm * (1.0 - gfrac) * (1.0 - f);
      flux[ia * ng + jb] += p.flux_lm * (1.0 - gfrac) * f;
      flux[ib * ng + ja] += p.flux_lm * gfrac * (1.0 - f);
      flux[ib * ng + jb] += p.flux_lm * gfrac * f;
    } else {
      const std::size_t j = std::min(static_cast<std::size_t>(std::lround(u)), ng - 1);
      const std::size_t i = static_cast<std::size_t>(std::lround(v)) % nc;
      flux[i * ng + j] += p.flux_lm;
    }
  }
  for (std::size_t k = 0; k < flux.size(); ++k) flux[k] /= grid.solid_angle_sr[k];
  return flux;
}

Result<MeritTarget> merit_target(const MeritGrid& grid, const photometry::Distribution& target_in) {
  if (Status s = photometry::validate(target_in); !s.ok()) return s.error();
  if (target_in.type != photometry::PhotometricType::C)
    return make_error("the target must be a Type C distribution (Type A and B are not compared on a C-γ grid)");
  const photometry::Distribution target = photometry::expand_symmetry(target_in);
  const std::size_t nc = grid.c_deg.size(), ng = grid.gamma_deg.size();
  const double dc = 360.0 / static_cast<double>(nc), h = (180.0 / static_cast<double>(ng - 1)) * kDeg;
  MeritTarget t;
  t.candela.assign(grid.size(), 0.0);
  // Each node's value: the target averaged with the node's basis function
  // (what the traced nodes estimate), over 8 C samples across its support
  // (every 5° for one column).
  for (std::size_t i = 0; i < nc; ++i) {
    std::vector<std::pair<double, double>> cs;  // C [deg], weight
    if (nc == 1) {
      for (int k = 0; k < 72; ++k) cs.push_back({5.0 * k, 1.0 / 72.0});
    } else {
      double sum = 0.0;
      for (int k = 0; k < 16; ++k) {
        const double x = -1.0 + (k + 0.5) / 8.0;  // in units of ΔC, over (−1, 1)
        const double w = grid.smooth ? 1.0 - std::abs(x) : (std::abs(x) <= 0.5 ? 1.0 : 0.0);
        cs.push_back({std::fmod(grid.c_deg[i] + x * dc + 360.0, 360.0), w});
        sum += w;
      }
      for (auto& c : cs) c.second /= sum;
    }
    for (std::size_t j = 0; j < ng; ++j) {
      const double gamma = grid.gamma_deg[j] * kDeg;
      const auto f = [&](double x) {
        double v = 0.0;
        for (const auto& [c, w] : cs) v += w * photometry::interpolate(target, c, x / kDeg);
        return v;
      };
      const double omega = gamma_integral(gamma, h, grid.smooth, [](double) { return 1.0; });
      t.candela[i * ng + j] = gamma_integral(gamma, h, grid.smooth, f) / omega;
    }
  }
  for (std::size_t k = 0; k < t.candela.size(); ++k) {
    t.peak_cd = std::max(t.peak_cd, t.candela[k]);
    t.flux_lm += t.candela[k] * grid.solid_angle_sr[k];
  }
  if (!(t.peak_cd > 0.0)) return make_error("the target has no light on the merit's grid");
  photometry::Distribution at_nodes = merit_distribution(grid, t.candela);
  t.beam_deg = photometry::beam_angle(at_nodes, 0.0).angle_deg;
  t.field_deg = photometry::field_angle(at_nodes, 0.0).angle_deg;
  t.opening = target.opening;
  at_nodes.opening = target.opening;
  t.ugr = merit_ugr(at_nodes, &t.ugr_undefined);
  return t;
}

double merit_ugr(const photometry::Distribution& d, std::string* why) {
  const photometry::UgrTable table = photometry::ugr_table(d);
  if (!table.defined) {
    if (why) *why = table.why_undefined;
    return std::numeric_limits<double>::quiet_NaN();
  }
  const std::vector<std::array<double, 2>> rooms = photometry::ugr_room_sizes();
  for (std::size_t r = 0; r < rooms.size(); ++r)
    if (rooms[r][0] == 4.0 && rooms[r][1] == 8.0) {
      const double a = table.rooms[r].crosswise[0], b = table.rooms[r].endwise[0];
      if (why && !std::isfinite(a) && !std::isfinite(b)) *why = "no light reaches the eye in the 4H × 8H room";
      return std::isfinite(a) && std::isfinite(b) ? std::max(a, b) : std::isfinite(a) ? a : b;
    }
  if (why) *why = "no 4H × 8H room in the UGR table";
  return std::numeric_limits<double>::quiet_NaN();
}

double merit_ugr(const photometry::Distribution& d, const MeritSpec::Ugr& cell, std::string* why) {
  const photometry::UgrTable table = photometry::ugr_table(d);
  if (!table.defined) {
    if (why) *why = table.why_undefined;
    return std::numeric_limits<double>::quiet_NaN();
  }
  const std::vector<std::array<double, 2>> rooms = photometry::ugr_room_sizes();
  for (std::size_t r = 0; r < rooms.size() && r < table.rooms.size(); ++r)
    if (rooms[r][0] == cell.x_h && rooms[r][1] == cell.y_h) {
      const std::size_t k = std::min(cell.reflectance_set, photometry::kUgrReflectances.size() - 1);
      const double a = table.rooms[r].crosswise[k], b = table.rooms[r].endwise[k];
      const double v = cell.view == 1   ? a
                       : cell.view == 2 ? b
                       : std::isfinite(a) && std::isfinite(b) ? std::max(a, b)
                       : std::isfinite(a)                     ? a
                                                              : b;
      if (why && !std::isfinite(v)) *why = "no light reaches the eye in the " + ugr_cell_name(cell) + " room";
      return v;
    }
  if (why) *why = "no " + ugr_cell_name(cell) + " room in the UGR table";
  return std::numeric_limits<double>::quiet_NaN();
}

std::string ugr_cell_name(const MeritSpec::Ugr& cell) {
  const std::array<double, 3>& r =
      photometry::kUgrReflectances[std::min(cell.reflectance_set, photometry::kUgrReflectances.size() - 1)];
  return format_number(cell.x_h) + "H × " + format_number(cell.y_h) + "H, " + format_number(100.0 * r[0]) + "/" +
         format_number(100.0 * r[1]) + "/" + format_number(100.0 * r[2]) + ", " +
         (cell.view == 1 ? "crosswise" : cell.view == 2 ? "endwise" : "the larger of crosswise and endwise");
}

void set_target_ugr(const MeritSpec& spec, const MeritGrid& grid, MeritTarget* target) {
  if (!spec.ugr) return;
  photometry::Distribution at_nodes = merit_distribution(grid, target->candela);
  at_nodes.opening = target->opening;
  target->ugr_undefined.clear();
  target->ugr = merit_ugr(at_nodes, *spec.ugr, &target->ugr_undefined);
}

Status check_merit_terms(const MeritSpec& spec, const MeritTarget& target, const std::string& design_path,
                         const std::string& target_path) {
  if (spec.ugr && !spec.ugr->limit && !std::isfinite(target.ugr))
    return make_error(design_path, spec.ugr->line,
                      "[merit]: 'ugr' without a limit compares the design's UGR with the target's, but the target " +
                          io::shown(std::filesystem::path(target_path).filename().string()) + " has none (" +
                          (target.ugr_undefined.empty() ? std::string("undefined") : target.ugr_undefined) +
                          "); give the target's luminous opening, or write the term as a limit (ugr = { limit = 19 })");
  for (auto [weight, angle, key, line, fraction] :
       {std::tuple{spec.beam_weight, target.beam_deg, "beam", spec.beam_line, "50"},
        std::tuple{spec.field_weight, target.field_deg, "field", spec.field_line, "10"}})
    if (weight > 0.0 && !std::isfinite(angle))
      return make_error(design_path, line ? line : spec.line,
                        std::string("[merit]: '") + key + "' compares with the target's " + key + " angle, but the target " +
                            io::shown(std::filesystem::path(target_path).filename().string()) +
                            " has none (its C0–C180 plane never falls to " + fraction + " % of its maximum)");
  return Ok{};
}

std::vector<std::string> merit_limit_names(const MeritSpec& spec) {
  std::vector<std::string> out;
  if (spec.max_cd_above && spec.max_cd_above->limit_cd) out.push_back("max_cd_above");
  if (spec.ugr && spec.ugr->limit) out.push_back("ugr");
  if (spec.bug)
    for (const BugZoneLimit& z : bug_zone_limits(*spec.bug)) out.push_back(z.name);
  if (spec.size) {
    if (spec.size->radius_mm) out.push_back("size radius");
    if (spec.size->height_mm) out.push_back("size height");
  }
  return out;
}

photometry::Distribution merit_distribution(const MeritGrid& grid, const std::vector<double>& candela) {
  photometry::Distribution d;
  d.type = photometry::PhotometricType::C;
  const std::size_t nc = grid.c_deg.size();
  d.symmetry = nc == 1 ? photometry::Symmetry::Rotational : photometry::Symmetry::None;
  d.horizontal_deg = grid.c_deg;
  d.vertical_deg = grid.gamma_deg;
  d.candela = candela;
  if (nc > 1) {  // the closing plane at 360
    d.horizontal_deg.push_back(360.0);
    d.candela.insert(d.candela.end(), candela.begin(), candela.begin() + static_cast<long>(grid.gamma_deg.size()));
  }
  d.absolute = true;
  d.lamps.push_back(photometry::LampSet{});
  d.lamps.back().flux_lm = photometry::kNaN;
  return d;
}

MeritValue evaluate_merit(const MeritSpec& spec, const MeritGrid& grid, const MeritTarget& target,
                          const std::vector<double>& candela, double lor, const MeritGeometry& geometry) {
  MeritValue m;
  m.lor = lor;
  m.target_beam_deg = target.beam_deg;
  double flux = 0.0;
  for (std::size_t k = 0; k < candela.size(); ++k) flux += candela[k] * grid.solid_angle_sr[k];
  const double scale = spec.absolute ? 1.0 : flux > 0.0 ? target.flux_lm / flux : 0.0;
  const std::size_t ng = grid.gamma_deg.size();
  double sum = 0.0, weights = 0.0;
  std::vector<double> scaled(candela.size());
  for (std::size_t k = 0; k < candela.size(); ++k) {
    scaled[k] = scale * candela[k];
    double w = spec.gamma_weights.empty() ? 1.0 : 0.0;
    const double gamma = grid.gamma_deg[k % ng];
    for (const GammaWeight& r : spec.gamma_weights)
      if (gamma >= r.from_deg - 1e-9 && gamma <= r.to_deg + 1e-9) {
        w = r.weight;
        break;
      }
    const double d = scaled[k] - target.candela[k];
    sum += w * d * d;
    weights += w;
  }
  m.candela_rms_pct = weights > 0.0 ? 100.0 * std::sqrt(sum / weights) / target.peak_cd : 0.0;
  m.merit = spec.candela_weight * m.candela_rms_pct + spec.lor_weight * 100.0 * (1.0 - lor);
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  photometry::Distribution at_nodes = merit_distribution(grid, scaled);
  at_nodes.opening = geometry.opening;
  m.beam_deg = flux > 0.0 ? photometry::beam_angle(at_nodes, 0.0).angle_deg : kNaN;
  m.field_deg = flux > 0.0 ? photometry::field_angle(at_nodes, 0.0).angle_deg : kNaN;
  m.target_field_deg = target.field_deg;
  // A spread term: the miss in degrees; 180 where either angle is undefined.
  const auto miss = [](double a, double b) { return std::isfinite(a) && std::isfinite(b) ? std::abs(a - b) : 180.0; };
  if (spec.beam_weight > 0.0) m.merit += spec.beam_weight * miss(m.beam_deg, target.beam_deg);
  if (spec.field_weight > 0.0) m.merit += spec.field_weight * miss(m.field_deg, target.field_deg);
  // The largest candela at γ ≥ the cut-off: a limit or a term.
  m.max_cd_above = kNaN;
  if (spec.max_cd_above) {
    double largest = 0.0;
    for (std::size_t k = 0; k < scaled.size(); ++k)
      if (grid.gamma_deg[k % ng] >= spec.max_cd_above->gamma_deg - 1e-9 &&
          grid.gamma_deg[k % ng] <= spec.max_cd_above->to_deg + 1e-9)
        largest = std::max(largest, scaled[k]);
    m.max_cd_above = largest;
    if (spec.max_cd_above->limit_cd)
      m.limits.push_back(limit_value("max_cd_above", largest, *spec.max_cd_above->limit_cd));
    else
      m.merit += spec.max_cd_above->weight * 100.0 * largest / target.peak_cd;
  }
  // UGR 4H × 8H of the merit's candela from the design's opening.
  m.ugr = kNaN;
  m.target_ugr = target.ugr;
  if (spec.ugr) {
    std::string why;
    m.ugr = flux > 0.0 ? merit_ugr(at_nodes, *spec.ugr, &why) : kNaN;
    const bool no_area = geometry.opening.shape == photometry::OpeningShape::Point || !why.empty();
    if (spec.ugr->limit) {
      if (!std::isfinite(m.ugr) && no_area && flux > 0.0) {
        m.error = "[merit] ugr (line " + std::to_string(spec.ugr->line) + "): the design's UGR is undefined: " +
                  (why.empty() ? "no luminous opening" : why);
      }
      // No light reaches the eye: the limit holds.
      m.limits.push_back(std::isfinite(m.ugr) ? limit_value("ugr", m.ugr, *spec.ugr->limit)
                                              : MeritLimitValue{"ugr", m.ugr, *spec.ugr->limit, -1.0});
    } else if (std::isfinite(m.ugr)) {
      m.merit += spec.ugr->weight * std::abs(m.ugr - target.ugr);
    } else {
      m.error = "[merit] ugr (line " + std::to_string(spec.ugr->line) + "): the design's UGR is undefined: " +
                (why.empty() ? "no luminous opening" : why);
    }
  }
  // BUG: each limited zone's lumens against its class limit.
  if (spec.bug) {
    const photometry::BugZones zones =
        flux > 0.0 ? photometry::bug_rating(at_nodes).zones_lm : photometry::BugZones{};
    for (const BugZoneLimit& z : bug_zone_limits(*spec.bug)) m.limits.push_back(limit_value(z.name, zones.*z.zone, z.limit));
  }
  if (spec.size) {
    if (spec.size->radius_mm) m.limits.push_back(limit_value("size radius", geometry.radius_mm, *spec.size->radius_mm));
    if (spec.size->height_mm) m.limits.push_back(limit_value("size height", geometry.height_mm, *spec.size->height_mm));
  }
  // Penalties: each limit's excess at its table's weight.
  for (const MeritLimitValue& l : m.limits) {
    const double weight = l.name == "max_cd_above" ? spec.max_cd_above->weight
                          : l.name == "ugr"         ? spec.ugr->weight
                          : l.name.rfind("bug", 0) == 0 ? spec.bug->weight
                                                        : spec.size->weight;
    const double excess = std::isfinite(l.c) ? std::max(0.0, l.c) : 1.0;
    m.penalty += weight * 100.0 * excess;
  }
  m.merit += m.penalty;
  return m;
}

}  // namespace gonio::design
