#include "design/reflector_design.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "design/design_file.h"
#include "design/flux_map.h"
#include "photometry/format.h"

namespace gonio::design {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
std::string deg(double rad) { return format_number(rad / kDeg, 4) + "°"; }

}  // namespace

double rotational_intensity(const photometry::Distribution& expanded, double gamma_deg) {
  if (expanded.horizontal_deg.size() <= 2) return photometry::interpolate(expanded, 0.0, gamma_deg);
  double sum = 0.0;
  const int planes = 72;
  for (int i = 0; i < planes; ++i) sum += photometry::interpolate(expanded, 5.0 * i, gamma_deg);
  return sum / planes;
}

photometry::Distribution rotational_distribution(const std::vector<double>& gamma_deg,
                                                 const std::vector<double>& candela) {
  photometry::Distribution d;
  d.type = photometry::PhotometricType::C;
  d.symmetry = photometry::Symmetry::Rotational;
  d.horizontal_deg = {0.0};
  d.vertical_deg = gamma_deg;
  d.candela = candela;
  d.absolute = true;
  d.lamps.push_back(photometry::LampSet{});
  d.lamps.back().flux_lm = photometry::kNaN;
  return d;
}

Result<ReflectorDesign> design_reflector(const photometry::Distribution& emitter_in,
                                         const photometry::Distribution& target_in,
                                         const ReflectorDesignOptions& o) {
  if (!(o.from_deg >= 0.0 && o.to_deg <= 180.0 && o.from_deg < o.to_deg))
    return make_error("the cone must be FROM,TO with 0 ≤ FROM < TO ≤ 180 (degrees from the nadir)");
  if (o.nodes < 4) return make_error("the profile needs at least 4 points");
  const photometry::Distribution emitter = photometry::expand_symmetry(emitter_in);
  const photometry::Distribution target = photometry::expand_symmetry(target_in);
  const double from = o.from_deg * kDeg, to = o.to_deg * kDeg;

  FluxMapOptions fo;
  fo.from_deg = o.from_deg;
  fo.to_deg = o.to_deg;
  fo.absolute = o.absolute;
  fo.efficiency = o.reflectance;
  fo.allow_deficit = o.allow_deficit;
  Result<FluxMap> fm = flux_map(emitter, target, fo);
  if (!fm.ok()) return fm.error();
  ReflectorDesign out;
  static_cast<FluxMapFigures&>(out) = *fm;

  // The map θ → φ.
  const double sign = o.map == ReflectorMap::Uncrossed ? 1.0 : -1.0;
  auto phi_of = [&](double theta) { return sign * fm->phi(theta, true); };
  // RK4 from θ_to down to θ_from on d(ln r)/dθ = cot((φ − θ)/2).
  const int n = std::max(o.steps, o.nodes);
  const int per_node = (n + o.nodes - 2) / (o.nodes - 1);
  const int steps = per_node * (o.nodes - 1);
  const double h = (to - from) / steps;
  out.theta.resize(static_cast<std::size_t>(steps) + 1);
  out.phi.resize(out.theta.size());
  out.r.resize(out.theta.size());
  auto slope = [&](double theta) {
    const double half = 0.5 * (phi_of(theta) - theta);
    return std::cos(half) / std::sin(half);
  };
  // φ − θ must keep its sign over the cone.
  double first_sign = 0.0;
  for (int i = 0; i <= steps; ++i) {
    const double theta = from + h * i;
    const double d = phi_of(theta) - theta;
    const double s = d > 0.0 ? 1.0 : -1.0;
    if (std::abs(d) < 1e-9 || (first_sign != 0.0 && s != first_sign))
      return make_error("the map sends the ray at θ = " + deg(theta) + " back along itself (φ = " +
                        deg(phi_of(theta)) + "): a reflector there would have to pass through the source or run to "
                        "infinity. Choose the crossed map (--map crossed) or another cone (--cone)");
    first_sign = s;
  }
  double y = std::log(o.distance_m);
  for (int i = steps; i >= 0; --i) {
    const double theta = from + h * i;
    const auto k = static_cast<std::size_t>(i);
    out.theta[k] = theta;
    out.phi[k] = phi_of(theta);
    out.r[k] = std::exp(y);
    if (i == 0) break;
    // The slope depends on θ alone, so RK4 is Simpson's rule over each step (downward in θ).
    const double k1 = slope(theta), k2 = slope(theta - 0.5 * h), k4 = slope(theta - h);
    y -= h * (k1 + 4.0 * k2 + k4) / 6.0;
    if (!std::isfinite(y) || y > std::log(o.distance_m) + 30.0)
      return make_error("the profile runs to infinity near θ = " + deg(theta) + ": the map turns the ray there by "
                        "almost nothing");
  }
  for (int j = 0; j < o.nodes; ++j) {
    const auto k = static_cast<std::size_t>(j * per_node);
    out.profile.theta.push_back(out.theta[k]);
    out.profile.r.push_back(out.r[k]);
  }
  return out;
}

photometry::Distribution linear_map_target(const photometry::Distribution& emitter_in, double k, double c,
                                           double from_deg, double to_deg, double step_deg) {
  const photometry::Distribution emitter = photometry::expand_symmetry(emitter_in);
  std::vector<double> gamma, candela;
  const int n = static_cast<int>(std::lround(180.0 / step_deg));
  const double from = from_deg * kDeg, to = to_deg * kDeg;
  for (int i = 0; i <= n; ++i) {
    const double gd = 180.0 * i / n;
    const double gr = std::max(gd * kDeg, 1e-7);
    double v = gd < from_deg ? rotational_intensity(emitter, gd) : 0.0;
    for (double sgn : {1.0, -1.0}) {  // φ = ±γ
      const double theta = (sgn * gr - c) / k;
      if (theta >= from - 1e-12 && theta <= to + 1e-12)
        v += rotational_intensity(emitter, theta / kDeg) * std::sin(theta) / (std::abs(k) * std::sin(gr));
    }
    gamma.push_back(gd);
    candela.push_back(v);
  }
  return rotational_distribution(gamma, candela);
}

io::TomlNode reflector_design_document(const ReflectorDesign& design, const std::string& emitter_file,
                                       double reflectance, const std::string& name, const std::string& emitter_key) {
  io::TomlNode doc = toml_table();
  toml_set(doc, "length_unit", toml_string("mm"));
  io::TomlNode mirror = toml_table();
  toml_set(mirror, "mirror", toml_number(reflectance));
  io::TomlNode materials = toml_table();
  toml_set(materials, "reflector", std::move(mirror));
  toml_set(doc, "materials", std::move(materials));
  io::TomlNode emitter = toml_table();
  toml_set(emitter, "name", toml_string("emitter"));
  toml_set(emitter, "position", toml_array({toml_number(0.0), toml_number(0.0), toml_number(0.0)}));
  toml_set(emitter, emitter_key, toml_string(emitter_file));
  toml_set(doc, "emitters", toml_array({std::move(emitter)}));
  io::TomlNode reflector = toml_table();
  toml_set(reflector, "name", toml_string(name));
  toml_set(reflector, "material", toml_string("reflector"));
  toml_set(reflector, "profile", toml_string("polar"));
  std::vector<io::TomlNode> theta, r;
  for (std::size_t i = 0; i < design.profile.theta.size(); ++i) {
    // Rounded to what the file needs: 1e-9 of a degree, 1 nm.
    theta.push_back(toml_number(std::round(design.profile.theta[i] / kDeg * 1e9) / 1e9));
    const double mm = std::round(design.profile.r[i] * 1e9) / 1e6;
    r.push_back(toml_variable(mm, std::round(0.8 * mm * 1e6) / 1e6, std::round(1.25 * mm * 1e6) / 1e6));
  }
  toml_set(reflector, "theta_deg", toml_array(std::move(theta)));
  toml_set(reflector, "r", toml_array(std::move(r)));
  toml_set(doc, "reflectors", toml_array({std::move(reflector)}));
  return doc;
}

double linear_map_r(double k, double c, double theta, double to, double distance_m) {
  auto f = [&](double t) { return std::pow(std::abs(std::sin(((k - 1.0) * t + c) / 2.0)), 2.0 / (k - 1.0)); };
  return distance_m * f(theta) / f(to);
}

std::vector<float> die_rays(const photometry::Distribution& emitter_in, double width_m, double height_m,
                            std::size_t count) {
  const photometry::Distribution emitter = photometry::expand_symmetry(emitter_in);
  std::vector<double> is(kFluxMapSamples);
  for (std::size_t i = 0; i < kFluxMapSamples; ++i)
    is[i] = rotational_intensity(emitter, 180.0 * static_cast<double>(i) / static_cast<double>(kFluxMapSamples - 1));
  const std::vector<double> cum = cumulative_flux(is);
  std::vector<float> rays;
  if (count == 0 || !(cum.back() > 0.0)) return rays;
  rays.reserve(7 * count);
  const double flux = cum.back() / static_cast<double>(count);
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  std::mt19937_64 random(1);
  std::uniform_real_distribution<double> unit(-0.5, 0.5);
  for (std::size_t i = 0; i < count; ++i) {
    const double gamma = gamma_at_cumulative(cum, (static_cast<double>(i) + 0.5) / static_cast<double>(count) * cum.back());
    const double c = 2.0 * kPi * std::fmod(golden * static_cast<double>(i), 1.0);
    const double x = unit(random) * width_m, y = unit(random) * height_m;
    // The photometric frame: nadir −Z, C0 +X, C90 +Y.
    const double kx = std::sin(gamma) * std::cos(c), ky = std::sin(gamma) * std::sin(c), kz = -std::cos(gamma);
    for (double v : {x * 1e3, y * 1e3, 0.0, kx, ky, kz, flux}) rays.push_back(static_cast<float>(v));
  }
  return rays;
}

photometry::Distribution feedback_target(const photometry::Distribution& design_target_in,
                                         const photometry::Distribution& target_in,
                                         const photometry::Distribution& traced_in, double step_deg,
                                         const std::function<double(double)>& share) {
  const photometry::Distribution design_target = photometry::expand_symmetry(design_target_in);
  const photometry::Distribution target = photometry::expand_symmetry(target_in);
  const photometry::Distribution traced = photometry::expand_symmetry(traced_in);
  // The fluxes of the target and the trace, on the fine grid.
  std::vector<double> t_fine(kFluxMapSamples), p_fine(kFluxMapSamples);
  for (std::size_t i = 0; i < kFluxMapSamples; ++i) {
    const double g = 180.0 * static_cast<double>(i) / static_cast<double>(kFluxMapSamples - 1);
    t_fine[i] = rotational_intensity(target, g);
    p_fine[i] = rotational_intensity(traced, g);
  }
  const double t_flux = cumulative_flux(t_fine).back(), p_flux = cumulative_flux(p_fine).back();
  const double s = p_flux > 0.0 ? t_flux / p_flux : 1.0;
  // The ratio on the traced grid's nodes: the target averaged over each
  // node's band (midpoints to the neighbours, weighted by sin γ) against the
  // trace's node value, which is that band's flux over its solid angle.
  const std::vector<double>& nodes = traced.vertical_deg;
  std::vector<double> ratio(nodes.size(), 1.0);
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    const double lo = j == 0 ? nodes[0] : 0.5 * (nodes[j - 1] + nodes[j]);
    const double hi = j + 1 == nodes.size() ? nodes[j] : 0.5 * (nodes[j] + nodes[j + 1]);
    double sum = 0.0, weight = 0.0;
    const int n = 64;
    for (int m = 0; m < n; ++m) {
      const double g = lo + (hi - lo) * (m + 0.5) / n;
      const double w = std::max(std::sin(g * kDeg), 1e-6);
      sum += w * rotational_intensity(target, g);
      weight += w;
    }
    const double t_bar = hi > lo ? sum / weight : rotational_intensity(target, nodes[j]);
    const double p = s * rotational_intensity(traced, nodes[j]);
    if (t_bar > 0.0 && p > 0.0) ratio[j] = std::clamp(t_bar / p, 0.5, 2.0);
    if (share) ratio[j] = std::pow(ratio[j], std::clamp(share(nodes[j]), 0.0, 1.0));
  }
  auto ratio_at = [&](double g) {
    if (nodes.size() < 2) return 1.0;
    const auto it = std::upper_bound(nodes.begin(), nodes.end(), g);
    if (it == nodes.begin()) return ratio.front();
    if (it == nodes.end()) return ratio.back();
    const std::size_t j = static_cast<std::size_t>(it - nodes.begin());
    const double t = (g - nodes[j - 1]) / (nodes[j] - nodes[j - 1]);
    return ratio[j - 1] + t * (ratio[j] - ratio[j - 1]);
  };
  std::vector<double> gamma, candela;
  const int n = static_cast<int>(std::lround(180.0 / step_deg));
  for (int i = 0; i <= n; ++i) {
    const double g = 180.0 * i / n;
    gamma.push_back(g);
    candela.push_back(rotational_intensity(design_target, g) * ratio_at(g));
  }
  // Renormalised to T_n's flux.
  std::vector<double> before(kFluxMapSamples), after(kFluxMapSamples);
  const photometry::Distribution corrected = photometry::expand_symmetry(rotational_distribution(gamma, candela));
  for (std::size_t i = 0; i < kFluxMapSamples; ++i) {
    const double g = 180.0 * static_cast<double>(i) / static_cast<double>(kFluxMapSamples - 1);
    before[i] = rotational_intensity(design_target, g);
    after[i] = rotational_intensity(corrected, g);
  }
  const double b = cumulative_flux(before).back(), a = cumulative_flux(after).back();
  if (a > 0.0 && b > 0.0)
    for (double& v : candela) v *= b / a;
  return rotational_distribution(gamma, candela);
}

photometry::Distribution feedback_target_cumulative(const photometry::Distribution& design_target_in,
                                                    const photometry::Distribution& target_in,
                                                    const photometry::Distribution& traced_in, double step_deg) {
  const photometry::Distribution dn = photometry::expand_symmetry(design_target_in);
  const photometry::Distribution t = photometry::expand_symmetry(target_in);
  const photometry::Distribution p = photometry::expand_symmetry(traced_in);
  // The target as the trace bins it: averaged over each traced node's γ
  // band (weighted by sin γ) and interpolated linearly between the nodes as
  // the trace is, so that a trace equal to the target shifts nothing (a
  // target's edge, sharp, against the trace's 1° bins would).
  const std::vector<double>& nodes = p.vertical_deg;
  std::vector<double> t_bar(nodes.size(), 0.0);
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    const double lo = j == 0 ? nodes[0] : 0.5 * (nodes[j - 1] + nodes[j]);
    const double hi = j + 1 == nodes.size() ? nodes[j] : 0.5 * (nodes[j] + nodes[j + 1]);
    double sum = 0.0, weight = 0.0;
    for (int m = 0; m < 64; ++m) {
      const double g = lo + (hi - lo) * (m + 0.5) / 64;
      const double w = std::max(std::sin(g * kDeg), 1e-6);
      sum += w * rotational_intensity(t, g);
      weight += w;
    }
    t_bar[j] = hi > lo ? sum / weight : rotational_intensity(t, nodes[j]);
  }
  auto t_binned = [&](double g) {
    if (nodes.size() < 2) return rotational_intensity(t, g);
    const auto it = std::upper_bound(nodes.begin(), nodes.end(), g);
    if (it == nodes.begin()) return t_bar.front();
    if (it == nodes.end()) return t_bar.back();
    const std::size_t j = static_cast<std::size_t>(it - nodes.begin());
    const double f = (g - nodes[j - 1]) / (nodes[j] - nodes[j - 1]);
    return t_bar[j - 1] + f * (t_bar[j] - t_bar[j - 1]);
  };
  std::vector<double> fd(kFluxMapSamples), ft(kFluxMapSamples), fp(kFluxMapSamples);
  for (std::size_t i = 0; i < kFluxMapSamples; ++i) {
    const double g = 180.0 * static_cast<double>(i) / static_cast<double>(kFluxMapSamples - 1);
    fd[i] = rotational_intensity(dn, g);
    ft[i] = t_binned(g);
    fp[i] = rotational_intensity(p, g);
  }
  const std::vector<double> cd = cumulative_flux(fd), ct = cumulative_flux(ft), cp = cumulative_flux(fp);
  std::vector<double> gamma, candela;
  const int n = static_cast<int>(std::lround(180.0 / step_deg));
  for (int i = 0; i <= n; ++i) gamma.push_back(180.0 * i / n);
  if (!(cd.back() > 0.0 && ct.back() > 0.0 && cp.back() > 0.0)) {
    for (double g : gamma) candela.push_back(rotational_intensity(dn, g));
    return rotational_distribution(gamma, candela);
  }
  // The moved quantiles γ_N(u) on a fine grid of u, increasing.
  const int m = 20000;
  std::vector<double> u(m + 1), moved(m + 1);
  for (int k = 0; k <= m; ++k) {
    const double q = static_cast<double>(k) / m;
    u[static_cast<std::size_t>(k)] = q;
    const double g = gamma_at_cumulative(cd, q * cd.back()) + gamma_at_cumulative(ct, q * ct.back()) -
                     gamma_at_cumulative(cp, q * cp.back());
    moved[static_cast<std::size_t>(k)] =
        std::clamp(k == 0 ? g : std::max(g, moved[static_cast<std::size_t>(k - 1)]), 0.0, kPi);
  }
  // The cumulative share at γ: the largest u whose moved quantile is ≤ γ (interpolated).
  auto share_below = [&](double g) {
    const auto it = std::upper_bound(moved.begin(), moved.end(), g);
    if (it == moved.begin()) return 0.0;
    if (it == moved.end()) return 1.0;
    const std::size_t k = static_cast<std::size_t>(it - moved.begin());
    const double a = moved[k - 1], b = moved[k];
    return u[k - 1] + (b > a ? (g - a) / (b - a) : 0.0) * (u[k] - u[k - 1]);
  };
  // Intensity of each γ node: the flux between its band's edges over the band's solid angle.
  for (std::size_t i = 0; i < gamma.size(); ++i) {
    const double lo = (i == 0 ? gamma[0] : 0.5 * (gamma[i - 1] + gamma[i])) * kDeg;
    const double hi = (i + 1 == gamma.size() ? gamma[i] : 0.5 * (gamma[i] + gamma[i + 1])) * kDeg;
    const double omega = 2.0 * kPi * (std::cos(lo) - std::cos(hi));
    candela.push_back(omega > 0.0 ? cd.back() * (share_below(hi) - share_below(lo)) / omega : 0.0);
  }
  return rotational_distribution(gamma, candela);
}

double design_share(const photometry::Distribution& emitter, const photometry::Distribution& target, double gamma_deg,
                    double from_deg, double to_deg, bool direct_above_to, double target_scale) {
  const double t = target_scale * rotational_intensity(target, gamma_deg);
  if (!(t > 0.0)) return 0.0;
  const bool direct = gamma_deg < from_deg || (direct_above_to && gamma_deg > to_deg);
  const double d = direct ? rotational_intensity(emitter, gamma_deg) : 0.0;
  return std::clamp(1.0 - d / t, 0.0, 1.0);
}

double away_from_steps(const photometry::Distribution& target, double peak_cd, double gamma_deg, double band_deg,
                       double jump) {
  const int n = static_cast<int>(std::ceil(4.0 * band_deg));  // pairs starting every 0.5° over [γ − band − ½, γ + band − ½]
  for (int i = 0; i <= n; ++i) {
    const double a = std::clamp(gamma_deg - band_deg + 0.5 * i - 0.5, 0.0, 179.0);
    if (std::abs(rotational_intensity(target, a + 1.0) - rotational_intensity(target, a)) > jump * peak_cd) return 0.0;
  }
  return 1.0;
}

double in_target_scale(const photometry::Distribution& target_in, const photometry::Distribution& traced_in) {
  const photometry::Distribution target = photometry::expand_symmetry(target_in);
  const photometry::Distribution traced = photometry::expand_symmetry(traced_in);
  std::vector<double> t(kFluxMapSamples), p(kFluxMapSamples);
  double peak = 0.0;
  for (std::size_t i = 0; i < kFluxMapSamples; ++i) {
    const double g = 180.0 * static_cast<double>(i) / static_cast<double>(kFluxMapSamples - 1);
    t[i] = rotational_intensity(target, g);
    p[i] = rotational_intensity(traced, g);
    peak = std::max(peak, t[i]);
  }
  for (std::size_t i = 0; i < kFluxMapSamples; ++i)
    if (!(t[i] > 1e-6 * peak)) t[i] = p[i] = 0.0;
  const double tf = cumulative_flux(t).back(), pf = cumulative_flux(p).back();
  return tf > 0.0 && pf > 0.0 ? tf / pf : 1.0;
}

double profile_change(const PolarProfile& a, const PolarProfile& b) {
  if (a.r.size() != b.r.size() || a.r.empty()) return std::numeric_limits<double>::infinity();
  double worst = 0.0;
  for (std::size_t i = 0; i < a.r.size(); ++i) worst = std::max(worst, std::abs(b.r[i] / a.r[i] - 1.0));
  return worst;
}

}  // namespace gonio::design
