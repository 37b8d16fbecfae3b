#include "photometry/summary.h"

#include <cmath>
#include <numbers>

#include "photometry/angles.h"
#include "photometry/flux.h"
#include "photometry/frame.h"

namespace gonio::photometry {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

double input_power_w(const Distribution& d) {
  if (std::isfinite(d.input_watts) && d.input_watts > 0.0) return d.input_watts;
  if (d.lamps.empty()) return kNaN;
  double sum = 0.0;
  for (const LampSet& l : d.lamps) {
    if (!(std::isfinite(l.power_w) && l.power_w > 0.0)) return kNaN;
    sum += l.power_w;
  }
  return sum;
}

Summary summarize(const Distribution& d) {
  GONIO_CHECK_MSG(validate(d).ok(), "summarize needs a valid distribution");
  Summary s;
  const ZonalFlux zones(d);
  s.flux_lm = zones.total_lm();
  s.rated_lamp_flux_lm = d.rated_lamp_flux_lm();
  s.lor_defined = !d.absolute && s.rated_lamp_flux_lm > 0.0;
  if (s.lor_defined) s.lor = s.flux_lm / s.rated_lamp_flux_lm;
  s.downward_flux_lm = zones.zone_lm(0.0, 90.0);
  s.upward_flux_lm = zones.zone_lm(90.0, 180.0);
  if (s.flux_lm != 0.0) s.dff = s.downward_flux_lm / s.flux_lm;
  for (auto [from, to] :
       {std::pair{0.0, 30.0}, {0.0, 40.0}, {0.0, 60.0}, {0.0, 90.0}, {90.0, 180.0}, {0.0, 180.0}})
    s.zones.push_back({from, to, zones.zone_lm(from, to)});
  for (int i = 0; i < 18; ++i)
    s.zones_10deg.push_back({10.0 * i, 10.0 * (i + 1), zones.zone_lm(10.0 * i, 10.0 * (i + 1))});

  std::size_t best = 0;
  for (std::size_t i = 1; i < d.candela.size(); ++i)
    if (d.candela[i] > d.candela[best]) best = i;
  const std::size_t nv = d.vertical_count();
  s.max_intensity_cd = d.candela[best];
  s.max_horizontal_deg = d.horizontal_deg[best / nv];
  s.max_vertical_deg = d.vertical_deg[best % nv];
  if (d.type == PhotometricType::C) {
    s.max_c_deg = s.max_horizontal_deg;
    s.max_gamma_deg = s.max_vertical_deg;
  } else {
    const CGamma cg = c_gamma_from_direction(
        direction_from_grid(d.type, s.max_horizontal_deg, s.max_vertical_deg));
    s.max_c_deg = cg.c_rad / kDeg;
    s.max_gamma_deg = cg.gamma_rad / kDeg;
  }

  s.beam_c0_c180 = beam_angle(d, 0.0);
  s.beam_c90_c270 = beam_angle(d, 90.0);
  s.field_c0_c180 = field_angle(d, 0.0);
  s.field_c90_c270 = field_angle(d, 90.0);

  s.cie_flux_code = cie_flux_code(zones, s.lor);
  s.input_power_w = input_power_w(d);
  if (std::isfinite(s.input_power_w)) s.efficacy_lm_per_w = s.flux_lm / s.input_power_w;
  return s;
}

}  // namespace gonio::photometry
