#include "design/lens_design.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "design/design_file.h"
#include "design/flux_map.h"
#include "photometry/format.h"

namespace gonio::design {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

std::string deg(double rad) { return format_number(rad / kDeg, 4) + "°"; }

}  // namespace

Status integrate_lens_profile(const std::function<double(double)>& phi_of, const LensDesignOptions& o,
                              LensDesign& out) {
  if (!(o.ior > 1.0)) return make_error("the lens's index must be > 1");
  if (!(o.to_deg > 0.0 && o.to_deg < 90.0)) return make_error("the cone must be 0,TO with 0 < TO < 90");
  if (o.nodes < 4) return make_error("the profile needs at least 4 points");
  const double n = o.ior, to = o.to_deg * kDeg;
  // The largest turn a refraction from glass into air makes: the ray that
  // leaves grazing, at the critical angle: arccos(1/n).
  const double limit = std::acos(1.0 / n);
  const int wanted = std::max(o.steps, o.nodes);
  const int per_node = (wanted + o.nodes - 2) / (o.nodes - 1);
  const int steps = per_node * (o.nodes - 1);
  const double h = to / steps;
  out.theta.assign(static_cast<std::size_t>(steps) + 1, 0.0);
  out.phi.assign(out.theta.size(), 0.0);
  out.r.assign(out.theta.size(), 0.0);
  out.largest_deviation_deg = 0.0;
  for (int i = 0; i <= steps; ++i) {
    const double theta = h * i;
    const double d = phi_of(theta) - theta;
    out.largest_deviation_deg = std::max(out.largest_deviation_deg, std::abs(d) / kDeg);
    if (!(std::abs(d) < limit))
      return make_error("total internal reflection at the outer surface: the map turns the ray at θ = " + deg(theta) +
                        " to φ = " + deg(phi_of(theta)) + ", by " + deg(std::abs(d)) +
                        ", more than a refraction out of glass of index " + format_number(n) + " can (arccos(1/n) = " +
                        deg(limit) + "). Catch a narrower cone (--cone), or choose the other map (--map)");
  }
  // d(ln r)/dθ = sin(φ − θ)/(n − cos(φ − θ)); it depends on θ alone, so RK4 is Simpson's rule.
  auto slope = [&](double theta) {
    const double d = phi_of(theta) - theta;
    return std::sin(d) / (n - std::cos(d));
  };
  double y = std::log(o.distance_m);
  out.thinnest_m = INFINITY;
  for (int i = 0; i <= steps; ++i) {
    const double theta = h * i;
    const auto k = static_cast<std::size_t>(i);
    out.theta[k] = theta;
    out.phi[k] = phi_of(theta);
    out.r[k] = std::exp(y);
    out.thinnest_m = std::min(out.thinnest_m, out.r[k] - o.inner_radius_m);
    if (!(out.r[k] > o.inner_radius_m))
      return make_error("the lens would be thinner than zero at θ = " + deg(theta) + ": the outer surface comes to r = " +
                        format_number(out.r[k] * 1e3) + " mm, inside the inner sphere (" +
                        format_number(o.inner_radius_m * 1e3) + " mm). Give a larger --distance or a smaller --inner");
    if (i == steps) break;
    y += h * (slope(theta) + 4.0 * slope(theta + 0.5 * h) + slope(theta + h)) / 6.0;
    if (!std::isfinite(y) || y > std::log(o.distance_m) + 30.0)
      return make_error("the profile runs to infinity near θ = " + deg(theta));
  }
  out.outer = PolarProfile{};
  for (int j = 0; j < o.nodes; ++j) {
    const auto k = static_cast<std::size_t>(j * per_node);
    out.outer.theta.push_back(out.theta[k]);
    out.outer.r.push_back(out.r[k]);
  }
  out.inner_radius_m = o.inner_radius_m;
  return Ok{};
}

Result<LensDesign> design_lens(const photometry::Distribution& emitter, const photometry::Distribution& target,
                               const LensDesignOptions& o) {
  if (!(o.inner_radius_m > 0.0 && o.distance_m > o.inner_radius_m))
    return make_error("the outer surface's vertex (--distance) must lie beyond the inner sphere (--inner)");
  FluxMapOptions fo;
  fo.from_deg = 0.0;
  fo.to_deg = o.to_deg;
  fo.absolute = o.absolute;
  fo.efficiency = o.transmittance;
  fo.direct_above_to = true;
  fo.part = "lens";
  fo.widen = "a larger TO in --cone";
  fo.allow_deficit = o.allow_deficit;
  Result<FluxMap> fm = flux_map(emitter, target, fo);
  if (!fm.ok()) return fm.error();
  LensDesign out;
  static_cast<FluxMapFigures&>(out) = *fm;
  const double sign = o.map == ReflectorMap::Uncrossed ? 1.0 : -1.0;
  if (Status s = integrate_lens_profile([&](double theta) { return sign * fm->phi(theta, false); }, o, out); !s.ok())
    return s.error();
  return out;
}

double linear_lens_r(double k, double n, double theta, double r0) {
  const double a = k - 1.0;
  return r0 * std::pow((n - std::cos(a * theta)) / (n - 1.0), 1.0 / a);
}

photometry::Distribution linear_lens_target(const photometry::Distribution& emitter_in, double k, double to_deg,
                                            double step_deg) {
  const photometry::Distribution emitter = photometry::expand_symmetry(emitter_in);
  std::vector<double> gamma, candela;
  const int n = static_cast<int>(std::lround(180.0 / step_deg));
  for (int i = 0; i <= n; ++i) {
    const double gd = 180.0 * i / n;
    const double gr = std::max(gd * kDeg, 1e-7);
    double v = gd > to_deg ? rotational_intensity(emitter, gd) : 0.0;
    const double theta = gr / std::abs(k);  // |φ| = |k|·θ
    if (theta <= to_deg * kDeg + 1e-12)
      v += rotational_intensity(emitter, theta / kDeg) * std::sin(theta) / (std::abs(k) * std::sin(gr));
    gamma.push_back(gd);
    candela.push_back(v);
  }
  return rotational_distribution(gamma, candela);
}

io::TomlNode lens_design_document(const LensDesign& design, const std::string& emitter_file, double ior,
                                  const std::string& name, const std::string& emitter_key) {
  io::TomlNode doc = toml_table();
  toml_set(doc, "length_unit", toml_string("mm"));
  io::TomlNode glass = toml_table();
  toml_set(glass, "dielectric", toml_number(1.0));
  toml_set(glass, "ior", toml_number(ior));
  io::TomlNode materials = toml_table();
  toml_set(materials, "lens", std::move(glass));
  toml_set(doc, "materials", std::move(materials));
  io::TomlNode emitter = toml_table();
  toml_set(emitter, "name", toml_string("emitter"));
  toml_set(emitter, "position", toml_array({toml_number(0.0), toml_number(0.0), toml_number(0.0)}));
  toml_set(emitter, emitter_key, toml_string(emitter_file));
  toml_set(doc, "emitters", toml_array({std::move(emitter)}));
  io::TomlNode lens = toml_table();
  toml_set(lens, "name", toml_string(name));
  toml_set(lens, "material", toml_string("lens"));
  const double to_deg = std::round(design.outer.theta.back() / kDeg * 1e9) / 1e9;
  const double ri = std::round(design.inner_radius_m * 1e9) / 1e6;
  io::TomlNode inner = toml_table();
  toml_set(inner, "profile", toml_string("polar"));
  toml_set(inner, "theta_deg", toml_array({toml_number(0.0), toml_number(to_deg)}));
  toml_set(inner, "r", toml_array({toml_number(ri), toml_number(ri)}));
  toml_set(lens, "inner", std::move(inner));
  io::TomlNode outer = toml_table();
  toml_set(outer, "profile", toml_string("polar"));
  std::vector<io::TomlNode> theta, r;
  for (std::size_t i = 0; i < design.outer.theta.size(); ++i) {
    theta.push_back(toml_number(std::round(design.outer.theta[i] / kDeg * 1e9) / 1e9));
    const double mm = std::round(design.outer.r[i] * 1e9) / 1e6;
    r.push_back(toml_variable(mm, std::round(0.8 * mm * 1e6) / 1e6, std::round(1.25 * mm * 1e6) / 1e6));
  }
  toml_set(outer, "theta_deg", toml_array(std::move(theta)));
  toml_set(outer, "r", toml_array(std::move(r)));
  toml_set(lens, "outer", std::move(outer));
  toml_set(doc, "lenses", toml_array({std::move(lens)}));
  return doc;
}

}  // namespace gonio::design
