// Texel neighbourhoods on a cube map: which texel lies next to a texel, across
// face edges and cube corners, with the adjacent face's orientation.
//
// Inside a face the neighbour of (x, y) at offset (dx, dy) is (x + dx, y + dy).
// Beyond an edge it is the texel of the adjacent face that the continued face
// grid meets there: the texel containing the direction of the virtual texel
// centre one step past the edge (that point lies within half a texel of the
// adjacent texel's centre, so the look-up is exact). Beyond a corner there is
// nothing: three faces meet at a cube corner, so a corner texel has seven
// neighbours, not eight.
//
// Works for any face size ≥ 1 (the pyramid's levels go down to 1 × 1 faces,
// where each face's single texel has the four adjacent faces as neighbours).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace gonio::sim {

// The four edges of a face, in face-pixel terms (x grows right, y down).
enum class FaceEdge : int { Left = 0, Right = 1, Top = 2, Bottom = 3 };

class CubeNeighbours {
 public:
  static constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

  // Builds the edge tables for faces of `face_size` texels (1 ≤ face_size ≤
  // 16384), 24 · face_size entries.
  explicit CubeNeighbours(int face_size);

  int face_size() const { return n_; }

  // The texel index ((face · N + y) · N + x, sim/detectors/cube_map.h) just beyond
  // `edge` of `face`, at `position` along that edge (y for Left/Right, x for
  // Top/Bottom), 0 ≤ position < N.
  std::size_t across_edge(int face, FaceEdge edge, int position) const {
    return across_[(static_cast<std::size_t>(face) * 4 + static_cast<std::size_t>(edge)) * n_ +
                   static_cast<std::size_t>(position)];
  }

  // The texel at offset (dx, dy) ∈ {−1, 0, 1}² from texel (x, y) of `face`,
  // or kNone where that offset points past a cube corner.
  std::size_t neighbour(int face, int x, int y, int dx, int dy) const;

 private:
  int n_;
  std::vector<std::uint32_t> across_;  // [face][edge][position] → texel index
};

}  // namespace gonio::sim
