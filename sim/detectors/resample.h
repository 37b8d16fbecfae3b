// Resampling the far field to a Type C grid: the step from the direction cube
// map (world directions, per-texel flux) to the candela table of an IES or
// LDT file (photometric C-γ angles).
//
// Bins. The grid has C-planes C_i = i·ΔC for i = 0 … 360/ΔC − 1 and vertical
// angles γ_j = j·Δγ for j = 0 … 180/Δγ. Every grid point owns the bin centred
// on it: γ in [γ_j − Δγ/2, γ_j + Δγ/2] and C in [C_i − ΔC/2, C_i + ΔC/2]
// (wrapping at 0/360). The two poles are special: the cap γ < Δγ/2 around the
// nadir and the cap γ > 180° − Δγ/2 around the zenith are one bin each,
// shared by every C-plane, so a file's nadir (and zenith) has one value
// whatever the plane, as LM-63 and EULUMDAT readers expect. The bins tile the
// sphere without gaps or overlaps.
//
// Intensity. A grid point's intensity is the flux that falls into its bin
// divided by the bin's solid angle, so that Σ I·Ω over the bins is exactly the
// map's flux (no point sampling, nothing lost or counted twice). Texels are
// shared between bins by the solid angle of their overlap (flux assumed
// uniform inside a texel). Overlaps: each texel is subdivided (quadtree on
// the face) until a piece provably lies in one bin, or is smaller than half
// the narrowest bin around it (and short enough that γ-circles are straight
// across it to 1/400 of its size); such a leaf is cut along the bin
// boundaries crossing it (C-boundaries are exactly straight on a cube face)
// and each part gets its exact spherical-polygon solid angle. A bin's solid
// angle is the sum of its overlaps: the exact ΔC·(cos γ_lo − cos γ_hi) to
// better than 1e-3 relative (about 4e-4 at the defaults), and exactly the
// region whose flux the bin collects.
//
// Cost. The overlap is a sparse matrix built once per (face size, frame,
// grid), in parallel and deterministic: about 0.07 s on two cores at the
// defaults (5° × 2.5°, face 128, 155 k non-zeros), 0.35 s for the
// latitude-longitude map's 1.4° grid at face 128, 0.7 s at 1° × 1° (face
// 256; gonio_resample_bench); the commands keep it on disk
// (tools/run/resampler_cache.h). Applying it to a map costs one multiply-add per non-zero
// (0.3 ms at the defaults, three times one read of the map), so a
// simulation can resample after every iteration (sim/detectors/resample_bench.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <span>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/distribution.h"
#include "photometry/frame.h"
#include "sim/detectors/far_field.h"

namespace gonio::sim {

// The Type C grid of an output file: uniform steps, or (non-uniform grids:
// --gamma-angles, --c-angles, --grid-like) the angles themselves.
//
// Non-uniform bins. Every angle owns the interval up to the midpoints with its
// neighbours: γ_j's bin is [(γ_{j−1} + γ_j)/2, (γ_j + γ_{j+1})/2], C_i's
// likewise, wrapping at 0/360 (C_0 = 0 reaches back to (C_last − 360)/2).
// For uniform steps these are the bins described above.
struct CGammaGrid {
  CGammaGrid() = default;
  // Uniform steps (C, then γ).
  CGammaGrid(double c_step, double gamma_step) : c_step_deg(c_step), gamma_step_deg(gamma_step) {}

  double c_step_deg = 5.0;      // [deg] spacing of C-planes; 360 / c_step_deg is whole
  double gamma_step_deg = 2.5;  // [deg] spacing of γ; 180 / gamma_step_deg is whole
  // Explicit angles [deg], ascending; empty: the step above. C-planes lie in
  // [0, 360) with the first at 0; γ runs from 0 to 180, both ends included.
  std::vector<double> c_angles_deg;
  std::vector<double> gamma_angles_deg;

  int c_count() const;      // C-planes in [0, 360)
  int gamma_count() const;  // γ angles in [0, 180], both ends included

  // Bins: the nadir cap (index 0), the zenith cap (1), then one per
  // (C-plane i, interior γ index j = 1 … gamma_count() − 2).
  std::size_t bin_count() const;
  // The bin of grid point (i, j); every i gives the cap bin at j = 0 and at
  // j = gamma_count() − 1.
  std::size_t bin(int c_index, int gamma_index) const;

  double c_deg(int c_index) const {
    return c_angles_deg.empty() ? c_index * c_step_deg : c_angles_deg[static_cast<std::size_t>(c_index)];
  }
  double gamma_deg(int gamma_index) const {
    return gamma_angles_deg.empty() ? gamma_index * gamma_step_deg
                                    : gamma_angles_deg[static_cast<std::size_t>(gamma_index)];
  }
  // The edges of a bin [deg]: γ from gamma_lower_deg to gamma_upper_deg (0
  // and 180 at the caps' outer ends); C from c_lower_deg (below 0 for plane
  // 0) to c_upper_deg (above 360 only for the last plane when wrapping).
  double gamma_lower_deg(int gamma_index) const;
  double gamma_upper_deg(int gamma_index) const;
  double c_lower_deg(int c_index) const;
  double c_upper_deg(int c_index) const;
  // The index of C-plane `c_deg` (within 1e-9°), or −1 where there is none.
  int c_index_of(double c_deg) const;
  // Whether both axes are uniform steps (no explicit lists).
  bool uniform() const { return c_angles_deg.empty() && gamma_angles_deg.empty(); }
  // The narrowest bin width along γ, and along C [deg].
  double finest_gamma_step_deg() const;
  double finest_c_step_deg() const;
  // "C step 5 deg, gamma step 2.5 deg", or the lists' counts and ranges.
  std::string describe() const;
};

// Smallest and largest steps accepted [deg]. Uniform C steps stay at 0.5° or
// more (C-planes 0.1° apart would be 3600 planes, more than any format
// reader expects); γ goes down to 0.1°, for narrow beams, and so do the
// gaps of an explicit list. The cube map follows the finest γ step (see
// face_size_for); docs/validation.md, "Narrow beams and non-uniform grids",
// has what that costs.
inline constexpr double kMinGridStepDeg = 0.5;
inline constexpr double kMinGammaStepDeg = 0.1;
inline constexpr double kMaxGridStepDeg = 90.0;
// Most angles in an explicit list (γ every 0.1° from 0 to 180 is 1801).
inline constexpr std::size_t kMaxGridAngles = 3601;

// Checks that both steps lie in their ranges ([kMinGridStepDeg,
// kMaxGridStepDeg] for C, from kMinGammaStepDeg for γ) and divide 360° (C)
// and 180° (γ) into whole numbers of steps; explicit lists instead must be
// finite, strictly ascending with gaps of at least kMinGammaStepDeg (1e-9°
// slack), C in [0, 360) from 0, γ from 0 to 180. The error names the step
// or list and what would be valid.
Status validate(const CGammaGrid& grid);

// Cube-map face size for a grid: two texels per step of the finest bin width
// (C or γ) at the face centre, where texels are largest (so at least two
// everywhere): CubeMapGrid::face_size_for_step, up to kMaxAutoFaceSize.
// 5° × 2.5° → 128, 1° steps → 256, 0.5° → 512, 0.25° and finer → 1024 (face
// sizes are powers of two). Below 0.25° a texel at the face centre spans
// 0.11°, about one 0.1° step; two per step (2048) cost four times the memory
// (4 GB against 1 GB on two threads, docs/validation.md), so --face-size asks
// for it explicitly.
inline constexpr int kMaxAutoFaceSize = 1024;
int face_size_for(const CGammaGrid& grid);

// Exact solid angle [sr] of a bin: ΔC·(cos γ_lo − cos γ_hi), or 2π(1 − cos γ_edge)
// for a cap.
double exact_bin_solid_angle(const CGammaGrid& grid, std::size_t bin);

// A far field gathered into the bins of a C-γ grid, before any symmetry.
// Vectors are indexed by CGammaGrid::bin().
struct BinnedField {
  CGammaGrid grid;
  std::vector<double> flux_lm;         // flux collected per bin [lm]
  std::vector<double> solid_angle_sr;  // the bin's region as the overlaps cover it [sr]
  std::vector<double> variance_lm2;    // estimated variance of flux_lm [lm²] (see below)
  std::vector<double> photons;         // photons counted into the bin (fractional: shared texels)

  double intensity_cd(std::size_t bin) const { return flux_lm[bin] / solid_angle_sr[bin]; }
  double total_flux_lm() const;
};

// The overlap builder's revision: raise it whenever a change to the builder
// changes its rows, so that stored ones (tools/run/resampler_cache.h) are rebuilt.
inline constexpr int kResamplerRevision = 3;

// Precomputed overlap of a cube map's texels with a grid's bins, seen through
// the luminaire's photometric frame (world direction → local (C, γ) by
// frame.to_local and photometry::c_gamma_from_direction).
class Resampler {
 public:
  // Requires validate(grid).ok() and an orthonormal frame.
  Resampler(int face_size, const photometry::PhotometricFrame& frame, const CGammaGrid& grid);

  int face_size() const { return face_size_; }
  const CGammaGrid& grid() const { return grid_; }
  std::size_t nonzeros() const { return texel_.size(); }
  // Per bin: the solid angle of its region [sr] (sum of overlaps).
  const std::vector<double>& bin_solid_angle_sr() const { return solid_angle_sr_; }

  // Bins a far field of this face size. Flux is conserved to rounding: each
  // texel's flux is split over the bins by fractions that sum to 1.
  // Variance: texel flux is taken as photons of equal weight, Poisson in
  // number, so Var(texel) = flux² / photons; a bin's variance is
  // Σ fraction² · Var(texel) (0 for a map without photon counts).
  BinnedField bin(const FarField& field) const;
  // Only the flux per bin of a far field's texel fluxes (face size N: 6N²
  // values), summed as bin() sums it (the same values): for estimates that
  // read no variance or photon counts (issue 40).
  std::vector<double> bin_flux(std::span<const double> texel_flux_lm) const;

  // The matrix as stored (tools/run/resampler_cache.h): compressed rows, one per
  // bin (row_start has bin_count() + 1 entries), each the texels the bin
  // draws from and the fraction of each texel's flux it receives.
  struct Rows {
    std::vector<std::uint64_t> row_start;
    std::vector<std::uint32_t> texel;
    std::vector<double> fraction;
    std::vector<double> solid_angle_sr;  // per bin
  };
  Rows rows() const;
  // A resampler from stored rows, which are checked for shape (sizes, order,
  // texels in range, finite fractions in [0, 1], positive solid angles) but
  // not recomputed: the caller keys them by the face size, frame and grid
  // they were built for.
  static Result<Resampler> from_rows(int face_size, const CGammaGrid& grid, Rows rows);

 private:
  Resampler(int face_size, const CGammaGrid& grid) : face_size_(face_size), grid_(grid) {}

  int face_size_;
  CGammaGrid grid_;
  // Compressed rows, one row per bin: texel indices and the fraction of that
  // texel's flux the bin receives.
  std::vector<std::size_t> row_start_;
  std::vector<std::uint32_t> texel_;
  std::vector<double> fraction_;
  std::vector<double> solid_angle_sr_;
};

// The Type C distribution of a binned field, averaged over the directions the
// symmetry makes equivalent (each value: the flux of all equivalent bins over
// their solid angle, so the flux stays the same), on the symmetry's range of
// C-planes: None 0…360 (360 repeats 0), C0-C180 0…180, C90-C270 90…270,
// Quadrant 0…90, Rotational the single plane 0. Requires
// grid_supports(field.grid, symmetry). The result is absolute photometry
// (candela as simulated, no lamp sets); callers add lamp data and labels.
photometry::Distribution to_distribution(const BinnedField& field, photometry::Symmetry symmetry);

}  // namespace gonio::sim
