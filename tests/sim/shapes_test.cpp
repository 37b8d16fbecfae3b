#include "sim/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <tuple>
#include <vector>

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;

Vec3 at(const Mesh& m, std::uint32_t v) {
  return {m.positions[v].x, m.positions[v].y, m.positions[v].z};
}

// Vertex ids after welding identical positions (lathe creases duplicate
// vertices so each side keeps its normal).
std::vector<std::uint32_t> welded_ids(const Mesh& m) {
  std::map<std::tuple<float, float, float>, std::uint32_t> seen;
  std::vector<std::uint32_t> id(m.positions.size());
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    const auto key = std::make_tuple(m.positions[v].x, m.positions[v].y, m.positions[v].z);
    id[v] = seen.emplace(key, static_cast<std::uint32_t>(seen.size())).first->second;
  }
  return id;
}

struct EdgeCheck {
  std::size_t boundary_edges = 0;  // directed edges without their opposite
  std::size_t repeated_edges = 0;  // directed edges used twice: inconsistent winding
};

// Every edge shared by exactly two triangles with opposite directions is a
// closed, consistently oriented surface.
EdgeCheck check_edges(const Mesh& m, bool weld) {
  std::vector<std::uint32_t> id(m.positions.size());
  if (weld) {
    id = welded_ids(m);
  } else {
    for (std::size_t v = 0; v < id.size(); ++v) id[v] = static_cast<std::uint32_t>(v);
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (std::size_t t = 0; t < m.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k)
      ++directed[{id[m.indices[3 * t + k]], id[m.indices[3 * t + (k + 1) % 3]]}];
  EdgeCheck c;
  for (const auto& [edge, count] : directed) {
    if (count > 1) c.repeated_edges += static_cast<std::size_t>(count - 1);
    if (!directed.contains({edge.second, edge.first})) ++c.boundary_edges;
  }
  return c;
}

void expect_closed(const Mesh& m, bool weld = false) {
  const EdgeCheck c = check_edges(m, weld);
  EXPECT_EQ(c.boundary_edges, 0u) << m.name;
  EXPECT_EQ(c.repeated_edges, 0u) << m.name;
}

void expect_no_degenerate_triangles(const Mesh& m) {
  for (std::size_t t = 0; t < m.triangle_count(); ++t)
    ASSERT_GT(triangle_area_m2(m, t), 0.0) << m.name << " triangle " << t;
}

// Shading normals are unit, face the same side as the triangles they belong
// to, and tangents are unit and perpendicular to them.
void expect_consistent_normals(const Mesh& m) {
  ASSERT_EQ(m.normals.size(), m.positions.size());
  for (const Vec3f& n : m.normals) EXPECT_NEAR(std::hypot(n.x, n.y, n.z), 1.0, 1e-6);
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 ng = triangle_normal(m, t);
    for (int k = 0; k < 3; ++k) {
      const Vec3f n = m.normals[m.indices[3 * t + k]];
      EXPECT_GT(dot(ng, Vec3{n.x, n.y, n.z}), 0.5) << m.name << " triangle " << t;
    }
  }
  if (!m.tangents.empty()) {
    ASSERT_EQ(m.tangents.size(), m.positions.size());
    for (std::size_t v = 0; v < m.tangents.size(); ++v) {
      const Vec3 t{m.tangents[v].x, m.tangents[v].y, m.tangents[v].z};
      const Vec3 n{m.normals[v].x, m.normals[v].y, m.normals[v].z};
      EXPECT_NEAR(length(t), 1.0, 1e-6);
      EXPECT_NEAR(dot(t, n), 0.0, 1e-6);
    }
  }
}

// Closed forms of a surface of revolution faceted into n segments: between
// profile points (r1, y1) and (r2, y2) each facet is a planar isosceles
// trapezoid with parallel sides 2r·sin(π/n) at distances r·cos(π/n) from the
// axis, and the band encloses a frustum of a regular n-gon pyramid.
double band_area(double r1, double y1, double r2, double y2, int n) {
  const double c = std::cos(kPi / n), s = std::sin(kPi / n);
  const double h = std::hypot(y2 - y1, c * (r2 - r1));
  return n * (r1 + r2) * s * h;
}
double polygon_area(double r, int n) { return 0.5 * n * r * r * std::sin(2.0 * kPi / n); }
double band_volume(double r1, double y1, double r2, double y2, int n) {
  const double a1 = polygon_area(r1, n), a2 = polygon_area(r2, n);
  return (y2 - y1) / 3.0 * (a1 + a2 + std::sqrt(a1 * a2));
}

TEST(Shapes, DiscIsARegularPolygonFacingUp) {
  const int n = 48;
  const Mesh m = disc(0.25, n);
  EXPECT_NEAR(surface_area_m2(m), polygon_area(0.25, n), 1e-7);
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 ng = triangle_normal(m, t);
    EXPECT_NEAR(ng.y, 1.0, 1e-9);
  }
  for (const Vec3f& p : m.positions) EXPECT_EQ(p.y, 0.0f);
  // An open surface: the rim is its only boundary.
  EXPECT_EQ(check_edges(m, false).boundary_edges, static_cast<std::size_t>(n));
  EXPECT_EQ(check_edges(m, false).repeated_edges, 0u);
  expect_consistent_normals(m);
  expect_no_degenerate_triangles(m);
  // Converges to the circle: area defect of a regular n-gon ≈ (2π³/3n²) r².
  const double defect = kPi - surface_area_m2(disc(1.0, 512));
  EXPECT_NEAR(defect, 2.0 * kPi * kPi * kPi / (3.0 * 512 * 512), 1e-6);
}

TEST(Shapes, SphereIsClosedOutwardAndMatchesItsClosedForms) {
  const double r = 0.3;
  const int n = 40, rings = 20;
  const Mesh m = sphere(r, n, rings);
  expect_closed(m);
  expect_no_degenerate_triangles(m);
  expect_consistent_normals(m);
  for (const Vec3f& p : m.positions) EXPECT_NEAR(std::hypot(p.x, p.y, p.z), r, 1e-7);

  double area = 0.0, volume = 0.0;
  for (int k = 0; k < rings; ++k) {
    const double t0 = kPi * k / rings, t1 = kPi * (k + 1) / rings;
    const double r0 = r * std::sin(t0), r1 = r * std::sin(t1);
    const double y0 = -r * std::cos(t0), y1 = -r * std::cos(t1);
    area += band_area(r0, y0, r1, y1, n);
    volume += band_volume(r0, y0, r1, y1, n);
  }
  EXPECT_NEAR(surface_area_m2(m), area, 1e-6 * area);
  EXPECT_NEAR(enclosed_volume_m3(m), volume, 1e-6 * volume);  // positive: outward
  // And it converges to the sphere at second order.
  const double e1 = std::abs(enclosed_volume_m3(sphere(1.0, 32, 16)) - 4.0 / 3.0 * kPi);
  const double e2 = std::abs(enclosed_volume_m3(sphere(1.0, 64, 32)) - 4.0 / 3.0 * kPi);
  EXPECT_NEAR(e1 / e2, 4.0, 0.2);
  EXPECT_NEAR(surface_area_m2(sphere(1.0, 256, 128)), 4.0 * kPi, 4.0 * kPi * 1e-3);
  // Every triangle faces away from the centre.
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 c = (at(m, m.indices[3 * t]) + at(m, m.indices[3 * t + 1]) +
                    at(m, m.indices[3 * t + 2])) / 3.0;
    EXPECT_GT(dot(triangle_normal(m, t), c), 0.0);
  }
}

TEST(Shapes, BoxAndSlab) {
  const Mesh b = box(1.0, 2.0, 3.0);
  expect_closed(b);
  expect_no_degenerate_triangles(b);
  EXPECT_EQ(b.triangle_count(), 12u);
  EXPECT_DOUBLE_EQ(surface_area_m2(b), 2.0 * (1 * 2 + 2 * 3 + 3 * 1));
  EXPECT_DOUBLE_EQ(enclosed_volume_m3(b), 6.0);
  for (std::size_t t = 0; t < b.triangle_count(); ++t) {
    const Vec3 c = (at(b, b.indices[3 * t]) + at(b, b.indices[3 * t + 1]) +
                    at(b, b.indices[3 * t + 2])) / 3.0;
    EXPECT_GT(dot(triangle_normal(b, t), c), 0.0) << "triangle " << t << " faces inwards";
  }

  const Mesh s = slab(4.0, 2.0, 0.01);
  expect_closed(s);
  EXPECT_NEAR(enclosed_volume_m3(s), 4.0 * 2.0 * 0.01, 1e-6 * 0.08);  // float positions
  for (const Vec3f& p : s.positions) {
    EXPECT_FLOAT_EQ(std::abs(p.x), 2.0f);
    EXPECT_FLOAT_EQ(std::abs(p.y), 0.005f);
    EXPECT_FLOAT_EQ(std::abs(p.z), 1.0f);
  }
}

TEST(Shapes, ParaboloidLiesOnTheIdealSurfaceAndFacesItsFocus) {
  const double f = 0.04, aperture = 0.1, hole = 0.015;
  const int rings = 30, n = 90;
  const Mesh m = paraboloid(f, aperture, hole, rings, n);
  expect_no_degenerate_triangles(m);
  expect_consistent_normals(m);
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    const Vec3 p = at(m, static_cast<std::uint32_t>(v));
    const double rho2 = p.x * p.x + p.z * p.z;
    EXPECT_NEAR(p.y, f - rho2 / (4 * f), 1e-7);
    // Focal property: distance to the focus equals distance to the directrix y = 2f.
    EXPECT_NEAR(length(p), 2 * f - p.y, 1e-6);
    // The exact normal bisects the ray from the focus and the axis direction −Y,
    // so a ray from the focus leaves along −Y after a mirror reflection.
    const Vec3 nrm{m.normals[v].x, m.normals[v].y, m.normals[v].z};
    const Vec3 d = normalize(p);
    const Vec3 out = d - 2.0 * dot(d, nrm) * nrm;
    EXPECT_NEAR(out.y, -1.0, 1e-6);
  }
  for (std::size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 c = (at(m, m.indices[3 * t]) + at(m, m.indices[3 * t + 1]) +
                    at(m, m.indices[3 * t + 2])) / 3.0;
    EXPECT_GT(dot(triangle_normal(m, t), -c), 0.0) << "triangle " << t << " faces away from the focus";
  }
  // Open at the hole and the aperture.
  EXPECT_EQ(check_edges(m, false).boundary_edges, 2u * n);
  EXPECT_EQ(check_edges(m, false).repeated_edges, 0u);

  double area = 0.0;
  for (int k = 0; k < rings; ++k) {
    const double r0 = hole + (aperture - hole) * k / rings;
    const double r1 = hole + (aperture - hole) * (k + 1) / rings;
    area += band_area(r0, f - r0 * r0 / (4 * f), r1, f - r1 * r1 / (4 * f), n);
  }
  EXPECT_NEAR(surface_area_m2(m), area, 1e-6 * area);
  // The smooth paraboloid: A = (8πf²/3)[(1 + b²/4f²)^{3/2} − (1 + a²/4f²)^{3/2}].
  auto smooth = [&](double a, double b) {
    return 8.0 * kPi * f * f / 3.0 *
           (std::pow(1 + b * b / (4 * f * f), 1.5) - std::pow(1 + a * a / (4 * f * f), 1.5));
  };
  const Mesh fine = paraboloid(f, aperture, hole, 200, 720);
  EXPECT_NEAR(surface_area_m2(fine), smooth(hole, aperture), 1e-4 * smooth(hole, aperture));

  // Without a hole the vertex is a single pole vertex facing the focus.
  const Mesh closed_top = paraboloid(f, aperture, 0.0, 8, 16);
  EXPECT_EQ(check_edges(closed_top, false).boundary_edges, 16u);
  expect_consistent_normals(closed_top);
}

TEST(Shapes, LatheOfAClosedProfileIsAClosedRing) {
  // A washer: rectangle r in [1, 2], y in [0, 0.5], walked with the solid on
  // the left so that the front faces out.
  const ProfilePoint profile[] = {{2.0, 0.0}, {2.0, 0.5}, {1.0, 0.5}, {1.0, 0.0}};
  const int n = 36;
  LatheOptions options;
  options.segments = n;
  options.closed_profile = true;
  const Mesh m = lathe(profile, options);
  expect_no_degenerate_triangles(m);
  expect_consistent_normals(m);
  // Every corner is a crease: rings are duplicated, so closed only once welded.
  expect_closed(m, /*weld=*/true);
  EXPECT_GT(check_edges(m, false).boundary_edges, 0u);
  const double volume = 0.5 * (polygon_area(2.0, n) - polygon_area(1.0, n));
  EXPECT_NEAR(enclosed_volume_m3(m), volume, 1e-6 * volume);
  const double area = 2 * (polygon_area(2.0, n) - polygon_area(1.0, n)) +
                      band_area(2.0, 0.0, 2.0, 0.5, n) + band_area(1.0, 0.0, 1.0, 0.5, n);
  EXPECT_NEAR(surface_area_m2(m), area, 1e-6 * area);

  // Without shading normals nothing is duplicated: closed by index.
  options.shading_normals = false;
  const Mesh flat = lathe(profile, options);
  expect_closed(flat);
  EXPECT_TRUE(flat.normals.empty());
  EXPECT_NEAR(enclosed_volume_m3(flat), volume, 1e-6 * volume);
}

TEST(Shapes, LatheOfAnAxisToAxisProfileIsAClosedLens) {
  // A plano-convex lens: flat bottom disc, spherical cap on top.
  std::vector<ProfilePoint> profile = {{0.0, 0.0}, {0.02, 0.0}};
  const double R = 0.03, cap_centre = 0.0 - std::sqrt(R * R - 0.02 * 0.02);
  const int arc = 12;
  const double a0 = std::asin(0.02 / R);
  for (int k = 1; k <= arc; ++k) {
    const double a = a0 * (1.0 - static_cast<double>(k) / arc);
    profile.push_back({k == arc ? 0.0 : R * std::sin(a), cap_centre + R * std::cos(a)});
  }
  // Walked bottom centre → rim → top, the front (normal (dy, −dr)) faces out.
  const int n = 64;
  LatheOptions options;
  options.segments = n;
  const Mesh m = lathe(profile, options);
  expect_no_degenerate_triangles(m);
  expect_consistent_normals(m);
  expect_closed(m, /*weld=*/true);
  double volume = 0.0;
  for (std::size_t i = 0; i + 1 < profile.size(); ++i)
    volume += band_volume(profile[i].r_m, profile[i].y_m, profile[i + 1].r_m, profile[i + 1].y_m, n);
  EXPECT_GT(volume, 0.0);
  EXPECT_NEAR(enclosed_volume_m3(m), volume, 1e-6 * volume);
  // The rim is a crease (90° − the cap's edge angle), the arc is smooth.
  const auto ids = welded_ids(m);
  std::size_t duplicates = m.positions.size() - (*std::max_element(ids.begin(), ids.end()) + 1);
  EXPECT_EQ(duplicates, static_cast<std::size_t>(n));
}

TEST(Shapes, TransformKeepsOrientationAndScalesVolume) {
  Mesh m = sphere(0.5, 24, 12);
  const double v0 = enclosed_volume_m3(m);
  const Vec3 centre{0.3, -1.0, 2.0};
  transform(m, translation(centre) * rotation({1, 2, 3}, 0.7) * scaling(2.0, 1.0, 1.0));
  EXPECT_NEAR(enclosed_volume_m3(m), 2.0 * v0, 1e-5 * v0);
  expect_closed(m);
  expect_consistent_normals(m);

  // A mirror keeps the front side outside: the winding is reversed.
  Mesh mirrored = sphere(0.5, 24, 12);
  transform(mirrored, translation(centre) * scaling(-1.0, 1.0, 1.0));
  EXPECT_NEAR(enclosed_volume_m3(mirrored), v0, 1e-5 * v0);
  expect_consistent_normals(mirrored);
  for (std::size_t v = 0; v < mirrored.positions.size(); ++v) {
    const Vec3 n{mirrored.normals[v].x, mirrored.normals[v].y, mirrored.normals[v].z};
    EXPECT_GT(dot(n, at(mirrored, static_cast<std::uint32_t>(v)) - centre), 0.0);
  }

  flip(mirrored);
  EXPECT_NEAR(enclosed_volume_m3(mirrored), -v0, 1e-5 * v0);
  expect_consistent_normals(mirrored);
}

}  // namespace
}  // namespace gonio::sim
