// The derived values of a distribution that data sheets, `gonio info` and
// the writers quote: flux, light output ratio, downward fraction, zonal
// lumens, peak intensity, beam and field angles, CIE flux code, efficacy.
#pragma once

#include <vector>

#include "photometry/beam.h"
#include "photometry/cie_flux_code.h"
#include "photometry/distribution.h"

namespace gonio::photometry {

// Flux in a zone of angle from the nadir.
struct Zone {
  double from_deg;  // [deg] from the nadir
  double to_deg;    // [deg] from the nadir
  double flux_lm;   // [lm]
};

struct Summary {
  // Total luminous flux of the distribution in absolute lumens: for relative
  // photometry the luminaire fitted with its rated lamps, for absolute
  // photometry as measured. This is `flux_lm` in `gonio info --json`.
  double flux_lm = kNaN;             // [lm]
  double rated_lamp_flux_lm = kNaN;  // sum over lamp sets [lm]; NaN for absolute photometry
  // Light output ratio, flux_lm / rated_lamp_flux_lm. Only relative
  // photometry has one: for absolute photometry (no rated lamp flux) it is
  // NaN and lor_defined is false.
  bool lor_defined = false;
  double lor = kNaN;               // [1]
  double downward_flux_lm = kNaN;  // γ 0…90° [lm]
  double upward_flux_lm = kNaN;    // γ 90…180° [lm]
  double dff = kNaN;               // downward flux fraction [1]; NaN when flux_lm is 0
  // Standard zones 0–30°, 0–40°, 0–60°, 0–90°, 90–180°, 0–180°, in that order.
  std::vector<Zone> zones;
  // The 18 zones of 10°: 0–10°, 10–20°, …, 170–180°.
  std::vector<Zone> zones_10deg;

  // The largest stored intensity and where it is: in the file's own grid
  // angles, and as Type C angles (the same for Type C files).
  double max_intensity_cd = kNaN;    // [cd]
  double max_horizontal_deg = kNaN;  // C or H of the maximum [deg]
  double max_vertical_deg = kNaN;    // γ or V of the maximum [deg]
  double max_c_deg = kNaN;           // C of the maximum [deg]
  double max_gamma_deg = kNaN;       // γ of the maximum [deg]

  // Beam (50 %) and field (10 %) angles, photometry/beam.h.
  BeamSpread beam_c0_c180, beam_c90_c270;
  BeamSpread field_c0_c180, field_c90_c270;

  CieFluxCode cie_flux_code;

  double input_power_w = kNaN;      // input_power_w(d) [W]; NaN if unknown
  double efficacy_lm_per_w = kNaN;  // flux_lm / input_power_w [lm/W]; NaN if the power is unknown
};

// Every value above for `d`. Requires validate(d).ok().
Summary summarize(const Distribution& d);

// The luminaire's electrical input [W]: `input_watts` if it is a positive
// number, else the sum of the lamp sets' wattage if every set has one, else NaN.
double input_power_w(const Distribution& d);

}  // namespace gonio::photometry
