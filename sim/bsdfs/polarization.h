// Polarisation of photons at smooth dielectric interfaces.
//
// Fresnel reflectance depends on polarisation, and light reflected or
// refracted once is partly polarised: a slab's transmittance is the mean of
// its s and p transmittances (1 − R)/(1 + R), not (1 − R̄)/(1 + R̄) with the
// mean R̄ (at 75° on n = 1.52: 0.6148 against 0.5915). So a photon carries
// its polarisation once it meets a dielectric: a Jones vector, the complex
// transverse electric field of unit norm. Unpolarised light is represented
// exactly by photons with a uniformly random linear polarisation (their
// mixture has coherency matrix I/2).
//
// Conventions: s = (k × n)/|k × n| for incident direction k and normal n;
// each beam's p axis is k_beam × s; amplitudes follow Born & Wolf:
//   rs = (n1 cos i − n2 cos t)/(n1 cos i + n2 cos t)
//   rp = (n2 cos i − n1 cos t)/(n2 cos i + n1 cos t)
//   ts = 2 n1 cos i/(n1 cos i + n2 cos t), tp = 2 n1 cos i/(n2 cos i + n1 cos t)
// (normal incidence: reflected field = rs·E in the lab frame; grazing: −E).
// Beyond the critical angle cos t = i·√(sin²t − 1): |rs| = |rp| = 1 with
// the relative phase that makes linear light elliptical.
//
// Diffuse and glossy scattering depolarise (the photon forgets its state);
// a perfect mirror reflects the field as an ideal conductor.
#pragma once

#include <complex>

#include "photometry/vec3.h"
#include "sim/samplers/random.h"

namespace gonio::sim {

struct Polarization {
  bool polarized = false;     // false: unpolarised (no state yet)
  std::complex<double> e[3];  // Jones vector in world axes, ⟂ direction, Σ|e|² = 1
};

// Gives an unpolarised photon travelling along unit `direction` a uniformly
// random linear polarisation (no-op if it already has a state).
void polarize_randomly(Polarization& p, const Vec3& direction, PhotonRandom& rng);

// Ideal conductor reflection of the field about unit normal n:
// E' = −E + 2(E·n)n.
void reflect_field(Polarization& p, const Vec3& n);

struct FresnelAmplitudes {
  std::complex<double> rs, rp, ts, tp;
  bool total_internal_reflection = false;
  double cos_t = 0.0;  // cos θt when refracted
};
// Amplitudes for cos θi in (0, 1] from index eta_i onto eta_t.
FresnelAmplitudes fresnel_amplitudes(double cos_i, double eta_i, double eta_t);

struct InterfaceOutcome {
  bool reflected;
  Vec3 direction;      // unit
  Polarization state;  // the field after the event
  double reflectance;  // the chance of reflection this photon had
};

// One smooth-interface event for a polarised photon travelling along unit
// `direction` onto unit normal `n` on its side (dot(direction, n) < 0):
// reflection with chance R = |rs|²|Es|² + |rp|²|Ep|² (u < R), else
// refraction; the field follows the chosen beam, renormalised.
InterfaceOutcome interface_event(const Polarization& state, const Vec3& direction, const Vec3& n,
                                 double eta_i, double eta_t, double u);

}  // namespace gonio::sim
