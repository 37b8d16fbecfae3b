// The only file that includes CGAL.
#include "io/model/model_check.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "io/model/model_check_cache.h"

namespace gonio::io {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Segment = Kernel::Segment_3;
using Tri = std::array<std::uint32_t, 3>;
namespace PMP = CGAL::Polygon_mesh_processing;

// Self-intersection search stops after this many pairs: the mesh is broken
// either way, and a soup of coincident copies would otherwise be quadratic.
constexpr std::size_t kMaxPairs = 10000;

std::string point_text(const Point& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%g, %g, %g)", p.x(), p.y(), p.z());
  return buf;
}

// One mesh with vertices merged by exact position.
struct Welded {
  std::vector<Point> points;
  std::vector<Tri> triangles;           // non-degenerate, welded
  std::vector<std::uint32_t> source;    // index of each in the mesh's triangle list
  std::size_t degenerate = 0;
  std::size_t first_degenerate = 0;
};

Welded weld(const sim::Mesh& mesh) {
  Welded w;
  const std::size_t n = mesh.positions.size();
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  auto key = [&](std::uint32_t i) {
    // +0.0f for −0.0f, so that the two zeros are one position.
    const sim::Vec3f& p = mesh.positions[i];
    return std::array<float, 3>{p.x + 0.0f, p.y + 0.0f, p.z + 0.0f};
  };
  // Equal keys are one point whatever their order, so an unstable parallel
  // sort gives the same ids.
  tbb::parallel_sort(order.begin(), order.end(), [&](auto a, auto b) { return key(a) < key(b); });
  std::vector<std::uint32_t> id(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || key(order[k]) != key(order[k - 1])) {
      const sim::Vec3f& p = mesh.positions[order[k]];
      w.points.emplace_back(p.x, p.y, p.z);
    }
    id[order[k]] = static_cast<std::uint32_t>(w.points.size() - 1);
  }
  const std::size_t triangles = mesh.triangle_count();
  std::vector<char> degenerate(triangles, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles, 4096),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t t = r.begin(); t != r.end(); ++t) {
                        const Tri tri{id[mesh.indices[3 * t]], id[mesh.indices[3 * t + 1]],
                                      id[mesh.indices[3 * t + 2]]};
                        degenerate[t] = tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] ||
                                        CGAL::collinear(w.points[tri[0]], w.points[tri[1]], w.points[tri[2]]);
                      }
                    });
  w.triangles.reserve(triangles);
  w.source.reserve(triangles);
  for (std::size_t t = 0; t < triangles; ++t) {
    if (degenerate[t]) {
      if (w.degenerate++ == 0) w.first_degenerate = t;
      continue;
    }
    w.triangles.push_back({id[mesh.indices[3 * t]], id[mesh.indices[3 * t + 1]], id[mesh.indices[3 * t + 2]]});
    w.source.push_back(static_cast<std::uint32_t>(t));
  }
  return w;
}

// A floating-point filter in front of the exact fold test: true when p and q
// are certainly not coplanar with the edge (u, v) on the same side, with
// margins far above the rounding error of these few products. Neighbours in
// flat regions are exactly coplanar, where the exact predicates would fall
// back to multi-precision arithmetic; here they are decided by the side test.
bool clearly_not_folded(const Point& u, const Point& v, const Point& p, const Point& q) {
  const Kernel::Vector_3 e = v - u, a = p - u, b = q - u;
  const Kernel::Vector_3 na = CGAL::cross_product(e, a), nb = CGAL::cross_product(e, b);
  const double scale = std::sqrt(e.squared_length() * a.squared_length() * b.squared_length());
  const double margin = 1e-9 * scale;
  if (std::abs(na * b) > margin) return true;  // q off the plane of (u, v, p)
  return na * nb < -margin * std::sqrt(e.squared_length());  // opposite sides of the edge
}

// The same kind of filter for two triangles (v, a1, a2) and (v, b1, b2) that
// share only v: true when they certainly meet in v alone — one lies on one
// side of the other's plane, or, coplanar, a line through v along one of
// their edges separates them.
bool clearly_apart_at_vertex(const Point& v, const Point& a1, const Point& a2, const Point& b1,
                             const Point& b2) {
  const Kernel::Vector_3 ea1 = a1 - v, ea2 = a2 - v, eb1 = b1 - v, eb2 = b2 - v;
  const double la1 = std::sqrt(ea1.squared_length()), la2 = std::sqrt(ea2.squared_length());
  const double lb1 = std::sqrt(eb1.squared_length()), lb2 = std::sqrt(eb2.squared_length());
  const Kernel::Vector_3 na = CGAL::cross_product(ea1, ea2), nb = CGAL::cross_product(eb1, eb2);
  constexpr double k = 1e-9;
  // One triangle on one side of the other's plane, touching it only at v.
  auto one_side = [&](const Kernel::Vector_3& n, double ln, const Kernel::Vector_3& x1, double l1,
                      const Kernel::Vector_3& x2, double l2) {
    const double s1 = n * x1, s2 = n * x2;
    const double m1 = k * ln * l1, m2 = k * ln * l2;
    return (s1 > m1 && s2 > m2) || (s1 < -m1 && s2 < -m2);
  };
  if (one_side(na, la1 * la2, eb1, lb1, eb2, lb2) || one_side(nb, lb1 * lb2, ea1, la1, ea2, la2))
    return true;
  // Coplanar: both of one triangle's far corners strictly outside the other's
  // wedge across the line of one of its edges. The wedge of (v, e1, e2) lies
  // where (e1 × x)·n ≥ 0 and (x × e2)·n ≥ 0 with n = e1 × e2.
  auto outside = [&](const Kernel::Vector_3& e1, double l1, const Kernel::Vector_3& e2, double l2,
                     const Kernel::Vector_3& n, double ln, const Kernel::Vector_3& x1, double lx1,
                     const Kernel::Vector_3& x2, double lx2) {
    const double m1 = k * ln * lx1, m2 = k * ln * lx2;
    const bool beyond_e1 = CGAL::cross_product(e1, x1) * n < -m1 * l1 &&
                           CGAL::cross_product(e1, x2) * n < -m2 * l1;
    const bool beyond_e2 = CGAL::cross_product(x1, e2) * n < -m1 * l2 &&
                           CGAL::cross_product(x2, e2) * n < -m2 * l2;
    return beyond_e1 || beyond_e2;
  };
  return outside(ea1, la1, ea2, la2, na, la1 * la2, eb1, lb1, eb2, lb2) ||
         outside(eb1, lb1, eb2, lb2, nb, lb1 * lb2, ea1, la1, ea2, la2);
}

// Whether two non-degenerate triangles of one mesh intersect other than in
// the vertices and edge they share.
bool faces_intersect(const Welded& w, const Tri& a, const Tri& b) {
  std::array<int, 3> shared_in_b{-1, -1, -1};  // for each vertex of a, its slot in b
  int shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[static_cast<std::size_t>(i)] == b[static_cast<std::size_t>(j)]) {
        shared_in_b[static_cast<std::size_t>(i)] = j;
        ++shared;
      }
  const auto P = [&](std::uint32_t v) -> const Point& { return w.points[v]; };
  if (shared == 3) return true;  // the same triangle twice
  if (shared == 2) {
    // Shared edge (u, v): the triangles overlap when they are coplanar and
    // their third vertices lie on the same side of the edge (a fold).
    int ia = 0;
    while (shared_in_b[static_cast<std::size_t>(ia)] != -1) ++ia;
    std::uint32_t q = 0;
    for (std::uint32_t v : b)
      if (v != a[0] && v != a[1] && v != a[2]) q = v;
    const std::uint32_t p = a[static_cast<std::size_t>(ia)];
    const std::uint32_t u = a[static_cast<std::size_t>((ia + 1) % 3)];
    const std::uint32_t v = a[static_cast<std::size_t>((ia + 2) % 3)];
    if (clearly_not_folded(P(u), P(v), P(p), P(q))) return false;
    return CGAL::coplanar(P(u), P(v), P(p), P(q)) &&
           CGAL::coplanar_orientation(P(u), P(v), P(p), P(q)) == CGAL::POSITIVE;
  }
  const Triangle ta(P(a[0]), P(a[1]), P(a[2]));
  const Triangle tb(P(b[0]), P(b[1]), P(b[2]));
  if (shared == 1) {
    // Shared vertex: any further contact reaches the opposite edge of one of
    // the two triangles.
    int ia = 0;
    while (shared_in_b[static_cast<std::size_t>(ia)] == -1) ++ia;
    const int ib = shared_in_b[static_cast<std::size_t>(ia)];
    const Segment opposite_a(P(a[static_cast<std::size_t>((ia + 1) % 3)]),
                             P(a[static_cast<std::size_t>((ia + 2) % 3)]));
    const Segment opposite_b(P(b[static_cast<std::size_t>((ib + 1) % 3)]),
                             P(b[static_cast<std::size_t>((ib + 2) % 3)]));
    if (clearly_apart_at_vertex(P(a[static_cast<std::size_t>(ia)]), opposite_a.source(),
                                opposite_a.target(), opposite_b.source(), opposite_b.target()))
      return false;
    return CGAL::do_intersect(ta, opposite_b) || CGAL::do_intersect(tb, opposite_a);
  }
  return CGAL::do_intersect(ta, tb);
}

struct Intersections {
  std::size_t pairs = 0;
  bool capped = false;
  // The smallest pair of the mesh's triangle indices among those found.
  std::pair<std::size_t, std::size_t> first{SIZE_MAX, SIZE_MAX};

  void add(const Intersections& o) {
    pairs += o.pairs;
    capped = capped || o.capped;
    first = std::min(first, o.first);
  }
};

struct StopSearch {};

// Below this many boxes CGAL's streamed segment tree scans them pair by pair.
// Its default, 10, recurses deeper than pays here: at 10⁶ triangles 100
// took 0.82 s against 1.06 s for the glass part's checks and 0.51 s against
// 0.70 s for the faceted reflector's (gonio_setup_benchmarks BM_Check,
// medians of 3, same run; 50: 0.90 / 0.54 s, 200: 0.81 / 0.52 s, 400:
// 0.86 / 0.52 s). Any value finds the same pairs; only which pairs a capped
// search (kMaxPairs) reaches first may differ (kModelCheckRevision 2).
constexpr std::ptrdiff_t kBoxCutoff = 100;

// Boxes of welded triangles in floats: the positions are floats, so the
// boxes are exact. Info: the triangle's index in Welded::triangles.
using Box = CGAL::Box_intersection_d::Box_with_info_d<float, 3, std::uint32_t>;

// One sequential box search over `boxes`, reporting only the pairs whose
// boxes' overlap starts (along `axis`) in [from, to): with the boxes of
// every slab that contains such a start, each pair belongs to exactly one
// slab. At most kMaxPairs pairs are counted.
Intersections search_slab(const Welded& w, std::vector<Box>& boxes, int axis, float from, float to) {
  Intersections out;
  auto report = [&](const Box& x, const Box& y) {
    const float start = std::max(x.min_coord(axis), y.min_coord(axis));
    if (start < from || !(start < to)) return;
    const std::uint32_t i = x.info(), j = y.info();
    if (!faces_intersect(w, w.triangles[i], w.triangles[j])) return;
    const std::pair<std::size_t, std::size_t> pair{std::min(w.source[i], w.source[j]),
                                                   std::max(w.source[i], w.source[j])};
    out.first = std::min(out.first, pair);
    if (++out.pairs >= kMaxPairs) throw StopSearch{};
  };
  try {
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), report, kBoxCutoff);
  } catch (const StopSearch&) {
    out.capped = true;
  }
  return out;
}

// Pairs of triangles that intersect. A large mesh is cut into slabs along
// its longest axis at quantiles of the boxes' lower ends, each slab searched
// on its own (in parallel); the slabs depend on the mesh alone, so the count,
// the cap and the first pair do not depend on the thread count.
Intersections self_intersections(const Welded& w, std::size_t slab_triangles) {
  const std::size_t n = w.triangles.size();
  std::vector<Box> boxes;
  boxes.reserve(n);
  constexpr float kInf = std::numeric_limits<float>::infinity();
  float lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
  for (std::size_t t = 0; t < n; ++t) {
    const Tri& tri = w.triangles[t];
    float b_lo[3], b_hi[3];
    for (int k = 0; k < 3; ++k) {
      const float a = static_cast<float>(w.points[tri[0]][k]), b = static_cast<float>(w.points[tri[1]][k]),
                  c = static_cast<float>(w.points[tri[2]][k]);
      b_lo[k] = std::min({a, b, c});
      b_hi[k] = std::max({a, b, c});
      lo[k] = std::min(lo[k], b_lo[k]);
      hi[k] = std::max(hi[k], b_hi[k]);
    }
    boxes.emplace_back(b_lo, b_hi, static_cast<std::uint32_t>(t));
  }
  const std::size_t slabs = std::clamp<std::size_t>(n / std::max<std::size_t>(slab_triangles, 1), 1, 256);
  if (slabs == 1) return search_slab(w, boxes, 0, -kInf, kInf);

  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
  // Cuts at quantiles of the boxes' lower ends, from a sample taken at a
  // fixed stride (the cuts depend on the mesh alone).
  const std::size_t stride = std::max<std::size_t>(1, n / (256 * slabs));
  std::vector<float> starts;
  starts.reserve(n / stride + 1);
  for (std::size_t t = 0; t < n; t += stride) starts.push_back(boxes[t].min_coord(axis));
  std::sort(starts.begin(), starts.end());
  std::vector<float> cuts{-kInf};
  for (std::size_t s = 1; s < slabs; ++s) {
    const float c = starts[s * starts.size() / slabs];
    if (c > cuts.back()) cuts.push_back(c);
  }
  cuts.push_back(kInf);
  // Each box goes to the slabs its extent along the axis meets: from the
  // slab of its lower end to that of its upper end. Lists of box indices in
  // index order, built in parallel by chunks (counted, then filled), so a
  // slab's boxes are the same whatever the thread count.
  const std::size_t slab_count = cuts.size() - 1;
  const auto slab_of = [&](float x) {
    return static_cast<std::size_t>(std::upper_bound(cuts.begin() + 1, cuts.end() - 1, x) - (cuts.begin() + 1));
  };
  constexpr std::size_t kChunk = 65536;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  // Calls f(box, slab) for each box of chunk c and each slab it goes to.
  const auto for_each_membership = [&](std::size_t c, auto&& f) {
    for (std::size_t t = c * kChunk; t < std::min(n, (c + 1) * kChunk); ++t)
      for (std::size_t s = slab_of(boxes[t].min_coord(axis)); s <= slab_of(boxes[t].max_coord(axis)); ++s)
        f(t, s);
  };
  std::vector<std::size_t> count(chunks * slab_count, 0);  // [chunk][slab], then offsets
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    for_each_membership(c, [&](std::size_t, std::size_t s) { ++count[c * slab_count + s]; });
  });
  std::vector<std::size_t> slab_begin(slab_count + 1, 0);
  std::size_t total = 0;
  for (std::size_t s = 0; s < slab_count; ++s) {
    slab_begin[s] = total;
    for (std::size_t c = 0; c < chunks; ++c) {
      const std::size_t k = count[c * slab_count + s];
      count[c * slab_count + s] = total;
      total += k;
    }
  }
  slab_begin[slab_count] = total;
  std::vector<std::uint32_t> members(total);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    for_each_membership(c, [&](std::size_t t, std::size_t s) {
      members[count[c * slab_count + s]++] = static_cast<std::uint32_t>(t);
    });
  });
  std::vector<Intersections> found(slab_count);
  tbb::parallel_for(std::size_t{0}, found.size(), [&](std::size_t s) {
    std::vector<Box> mine;
    mine.reserve(slab_begin[s + 1] - slab_begin[s]);
    for (std::size_t k = slab_begin[s]; k < slab_begin[s + 1]; ++k) mine.push_back(boxes[members[k]]);
    found[s] = search_slab(w, mine, axis, cuts[s], cuts[s + 1]);
  });
  Intersections out;
  for (const Intersections& f : found) out.add(f);
  return out;
}

struct Topology {
  std::size_t boundary = 0, non_manifold = 0, inconsistent = 0;
  std::pair<std::uint32_t, std::uint32_t> first_boundary{0, 0};
};

// Every directed edge as (low, high, forward), sorted: the uses of one edge
// are neighbours, and edges come in the order of their vertex pair.
struct DirectedEdge {
  std::uint32_t low, high;
  bool forward;  // used as (low → high)
  bool operator<(const DirectedEdge& o) const {
    return std::tie(low, high, forward) < std::tie(o.low, o.high, o.forward);
  }
};

Topology edge_topology(const Welded& w) {
  std::vector<DirectedEdge> edges(3 * w.triangles.size());
  tbb::parallel_for(std::size_t{0}, w.triangles.size(), [&](std::size_t i) {
    const Tri& t = w.triangles[i];
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      edges[3 * i + k] = {std::min(a, b), std::max(a, b), a < b};
    }
  });
  tbb::parallel_sort(edges.begin(), edges.end());
  Topology out;
  for (std::size_t k = 0; k < edges.size();) {
    std::size_t end = k, forward = 0;
    while (end < edges.size() && edges[end].low == edges[k].low && edges[end].high == edges[k].high)
      forward += edges[end++].forward ? 1 : 0;
    const std::size_t total = end - k;
    if (total == 1) {
      if (out.boundary++ == 0) out.first_boundary = {edges[k].low, edges[k].high};
    } else if (total > 2) {
      ++out.non_manifold;
    } else if (forward != 1) {
      ++out.inconsistent;
    }
    k = end;
  }
  return out;
}

// For a closed, consistently oriented mesh of one connected piece: whether
// it faces inwards, decided by the sign of its enclosed volume where that is
// clear; nothing where the mesh has several pieces (shells may nest: CGAL
// decides) or the volume is too small to trust its sign.
std::optional<bool> single_shell_inverted(const Welded& w) {
  // Union-find over the vertices of each triangle.
  std::vector<std::uint32_t> parent(w.points.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const Tri& t : w.triangles)
    for (std::size_t k = 1; k < 3; ++k) {
      const std::uint32_t a = find(t[0]), b = find(t[k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  const std::uint32_t root = find(w.triangles[0][0]);
  for (const Tri& t : w.triangles)
    if (find(t[0]) != root) return std::nullopt;
  // Signed volume about the first point (nearby, so little cancellation),
  // summed in a fixed order.
  const Point& o = w.points[w.triangles[0][0]];
  double volume6 = 0.0, scale = 0.0;
  for (const Tri& t : w.triangles) {
    const Kernel::Vector_3 a = w.points[t[0]] - o, b = w.points[t[1]] - o, c = w.points[t[2]] - o;
    volume6 += CGAL::determinant(a, b, c);
    scale += std::sqrt(a.squared_length() * b.squared_length() * c.squared_length());
  }
  // Rounding error of the sum is far below 1e-9 of the sum of |terms|.
  if (!(std::abs(volume6) > 1e-9 * scale)) return std::nullopt;
  return volume6 < 0.0;
}

// For a closed, consistently oriented, self-intersection-free mesh: the
// number of triangles whose orientation differs from the one that makes the
// mesh bound a volume (outer shells out, cavities in). Nullopt when CGAL
// cannot build the mesh (non-manifold vertices).
std::optional<std::size_t> inverted_triangles(const Welded& w) {
  // Only the points the triangles use: CGAL's orientation code does not
  // expect isolated vertices.
  std::vector<std::size_t> remap(w.points.size(), SIZE_MAX);
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(w.triangles.size());
  for (const Tri& t : w.triangles) {
    std::vector<std::size_t> polygon;
    for (std::uint32_t v : t) {
      if (remap[v] == SIZE_MAX) {
        remap[v] = points.size();
        points.push_back(w.points[v]);
      }
      polygon.push_back(remap[v]);
    }
    polygons.push_back(std::move(polygon));
  }
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) return std::nullopt;
  using Mesh = CGAL::Surface_mesh<Point>;
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  if (mesh.number_of_faces() != polygons.size()) return std::nullopt;
  Mesh oriented = mesh;
  PMP::orient_to_bound_a_volume(oriented);
  // Compare each face's first directed edge: the soup's faces and vertices
  // keep their order in the mesh, and CGAL reverses whole faces.
  std::size_t flipped = 0;
  for (Mesh::Face_index f : mesh.faces()) {
    const auto h0 = mesh.halfedge(f);
    const auto h1 = oriented.halfedge(f);
    std::array<Mesh::Vertex_index, 3> a{}, b{};
    auto ha = h0;
    auto hb = h1;
    for (int k = 0; k < 3; ++k) {
      a[static_cast<std::size_t>(k)] = mesh.target(ha);
      b[static_cast<std::size_t>(k)] = oriented.target(hb);
      ha = mesh.next(ha);
      hb = oriented.next(hb);
    }
    // Same cyclic order ⇔ b is a rotation of a.
    const bool same = (a[0] == b[0] && a[1] == b[1]) || (a[0] == b[1] && a[1] == b[2]) ||
                      (a[0] == b[2] && a[1] == b[0]);
    if (!same) ++flipped;
  }
  return flipped;
}

// The findings of one mesh, each detail following the mesh's name.
std::vector<MeshFinding> check_mesh(const sim::Mesh& mesh, bool refractive, std::size_t slab_triangles) {
  std::vector<MeshFinding> findings;
  const Welded w = weld(mesh);

  if (w.degenerate > 0)
    findings.push_back({Severity::Warning, "degenerate-triangle",
                        ": " + std::to_string(w.degenerate) +
                            " degenerate (zero-area) triangles, the first is triangle " +
                            std::to_string(w.first_degenerate)});

  const Intersections hits = self_intersections(w, slab_triangles);
  if (hits.pairs > 0)
    findings.push_back({refractive ? Severity::Error : Severity::Warning, "self-intersection",
                        std::string(": ") + (hits.capped ? "at least " : "") + std::to_string(hits.pairs) +
                            " pairs of triangles intersect, the first are triangles " +
                            std::to_string(hits.first.first) + " and " + std::to_string(hits.first.second)});
  if (!refractive) return findings;

  const Topology topo = edge_topology(w);
  if (topo.boundary > 0)
    findings.push_back({Severity::Error, "open-volume",
                        " is refractive but not closed: " + std::to_string(topo.boundary) +
                            " boundary edges, e.g. " + point_text(w.points[topo.first_boundary.first]) +
                            " – " + point_text(w.points[topo.first_boundary.second]) +
                            "; light would enter the medium through a hole"});
  if (topo.non_manifold > 0)
    findings.push_back({Severity::Error, "non-manifold-volume",
                        " is refractive but " + std::to_string(topo.non_manifold) +
                            " edges are shared by more than two triangles"});
  if (topo.inconsistent > 0)
    findings.push_back({Severity::Error, "inconsistent-orientation",
                        " is refractive but " + std::to_string(topo.inconsistent) +
                            " edges join triangles wound in opposite senses"});
  if (topo.boundary == 0 && topo.non_manifold == 0 && topo.inconsistent == 0 && hits.pairs == 0 &&
      !w.triangles.empty()) {
    // One closed piece, the common case, needs no half-edge mesh: it faces
    // inwards as a whole or not at all.
    const std::optional<bool> whole = single_shell_inverted(w);
    const std::optional<std::size_t> inverted =
        whole ? std::optional<std::size_t>(*whole ? w.triangles.size() : 0) : inverted_triangles(w);
    if (inverted && *inverted > 0)
      findings.push_back({Severity::Error, "inverted-volume",
                          " is refractive but " + std::to_string(*inverted) + " of " +
                              std::to_string(w.triangles.size()) +
                              " triangles face into the volume they bound; normals must point "
                              "out of the medium"});
  }
  return findings;
}

}  // namespace

std::vector<Finding> check_model(const sim::SceneDesc& scene, const ModelCheckOptions& options,
                                 ModelCheckStats* stats) {
  const std::size_t n = scene.meshes.size();
  std::vector<char> refractive(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t m = scene.meshes[i].material;
    refractive[i] = m < scene.materials.size() && scene.materials[m].dielectric > 0.0;
  }
  // Each mesh into its own slot, from the cache or checked: the same findings
  // in the same order whatever the thread count. Cache entries: one per
  // large mesh, one for the small ones (io/model/model_check_cache.h), so that a
  // model edited in one large part is checked again in that part only.
  const bool use_cache = !options.cache_dir.empty();
  std::vector<CheckGroup> groups;
  CheckGroup small;
  for (std::size_t i = 0; i < n; ++i) {
    CheckGroup& g = scene.meshes[i].triangle_count() >= kOwnEntryTriangles ? groups.emplace_back() : small;
    g.meshes.push_back(i);
    g.refractive.push_back(refractive[i]);
  }
  if (!small.meshes.empty()) groups.push_back(std::move(small));
  std::vector<std::vector<MeshFinding>> results(n);
  std::vector<char> from_cache(n, 0);
  std::vector<std::uint64_t> keys(groups.size(), 0);
  if (use_cache)
    tbb::parallel_for(std::size_t{0}, groups.size(), [&](std::size_t g) {
      keys[g] = check_group_key(scene, groups[g]);
      if (auto cached = read_cached_checks(options.cache_dir, keys[g], scene, groups[g])) {
        for (std::size_t k = 0; k < groups[g].meshes.size(); ++k) {
          results[groups[g].meshes[k]] = std::move((*cached)[k]);
          from_cache[groups[g].meshes[k]] = 1;
        }
      }
    });
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t i) {
    if (!from_cache[i]) results[i] = check_mesh(scene.meshes[i], refractive[i] != 0, options.slab_triangles);
  });
  if (use_cache)
    tbb::parallel_for(std::size_t{0}, groups.size(), [&](std::size_t g) {
      if (from_cache[groups[g].meshes.front()]) return;
      std::vector<std::vector<MeshFinding>> found;
      for (std::size_t i : groups[g].meshes) found.push_back(results[i]);
      write_cached_checks(options.cache_dir, keys[g], scene, groups[g], found);
    });
  if (stats) {
    stats->meshes = n;
    stats->meshes_from_cache = static_cast<std::size_t>(std::count(from_cache.begin(), from_cache.end(), 1));
  }

  std::vector<Finding> findings;
  const SourceLoc where{scene.name, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    const sim::Mesh& mesh = scene.meshes[i];
    const sim::Material* material =
        mesh.material < scene.materials.size() ? &scene.materials[mesh.material] : nullptr;
    const std::string what =
        "mesh '" + mesh.name + "'" + (material ? " (material '" + material->name + "')" : "");
    for (const MeshFinding& f : results[i])
      findings.push_back({f.severity, f.code, what + f.detail, where});
  }
  return findings;
}

}  // namespace gonio::io
