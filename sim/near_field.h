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
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "photometry/frame.h"
#include "photometry/vec3.h"
#include "sim/scene.h"

namespace gonio::sim {


inline constexpr int kNearFieldPixels = 41;
inline constexpr double kNearFieldHalfWidthPerM = 2.0;  // half side / D

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
  double half_width_m(std::size_t plane) const { return kNearFieldHalfWidthPerM * distances_m[plane]; }
  double pixel_size_m(std::size_t plane) const { return 2.0 * half_width_m(plane) / kNearFieldPixels; }
};

// The luminaire's photometric centre [m, world], the planes' reference: in
// the photometric frame, the middle of the bounding box of every placed
// vertex, point emitter and ray-set ray start across C0 and C90, and its
// lowest point along the nadir — the centre of the bounding box's bottom
// face, where LM-63 puts the centre of a downward luminous opening (the
// bounding box's middle would put the source a half height too far, a
// 2·h/D error that fades only as 1/D). The origin for an empty scene.
Vec3 luminaire_centre(const SceneDesc& scene);

// One thread's counts (or a run's sum): per plane, per pixel, row-major.
struct NearFieldTally {
  std::vector<std::uint64_t> near_units;  // power units landing there along their path
  std::vector<std::uint64_t> far_units;   // power units whose direction from the centre lands there
  std::vector<std::uint64_t> moved;       // photons landing in one of the two pixels but not the other

  bool active() const { return !near_units.empty(); }
  void reset(const NearFieldPlanes& planes);  // zeroed counts sized for the planes
  void clear();                               // zero, keeping the sizes
  void add(const NearFieldTally& other);      // same sizes
  // Bins one escaped photon (origin [m], unit direction, power units).
  void add(const NearFieldPlanes& planes, const Vec3& origin, const Vec3& direction,
           std::uint64_t power_units);
};

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
  // |near − far| / far [%], and the largest of that plus two standard
  // deviations of photon noise (from `moved`) — the bound the 1 % criterion
  // is checked against.
  double max_deviation_pct = 0.0;
  double max_deviation_bound_pct = 0.0;
  std::uint64_t min_photons = 0;     // fewest far-field photons in a compared pixel
};

// The planes from summed counts; lm_per_unit: flux of one power unit [lm]
// (total flux / photons emitted / kPowerUnits, or per power unit emitted).
std::vector<NearFieldPlane> near_field_planes(const NearFieldPlanes& planes, const NearFieldTally& sum,
                                              double lm_per_unit);

// The smallest distance asked for from which the far field holds: that
// plane and every farther one have max_deviation_bound_pct ≤ limit_pct.
// None when the farthest plane fails (or no plane).
std::optional<double> far_field_distance_m(const std::vector<NearFieldPlane>& planes, double limit_pct = 1.0);

}  // namespace gonio::sim
