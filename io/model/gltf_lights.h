// The photometry of glTF's punctual lights: KHR_lights_punctual spot cones as
// rotational Type C profiles with their exact flux, and the photometric frame
// a light node defines (EXT_lights_ies and KHR_lights_punctual alike).
// Standard library only; io/model/gltf.cpp reads the file and calls these.
#pragma once

#include "photometry/distribution.h"
#include "photometry/frame.h"
#include "photometry/vec3.h"

namespace gonio::io {

// Flux of an isotropic point of intensity I [cd]: Φ = 4πI [lm].
double isotropic_flux_lm(double intensity_cd);

// KHR_lights_punctual's recommended spot falloff, relative to the intensity on
// the axis: s(θ)² with s = clamp((cos θ − cos θo)/(cos θi − cos θo), 0, 1),
// θ the angle from the spot axis [rad], θi/θo the inner/outer cone angles
// [rad]. When θi ≥ θo (invalid in the extension) the edge is hard at θo.
double khr_spot_falloff(double theta_rad, double inner_rad, double outer_rad);

// Exact flux of that spot [lm]: 2πI[(1 − cos θi) + (cos θi − cos θo)/3],
// or 2πI(1 − cos θo) for a hard edge.
double khr_spot_flux_lm(double intensity_cd, double inner_rad, double outer_rad);

// The spot as a rotational Type C distribution with absolute photometry: γ is
// the angle from the spot axis (γ = 0 where the light points), I(γ) = I·s(γ)².
// The γ grid holds 0, θi, 128 steps across the falloff, θo and 180°, so the
// bilinear interpolant integrates to khr_spot_flux_lm within 1e-4.
// Requires 0 ≤ θi, 0 < θo ≤ π/2 and I ≥ 0.
photometry::Distribution khr_spot_distribution(double intensity_cd, double inner_rad,
                                               double outer_rad);

// The photometric frame of a light on a node whose world transform maps the
// node's +X axis to `node_x` and +Z axis to `node_z` (rotation and scale
// only). EXT_lights_ies maps its (0°, 0°) direction to the node's −Z and
// makes the X/Z plane the vertical photometric plane through C0, so for
// Type C: nadir (γ = 0) = −Z, C0 = +X, C90 = +Y, zenith = +Z, all of the
// node. KHR_lights_punctual spots point down −Z as well, so the same frame
// puts their axis at γ = 0. Scale and shear are removed (+X is
// orthogonalised against +Z); both must be non-zero and not parallel.
photometry::PhotometricFrame light_frame(const Vec3& node_x, const Vec3& node_z);

}  // namespace gonio::io
