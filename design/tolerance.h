// Tolerance analysis (issue 42): the figures a trial is judged by, the Latin
// hypercube that draws Monte Carlo trials, the limits of --spec, and the
// statistics of gonio tolerance (tools/cli/cmd_tolerance.cpp; docs/tolerance.md).
// Every trial is traced with the same seed, so two trials differ by the
// luminaire, not by photon noise (common random numbers); the noise floor
// is the nominal traced again with other seeds.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "io/outputs/plot.h"
#include "photometry/diagnostics.h"
#include "photometry/distribution.h"

namespace gonio::design {

// The figures of one trial, in this order.
enum FigureIndex : std::size_t {
  kPeakCd,
  kPeakC,
  kPeakGamma,
  kBeamC0,
  kBeamC90,
  kFieldC0,
  kFieldC90,
  kFlux,
  kLor,
  kRms,
  kUgr,      // UGR of the 4H × 8H room, 70/50/20, crosswise (photometry::ugr_table); NaN without a luminous area
  kBugB,     // BUG rating's B, U and G (photometry::bug_rating), 0…5
  kBugU,
  kBugG,
  kCct,      // the whole luminaire's CCT [K] (spectral runs; NaN in grey ones)
  kDuvMax,   // Δu′v′ max over angle (sim::colour_over_angle; spectral runs)
  kAxisC0,   // the beam's axis: the tilt of the mean direction of the bins at ≥ half the peak
  kAxisC90,  // towards C0 and towards C90 [deg] (see beam_axis_deg)
  kDugr,     // CIE 232:2019's ΔUGR, the largest over the luminance images' views (runs that ask for
             // luminance images, --luminance-image; NaN otherwise): io::largest_delta_ugr
  kUgrCie232,  // kUgr + kDugr: the 4H × 8H UGR with CIE 232's correction (the datasheet's figure)
  kFigureCount
};
struct FigureInfo {
  const char* key;   // --spec and report.json's name: peak_cd, beam_c0, …
  const char* unit;  // "cd", "deg", "lm", "1", "% of peak"
  const char* text;  // for tables
};
const std::array<FigureInfo, kFigureCount>& figure_info();
// The figure by its key; nothing for an unknown one.
std::optional<std::size_t> figure_by_key(const std::string& key);

using FigureValues = std::array<double, kFigureCount>;

// The figures of a distribution (photometry::summarize: the peak and its
// C and γ, beam and field angles in C0-C180 and C90-C270, flux, LOR) and its
// RMS difference from `nominal` (photometry::compare on the C and γ steps
// given, % of the nominal's peak; 0 for the nominal itself).
Result<FigureValues> figures_of(const photometry::Distribution& d, const photometry::Distribution& nominal,
                                double c_step_deg, double gamma_step_deg);

// The beam's axis as two tilts from the nadir [deg]: the mean direction of
// the grid points whose intensity is at least half the peak, weighted by
// intensity × the solid angle around each point, turned towards C0 (first)
// and C90 (second): atan2(m·x, −m·z) and atan2(m·y, −m·z) in the photometric
// frame (x along C0, y along C90, z up). Sub-grid: a distribution turned by
// α about the C90 axis has its axis_c0 moved by α (to the accuracy of the
// grid's quadrature). Type C, symmetry none; NaN otherwise or when dark.
std::array<double, 2> beam_axis_deg(const photometry::Distribution& d);

// A Latin hypercube of `trials` points in [0, 1)^dims: each dimension's
// [0, 1) cut into `trials` equal strata, one point in each, the strata
// shuffled independently per dimension; deterministic in `seed`.
// [trial][dimension].
std::vector<std::vector<double>> latin_hypercube(std::size_t trials, std::size_t dims, std::uint64_t seed);

// One --spec limit: FIGURE=LO..HI (either end may be left out), FIGURE<=HI
// or FIGURE>=LO.
struct SpecLimit {
  std::size_t figure = 0;
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool holds(double v) const { return v >= lo && v <= hi; }
  std::string text() const;
};
// "beam_c0=24..28,flux=900..,ugr<=19" as limits; errors name the item.
Result<std::vector<SpecLimit>> parse_spec(const std::string& text);

// One --percentile item: P (the RMS difference from the nominal, the
// figure best and worst are chosen by) or FIGURE:P, 0 ≤ P ≤ 100.
struct PercentileChoice {
  std::size_t figure = kRms;
  double percent = 50.0;
  // "rms 95", "beam_c0 5": for messages; file stem "p95_rms", "p5_beam_c0".
  std::string text() const;
  std::string stem() const;
};
// "5,95,beam_c0:50" as choices, in order; errors name the item.
Result<std::vector<PercentileChoice>> parse_percentiles(const std::string& text);

// The trial at the P-th percentile of `values` by the nearest rank: the
// finite values sorted ascending (ties by their index), the one at rank
// max(1, ⌈P · n / 100⌉) of the n finite ones (P · n computed first, so
// that 95 · 20 / 100 is 19 exactly). Its index in `values`; nothing
// where no value is finite. P = 0 gives the smallest, 100 the largest.
std::optional<std::size_t> nearest_rank(const std::vector<double>& values, double percent);

// The inverse sensitivity of one tolerance, linear: the largest factor k
// by which its limits may be scaled so that nominal + k·change stays within
// the limit for the changes at both of its limits (a figure taken as linear
// in the tolerance); +inf where neither change moves towards a finite
// limit, 0 where the nominal is outside the limit already.
double allowed_scale(double nominal, double change_low, double change_high, const SpecLimit& limit);

// The traced inverse sensitivity scales a tolerance by at most this factor.
inline constexpr double kMaxInverseScale = 16.0;

// The photon noise of each figure: the sample standard deviation over the
// nominal and its re-traces with independent seeds; for the RMS difference
// the mean RMS difference of the re-traces from the nominal (the floor an
// RMS difference cannot go below). NaN with no re-trace.
FigureValues noise_floor(const FigureValues& nominal, const std::vector<FigureValues>& independent);

// A change is below the noise where |change| < kNoiseFactor · noise.
inline constexpr double kNoiseFactor = 2.0;
bool below_noise(double change, double noise);

// A histogram of values over `bins` equal bins between their extremes.
struct Histogram {
  std::vector<double> edges;  // bins + 1
  std::vector<std::size_t> counts;
};
Histogram histogram(const std::vector<double>& values, std::size_t bins);

// One row of the sensitivity table: a tolerance's change of one figure at
// its low and high limits.
struct SensitivityRow {
  std::string label;  // "LED.x U(±0.1) mm"
  double low = 0.0, high = 0.0;                // the tolerance's limits
  double change_low = 0.0, change_high = 0.0;  // figure − nominal
  double largest() const;                      // max |change|, NaN-aware
};
// A tornado chart of one figure's rows (largest first, as given): each
// tolerance a horizontal bar from its change at the low limit to the one at
// the high limit, the noise floor as dashed lines at ±kNoiseFactor·noise.
io::Figure tornado_figure(const std::string& title, const std::string& unit, const std::vector<SensitivityRow>& rows,
                          double noise);

}  // namespace gonio::design
