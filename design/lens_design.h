// Direct design of a lens of revolution for a point source and a rotationally
// symmetric target (`gonio design lens`, docs/design.md, "Direct design of a
// lens"): the refractive counterpart of the reflector's equation.
//
// The source sits at the origin inside a cavity: the lens's inner surface is
// a sphere of radius r_i centred on it, which every ray meets at normal
// incidence and passes undeviated. Inside the glass (index n) the ray at θ
// (from the nadir) meets the outer surface r(θ) and leaves at φ. Snell's law
// in vector form, n·u − v ∥ N (u, v the unit directions inside and outside,
// N the surface normal), with the surface's tangent r'·u + r·∂u/∂θ, gives
//
//   d(ln r)/dθ = sin(φ − θ) / (n − cos(φ − θ)),
//
// (n = 1 with v the reflected ray would be the mirror's cot((φ − θ)/2)
// instead). The map θ → φ is design/flux_map.h's over the cone [0, TO]:
// uncrossed (default), φ = +G⁻¹(u·G) — the axis to the axis, the cone's rim
// to the target's widest angle, every ray on its own side; crossed, φ the
// same magnitude across the axis (the rays cross it beyond the lens). Light
// above TO leaves directly.
//
// Exact cases: for φ = kθ the profile is r(θ) = r₀·((n − cos((k − 1)θ))/(n −
// 1))^(1/(k − 1)); k = 0 (collimated) is r₀(n − 1)/(n − cos θ), an ellipse of
// eccentricity 1/n with the source at its far focus.
//
// Errors: a refraction no surface can make (|φ − θ| ≥ arccos(1/n): total
// internal reflection at the outer surface), a profile that would come
// inside the inner sphere (a lens thinner than zero), and the map's own
// (design/flux_map.h).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "design/reflector_design.h"
#include "design/revolved.h"
#include "io/model/toml_tree.h"
#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::design {

struct LensDesignOptions {
  double to_deg = 60.0;          // the cone the lens catches: θ from 0 to TO [deg]
  ReflectorMap map = ReflectorMap::Uncrossed;
  double ior = 1.491;            // the glass's index (PMMA at 587.6 nm)
  double inner_radius_m = 0.005; // the cavity: the inner sphere's radius [m]
  double distance_m = 0.01;      // r(0): the outer surface's vertex below the source [m]
  int nodes = 61;                // the outer polar table's points
  int steps = 20000;             // RK4 steps over the cone
  bool absolute = false;         // the target's candela as they are
  double transmittance = 1.0;    // the share of the cone's flux the target is scaled to
  // Where the target asks less than the direct light (above TO), the lens
  // adds nothing there instead of an error: the feedback's corrected targets
  // (design::feedback_target), as ReflectorDesignOptions::allow_deficit.
  bool allow_deficit = false;
};

struct LensDesign : FluxMapFigures {  // direct light: θ > TO
  PolarProfile outer;                  // `nodes` points over [0, TO] [rad, m]
  double inner_radius_m = 0.0;
  std::vector<double> theta, phi, r;   // the fine solution [rad, rad, m]
  double largest_deviation_deg = 0.0;  // max |φ − θ|
  double thinnest_m = 0.0;             // min r(θ) − r_i
};

// The outer profile for a given map φ(θ) [rad → rad], integrated from
// r(0) = distance over [0, to] with `steps` RK4 steps: theta, phi, r filled.
// Errors: total internal reflection, thinner than zero.
Status integrate_lens_profile(const std::function<double(double)>& phi_of, const LensDesignOptions& options,
                              LensDesign& out);

Result<LensDesign> design_lens(const photometry::Distribution& emitter, const photometry::Distribution& target,
                               const LensDesignOptions& options);

// The exact case: r(θ) for φ = kθ with r(0) = r0.
double linear_lens_r(double k, double n, double theta, double r0);

// What φ = kθ makes of the emitter's light over [0, to], plus the direct
// light above `to`, on a γ grid of `step_deg` (as linear_map_target).
photometry::Distribution linear_lens_target(const photometry::Distribution& emitter, double k, double to_deg,
                                            double step_deg = 0.01);

// The design file of a designed lens (lengths in mm): [materials.lens] a
// dielectric of index n, the emitter at the origin with `emitter_file`, and
// [[lenses]] `name`: inner a polar sphere, outer the polar table with each r
// a variable bounded to [0.8 r, 1.25 r]. `emitter_key`: "profile" (a
// photometric file) or "ray_file" (a TM-25 ray file: an extended emitter).
io::TomlNode lens_design_document(const LensDesign& design, const std::string& emitter_file, double ior,
                                  const std::string& name, const std::string& emitter_key = "profile");

}  // namespace gonio::design
