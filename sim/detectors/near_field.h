// Near-field photometry: the illuminance on planes perpendicular to the
// nadir at distances D below the luminaire's centre, from the escaping
// photons themselves, beside what the far field predicts there.
//
// Each escaping photon is binned twice on every plane: where its last free
// path (origin, direction) meets the plane — the near field — and where a
// ray with its direction from the centre meets it — the far field, which
// is the integral of I(θ)·cos³θ/D² over the pixel for the run's own far
// field (the photons' directions, before any grid). Both tallies are integer
// power units (ledger.h) per pixel, so sums do not depend on threads, chunks
// or ranks; pairing the two on the same photons cancels most photon noise:
// a pixel's deviation differs from zero only through the photons that land
// in different pixels, and those are counted (`moved`) for its uncertainty.
//
// A plane at distance D is a square of side 4·D centred on the nadir point
// (θ up to 63.4° along C0 and C90), kNearFieldPixels pixels a side (odd: the
// centre pixel sits on the nadir). Columns run along C0 (from −2D to +2D),
// rows along C90 (from +2D at the top to −2D at the bottom).
//
// The far-field distance is judged on a coarser lattice of the same square,
// kCriterionCells a side (cells of 4D/21, 11° at the nadir), with its own
// integer tallies (so each cell's photon noise is counted exactly, not
// bounded from its pixels'): per cell, the deviation δ = (E − E_far)/E_far
// and its standard deviation σ = √moved / photons in E_far. Over the cells
// where E_far ≥ 10 % of the plane's largest cell, a plane
// - passes when every cell has |δ| + z₁σ ≤ 1 % (z₁ = 1.645, one-sided 95 %):
//   a plane with a cell truly beyond 1 % passes with a chance below 5 %
//   (an intersection–union test: every cell must pass, so no correction for
//   the number of cells is needed in this direction);
// - fails when some cell has |δ| − z_nσ > 1 %, z_n the two-sided Šidák
//   bound for n cells at 95 % (the chance that noise alone fails a plane
//   whose cells are all within 1 % stays below 5 % whatever n);
// - is undecided otherwise: too few photons to tell, and
//   `photons_to_tell` estimates how many would (σ falls as 1/√photons).
// Pixel-level figures (max_deviation_pct) stay beside it for the images.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "photometry/frame.h"
#include "photometry/vec3.h"
#include "sim/ledger.h"
#include "sim/scene.h"

namespace gonio::sim {

// An escaped photon kept for a ray file and the luminous centre
// (TracerTally::capture_below, sim/tracer/tracer.h).
struct EscapedRay {
  std::uint64_t photon = 0;  // run-wide index
  Vec3 origin;               // start of its last free path [m]
  Vec3 direction;            // unit
  std::uint64_t power_units = kPowerUnits;
};

inline constexpr int kNearFieldPixels = 41;
inline constexpr double kNearFieldHalfWidthPerM = 2.0;  // half side / D
inline constexpr int kCriterionCells = 21;               // the criterion's lattice, a side
inline constexpr double kFarFieldLimitPct = 1.0;         // the deviation the far field may have [%]
inline constexpr double kComparedFraction = 0.1;         // cells compared: E_far ≥ this × the maximum
inline constexpr double kConfidence = 0.95;              // of each verdict

// Where the planes lie: the centre (metres, world), the photometric frame
// (nadir = −up) and the distances [m], each > 0.
struct NearFieldPlanes {
  Vec3 centre;
  photometry::PhotometricFrame frame;
  std::vector<double> distances_m;

  int pixels() const { return kNearFieldPixels; }
  std::size_t pixel_count() const {
    return static_cast<std::size_t>(kNearFieldPixels) * static_cast<std::size_t>(kNearFieldPixels);
  }
  std::size_t cell_count() const {
    return static_cast<std::size_t>(kCriterionCells) * static_cast<std::size_t>(kCriterionCells);
  }
  double half_width_m(std::size_t plane) const { return kNearFieldHalfWidthPerM * distances_m[plane]; }
  double pixel_size_m(std::size_t plane) const { return 2.0 * half_width_m(plane) / kNearFieldPixels; }
  double cell_size_m(std::size_t plane) const { return 2.0 * half_width_m(plane) / kCriterionCells; }
};

// The luminaire's photometric centre [m, world], the planes' reference: in
// the photometric frame, the middle of the bounding box of every placed
// vertex, point emitter and ray-set ray start across C0 and C90, and its
// lowest point along the nadir — the centre of the bounding box's bottom
// face, where LM-63 puts the centre of a downward luminous opening (the
// bounding box's middle would put the source a half height too far, a
// 2·h/D error that fades only as 1/D). The origin for an empty scene.
Vec3 luminaire_centre(const SceneDesc& scene);

// Calls f(world point [m]) for every point that bounds the luminaire: each
// placed vertex, point emitter and ray-set ray start (luminaire_centre's
// box, and the luminance images' extent).
void for_each_luminaire_point(const SceneDesc& scene, const std::function<void(const Vec3&)>& f);

// The photometric centre the planes are measured from: the luminous centre
// of the light that heads for them, i.e. the power-weighted mean of the
// points where escaping photons that travel below the horizontal (towards
// the nadir: direction · up < 0) start their last free path — the middle
// of the light-emitting surfaces as the planes see them (a lamp's bulb, a
// diffuser's face, the opening of a reflector whose rim the light leaves
// from). `escaped`: escapes of a run's first photons (Simulation traces
// kCentrePilotPhotons of them before the run, so the planes never move).
// `fallback` (luminaire_centre) when none heads down.
inline constexpr std::uint64_t kCentrePilotPhotons = 65536;
Vec3 luminous_centre(const std::vector<EscapedRay>& escaped, const photometry::PhotometricFrame& frame,
                     const Vec3& fallback);

// One thread's counts (or a run's sum): per plane, per pixel, row-major.
struct NearFieldTally {
  std::vector<std::uint64_t> near_units;  // power units landing there along their path
  std::vector<std::uint64_t> far_units;   // power units whose direction from the centre lands there
  std::vector<std::uint64_t> moved;       // photons landing in one of the two pixels but not the other
  // The same three on the criterion's lattice (cell_count() per plane).
  std::vector<std::uint64_t> cell_near_units, cell_far_units, cell_moved;

  bool active() const { return !near_units.empty(); }
  void reset(const NearFieldPlanes& planes);  // zeroed counts sized for the planes
  void clear();                               // zero, keeping the sizes
  void add(const NearFieldTally& other);      // same sizes
  // Bins one escaped photon (origin [m], unit direction, power units).
  void add(const NearFieldPlanes& planes, const Vec3& origin, const Vec3& direction,
           std::uint64_t power_units);
};

enum class PlaneVerdict : std::uint8_t {
  Passes,     // every compared cell within 1 % at 95 % confidence
  Fails,      // some cell beyond 1 % at 95 % confidence (Šidák over the cells)
  Undecided,  // neither: too few photons to tell
};
const char* to_string(PlaneVerdict v);  // "passes", "fails", "undecided"

// One plane's result.
struct NearFieldPlane {
  double distance_m = 0.0;
  double half_width_m = 0.0;
  double pixel_size_m = 0.0;
  int pixels = 0;                    // a side
  std::vector<double> near_lx;       // row-major, pixel averages
  std::vector<double> far_lx;        // the far field's prediction, pixel averages
  double on_axis_lx = 0.0;           // centre pixel, near field
  double far_field_on_axis_lx = 0.0; // centre pixel, far field
  // Over the pixels where far_lx ≥ 10 % of its maximum: the largest
  // |near − far| / far [%] (photon noise included: the images' figure).
  double max_deviation_pct = 0.0;
  std::uint64_t min_photons = 0;     // fewest far-field photons in a compared pixel
  // The criterion (top of this header), over the compared cells:
  int cells_compared = 0;
  double cell_deviation_pct = 0.0;   // the largest |δ| [%]
  double upper_bound_pct = 0.0;      // the largest |δ| + z₁σ [%]
  double max_deviation_bound_pct = 0.0;  // = upper_bound_pct (report.json's older key)
  double lower_bound_pct = 0.0;      // the largest |δ| − z_nσ [%] (may be < 0)
  double z_fail = 0.0;               // z_n
  PlaneVerdict verdict = PlaneVerdict::Undecided;
  // Undecided: the photons after which it would be decided if each cell's
  // deviation stayed as measured (above 1 %: its lower bound
  // max(0, |δ| − z₁σ)) and σ fell as 1/√photons (0 when decided; +∞ when
  // that deviation sits at 1 %).
  double photons_to_tell = 0.0;
};

// The planes from summed counts; lm_per_unit: flux of one power unit [lm]
// (total flux / photons emitted / kPowerUnits, or per power unit emitted);
// `photons`: photons emitted so far (for photons_to_tell).
std::vector<NearFieldPlane> near_field_planes(const NearFieldPlanes& planes, const NearFieldTally& sum,
                                              double lm_per_unit, double photons = 0.0);

// z with P(Z > z) = p for a standard normal Z (0 < p < 1).
double normal_upper_quantile(double p);

struct FarFieldDistance {
  // The smallest distance asked for from which that plane and every farther
  // one pass; none when the farthest plane does not.
  std::optional<double> distance_m;
  // Why not: the farthest plane's verdict (Passes when found).
  PlaneVerdict farthest = PlaneVerdict::Undecided;
  // Found: the nearest plane before it that fails or is undecided (its
  // distance; none when every plane asked for passes).
  std::optional<double> nearer_plane_m;
  // Undecided planes from `distance_m`'s would-be run: the most photons one
  // of them needs (0 when none).
  double photons_to_tell = 0.0;
};
FarFieldDistance far_field_distance(const std::vector<NearFieldPlane>& planes);
// far_field_distance(planes).distance_m (the command line's older call).
std::optional<double> far_field_distance_m(const std::vector<NearFieldPlane>& planes);

}  // namespace gonio::sim
