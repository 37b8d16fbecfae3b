// The energy-conserving map of emitter angle to target angle that the direct
// designs share (design/reflector_design.h, design/lens_design.h): for a
// point source and a rotationally symmetric target (both averaged over C),
// the part catches the emitter's cone θ ∈ [from, to]; the light outside it
// leaves directly (below `from`, and above `to` where `direct_above_to`),
// D(φ) = I_s(φ); the part must add R(φ) = s·T(φ) − D(φ), s scaling the
// target to the flux that leaves (direct + efficiency × the cone's; or 1,
// `absolute`). F is the emitter's cumulative flux over the cone, G the
// cumulative of R from φ = 0, both on a 0.005° grid; the map is
// |φ(θ)| = G⁻¹(u·G_total) with u = (F(θ) − F(from))/F_cone, or 1 − u
// (`reversed`: the cone's inner edge to the target's widest angle).
#pragma once

#include <string>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::design {

struct FluxMapOptions {
  double from_deg = 0.0, to_deg = 180.0;  // the cone the part catches [deg from the nadir]
  bool absolute = false;                   // the target's candela as they are
  double efficiency = 1.0;                 // of the part: the flux it sends is efficiency × the cone's
  bool direct_above_to = false;            // light above `to` leaves directly too (else only below `from`)
  std::string part = "reflector";          // in messages: "a reflector can only add light"
  std::string widen = "a smaller FROM in --cone";  // in messages: how to catch more of the direct light
  bool allow_deficit = false;              // a target below the direct light: design the rest, no error
};

// The map's fluxes, as a design reports them (ReflectorDesign, LensDesign).
struct FluxMapFigures {
  double emitter_flux_lm = 0.0;  // the emitter's, all directions
  double cone_flux_lm = 0.0;     // into the cone, which the part catches
  double direct_flux_lm = 0.0;   // leaving directly (outside the cone)
  double target_scale = 1.0;     // s
  double target_from_deg = 0.0, target_to_deg = 0.0;  // where R > 0: the part's light's |φ| range
};

struct FluxMap : FluxMapFigures {
  std::vector<double> emitted, added;  // cumulative F (all γ) and G [lm] on the fine grid
  double from = 0.0, to = 0.0;         // [rad]
  // |φ| [rad] of the ray leaving the source at θ [rad].
  double phi(double theta, bool reversed) const;
};

// γ samples over 0…180° (0.005°) of the cumulative fluxes.
inline constexpr std::size_t kFluxMapSamples = 36001;

// Cumulative of 2π·f(γ)·sin γ over f's samples, evenly spaced over 0…180°
// (trapezoids) [lm for f in cd].
std::vector<double> cumulative_flux(const std::vector<double>& f);

// γ [rad] where the increasing cumulative table (evenly spaced over 0…π)
// reaches `value` (the first such γ).
double gamma_at_cumulative(const std::vector<double>& table, double value);

// Errors say why no part of this kind can give the target (without a file
// or line): no light in the cone, a target below the direct light (by more
// than 1 % of the part's flux), with `absolute` a flux the part cannot send.
Result<FluxMap> flux_map(const photometry::Distribution& emitter, const photometry::Distribution& target,
                         const FluxMapOptions& options);

}  // namespace gonio::design
