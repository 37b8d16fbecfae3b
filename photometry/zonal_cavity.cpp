#include "photometry/zonal_cavity.h"

#include <cmath>

#include "photometry/flux.h"

namespace gonio::photometry {
namespace {

constexpr double kA[9] = {0.0, 0.041, 0.070, 0.100, 0.136, 0.190, 0.315, 0.640, 2.100};
constexpr double kB[9] = {0.0, 0.98, 1.05, 1.12, 1.16, 1.25, 1.25, 1.25, 0.80};

}  // namespace

double zonal_multiplier(int zone, double rcr) {
  GONIO_CHECK_MSG(zone >= 0 && zone < 9 && rcr >= 0.0, "zonal_multiplier: zone 0..8, RCR >= 0");
  if (zone == 0 || rcr == 0.0) return 1.0;
  return std::exp(-kA[zone] * std::pow(rcr, kB[zone]));
}

double cavity_form_factor(double rcr) {
  return 0.026 + 0.503 * std::exp(-0.270 * rcr) + 0.470 * std::exp(-0.119 * rcr);
}

double coefficient_of_utilization(const CavityFlux& flux, double rcr, double rho_cc, double rho_w,
                                  double rho_fc) {
  double down = 0.0, direct = 0.0;
  for (int n = 0; n < 9; ++n) {
    down += flux.zones[n];
    direct += zonal_multiplier(n, rcr) * flux.zones[n];
  }
  if (rcr <= 0.0) return (down + rho_cc * flux.up) / (1.0 - rho_cc * rho_fc);
  const double f = cavity_form_factor(rcr);
  const double f_pw = 1.0 - f;                // plane → walls
  const double f_wp = f_pw * 2.5 / rcr;       // walls → one plane
  const double f_ww = 1.0 - 2.0 * f_wp;       // walls → walls
  // Unknowns: incident flux on ceiling cavity c, walls w, floor cavity p.
  const double dir_c = flux.up, dir_w = down - direct, dir_p = direct;
  double m[3][4] = {{1, -f_wp * rho_w, -f * rho_fc, dir_c},
                    {-f_pw * rho_cc, 1 - f_ww * rho_w, -f_pw * rho_fc, dir_w},
                    {-f * rho_cc, -f_wp * rho_w, 1, dir_p}};
  for (int k = 0; k < 3; ++k)
    for (int r = k + 1; r < 3; ++r) {
      const double q = m[r][k] / m[k][k];
      for (int c = k; c < 4; ++c) m[r][c] -= q * m[k][c];
    }
  double in[3];
  for (int k = 2; k >= 0; --k) {
    double v = m[k][3];
    for (int c = k + 1; c < 3; ++c) v -= m[k][c] * in[c];
    in[k] = v / m[k][k];
  }
  return in[2];
}

CavityFlux cavity_flux(const Distribution& d, double* reference_flux_lm, bool* relative_to_lamps) {
  const ZonalFlux z(d);
  const double lamps = d.rated_lamp_flux_lm();
  const bool relative = !d.absolute && std::isfinite(lamps) && lamps > 0.0;
  const double ref = relative ? lamps : z.total_lm();
  if (reference_flux_lm) *reference_flux_lm = ref;
  if (relative_to_lamps) *relative_to_lamps = relative;
  CavityFlux out;
  if (!(ref > 0.0)) return out;
  for (int n = 0; n < 9; ++n) out.zones[n] = z.zone_lm(10.0 * n, 10.0 * n + 10.0) / ref;
  out.up = z.zone_lm(90.0, 180.0) / ref;
  return out;
}

CuTable cu_table(const Distribution& d, double floor_reflectance) {
  GONIO_CHECK_MSG(validate(d).ok(), "cu_table needs a valid distribution");
  CuTable t;
  t.floor_reflectance = floor_reflectance;
  const CavityFlux flux = cavity_flux(d, &t.reference_flux_lm, &t.relative_to_lamps);
  if (!(t.reference_flux_lm > 0.0)) {
    t.why_undefined = "the distribution emits no light";
    return t;
  }
  for (int r = 0; r <= 10; ++r) {
    t.rcr.push_back(r);
    std::vector<double> row;
    for (const auto& [cc, w] : kCuReflectancePairs)
      row.push_back(coefficient_of_utilization(flux, r, cc, w, floor_reflectance));
    t.values.push_back(std::move(row));
  }
  t.defined = true;
  return t;
}

}  // namespace gonio::photometry
