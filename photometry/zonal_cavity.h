// Coefficients of utilisation by the IES zonal cavity method (IES Lighting
// Handbook, "Lighting calculations": the zonal cavity method and its CU
// tables).
//
// The model, and the source of each formula:
// - The room is three surfaces: the ceiling cavity (effective reflectance
//   ρcc, the luminaires in its plane), the walls of the room cavity (ρw) and
//   the floor cavity (effective reflectance ρfc, 20 % by default), whose
//   plane is the work plane. Room cavity ratio RCR = 5 h (L + W) / (L W), so
//   wall area / floor area = 2 RCR / 5 (definition of RCR, IES Handbook).
// - Zonal lumens in the nine 10° zones below the horizontal, φ_N, as
//   fractions of the rated lamp flux (luminaire flux for absolute
//   photometry). Direct flux onto the work plane Σ K_N φ_N with the Handbook's
//   zonal multipliers K_N = exp(−A_N RCR^B_N), constants per zone
//   (A, B) = (0, 0), (0.041, 0.98), (0.070, 1.05), (0.100, 1.12),
//   (0.136, 1.16), (0.190, 1.25), (0.315, 1.25), (0.640, 1.25), (2.100, 0.80);
//   the rest of the downward flux lands on the walls, the upward flux on the
//   ceiling cavity.
// - Form factor from the floor cavity to the ceiling cavity f(RCR): the
//   Handbook's fit f = 0.026 + 0.503 e^(−0.270 RCR) + 0.470 e^(−0.119 RCR);
//   from either plane to the walls 1 − f; from the walls to either plane
//   (1 − f)·5/(2 RCR); from the walls to themselves the rest (reciprocity
//   and closure of the box).
// - The three surfaces are uniformly lit and diffuse; the inter-reflected
//   flux is the exact solution of that three-surface exchange (the system the
//   Handbook's C0…C3 closed forms solve). CU = the flux incident on the work
//   plane / the lamp flux. At RCR 0 the walls vanish and
//   CU = (φ_down + ρcc φ_up) / (1 − ρcc ρfc).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "photometry/distribution.h"

namespace gonio::photometry {

// The 18 customary ceiling-cavity / wall reflectance pairs [1].
inline constexpr std::array<std::array<double, 2>, 18> kCuReflectancePairs = {{
    {0.8, 0.7}, {0.8, 0.5}, {0.8, 0.3}, {0.8, 0.1}, {0.7, 0.7}, {0.7, 0.5},
    {0.7, 0.3}, {0.7, 0.1}, {0.5, 0.5}, {0.5, 0.3}, {0.5, 0.1}, {0.3, 0.5},
    {0.3, 0.3}, {0.3, 0.1}, {0.1, 0.5}, {0.1, 0.3}, {0.1, 0.1}, {0.0, 0.0}}};

// The Handbook's zonal multiplier of the 10° zone N (0 = 0–10° … 8 = 80–90°).
double zonal_multiplier(int zone, double rcr);

// The Handbook's floor-to-ceiling cavity form factor f(RCR).
double cavity_form_factor(double rcr);

// Share of the lamp flux in each 10° zone below the horizontal and above it.
struct CavityFlux {
  std::array<double, 9> zones{};  // φ_N, zone N = [10N°, 10N + 10°] [1]
  double up = 0.0;                // φ_up [1]
};

// CU of one room [1] from the flux shares.
double coefficient_of_utilization(const CavityFlux& flux, double rcr, double rho_cc, double rho_w,
                                  double rho_fc);

struct CuTable {
  bool defined = false;
  std::string why_undefined;
  double floor_reflectance = 0.2;
  std::vector<double> rcr;                 // 0, 1, …, 10
  std::vector<std::vector<double>> values; // [rcr][pair] fractions of the lamp flux
  double reference_flux_lm = kNaN;         // the flux CU refers to [lm]
  bool relative_to_lamps = true;           // false: luminaire flux (absolute photometry)
};

// The flux shares of `d` relative to the rated lamp flux (the luminaire's
// own flux for absolute photometry or a file without lamp flux).
CavityFlux cavity_flux(const Distribution& d, double* reference_flux_lm = nullptr,
                       bool* relative_to_lamps = nullptr);

// The table for RCR 0…10 and kCuReflectancePairs. Requires validate(d).ok().
CuTable cu_table(const Distribution& d, double floor_reflectance = 0.2);

}  // namespace gonio::photometry
