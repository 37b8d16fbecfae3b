#include "design/flux_map.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "design/reflector_design.h"
#include "photometry/format.h"

namespace gonio::design {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr std::size_t kFine = kFluxMapSamples;

// Linear interpolation of a table on the fine grid at γ [rad].
double at(const std::vector<double>& table, double gamma) {
  const double h = kPi / static_cast<double>(table.size() - 1);
  const double x = std::clamp(gamma / h, 0.0, static_cast<double>(table.size() - 1));
  const std::size_t i = std::min(static_cast<std::size_t>(x), table.size() - 2);
  const double t = x - static_cast<double>(i);
  return table[i] + t * (table[i + 1] - table[i]);
}

std::string deg(double rad) { return format_number(rad / kDeg, 4) + "°"; }

}  // namespace

std::vector<double> cumulative_flux(const std::vector<double>& f) {
  std::vector<double> out(f.size(), 0.0);
  const double h = kPi / static_cast<double>(f.size() - 1);
  for (std::size_t i = 1; i < f.size(); ++i) {
    const double a = f[i - 1] * std::sin(h * static_cast<double>(i - 1));
    const double b = f[i] * std::sin(h * static_cast<double>(i));
    out[i] = out[i - 1] + 2.0 * kPi * 0.5 * (a + b) * h;
  }
  return out;
}

double gamma_at_cumulative(const std::vector<double>& table, double value) {
  const double h = kPi / static_cast<double>(table.size() - 1);
  if (value <= table.front()) return 0.0;
  if (value >= table.back()) {
    std::size_t i = table.size() - 1;
    while (i > 0 && table[i - 1] >= table.back()) --i;
    return h * static_cast<double>(i);
  }
  const std::size_t i = static_cast<std::size_t>(std::lower_bound(table.begin(), table.end(), value) - table.begin());
  const double a = table[i - 1], b = table[i];
  const double t = b > a ? (value - a) / (b - a) : 0.0;
  return h * (static_cast<double>(i - 1) + t);
}

double FluxMap::phi(double theta, bool reversed) const {
  const double u = std::clamp((at(emitted, theta) - at(emitted, from)) / cone_flux_lm, 0.0, 1.0);
  return gamma_at_cumulative(added, (reversed ? 1.0 - u : u) * added.back());
}

Result<FluxMap> flux_map(const photometry::Distribution& emitter_in, const photometry::Distribution& target_in,
                         const FluxMapOptions& o) {
  const photometry::Distribution emitter = photometry::expand_symmetry(emitter_in);
  const photometry::Distribution target = photometry::expand_symmetry(target_in);
  if (!(o.from_deg >= 0.0 && o.to_deg <= 180.0 && o.from_deg < o.to_deg))
    return make_error("the cone must be FROM,TO with 0 ≤ FROM < TO ≤ 180 (degrees from the nadir)");
  const double from = o.from_deg * kDeg, to = o.to_deg * kDeg;
  std::vector<double> is(kFine), it(kFine), direct(kFine), inside(kFine);
  for (std::size_t i = 0; i < kFine; ++i) {
    const double g = 180.0 * static_cast<double>(i) / static_cast<double>(kFine - 1);
    is[i] = rotational_intensity(emitter, g);
    it[i] = rotational_intensity(target, g);
  }
  // The emitter's light inside the cone and below it, on the fine grid (a
  // cone edge between samples splits that sample's interval).
  const std::vector<double> emitted = cumulative_flux(is);
  FluxMap out;
  out.emitter_flux_lm = emitted.back();
  out.cone_flux_lm = at(emitted, to) - at(emitted, from);
  out.direct_flux_lm = at(emitted, from);
  if (!(out.cone_flux_lm > 1e-9 * out.emitter_flux_lm) || !(out.emitter_flux_lm > 0.0))
    return make_error("the emitter sends no light into the cone " + deg(from) + " … " + deg(to) +
                      ", which the " + o.part + " would catch");
  for (std::size_t i = 0; i < kFine; ++i) {
    const double g = kPi * static_cast<double>(i) / static_cast<double>(kFine - 1);
    direct[i] = g < from || (o.direct_above_to && g > to) ? is[i] : 0.0;
  }
  if (o.direct_above_to) out.direct_flux_lm += out.emitter_flux_lm - at(emitted, to);
  const double target_flux = cumulative_flux(it).back();
  if (!(target_flux > 0.0)) return make_error("the target emits no light");
  if (!(o.efficiency > 0.0 && o.efficiency <= 1.0))
    return make_error(std::string(o.part == "reflector" ? "the reflectance" : "the transmittance") + " must lie in (0, 1]");
  const double reflected_lm = o.efficiency * out.cone_flux_lm;
  out.target_scale = o.absolute ? 1.0 : (out.direct_flux_lm + reflected_lm) / target_flux;
  // What the reflector must add; where the target asks less than the direct
  // light, no reflector can take light away.
  std::vector<double> reflected(kFine);
  double worst = 0.0, worst_at = 0.0;
  for (std::size_t i = 0; i < kFine; ++i) {
    reflected[i] = out.target_scale * it[i] - direct[i];
    if (-reflected[i] > worst) {
      worst = -reflected[i];
      worst_at = kPi * static_cast<double>(i) / static_cast<double>(kFine - 1);
    }
  }
  std::vector<double> deficit(kFine);
  for (std::size_t i = 0; i < kFine; ++i) deficit[i] = std::max(-reflected[i], 0.0);
  const double deficit_lm = cumulative_flux(deficit).back();
  if (deficit_lm > 0.01 * reflected_lm && !o.allow_deficit)
    return make_error("the target asks for less light than the emitter sends there directly (at γ = " + deg(worst_at) +
                      ": " + format_number(out.target_scale * at(it, worst_at)) + " cd against " +
                      format_number(at(direct, worst_at)) + " cd direct; " + format_number(deficit_lm) +
                      " lm in all): a " + o.part + " can only add light. Widen the cone the " + o.part + " catches (" +
                      o.widen + ") or give a target with more light there");
  // Where the direct light already gives all but kNegligibleAdded of the
  // target, the part adds nothing: the residue there is rounding between two
  // tabulations of the same direct light (and of s), not light to place. Left
  // in, it grows G up to 180°, and G⁻¹ at u = 1 (the cone's rim) found the
  // last γ where G still grew (90° for a lens whose refracted light overlaps
  // the direct light): a map no part can make. Where there is no direct light
  // R = s·T, so a reflector's map above FROM is untouched.
  constexpr double kNegligibleAdded = 1e-3;
  for (std::size_t i = 0; i < kFine; ++i)
    reflected[i] = reflected[i] < kNegligibleAdded * out.target_scale * it[i] ? 0.0 : reflected[i];
  const std::vector<double> g = cumulative_flux(reflected);
  if (!(g.back() > 0.0)) return make_error("the target leaves nothing for the " + o.part + " to add to the direct light");
  if (o.absolute) {
    const double asked = g.back();
    if (std::abs(asked - reflected_lm) > 0.01 * reflected_lm)
      return make_error("the target asks the " + o.part + " for " + format_number(asked) +
                        " lm beyond the direct light, but it " + (o.part == "reflector" ? "reflects " : "transmits ") +
                        format_number(reflected_lm) + " lm of what the emitter sends into the cone " +
                        deg(from) + " … " + deg(to) + (asked > reflected_lm ? ": more flux than the emitter has there"
                                                                            : ": the rest would have nowhere to go") +
                        " (change the cone, or drop --absolute to design the target's shape)");
  }
  out.target_from_deg = gamma_at_cumulative(g, 0.0) / kDeg;
  out.target_to_deg = gamma_at_cumulative(g, g.back()) / kDeg;

  out.emitted = emitted;
  out.added = g;
  out.from = from;
  out.to = to;
  return out;
}

}  // namespace gonio::design
