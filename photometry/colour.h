// Colorimetry of the CIE 1931 2° standard observer: tristimulus values of a
// spectrum, chromaticity x, y, the CIE 1976 UCS u′, v′ and the CIE 1960 u, v,
// and correlated colour temperature with Duv.
//
// Colour-matching functions: CIE 1931 2°, 360–830 nm in 5 nm steps, read
// from Debian's colord-data at build time (cmake/cie_cmf.cmake). Tristimulus
// integration follows CIE 15:2004 section 7.1: a sum over the 5 nm grid,
// X = Σ S(λ) x̄(λ) Δλ, with S linearly interpolated at the grid's wavelengths
// (photometry/spectrum.h).
//
// CCT and Duv: Ohno (2014), "Practical Use and Calculation of CCT and Duv",
// LEUKOS 10(1):47–55 — the combined method: the nearest point of a table of
// Planckian (u, v) (1000 K to 10⁶ K, here in 0.1 % steps, each computed from
// Planck's law with c₂ = 1.4388·10⁻² m·K and the same colour-matching
// functions), then the triangular solution where |Duv| < 0.002 and the
// parabolic solution elsewhere. Duv is the signed distance in CIE 1960 (u, v)
// from the Planckian locus, positive above it (towards green).
#pragma once

#include "photometry/spectrum.h"

namespace gonio::photometry {

// The luminous efficacy of radiation at 555 nm used with ȳ: Km [lm/W].
inline constexpr double kKm_lm_per_W = 683.002;

struct Tristimulus {
  double X = 0.0, Y = 0.0, Z = 0.0;  // in the spectrum's units × nm
};

struct Chromaticity {
  double x = 0.0, y = 0.0;  // CIE 1931
};

struct UvPrime {
  double u_prime = 0.0, v_prime = 0.0;  // CIE 1976 UCS
};

struct CctDuv {
  double cct_k = 0.0;  // correlated colour temperature [K]; NaN outside 1000 K .. 10⁶ K
  double duv = 0.0;    // signed distance from the Planckian locus in CIE 1960 (u, v)
};

// The colour-matching functions at any wavelength: linear between the 5 nm
// samples, 0 outside 360–830 nm.
struct CmfValue {
  double x_bar = 0.0, y_bar = 0.0, z_bar = 0.0;
};
CmfValue cie1931_cmf(double wavelength_nm);
// The table itself (95 samples from 360 nm in 5 nm steps).
inline constexpr double kCmfFirstNm = 360.0;
inline constexpr double kCmfStepNm = 5.0;
inline constexpr int kCmfCount = 95;
CmfValue cie1931_cmf_sample(int index);

// X, Y, Z of a spectrum (CIE 15 summation on the 5 nm grid).
Tristimulus tristimulus(const SampledSpectrum& s);

// x, y; u′, v′ (u′ = 4X/(X+15Y+3Z), v′ = 9Y/(X+15Y+3Z)). NaN for black.
Chromaticity chromaticity(const Tristimulus& t);
UvPrime uv_prime(const Tristimulus& t);
UvPrime uv_prime(const Chromaticity& c);
Chromaticity chromaticity(const UvPrime& uv);

// Distance between two chromaticities in the CIE 1976 UCS, Δu′v′.
double delta_uv_prime(const UvPrime& a, const UvPrime& b);

// CCT and Duv from CIE 1960 (u, v) = (u′, 2v′/3) by Ohno's combined method.
CctDuv cct_duv(const UvPrime& uv);
inline CctDuv cct_duv(const Tristimulus& t) { return cct_duv(uv_prime(t)); }

// The Planckian radiator's u′, v′ at a temperature (same CMFs, same c₂).
UvPrime planckian_uv_prime(double temperature_k);

}  // namespace gonio::photometry
