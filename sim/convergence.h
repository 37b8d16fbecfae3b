// Convergence: how far a far field (raw, or a filtered preview) is from a
// reference run, in the measures of the reference thesis's evaluation
// (Krösl 2016, section 8.1: RMSE, PSNR and SNR of the cube map after mean
// scaling) and in the photometric measures of the candela table a file
// would hold; and the rate at which an error falls.
//
// Cube map, after mean scaling. Over the T texels of the map (each texel
// counts once, as a pixel of the thesis's intensity images), with x_t the
// intensity of the map under test and r_t the reference's [cd]:
//   x̂_t = x_t / x̄,  r̂_t = r_t / r̄,  x̄ = (1/T) Σ x_t,  r̄ = (1/T) Σ r_t
//   MSE  = (1/T) Σ (x̂_t − r̂_t)²  −  ν,   ν = (1/T) Σ r̂_t² / n_t
//   RMSE = √MSE
//   PSNR = 10 log10(max_t r̂_t² / MSE)   [dB]
//   SNR  = 10 log10(((1/T) Σ r̂_t²) / MSE) [dB]
// ν is the reference's own noise: its photons carry equal power, so the
// count n_t of texel t is Poisson and Var(r̂_t) ≈ r̂_t² / n_t (texels without
// photons add 0). The reference is independent of the map under test (its
// own seed), so its noise adds ν to the expected squared difference, and
// subtracting ν leaves an unbiased estimate of the map's own squared error.
// The thesis did not subtract it; its RMSE of two references against each
// other (8.1.3) is this floor. Where MSE ≤ 0 (the map is as close as the
// reference's noise lets one see) RMSE, PSNR and SNR are NaN.
//
// Candela table. The map (a preview as flux = intensity × texel solid angle)
// is resampled into the bins of a Type C grid (sim/detectors/resample.h, no symmetry
// averaging), giving per bin b its intensity I_b, solid angle Ω_b and the
// reference's R_b with variance v_b (sim/detectors/resample.h's estimate). Errors are
// relative to the reference's peak R_max = max_b R_b, as in
// photometry/compare.h:
//   rms_pct = 100 · √((Σ Ω_b (I_b − R_b)² − Σ Ω_b v_b) / Σ Ω_b) / R_max
//   max_pct = 100 · max_b |I_b − R_b| / R_max   (includes the reference's noise)
//   flux_pct = 100 · (Φ − Φ_ref) / Φ_ref          (Φ = Σ flux of the map)
// rms_pct is NaN where the bracket is ≤ 0.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "sim/detectors/far_field.h"
#include "sim/detectors/resample.h"

namespace gonio::sim {

struct CubeMapError {
  double rmse = 0.0;      // [1] after mean scaling, reference noise taken out (NaN: below it)
  double psnr_db = 0.0;   // [dB]
  double snr_db = 0.0;    // [dB]
  double raw_mse = 0.0;   // (1/T) Σ (x̂ − r̂)², before taking out ν [1]
};

struct TableError {
  double rms_pct = 0.0;   // RMS error relative to the reference peak [%] (NaN: below its noise)
  double raw_rms_pct = 0.0;  // the same before taking out the reference's noise [%]
  double max_pct = 0.0;   // largest error relative to the reference peak [%]
  double flux_pct = 0.0;  // flux error [%]
};

class ConvergenceReference {
 public:
  // The reference far field (plain emission: photons of equal power) and the
  // resampler of the candela table (same face size). Errors: a reference
  // without any escaped flux (nothing to compare against).
  static Result<ConvergenceReference> create(const FarField& reference,
                                             std::shared_ptr<const Resampler> resampler);

  // Errors of a map of texel intensities [cd] (size: the reference's texel
  // count), e.g. FarField intensities or PreviewFilter::intensity_cd().
  // A map without flux has no mean to scale by: its errors are those of an
  // all-zero map against the scaled reference.
  CubeMapError cube_map_error(std::span<const double> intensity_cd) const;
  TableError table_error(std::span<const double> intensity_cd) const;

  // The reference's own noise in both measures: √ν after mean scaling [1],
  // and 100·√(Σ Ω_b v_b / Σ Ω_b) / R_max [%].
  double cube_map_noise() const { return std::sqrt(noise_nu_); }
  double table_noise_pct() const;

  const FarField& far_field() const { return reference_; }
  const Resampler& resampler() const { return *resampler_; }
  const BinnedField& table() const { return table_; }
  double peak_cd() const { return peak_cd_; }  // R_max [cd]

 private:
  ConvergenceReference(FarField reference, std::shared_ptr<const Resampler> resampler);

  FarField reference_;
  std::shared_ptr<const Resampler> resampler_;
  std::vector<double> scaled_;   // r̂_t
  double noise_nu_ = 0.0;        // ν
  double peak_sq_ = 0.0;         // max r̂²
  double mean_sq_ = 0.0;         // (1/T) Σ r̂²
  BinnedField table_;
  double peak_cd_ = 0.0;
  double table_noise_ = 0.0;     // Σ Ω_b v_b
  double table_solid_angle_ = 0.0;
};

// Intensities [cd] of every texel of a far field.
std::vector<double> texel_intensities(const FarField& field);

// Least-squares slope of log y against log x over the points where both are
// finite and > 0; NaN with fewer than two such points or no spread in x.
double log_log_slope(std::span<const double> x, std::span<const double> y);

// Where a falling series y(x) drops below `level` for good: the x at which
// the log-log line between the last point above the level and the next one
// crosses it; x[0] if every point is at or below it; NaN if the last point is
// above it. A NaN y counts as below (an error lost in the reference's noise).
// x ascending, > 0.
double crossing(std::span<const double> x, std::span<const double> y, double level);

}  // namespace gonio::sim
