#include "photometry/cie_flux_code.h"

#include <cmath>
#include <cstdio>

#include "photometry/flux.h"

namespace gonio::photometry {

CieFluxCode cie_flux_code(const ZonalFlux& zones, double lor) {
  CieFluxCode code;
  const double total = zones.total_lm();
  const double down = zones.zone_lm(0.0, 90.0);
  if (down > 0.0) {
    code.n1 = 100.0 * zones.zone_lm(0.0, kCieCone1Deg) / down;
    code.n2 = 100.0 * zones.zone_lm(0.0, kCieCone2Deg) / down;
    code.n3 = 100.0 * zones.zone_lm(0.0, kCieCone3Deg) / down;
  }
  if (total > 0.0) code.n4 = 100.0 * down / total;
  code.n5 = 100.0 * lor;
  return code;
}

CieFluxCode cie_flux_code(const Distribution& d) {
  const ZonalFlux zones(d);
  const double lamps = d.rated_lamp_flux_lm();
  return cie_flux_code(zones, !d.absolute && lamps > 0.0 ? zones.total_lm() / lamps : kNaN);
}

std::string to_string(const CieFluxCode& code) {
  std::string out;
  for (double n : {code.n1, code.n2, code.n3, code.n4, code.n5}) {
    if (!out.empty()) out += ' ';
    if (std::isfinite(n)) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.0f", std::nearbyint(n));
      out += buf;
    } else {
      out += '-';
    }
  }
  return out;
}

}  // namespace gonio::photometry
