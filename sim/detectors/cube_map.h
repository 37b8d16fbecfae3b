// Geometry of the direction cube map that holds the far field: which texel a
// direction falls into, the direction of a texel, and exact texel solid angles.
//
// Face order and orientation follow OpenEXR's cube-map environment maps
// (ImfEnvmap.h): faces +X, −X, +Y, −Y, +Z, −Z stacked top to bottom in one
// N × 6N image. Within a face, pixel x grows to the right and pixel y
// downwards; with face coordinates a = 2(x + ½)/N − 1 and b = 2(y + ½)/N − 1
// at texel centres, the (unnormalised) directions are
//     +X: ( 1, −b,  a)    −X: (−1, −b, −a)
//     +Y: ( a,  1, −b)    −Y: ( a, −1,  b)
//     +Z: (−a, −b,  1)    −Z: ( a, −b, −1)
// Texels are areas: texel (x, y) covers a ∈ [2x/N − 1, 2(x+1)/N − 1], and so
// for b. (OpenEXR's own sampling helpers put pixel centres on the cube edges;
// Gonio bins photons into areas, so its texel centres sit half a texel in.)
//
// Texel index: (face · N + y) · N + x.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "photometry/vec3.h"

namespace gonio::sim {

enum class CubeFace : int { PosX = 0, NegX = 1, PosY = 2, NegY = 3, PosZ = 4, NegZ = 5 };

inline constexpr int kCubeFaces = 6;

// Where a direction meets the cube: the face, and continuous face coordinates
// a, b in [−1, 1].
struct CubePoint {
  int face;
  double a;
  double b;
};

class CubeMapGrid {
 public:
  // face_size ≥ 1 texels along each edge of a face.
  explicit CubeMapGrid(int face_size);

  int face_size() const { return n_; }
  std::size_t texel_count() const { return 6 * static_cast<std::size_t>(n_) * n_; }
  std::size_t index(int face, int x, int y) const {
    return (static_cast<std::size_t>(face) * n_ + y) * n_ + x;
  }

  // The face and face coordinates of a non-zero direction (need not be unit).
  static CubePoint locate(const Vec3& direction);
  // The point on the cube (unnormalised direction) at face coordinates a, b.
  static Vec3 direction(int face, double a, double b);
  // Exact solid angle [sr] of the face rectangle [a0, a1] × [b0, b1].
  static double solid_angle(double a0, double b0, double a1, double b1);

  // The texel a non-zero direction falls into.
  std::size_t texel_of(const Vec3& direction) const;
  // Unit direction through the centre of a texel.
  Vec3 texel_direction(std::size_t texel) const;
  // Exact solid angle of a texel [sr]; the six faces' texels sum to 4π.
  double texel_solid_angle(std::size_t texel) const {
    return face_solid_angle_[texel % (static_cast<std::size_t>(n_) * n_)];
  }

  // Smallest power-of-two face size whose largest texel (at a face centre)
  // spans at most `step_deg / texels_per_step` degrees: the resolution an
  // output grid with that angular step needs.
  static int face_size_for_step(double step_deg, double texels_per_step = 2.0);

 private:
  int n_;
  std::vector<double> face_solid_angle_;  // N × N, identical on every face
};

}  // namespace gonio::sim
