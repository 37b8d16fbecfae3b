// The preview filter: the multi-resolution pull-push filter of the reference
// thesis (Krösl 2016, chapter 6 and section 7.3), on the far-field cube map
// with exact texel solid angles. It turns the noisy photon histogram of an
// early iteration into a smooth preview and reproduces the histogram exactly
// once every texel holds enough photons. It reads the far field and writes its
// own map; it never writes back.
//
// Pull: sim/filter/pyramid.h sums flux, photons and solid angle up the pyramid.
// Push, from the second-coarsest level in use down to level 0, texel by texel
// (the coarsest level keeps its own values):
//   - a texel with more photons than the threshold is stable and keeps its
//     own intensity (flux / solid angle of that level);
//   - with adaptive stability (the default; beyond the thesis) so is a texel
//     whose photon count contradicts the interpolated estimate where a
//     neighbour's does too (see PreviewFilterParams::adaptive);
//   - on levels ≥ 2 an unstable texel on a shadow border keeps its own
//     intensity too (is_shadow_border below; with the adaptive default's
//     high threshold it rarely applies, and made no measurable difference);
//   - every other texel is upsampled: its intensity is interpolated from the
//     next coarser level's filtered intensities around the texel's centre.
//
// What is interpolated is intensity [cd] = flux / solid angle: the density
// whose mean over a coarse texel the pyramid holds exactly, whatever the texel
// sizes. On a flat image of equal texels and equal photons (the thesis's
// setting) a coarse texel's intensity is its photon sum / 4 in fine-texel
// units, so this is exactly the thesis's "interpolate the counts, divide by
// four".
//
// Interpolation look-ups cross face edges (the texel across an edge, with the
// adjacent face's orientation: sim/filter/cube_neighbours.h). Beyond a cube corner,
// where only three faces meet, the missing fourth look-up is the mean of the
// three texels that meet there, so corners get no dark spot.
//
// Cost: allocation only in the constructor; apply() runs in parallel (TBB)
// and gives the same result with any thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sim/detectors/far_field.h"
#include "sim/filter/pyramid.h"

namespace gonio::sim {

enum class Interpolation {
  None,       // the preview is the raw map
  Bilinear,   // bilinear in the coarser level's texel grid
  Bilateral,  // thesis 6.4.4: Gaussian closeness × range term on the bilinear estimate
};

// What the bilateral range term measures an intensity difference against.
enum class RangeScale {
  LocalMax,  // |I_coarse − Ĩ| / max of the four coarse intensities (default)
  Estimate,  // |I_coarse − Ĩ| / Ĩ, relative to the bilinear estimate Ĩ
};

// The defaults were chosen by measurement (benchmarks/filter_study.cpp, see
// docs/validation.md): the preview's error against the converged map on synthetic
// far fields (smooth lobes, hard cut-offs, a 10° beam, a spot over a cube
// corner, strut shadows) from 0.25 to 640 photons per texel, on faces of 128
// and 256 texels.
struct PreviewFilterParams {
  Interpolation interpolation = Interpolation::Bilateral;
  // A texel with more photons than this is stable [photons], ≥ 0. With
  // adaptive stability (the default) it is the count above which a texel is
  // kept whatever the test says: 6400 photons, a relative standard error of
  // 1.25 %. Without it, the thesis's fixed threshold; kFixedThreshold is the
  // measured best.
  double threshold_photons = 6400.0;
  static constexpr double kFixedThreshold = 100.0;
  // Pyramid levels in use, level 0 included (1 = no filtering); 0 = enough
  // that the coarsest level has faces of 16 texels (4 levels at 128, 5 at
  // 256; at least 2). Clamped to what the face size allows
  // (CubePyramid::max_levels).
  int levels = 0;
  // Bilateral closeness σ_d, in texel spacings of the coarser level. > 0.
  double sigma_d = 0.5;
  // Bilateral range σ_r, an intensity difference as a fraction of the
  // brightest of the four coarse texels interpolated (range_scale). > 0.
  double sigma_r = 0.2;
  RangeScale range_scale = RangeScale::LocalMax;
  // The thesis's shadow-border rule on levels ≥ 2.
  bool shadow_borders = true;
  // Adaptive stability: below the threshold a texel is still stable when its
  // photon count n contradicts the upsampled estimate, i.e. when the
  // variance-stabilised (Anscombe) difference |2√(n + 3/8) − 2√(m + 3/8)|
  // exceeds adaptive_z, with m the photons the estimate predicts for the
  // texel (estimate × solid angle × photons per lumen of the whole map).
  // Poisson noise gives that difference a standard deviation of about 1, so
  // real detail (a cut-off, a shadow, a beam) is kept as soon as the photons
  // show it, while noise is smoothed: the threshold follows the photon
  // density, per texel. A contradiction counts only where one of the
  // texel's 8 neighbours (across face edges too) contradicts its estimate
  // the same way: detail spans texels, while a lone contradiction is chance
  // (~5·10⁻⁴ of the texels where a few photons are expected, at z = 3.5),
  // and kept, it showed as a dark speck in a bright region. Measured
  // (gonio_filter_study --confirm, error ÷ raw error): synthetic fields
  // 0.304 against 0.312 without the rule, traced luminaires 0.336 against
  // 0.332. With the rule z = 3 scores better still (0.289, 0.314) but two
  // neighbours' chance contradictions then meet often enough to leave
  // pairs of dark texels (6 in 64 smooth 64²-texel previews, none at 3.5),
  // so 3.5 stays.
  bool adaptive = true;
  double adaptive_z = 3.5;  // [standard deviations] > 0
};

// What one apply() did, for reports and tests.
struct PreviewStats {
  int levels_used = 0;
  std::size_t stable_texels = 0;     // level-0 texels that kept their raw value
  std::size_t upsampled_texels = 0;  // level-0 texels replaced by interpolation
  double raw_flux_lm = 0.0;          // total flux of the far field [lm]
  double preview_flux_lm = 0.0;      // Σ preview intensity × texel solid angle [lm]
};

// The thesis's shadow-border rule (6.4.2) for an unstable texel holding
// `photons`: a neighbour is stable when the pair's sum reaches twice the
// threshold; with three to six stable neighbours the texel lies on a shadow
// border. Fewer means no bright region next to it, more an isolated texel in
// a bright region, which is upsampled. `neighbour_photons` holds 8 values, or
// 7 at a cube corner.
bool is_shadow_border(double photons, std::span<const double> neighbour_photons,
                      double threshold_photons);

class PreviewFilter {
 public:
  // A filter for far fields with faces of `face_size` texels and the cube
  // map's exact texel solid angles. Checks the parameters (GONIO_CHECK).
  PreviewFilter(int face_size, const PreviewFilterParams& params);
  // The same over given texel solid angles of one face (face_size² values
  // [sr], identical on every face); see CubePyramid.
  PreviewFilter(int face_size, const PreviewFilterParams& params,
                std::span<const double> face_solid_angle_sr);

  const PreviewFilterParams& params() const { return params_; }
  // New parameters for the next apply(); allocates nothing.
  void set_params(const PreviewFilterParams& params);
  // Levels the current parameters use on this face size.
  int levels_used() const;
  // The levels of the automatic choice (params.levels = 0) for a face size.
  static int auto_levels(int face_size);

  // Filters the field (same face size) into the preview map.
  const PreviewStats& apply(const FarField& field);

  // The preview after the last apply(): intensity [cd] per texel, cube-map
  // texel order. A stable texel holds exactly field.intensity_cd(texel).
  std::span<const double> intensity_cd() const { return output_; }
  const PreviewStats& stats() const { return stats_; }
  int face_size() const { return n_; }

 private:
  void fill_halo(int level, std::vector<double>& padded, bool corners) const;
  void push_level(int level, int top, double photons_per_lm);

  int n_;
  PreviewFilterParams params_;
  CubePyramid pyramid_;
  // Per level k ≥ 1: filtered intensities [cd] of each face with a one-texel
  // border (ghost texels copied from the adjacent faces), (M + 2)² per face.
  std::vector<std::vector<double>> filtered_;
  // Per level k ≥ 2: photon counts with the same border, for the shadow-border rule.
  std::vector<std::vector<double>> counts_;
  // Per level below the coarsest: +1 / −1 / 0 where the photon count
  // contradicts the upsampled estimate upwards / downwards / not (adaptive
  // stability), with the same border.
  std::vector<std::vector<double>> contradictions_;
  std::vector<double> estimates_;  // upsampled estimates of the level being pushed [cd]
  // Per level: for each face, edge and position, the padded index of the
  // texel across that edge.
  std::vector<std::vector<std::uint32_t>> halo_source_;
  std::vector<double> output_;     // level 0 [cd]
  std::vector<double> row_flux_;   // preview flux per level-0 row [lm]
  std::vector<std::uint32_t> row_stable_;
  PreviewStats stats_;
};

}  // namespace gonio::sim
