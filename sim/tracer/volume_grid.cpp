#include "sim/tracer/volume_grid.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <unordered_map>

namespace gonio::sim {
namespace {

// Whether triangle (a, b, c) meets the box centred at `centre` with half
// sides `half` (Akenine-Möller's separating axes: the box's three, the
// triangle's normal, the nine edge-by-axis cross products).
bool triangle_meets_box(const Vec3& centre, double half, Vec3 a, Vec3 b, Vec3 c) {
  a = a - centre;
  b = b - centre;
  c = c - centre;
  const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const auto separated = [&](const Vec3& axis) {
    const double pa = dot(a, axis), pb = dot(b, axis), pc = dot(c, axis);
    const double r = half * (std::abs(axis.x) + std::abs(axis.y) + std::abs(axis.z));
    return std::min({pa, pb, pc}) > r || std::max({pa, pb, pc}) < -r;
  };
  for (const Vec3& axis : axes)
    if (separated(axis)) return false;
  const Vec3 edges[3] = {b - a, c - b, a - c};
  if (separated(cross(edges[0], edges[1]))) return false;
  for (const Vec3& e : edges)
    for (const Vec3& axis : axes)
      if (separated(cross(e, axis))) return false;
  return true;
}

struct Triangle {
  Vec3 a, b, c;
};

// Every edge of the mesh (by its corners' positions) bounds exactly two of
// its triangles, in opposite senses: each directed edge once, and its
// reverse once.
bool mesh_closed(const Mesh& m) {
  if (m.indices.size() < 3 || m.indices.size() % 3 != 0) return false;
  using Key = std::array<std::uint32_t, 6>;
  struct Hash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ULL;
      for (std::uint32_t v : k) h = (h ^ v) * 0x100000001b3ULL;
      return static_cast<std::size_t>(h ^ (h >> 29));
    }
  };
  const auto key = [&](std::uint32_t a, std::uint32_t b) {
    const Vec3f& p = m.positions[a];
    const Vec3f& q = m.positions[b];
    return Key{std::bit_cast<std::uint32_t>(p.x), std::bit_cast<std::uint32_t>(p.y), std::bit_cast<std::uint32_t>(p.z),
               std::bit_cast<std::uint32_t>(q.x), std::bit_cast<std::uint32_t>(q.y), std::bit_cast<std::uint32_t>(q.z)};
  };
  std::unordered_map<Key, int, Hash> directed;
  directed.reserve(m.indices.size());
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = m.indices[t + static_cast<std::size_t>(e)];
      const std::uint32_t b = m.indices[t + static_cast<std::size_t>((e + 1) % 3)];
      if (a >= m.positions.size() || b >= m.positions.size()) return false;
      if (++directed[key(a, b)] > 1) return false;
    }
  for (const auto& [k, count] : directed) {
    const Key reverse{k[3], k[4], k[5], k[0], k[1], k[2]};
    const auto it = directed.find(reverse);
    if (it == directed.end() || it->second != 1) return false;
  }
  return true;
}

constexpr std::uint32_t kMaxPlaneEntries = std::uint32_t{1} << 22;  // 32 bytes each

constexpr std::uint32_t kMaxSides = 64;  // planes a cell may list for Walk::below

}  // namespace

bool VolumeGrid::walk_free(const Vec3& p, const Vec3& q, Walk& w) const {
  if (w.cell < 0) {
    // No sides kept (a reset walk, or a crowded cell): the ball and sides
    // at p first, which may hold q already.
    double wall_p = 0.0;
    const std::int64_t c = locate(p, &wall_p);
    if (c < 0 || !ball_at(p, c, wall_p, w)) {
      // Outside the grid, within a margin of a plane, or too many planes
      // to keep their sides: the two ends' scan.
      const bool free = segment_free(p, q);
      w.reset();
      return free;
    }
    const Vec3 d = q - w.centre;
    if (dot(d, d) < w.radius2) return true;
  }
  double wall_q = 0.0;
  const std::int64_t c = locate(q, &wall_q);
  if (c < 0) {
    w.reset();
    return false;
  }
  if (c == w.cell) return sides_free(q, wall_q, w);
  // Ends in two cells sharing a face (together one box, which holds the
  // segment): q against w.cell's planes on the centre's sides (p's), then
  // both ends against c's planes, whose sides at q become w's.
  const std::int64_t from = w.cell;
  if (!face_neighbours(from, c)) {
    w.reset();
    return false;
  }
  const auto f = static_cast<std::size_t>(from);
  for (std::uint32_t k = 0; k < start_[f + 1] - start_[f]; ++k) {
    const std::array<double, 4>& pl = planes_[start_[f] + k];
    const double sq = plane_offset(pl, q);
    if (!((((w.below >> k) & 1u) ? -sq : sq) > plane_margin_)) {
      w.reset();
      return false;
    }
  }
  const auto cell = static_cast<std::size_t>(c);
  const std::uint32_t first = start_[cell];
  const std::uint32_t n = start_[cell + 1] - first;
  double near = wall_q - margin_ + plane_margin_;
  std::uint64_t below = 0;
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::array<double, 4>& pl = planes_[first + k];
    const double sp = plane_offset(pl, p), sq = plane_offset(pl, q);
    if (!((sp > plane_margin_ && sq > plane_margin_) || (sp < -plane_margin_ && sq < -plane_margin_))) {
      w.reset();
      return false;
    }
    if (sq < 0.0 && k < kMaxSides) below |= std::uint64_t{1} << k;
    near = std::min(near, std::abs(sq));
  }
  const double r = near - plane_margin_;
  w.centre = q;
  w.radius2 = r * r;
  w.cell = n <= kMaxSides ? c : -1;
  w.below = below;
  return true;
}

bool VolumeGrid::sides_free(const Vec3& q, double wall, Walk& w) const {
  const auto cell = static_cast<std::size_t>(w.cell);
  const std::uint32_t first = start_[cell];
  const std::uint32_t n = start_[cell + 1] - first;
  double near = wall - margin_ + plane_margin_;
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::array<double, 4>& pl = planes_[first + k];
    const double sq = plane_offset(pl, q);
    const double away = ((w.below >> k) & 1u) ? -sq : sq;
    if (!(away > plane_margin_)) {
      w.reset();
      return false;
    }
    near = std::min(near, away);
  }
  const double r = near - plane_margin_;
  w.centre = q;
  w.radius2 = r * r;
  return true;
}

bool VolumeGrid::ball_at(const Vec3& q, std::int64_t c, double wall, Walk& w) const {
  const auto cell = static_cast<std::size_t>(c);
  const std::uint32_t first = start_[cell];
  const std::uint32_t n = start_[cell + 1] - first;
  double near = wall - margin_ + plane_margin_;
  std::uint64_t below = 0;
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::array<double, 4>& pl = planes_[first + k];
    const double sq = plane_offset(pl, q);
    if (sq < 0.0 && k < kMaxSides) below |= std::uint64_t{1} << k;
    near = std::min(near, std::abs(sq));
  }
  const double r = near - plane_margin_;
  if (!(r > 0.0)) {
    w.reset();
    return false;
  }
  w.centre = q;
  w.radius2 = r * r;
  w.cell = n <= kMaxSides ? c : -1;
  w.below = below;
  return w.cell >= 0;
}

bool VolumeGrid::face_neighbours(std::int64_t c, std::int64_t d) const {
  const std::int64_t nx = dims_[0], nxy = dims_[0] * dims_[1];
  return std::abs(c % nx - d % nx) + std::abs((c / nx) % dims_[1] - (d / nx) % dims_[1]) + std::abs(c / nxy - d / nxy) ==
         1;
}

bool VolumeGrid::across(const Vec3& p, const Vec3& q, std::int64_t c, std::int64_t d) const {
  return face_neighbours(c, d) && planes_free(p, q, static_cast<std::size_t>(c)) &&
         planes_free(p, q, static_cast<std::size_t>(d));
}

std::optional<VolumeGrid> VolumeGrid::build(const SceneDesc& scene, double mean_free_paths, std::size_t max_cells) {
  if (!(mean_free_paths > 0.0)) return std::nullopt;
  double mu_t = 0.0;
  for (const Material& m : scene.materials)
    if (m.scattering_per_m > 0.0) mu_t = std::max(mu_t, m.scattering_per_m + m.attenuation_per_m);
  if (!(mu_t > 0.0)) return std::nullopt;
  // The box of the scattering parts (as placed).
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  const auto take = [&](const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  };
  const auto scatters = [&](const Mesh& m) {
    return m.material < scene.materials.size() && scene.materials[m.material].scattering_per_m > 0.0;
  };
  for (const Mesh& m : scene.meshes)
    if (!m.instanced && scatters(m))
      for (const Vec3f& p : m.positions) take(to_double(p));
  for (const Instance& i : scene.instances)
    if (i.mesh < scene.meshes.size() && scatters(scene.meshes[i.mesh]))
      for (const Vec3f& p : scene.meshes[i.mesh].positions) take(i.to_world.point(to_double(p)));
  if (!(lo.x <= hi.x)) return std::nullopt;
  VolumeGrid g;
  const Vec3 extent = hi - lo;
  const double scale = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y),
                                 std::abs(hi.z)});
  g.margin_ = 1e-6 * scale + 1e-9;
  g.cell_m_ = mean_free_paths / mu_t;
  const auto cells_for = [&](double h) {
    double n = 1.0;
    for (double e : {extent.x, extent.y, extent.z}) n *= std::floor(e / h) + 1.0;
    return n;
  };
  while (cells_for(g.cell_m_) > static_cast<double>(max_cells)) g.cell_m_ *= 1.25;
  g.inv_cell_ = 1.0 / g.cell_m_;
  g.lower_ = lo - Vec3{0.5 * g.cell_m_, 0.5 * g.cell_m_, 0.5 * g.cell_m_};
  g.dims_[0] = static_cast<std::int64_t>(std::floor(extent.x / g.cell_m_)) + 2;
  g.dims_[1] = static_cast<std::int64_t>(std::floor(extent.y / g.cell_m_)) + 2;
  g.dims_[2] = static_cast<std::int64_t>(std::floor(extent.z / g.cell_m_)) + 2;
  for (int a = 0; a < 3; ++a) g.dims_f_[a] = static_cast<double>(g.dims_[a]);
  const auto cells = static_cast<std::size_t>(g.dims_[0] * g.dims_[1] * g.dims_[2]);

  // Every triangle of the scene as placed, with its plane.
  // (Only those whose box meets the grid's.)
  const Vec3 upper = g.lower_ + Vec3{static_cast<double>(g.dims_[0]) * g.cell_m_, static_cast<double>(g.dims_[1]) * g.cell_m_,
                                     static_cast<double>(g.dims_[2]) * g.cell_m_};
  std::vector<Triangle> tris;
  const auto add_mesh = [&](const Mesh& m, const Affine* place) {
    for (std::size_t t = 0; 3 * t + 2 < m.indices.size(); ++t) {
      Vec3 v[3];
      for (int k = 0; k < 3; ++k) {
        v[k] = to_double(m.positions[m.indices[3 * t + static_cast<std::size_t>(k)]]);
        if (place) v[k] = place->point(v[k]);
      }
      const double w = g.margin_;
      if (std::max({v[0].x, v[1].x, v[2].x}) < g.lower_.x - w || std::min({v[0].x, v[1].x, v[2].x}) > upper.x + w ||
          std::max({v[0].y, v[1].y, v[2].y}) < g.lower_.y - w || std::min({v[0].y, v[1].y, v[2].y}) > upper.y + w ||
          std::max({v[0].z, v[1].z, v[2].z}) < g.lower_.z - w || std::min({v[0].z, v[1].z, v[2].z}) > upper.z + w)
        continue;
      tris.push_back({v[0], v[1], v[2]});
    }
  };
  for (const Mesh& m : scene.meshes)
    if (!m.instanced) add_mesh(m, nullptr);
  for (const Instance& i : scene.instances)
    if (i.mesh < scene.meshes.size()) add_mesh(scene.meshes[i.mesh], &i.to_world);

  // Two passes (count, then fill) over the cells each triangle's box covers.
  const double half = 0.5 * g.cell_m_ + g.margin_;
  std::vector<std::uint32_t> count(cells + 1, 0);
  const auto each_cell = [&](const Triangle& t, auto&& f) {
    std::int64_t a[3], b[3];
    const double tl[3] = {std::min({t.a.x, t.b.x, t.c.x}), std::min({t.a.y, t.b.y, t.c.y}),
                          std::min({t.a.z, t.b.z, t.c.z})};
    const double th[3] = {std::max({t.a.x, t.b.x, t.c.x}), std::max({t.a.y, t.b.y, t.c.y}),
                          std::max({t.a.z, t.b.z, t.c.z})};
    const double gl[3] = {g.lower_.x, g.lower_.y, g.lower_.z};
    for (int k = 0; k < 3; ++k) {
      a[k] = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor((tl[k] - g.margin_ - gl[k]) * g.inv_cell_)));
      b[k] = std::min<std::int64_t>(g.dims_[k] - 1,
                                    static_cast<std::int64_t>(std::floor((th[k] + g.margin_ - gl[k]) * g.inv_cell_)));
      if (a[k] > b[k]) return;
    }
    for (std::int64_t z = a[2]; z <= b[2]; ++z)
      for (std::int64_t y = a[1]; y <= b[1]; ++y)
        for (std::int64_t x = a[0]; x <= b[0]; ++x) {
          const Vec3 centre = g.lower_ + Vec3{(static_cast<double>(x) + 0.5) * g.cell_m_,
                                              (static_cast<double>(y) + 0.5) * g.cell_m_,
                                              (static_cast<double>(z) + 0.5) * g.cell_m_};
          if (triangle_meets_box(centre, half, t.a, t.b, t.c))
            f(static_cast<std::size_t>((z * g.dims_[1] + y) * g.dims_[0] + x));
        }
  };
  for (const Triangle& t : tris) each_cell(t, [&](std::size_t c) { ++count[c + 1]; });
  std::uint64_t total = 0;
  for (std::size_t c = 0; c < cells; ++c) total += count[c + 1];
  if (total > kMaxPlaneEntries) return std::nullopt;
  for (std::size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
  // No grid (a ray query per free path, as without one) where its lists
  // would take more than 128 MiB: a part of millions of triangles.
  if (count[cells] > kMaxPlaneEntries) return std::nullopt;
  g.start_ = count;
  g.planes_.assign(count[cells], {0.0, 0.0, 0.0, 0.0});
  std::vector<std::uint32_t> fill(count.begin(), count.end() - 1);
  for (const Triangle& t : tris) {
    const Vec3 n = cross(t.b - t.a, t.c - t.a);
    const double len = length(n);
    // A degenerate triangle has no plane: its cells are never free (a
    // plane through the cell's far corner with sides the walk cannot
    // pass: both sides' tests fail for every point).
    const std::array<double, 4> plane =
        len > 0.0 ? std::array<double, 4>{n.x / len, n.y / len, n.z / len, dot(n, t.a) / len}
                  : std::array<double, 4>{0.0, 0.0, 0.0, 0.0};
    each_cell(t, [&](std::size_t c) { g.planes_[fill[c]++] = plane; });
  }
  // One plane for nearly coplanar facets in each cell: where two planes'
  // signed distances differ by at most 0.25 × margin at the cell's eight
  // corners (hence everywhere in the cell: the difference is linear), the
  // second is dropped; the test's margin of 1.25 × margin keeps it passed
  // beyond the margin.
  g.plane_margin_ = 1.25 * g.margin_;
  const double merge = 0.25 * g.margin_;
  std::vector<std::array<double, 4>> kept;
  kept.reserve(g.planes_.size());
  std::vector<std::uint32_t> start(cells + 1, 0);
  for (std::size_t c = 0; c < cells; ++c) {
    const std::int64_t x = static_cast<std::int64_t>(c) % g.dims_[0];
    const std::int64_t y = (static_cast<std::int64_t>(c) / g.dims_[0]) % g.dims_[1];
    const std::int64_t z = static_cast<std::int64_t>(c) / (g.dims_[0] * g.dims_[1]);
    const Vec3 corner0 = g.lower_ + Vec3{static_cast<double>(x) * g.cell_m_, static_cast<double>(y) * g.cell_m_,
                                         static_cast<double>(z) * g.cell_m_};
    const auto first = kept.size();
    for (std::uint32_t k = g.start_[c]; k < g.start_[c + 1]; ++k) {
      const std::array<double, 4>& b = g.planes_[k];
      bool covered = false;
      for (std::size_t i = first; i < kept.size() && !covered; ++i) {
        const std::array<double, 4>& a = kept[i];
        if (a[0] == 0.0 && a[1] == 0.0 && a[2] == 0.0) continue;  // a degenerate triangle's
        for (const double sign : {1.0, -1.0}) {
          double worst = 0.0;
          for (int corner = 0; corner < 8; ++corner) {
            const Vec3 v = corner0 + Vec3{(corner & 1) ? g.cell_m_ : 0.0, (corner & 2) ? g.cell_m_ : 0.0,
                                          (corner & 4) ? g.cell_m_ : 0.0};
            const double da = a[0] * v.x + a[1] * v.y + a[2] * v.z - a[3];
            const double db = b[0] * v.x + b[1] * v.y + b[2] * v.z - b[3];
            worst = std::max(worst, std::abs(da - sign * db));
          }
          if (worst <= merge) covered = true;
        }
      }
      if (!covered) kept.push_back(b);
    }
    start[c + 1] = static_cast<std::uint32_t>(kept.size());
  }
  g.planes_ = std::move(kept);
  g.start_ = std::move(start);
  g.closed_.assign(scene.meshes.size(), 0);
  for (std::size_t i = 0; i < scene.meshes.size(); ++i)
    if (scatters(scene.meshes[i])) g.closed_[i] = mesh_closed(scene.meshes[i]) ? 1 : 0;
  return g;
}

}  // namespace gonio::sim
