// The only file that includes CGAL.
#include "io/model_check.h"

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
#include <map>
#include <numeric>
#include <optional>
#include <string>
#include <utility>

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
  std::vector<std::size_t> source;      // index of each in the mesh's triangle list
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
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return key(a) < key(b); });
  std::vector<std::uint32_t> id(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || key(order[k]) != key(order[k - 1])) {
      const sim::Vec3f& p = mesh.positions[order[k]];
      w.points.emplace_back(p.x, p.y, p.z);
    }
    id[order[k]] = static_cast<std::uint32_t>(w.points.size() - 1);
  }
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const Tri tri{id[mesh.indices[3 * t]], id[mesh.indices[3 * t + 1]], id[mesh.indices[3 * t + 2]]};
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] ||
        CGAL::collinear(w.points[tri[0]], w.points[tri[1]], w.points[tri[2]])) {
      if (w.degenerate++ == 0) w.first_degenerate = t;
      continue;
    }
    w.triangles.push_back(tri);
    w.source.push_back(t);
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
  std::pair<std::size_t, std::size_t> first{0, 0};
};

struct StopSearch {};

Intersections self_intersections(const Welded& w) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
  std::vector<Box> boxes;
  boxes.reserve(w.triangles.size());
  for (std::size_t t = 0; t < w.triangles.size(); ++t) {
    const Tri& tri = w.triangles[t];
    boxes.emplace_back(w.points[tri[0]].bbox() + w.points[tri[1]].bbox() + w.points[tri[2]].bbox(), t);
  }
  Intersections out;
  auto report = [&](const Box& x, const Box& y) {
    const std::size_t i = x.info(), j = y.info();
    if (!faces_intersect(w, w.triangles[i], w.triangles[j])) return;
    if (out.pairs == 0) out.first = {std::min(w.source[i], w.source[j]), std::max(w.source[i], w.source[j])};
    if (++out.pairs >= kMaxPairs) throw StopSearch{};
  };
  try {
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), report);
  } catch (const StopSearch&) {
    out.capped = true;
  }
  return out;
}

struct EdgeUse {
  std::uint32_t forward = 0;   // used as (low → high)
  std::uint32_t backward = 0;  // used as (high → low)
};

struct Topology {
  std::size_t boundary = 0, non_manifold = 0, inconsistent = 0;
  std::pair<std::uint32_t, std::uint32_t> first_boundary{0, 0};
};

Topology edge_topology(const Welded& w) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, EdgeUse> edges;
  for (const Tri& t : w.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
      EdgeUse& e = edges[{std::min(a, b), std::max(a, b)}];
      (a < b ? e.forward : e.backward) += 1;
    }
  Topology out;
  for (const auto& [edge, use] : edges) {
    const std::uint32_t total = use.forward + use.backward;
    if (total == 1) {
      if (out.boundary++ == 0) out.first_boundary = edge;
    } else if (total > 2) {
      ++out.non_manifold;
    } else if (use.forward != 1) {
      ++out.inconsistent;
    }
  }
  return out;
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

}  // namespace

std::vector<Finding> check_model(const sim::SceneDesc& scene) {
  std::vector<Finding> findings;
  const SourceLoc where{scene.name, 0, 0};
  for (const sim::Mesh& mesh : scene.meshes) {
    const sim::Material* material =
        mesh.material < scene.materials.size() ? &scene.materials[mesh.material] : nullptr;
    const bool refractive = material && material->dielectric > 0.0;
    const std::string what =
        "mesh '" + mesh.name + "'" + (material ? " (material '" + material->name + "')" : "");
    const Welded w = weld(mesh);

    if (w.degenerate > 0)
      findings.push_back({Severity::Warning, "degenerate-triangle",
                          what + ": " + std::to_string(w.degenerate) +
                              " degenerate (zero-area) triangles, the first is triangle " +
                              std::to_string(w.first_degenerate),
                          where});

    const Intersections hits = self_intersections(w);
    if (hits.pairs > 0)
      findings.push_back({refractive ? Severity::Error : Severity::Warning, "self-intersection",
                          what + ": " + (hits.capped ? "at least " : "") +
                              std::to_string(hits.pairs) +
                              " pairs of triangles intersect, the first are triangles " +
                              std::to_string(hits.first.first) + " and " +
                              std::to_string(hits.first.second),
                          where});
    if (!refractive) continue;

    const Topology topo = edge_topology(w);
    if (topo.boundary > 0)
      findings.push_back(
          {Severity::Error, "open-volume",
           what + " is refractive but not closed: " + std::to_string(topo.boundary) +
               " boundary edges, e.g. " + point_text(w.points[topo.first_boundary.first]) + " – " +
               point_text(w.points[topo.first_boundary.second]) +
               "; light would enter the medium through a hole",
           where});
    if (topo.non_manifold > 0)
      findings.push_back({Severity::Error, "non-manifold-volume",
                          what + " is refractive but " + std::to_string(topo.non_manifold) +
                              " edges are shared by more than two triangles",
                          where});
    if (topo.inconsistent > 0)
      findings.push_back({Severity::Error, "inconsistent-orientation",
                          what + " is refractive but " + std::to_string(topo.inconsistent) +
                              " edges join triangles wound in opposite senses",
                          where});
    if (topo.boundary == 0 && topo.non_manifold == 0 && topo.inconsistent == 0 &&
        hits.pairs == 0 && !w.triangles.empty()) {
      const std::optional<std::size_t> inverted = inverted_triangles(w);
      if (inverted && *inverted > 0)
        findings.push_back({Severity::Error, "inverted-volume",
                            what + " is refractive but " + std::to_string(*inverted) + " of " +
                                std::to_string(w.triangles.size()) +
                                " triangles face into the volume they bound; normals must point "
                                "out of the medium",
                            where});
    }
  }
  return findings;
}

}  // namespace gonio::io
