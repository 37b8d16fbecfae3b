#include "sim/filter/cube_neighbours.h"

#include <algorithm>

#include "photometry/diagnostics.h"
#include "sim/detectors/cube_map.h"

namespace gonio::sim {

CubeNeighbours::CubeNeighbours(int face_size) : n_(face_size) {
  GONIO_CHECK_MSG(face_size >= 1 && face_size <= 16384, "cube-map face size out of range");
  const std::size_t n = static_cast<std::size_t>(n_);
  across_.resize(static_cast<std::size_t>(kCubeFaces) * 4 * n);
  const double half = 0.5 * n_;
  for (int face = 0; face < kCubeFaces; ++face) {
    for (int edge = 0; edge < 4; ++edge) {
      for (int p = 0; p < n_; ++p) {
        // The virtual texel one step past the edge, continuing the face grid.
        int x = p, y = p;
        switch (static_cast<FaceEdge>(edge)) {
          case FaceEdge::Left: x = -1; break;
          case FaceEdge::Right: x = n_; break;
          case FaceEdge::Top: y = -1; break;
          case FaceEdge::Bottom: y = n_; break;
        }
        const double a = (x + 0.5) / half - 1.0, b = (y + 0.5) / half - 1.0;
        const CubePoint q = CubeMapGrid::locate(CubeMapGrid::direction(face, a, b));
        GONIO_CHECK(q.face != face);
        const int qx = std::clamp(static_cast<int>((q.a + 1.0) * half), 0, n_ - 1);
        const int qy = std::clamp(static_cast<int>((q.b + 1.0) * half), 0, n_ - 1);
        across_[(static_cast<std::size_t>(face) * 4 + static_cast<std::size_t>(edge)) * n + p] =
            static_cast<std::uint32_t>((static_cast<std::size_t>(q.face) * n + qy) * n + qx);
      }
    }
  }
}

std::size_t CubeNeighbours::neighbour(int face, int x, int y, int dx, int dy) const {
  const int nx = x + dx, ny = y + dy;
  const bool out_x = nx < 0 || nx >= n_, out_y = ny < 0 || ny >= n_;
  if (out_x && out_y) return kNone;
  if (out_x) return across_edge(face, nx < 0 ? FaceEdge::Left : FaceEdge::Right, ny);
  if (out_y) return across_edge(face, ny < 0 ? FaceEdge::Top : FaceEdge::Bottom, nx);
  const std::size_t n = static_cast<std::size_t>(n_);
  return (static_cast<std::size_t>(face) * n + static_cast<std::size_t>(ny)) * n +
         static_cast<std::size_t>(nx);
}

}  // namespace gonio::sim
