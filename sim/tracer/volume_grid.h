// Free paths inside scattering parts without a ray query (issue 43).
//
// A uniform grid over the scattering parts' boxes; each cell lists the
// planes of every triangle of the scene that meets it (a separating-axis
// test, widened by the margin). A straight segment whose two ends lie in
// the same cell, at least the margin inside it, and on the same side of
// every plane listed there, at least the margin away, crosses no triangle:
// a free path drawn inside a part that ends there needs no ray query (the
// query would have found its face beyond the end: the margin is far wider
// than the rounding of a float ray query). Cells are a few mean free paths
// wide, so most of a walk's free paths start and end in one cell; a free
// path into a face neighbour is tested against both cells' planes.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "sim/scene.h"

namespace gonio::sim {

class VolumeGrid {
 public:
  // The grid for `scene`'s scattering parts with cells `mean_free_paths`
  // of the smallest mean free path (1/(μs + μa)) wide (wider where the
  // cells would exceed `max_cells`); none where no material scatters or
  // mean_free_paths <= 0.
  static std::optional<VolumeGrid> build(const SceneDesc& scene, double mean_free_paths,
                                         std::size_t max_cells = std::size_t{1} << 21);

  // Whether the segment from p to q provably crosses no triangle (false
  // also where it is not proven: different cells, outside the grid, near
  // a plane).
  bool segment_free(const Vec3& p, const Vec3& q) const {
    const std::int64_t c = cell_of(p);
    if (c < 0) return false;
    const std::int64_t d = cell_of(q);
    if (d < 0) return false;
    return c == d ? planes_free(p, q, static_cast<std::size_t>(c)) : across(p, q, c, d);
  }

  // A walk's memory between free paths (issue 43, third round): a ball
  // around a point of the walk that meets no triangle (its radius the
  // distance to the nearest plane listed in the point's cell and to the
  // cell's walls, less the margins) and the side of each of that cell's
  // planes there. A free path that starts in the ball is free where its
  // end lies in the ball too (the ball is convex): no scan; else, with its
  // end in the same cell, one dot product a plane for the end (the start's
  // sides are the centre's: the ball crosses no listed plane). reset()
  // wherever the photon moved by anything but a proven free path.
  struct Walk {
    Vec3 centre;
    double radius2 = 0.0;     // 0: no ball
    std::int64_t cell = -1;   // the centre's cell, whose planes' sides `below` holds; −1: none
    std::uint64_t below = 0;  // bit k: the centre lies below the cell's k-th plane
    void reset() {
      radius2 = 0.0;
      cell = -1;
    }
  };
  // segment_free(p, q) for a p inside w's ball (any p where w is reset);
  // where the segment is free, w's ball and sides are then those of a point
  // whose ball holds q; where it is not, w is reset.
  bool segment_free(const Vec3& p, const Vec3& q, Walk& w) const {
    const Vec3 d = q - w.centre;
    if (dot(d, d) < w.radius2) return true;
    return walk_free(p, q, w);
  }

  // Whether scene mesh `mesh` is a closed scattering part: every edge
  // (its corners' positions) bounds exactly two of its triangles, in
  // opposite senses. Only inside such a part does a free path that meets
  // no face end in the part for certain (sim/tracer/tracer.cpp: the walk
  // after entering it, and the query bounded at the drawn path, are for
  // these parts; an open part's inside ends at its hole).
  bool closed(std::uint32_t mesh) const { return mesh < closed_.size() && closed_[mesh] != 0; }

  double cell_m() const { return cell_m_; }
  std::size_t cell_count() const { return start_.empty() ? 0 : start_.size() - 1; }
  std::size_t plane_entries() const { return planes_.size(); }

 private:
  // The signed distance of p from the plane n·x = d (n unit).
  static double plane_offset(const std::array<double, 4>& n, const Vec3& p) {
    return n[0] * p.x + n[1] * p.y + n[2] * p.z - n[3];
  }
  // p and q on one side of every plane listed in `cell`, beyond the margin.
  bool planes_free(const Vec3& p, const Vec3& q, std::size_t cell) const {
    for (std::uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) {
      const std::array<double, 4>& n = planes_[k];
      const double sp = plane_offset(n, p), sq = plane_offset(n, q);
      if (!((sp > plane_margin_ && sq > plane_margin_) || (sp < -plane_margin_ && sq < -plane_margin_))) return false;
    }
    return true;
  }
  // segment_free(p, q, w) past its ball test.
  bool walk_free(const Vec3& p, const Vec3& q, Walk& w) const;
  // q against the planes of w.cell on the sides of w's centre, beyond the
  // margin; w's ball moved to q (`wall`: q's distance to the cell's walls)
  // where it passes, w reset where not.
  bool sides_free(const Vec3& q, double wall, Walk& w) const;
  // w's ball and sides at q, in cell c at `wall` from its walls; false
  // (w's sides unknown: cell −1) where q lies within the margin of a plane
  // or the cell lists more planes than `below` holds.
  bool ball_at(const Vec3& q, std::int64_t c, double wall, Walk& w) const;
  // The cell holding p at least the margin inside it, or −1; `wall`: p's
  // distance to that cell's nearest wall.
  std::int64_t locate(const Vec3& p, double* wall) const {
    const double f[3] = {(p.x - lower_.x) * inv_cell_, (p.y - lower_.y) * inv_cell_, (p.z - lower_.z) * inv_cell_};
    if (!(f[0] >= 0.0 && f[1] >= 0.0 && f[2] >= 0.0 && f[0] < dims_f_[0] && f[1] < dims_f_[1] && f[2] < dims_f_[2]))
      return -1;
    const std::int64_t i[3] = {static_cast<std::int64_t>(f[0]), static_cast<std::int64_t>(f[1]),
                               static_cast<std::int64_t>(f[2])};
    // In cells: the distance to the nearest wall, at most half a cell.
    const double g[3] = {f[0] - static_cast<double>(i[0]), f[1] - static_cast<double>(i[1]),
                         f[2] - static_cast<double>(i[2])};
    const double near =
        std::min({std::min(g[0], 1.0 - g[0]), std::min(g[1], 1.0 - g[1]), std::min(g[2], 1.0 - g[2])}) * cell_m_;
    if (!(near > margin_)) return -1;
    *wall = near;
    return (i[2] * dims_[1] + i[1]) * dims_[0] + i[0];
  }
  // Ends in cells c ≠ d: free where the cells share a face (together one
  // box, which holds the segment) and the planes of both allow it.
  bool across(const Vec3& p, const Vec3& q, std::int64_t c, std::int64_t d) const;
  // Whether cells c and d share a face (one step along one axis).
  bool face_neighbours(std::int64_t c, std::int64_t d) const;
  // The cell holding p at least the margin inside it, or −1.
  std::int64_t cell_of(const Vec3& p) const {
    const double f[3] = {(p.x - lower_.x) * inv_cell_, (p.y - lower_.y) * inv_cell_, (p.z - lower_.z) * inv_cell_};
    std::int64_t i[3];
    for (int a = 0; a < 3; ++a) {
      if (!(f[a] >= 0.0) || !(f[a] < static_cast<double>(dims_[a]))) return -1;
      i[a] = static_cast<std::int64_t>(f[a]);
      const double inside = (f[a] - static_cast<double>(i[a])) * cell_m_;
      if (!(inside > margin_) || !(inside < cell_m_ - margin_)) return -1;
    }
    return (i[2] * dims_[1] + i[1]) * dims_[0] + i[0];
  }

  Vec3 lower_;
  double cell_m_ = 0.0, inv_cell_ = 0.0, margin_ = 0.0;
  // The plane test's margin: 1.25 × margin_. A cell lists one plane for
  // facets whose planes differ by at most 0.25 × margin_ over the cell
  // (a flat quad's two triangles), so each dropped plane is still passed
  // beyond margin_ (volume_grid.cpp, merge_planes).
  double plane_margin_ = 0.0;
  std::int64_t dims_[3] = {0, 0, 0};
  double dims_f_[3] = {0.0, 0.0, 0.0};  // dims_ as doubles
  std::vector<std::uint32_t> start_;            // per cell, into planes_ (CSR)
  std::vector<std::array<double, 4>> planes_;   // n, d: n·x − d, n unit
  std::vector<char> closed_;                    // per scene mesh: closed() 
};

}  // namespace gonio::sim
