// Symmetry of a simulated distribution: which C-planes are equivalent,
// averaging over them, and deciding from the data which symmetry holds.
//
// Averaging N equivalent bins divides the variance of their estimate by N:
// by 2 for C0-C180 and C90-C270, by 4 for Quadrant, by the number of
// C-planes for Rotational (for bins off the mirror planes; bins on a mirror
// plane are their own images and gain less).
//
// Automatic choice. For every symmetry the grid supports, a chi-square test
// compares each group of equivalent bins with their common mean:
//   χ² = Σ_groups Σ_i (I_i − Ī)² / (Var_stat(I_i) + (ε·Ī)²)
// with Var_stat from the photon counts (Poisson, the pooled variance per
// lumen of the group times Ī/Ω_i) and ε a relative tolerance for the
// resampling's own discretisation (texels split between bins assume uniform
// flux inside, which mirror images of a bin do not see identically when the
// photometric frame is not aligned with the cube). Groups whose members
// expect fewer than `min_photons` photons are left out (Pearson's
// approximation needs them). The symmetry is rejected when the upper-tail
// probability of χ² with Σ(group size − 1) degrees of freedom is below the
// significance. The choice is the symmetry of highest order not rejected:
// Rotational, then Quadrant, then the better of C0-C180 and C90-C270 (higher
// p-value), then None.
//
// Power. Not rejecting a symmetry does not prove it: at few photons a real
// asymmetry hides in the noise. For each test the decision states the
// smallest asymmetry it detects 9 times in 10: equivalent bins deviating
// from their common mean by a relative d (RMS over the tested bins) add
// λ = d² · Σ Ī² / σ_i² to χ² (its noncentrality), and the test rejects with
// probability 0.9 once λ reaches the value where the noncentral χ²
// distribution (mean dof + λ, variance 2(dof + 2λ), taken as normal) puts 90 %
// of its mass beyond the critical value of the significance. That d falls as
// 1/√photons, down to the floor the tolerance ε sets.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "photometry/distribution.h"
#include "sim/detectors/resample.h"

namespace gonio::sim {

using photometry::Symmetry;

// "none", "C0-C180", "C90-C270", "quadrant", "rotational" (the names of
// photometry::to_string, case-insensitive); nullopt for anything else,
// including "auto" and Type A/B's "lateral".
std::optional<Symmetry> parse_symmetry(std::string_view name);

// Whether the grid has the planes a symmetry's output range needs: ΔC divides
// 180° for C0-C180, 90° for C90-C270 and Quadrant; always for None and
// Rotational. Lateral (Types A/B) is never supported here.
bool grid_supports(const CGammaGrid& grid, Symmetry symmetry);

// grid_supports as a Status whose error says what the symmetry needs, for
// command-line checks ("symmetry quadrant needs a C step dividing 90°, not 40°").
Status check_grid_supports(const CGammaGrid& grid, Symmetry symmetry);

// Number of directions the symmetry makes equivalent to a general one:
// 1, 2, 2, 4, or the number of C-planes for Rotational.
int symmetry_order(const CGammaGrid& grid, Symmetry symmetry);

// Groups of equivalent bins (orbits under the symmetry), each listed once,
// including groups of one (the caps, bins on mirror planes).
std::vector<std::vector<std::size_t>> equivalent_bins(const CGammaGrid& grid, Symmetry symmetry);

// Per bin (indexed like BinnedField), the intensity averaged over its group
// of equivalent bins: Σ flux / Σ solid angle [cd]. With None, each bin's own.
std::vector<double> symmetric_intensity_cd(const BinnedField& field, Symmetry symmetry);

struct SymmetryTestOptions {
  double significance = 1e-3;  // reject when the p-value is below this
  double tolerance = 0.005;    // ε: relative differences accepted as discretisation
  double min_photons = 5.0;    // least mean photon count per bin for a group to be tested
};

// One symmetry's test.
struct SymmetryTest {
  Symmetry symmetry = Symmetry::None;
  double chi_square = 0.0;
  double degrees_of_freedom = 0.0;
  double p_value = 1.0;
  std::size_t groups = 0;  // groups of two or more bins that entered the test
  bool rejected = false;
  // The smallest RMS relative deviation of equivalent bins from their mean
  // that the test rejects with probability kSymmetryTestPower (see "Power"
  // above) [1]; NaN when nothing was tested.
  double detectable_deviation = std::numeric_limits<double>::quiet_NaN();
};

inline constexpr double kSymmetryTestPower = 0.9;

struct SymmetryDecision {
  Symmetry symmetry = Symmetry::None;
  std::vector<SymmetryTest> tests;  // every candidate the grid supports, in test order
  std::string explanation;          // one line for stderr and the report, with the chosen test's power
};

// Decides the symmetry of a binned field as described at the top. A field
// without flux, or without any testable group, gets None and says why.
SymmetryDecision detect_symmetry(const BinnedField& field, const SymmetryTestOptions& options = {});

}  // namespace gonio::sim
