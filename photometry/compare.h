// Comparing two distributions: how far a simulated or converted distribution
// is from a reference, on one grid.
#pragma once

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::photometry {

struct CompareOptions {
  double c_step_deg = 5.0;      // common grid: C-plane step [deg], divides 360°
  double gamma_step_deg = 2.5;  // common grid: γ step [deg], divides 90°
  // Scale B by flux_a / flux_b before comparing intensities, so that only the
  // shape of the distributions is compared.
  bool normalize_flux = false;
};

// Both distributions are resampled (photometry/resample.h) onto one Type C
// grid covering the whole sphere, C 0…360° × γ 0…180° at the given steps.
// At each grid direction the difference is e = (scale · I_B − I_A) / I_ref,
// where I_ref is the largest intensity of A on the grid (the reference is A;
// if A is dark, B's largest). Differences are thus relative to the peak, not
// to the local intensity, so dark directions neither dominate nor vanish.
struct Comparison {
  double reference_cd = 0.0;  // I_ref [cd]
  double scale = 1.0;         // factor applied to B's intensities [1]
  // Root mean square of e over the sphere, each grid direction weighted by
  // the solid angle it stands for (the γ band between the midpoints to its
  // neighbours times its share of C), so dense polar sampling does not weigh
  // more than the equator. A scaled copy B = s·A gives |s − 1| · rms(I_A)/I_ref.
  double rms_relative = 0.0;  // [1]
  // Largest |e| and where it is; a scaled copy B = s·A gives exactly |s − 1|.
  double max_relative = 0.0;      // [1]
  double max_at_c_deg = 0.0;      // [deg]
  double max_at_gamma_deg = 0.0;  // [deg]
  // Total flux of each input, by total_flux_lm() on its own grid (before any
  // scaling), and their relation.
  double flux_a_lm = 0.0;    // [lm]
  double flux_b_lm = 0.0;    // [lm]
  double flux_ratio = kNaN;  // flux_b / flux_a [1]; NaN if A is dark
  // Beam and field angles of B minus those of A (photometry/beam.h; they do
  // not depend on scale) [deg]; NaN where either has none.
  double beam_difference_c0_c180_deg = kNaN;
  double beam_difference_c90_c270_deg = kNaN;
  double field_difference_c0_c180_deg = kNaN;
  double field_difference_c90_c270_deg = kNaN;
};

// Whether a and b are given on the same angles (to 1e-6°) over the whole
// sphere: the same type, vertical angles and C-planes once each file's
// symmetry is expanded. Where they differ, compare() interpolates both onto
// its common grid, and its figures hold the interpolation's error too.
bool same_angles(const Distribution& a, const Distribution& b);

// Compares B against the reference A. Errors: a grid the options cannot
// describe (see to_type_c()). Requires validate() of both to be ok.
Result<Comparison> compare(const Distribution& a, const Distribution& b,
                           const CompareOptions& options = {});

}  // namespace gonio::photometry
