// The CIE flux code (CIE 52-1982, the interior-lighting applied method): five
// numbers that sketch a luminaire's flux distribution, e.g. "44 76 95 100 70".
//
// The lower hemisphere is cut into cones about the nadir of solid angle π/2,
// π and 3π/2 sr — half-angles acos(3/4) = 41.41°, acos(1/2) = 60° and
// acos(1/4) = 75.52° — and 2π sr (90°):
//   N1, N2, N3  the flux in the 41.41°, 60° and 75.52° cones as a percentage
//               of the downward flux (the flux in the 90° cone);
//   N4          the downward flux as a percentage of the luminaire's total
//               flux (the downward flux fraction; DLOR / LOR);
//   N5          the light output ratio in percent (luminaire flux over rated
//               lamp flux); undefined (NaN) for absolute photometry.
// Luminaire data sheets print them rounded to integers.
#pragma once

#include <string>

#include "photometry/distribution.h"

namespace gonio::photometry {

// Solid angles π/2, π, 3π/2 sr about the nadir: the cone half-angles [deg].
inline constexpr double kCieCone1Deg = 41.409622109270856;  // acos(3/4)
inline constexpr double kCieCone2Deg = 60.0;                // acos(1/2)
inline constexpr double kCieCone3Deg = 75.522487814070002;  // acos(1/4)

struct CieFluxCode {
  double n1 = kNaN;  // % of the downward flux within 41.41° of the nadir; NaN if no downward flux
  double n2 = kNaN;  // % of the downward flux within 60°
  double n3 = kNaN;  // % of the downward flux within 75.52°
  double n4 = kNaN;  // % of the total flux emitted downward; NaN if the luminaire is dark
  double n5 = kNaN;  // light output ratio [%]; NaN for absolute photometry
};

// Requires validate(d).ok().
CieFluxCode cie_flux_code(const Distribution& d);

class ZonalFlux;
// The same from zones already prepared, with the light output ratio [1]
// (NaN where undefined).
CieFluxCode cie_flux_code(const ZonalFlux& zones, double lor);

// "N1 N2 N3 N4 N5", each rounded to the nearest integer (ties to even); an
// undefined number prints as "-".
std::string to_string(const CieFluxCode& code);

}  // namespace gonio::photometry
