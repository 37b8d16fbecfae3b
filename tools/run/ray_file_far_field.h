// The far field of an IES TM-25 ray set: what `gonio info`, `convert`,
// `plot`, `compare` and `check` see of a .tm25ray file.
//
// Method: every ray's luminous flux is added to the cube-map texel of its
// direction (sim::FarField, as the tracer bins escaping photons), and the
// map is resampled onto a Type C grid by sim::Resampler (area-weighted
// bins, flux kept to rounding) — the same two steps `gonio simulate` takes.
// Positions are ignored: this is the far field, the limit at infinite
// distance. Frame: the ray file's +z is the photometric nadir (γ = 0: an LED
// emitting along +z is a downlight), +x is C0 and −y C90 (right-handed with
// the zenith −z). Grid: C every 5°, γ every 2.5° (simulate's default), no
// symmetry averaging. With N rays a bin of the grid holds about
// N·Ω_bin/Ω_lit rays, so the bins' relative noise is about 1/√(that): the
// OSRAM set's 100,000 rays give ~6 % near the axis.
#pragma once

#include <string>

#include "io/photometric/photometric_file.h"
#include "io/photometric/tm25.h"
#include "photometry/distribution.h"
#include "photometry/frame.h"
#include "sim/detectors/resample.h"

namespace gonio::app {

// The ray file's frame (above).
photometry::PhotometricFrame ray_file_frame();

// The far field on `grid` (absolute photometry, luminous flux of the rays).
// Errors name `path`: no luminous flux per ray (radiant flux without both
// header fluxes), no flux at all.
Result<photometry::Distribution> ray_set_far_field(const io::Tm25RaySet& set, const std::string& path,
                                                   const sim::CGammaGrid& grid = {});

// read options' hook (io::PhotometricReadOptions::ray_set_far_field) on the
// default grid.
void enable_ray_files(io::PhotometricReadOptions& options);

}  // namespace gonio::app
