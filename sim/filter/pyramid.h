// The pull phase of the preview filter: an image pyramid over the far-field
// cube map.
//
// Level 0 is the far field itself (faces of N texels). Each texel of level
// k + 1 (faces of N / 2^(k+1) texels) sums the flux, the photon count and the
// solid angle of the 2 × 2 texels below it on the same face. Because solid
// angle is summed like flux, flux / solid angle is the exact mean intensity
// over a coarse texel on every level, although cube-map texels differ up to
// 5.2× in size.
//
// Face sizes: a level exists while the face size halves evenly, so a power of
// two N has log2(N) + 1 levels (down to 1 × 1 faces) and any other N fewer
// (100 → 100, 50, 25; an odd N has level 0 only). Requests for more levels are
// clamped; levels() says how many there are.
//
// Texel index on level k with face size M: (face · M + y) · M + x, as on the
// cube map (sim/detectors/cube_map.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sim/detectors/far_field.h"

namespace gonio::sim {

class CubePyramid {
 public:
  // 1 + how many times the face size n halves to an integer.
  static int max_levels(int n);

  // Levels 0 … levels − 1 (clamped to [1, max_levels(n)]) over faces of n
  // texels with the cube map's exact texel solid angles. Allocates every
  // buffer once.
  CubePyramid(int n, int levels);
  // The same over given texel solid angles of one face (n² values
  // [sr], row by row, identical on every face). A flat image of equal texels,
  // the reference thesis's setting, is all values equal.
  CubePyramid(int n, int levels, std::span<const double> face_solid_angle_sr);

  int levels() const { return levels_; }
  int face_size(int level) const { return n0_ >> level; }
  std::size_t texel_count(int level) const {
    const std::size_t m = static_cast<std::size_t>(face_size(level));
    return 6 * m * m;
  }

  // Sums the field up the pyramid (parallel; no allocation). The field's face
  // size must equal face_size(0). Level 0 is a view of the field's arrays:
  // valid while the field lives unchanged.
  void pull(const FarField& field);

  // Per texel of a level: accumulated flux [lm] and photons (after pull()).
  std::span<const double> flux_lm(int level) const;
  std::span<const std::uint64_t> photons(int level) const;
  // Solid angles [sr] of the face_size(level)² texels of one face, row by row
  // (identical on every face); they sum to 4π/6 on every level.
  std::span<const double> face_solid_angle_sr(int level) const {
    return solid_angle_[static_cast<std::size_t>(level)];
  }
  double solid_angle_sr(int level, std::size_t texel) const {
    const std::size_t m = static_cast<std::size_t>(face_size(level));
    return solid_angle_[static_cast<std::size_t>(level)][texel % (m * m)];
  }

 private:
  int n0_;
  int levels_;
  std::vector<std::vector<double>> solid_angle_;     // [level][y · M + x], one face
  std::vector<std::vector<double>> flux_;            // [level ≥ 1][texel]
  std::vector<std::vector<std::uint64_t>> photons_;  // [level ≥ 1][texel]
  std::span<const double> base_flux_;
  std::span<const std::uint64_t> base_photons_;
};

}  // namespace gonio::sim
