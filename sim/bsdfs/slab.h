// A plane-parallel sheet of a scattering medium (μs, μa, Henyey–Greenstein
// g) with smooth faces of index n in air: the optics a datasheet states
// (total transmittance and reflectance, haze, half-value angle) by a
// one-dimensional Monte Carlo of the same transport the tracer does inside a
// part (sim/bsdfs/volume.h), and the fit from those datasheet values back to
// (μs, μa).
//
// Definitions (as makers measure them, light arriving along the normal):
//   transmittance   all light leaving the far face (ISO 13468 / ASTM D1003
//                   total luminous transmittance), reflectance likewise on
//                   the near face including its Fresnel reflection;
//   haze            the share of the transmitted light that leaves more than
//                   2.5° from the incident direction (ASTM D1003);
//   half-value angle  the angle from the normal at which the transmitted
//                   intensity (flux per solid angle) falls to half its value
//                   along the normal (60° for a Lambertian transmitter;
//                   makers of opal sheet print it, e.g. DIN 5036-3 style).
//
// Fit. The two measured values do not fix three unknowns: g is given (the
// default 0.8 is a stated assumption, typical of polymer-bead diffusers;
// for thick opal sheet the result hardly depends on it, since diffuse
// transport depends on μs(1 − g)). For each trial μs one Monte Carlo run
// without absorption records every photon's path length L inside; any μa
// then weighs it by exp(−μa L), so μa follows from the transmittance by
// bisection without tracing again. The outer search over log μs matches
// the haze or the half-value angle. Deterministic: photon i of every run
// draws from (seed, i).
#pragma once

#include <cstdint>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/bsdfs/tabulated_bsdf.h"

namespace gonio::sim {

struct SlabMedium {
  double scattering_per_m = 0.0;  // μs [1/m]
  double absorption_per_m = 0.0;  // μa [1/m]
  double g = 0.0;                 // Henyey–Greenstein asymmetry
  double ior = 1.49;              // refractive index of the sheet
  double thickness_m = 0.003;     // [m]
};

struct SlabOptics {
  double transmittance = 0.0;    // total, at the incidence asked for
  double reflectance = 0.0;      // total, Fresnel included
  double haze = 0.0;             // normal incidence only (else 0)
  double half_value_deg = 0.0;   // normal incidence only (else 0); 90 if never reached
  double unscattered = 0.0;      // transmitted without scattering
  // Transmitted intensity per exit angle θ from the normal, relative to its
  // value along the normal, in bins of 2.5° (bin k: [2.5k, 2.5(k+1))°),
  // without the unscattered beam. The value along the normal and the
  // half-value angle come from a least-squares polynomial of degree 4 in
  // cos θ through these bins (the innermost bins alone hold few photons).
  std::vector<double> relative_intensity;
};

// `photons` photons of run `seed` at `incidence_deg` from the normal.
SlabOptics slab_optics(const SlabMedium& medium, double incidence_deg, std::uint64_t photons,
                       std::uint64_t seed = 1);

struct VolumeDatasheet {
  double transmittance = 0.0;   // total luminous transmittance, in (0, 1)
  double haze = -1.0;           // ASTM D1003 haze in (0, 1); < 0: not given
  double half_value_deg = -1.0; // half-value angle in (0, 90); < 0: not given
  double thickness_m = 0.0;     // > 0
  double ior = 1.49;
  double g = 0.8;               // assumed (see above)
};

// The sheet as a measured-style BSDF (sim/bsdfs/tabulated_bsdf.h): what a
// goniophotometer would record of it, for a thin part modelled as one
// surface (a shade of a single sheet of triangles). A three-dimensional
// Monte Carlo of the same transport, `photons` per angle of incidence at
// 0°, 10°, …, 80° and 89°, binned into rings of 5° split into patches about
// 5° wide; both faces alike (the `front` side; the back uses it).
TabulatedBsdf sheet_bsdf(const SlabMedium& medium, std::uint64_t photons, std::uint64_t seed = 1);

// (μs, μa) for a datasheet with the transmittance and exactly one of haze
// or half-value angle. An error where the values are out of range or no
// medium of that g reaches them (e.g. a haze the thickness cannot give).
Result<SlabMedium> fit_volume(const VolumeDatasheet& sheet, std::uint64_t photons = 20000,
                              std::uint64_t seed = 1);

}  // namespace gonio::sim
