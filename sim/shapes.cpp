#include "sim/shapes.h"

#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::sim {
namespace {

// Unit normal (dy, −dr) of the profile segment a → b, as (r, y) components.
std::pair<double, double> segment_normal(const ProfilePoint& a, const ProfilePoint& b) {
  const double dr = b.r_m - a.r_m, dy = b.y_m - a.y_m;
  const double len = std::hypot(dr, dy);
  return {dy / len, -dr / len};
}

// One ring of vertices (or a single pole vertex) at a profile point.
struct Ring {
  std::uint32_t first;  // index of the vertex at angle 0
  bool pole;            // a single vertex on the axis
};

}  // namespace

Mesh lathe(std::span<const ProfilePoint> profile, const LatheOptions& options) {
  const int n = options.segments;
  const std::size_t count = profile.size();
  GONIO_CHECK_MSG(n >= 3, "a lathe needs at least 3 segments around its axis");
  GONIO_CHECK_MSG(count >= 2, "a lathe profile needs at least 2 points");
  GONIO_CHECK_MSG(!options.closed_profile || count >= 3, "a closed profile needs 3 points");
  for (std::size_t i = 0; i < count; ++i) {
    const ProfilePoint& p = profile[i];
    GONIO_CHECK_MSG(std::isfinite(p.r_m) && std::isfinite(p.y_m) && p.r_m >= 0.0,
                    "lathe profile points need finite coordinates and r >= 0");
    const ProfilePoint& q = profile[(i + 1) % count];
    if (i + 1 < count || options.closed_profile)
      GONIO_CHECK_MSG(p.r_m != q.r_m || p.y_m != q.y_m, "consecutive profile points coincide");
  }

  const std::size_t segment_count = options.closed_profile ? count : count - 1;
  const double cos_crease = std::cos(options.crease_angle_deg * std::numbers::pi / 180.0);

  Mesh mesh;
  mesh.name = "lathe";
  std::vector<double> cos_phi(n), sin_phi(n);
  for (int j = 0; j < n; ++j) {
    const double phi = 2.0 * std::numbers::pi * j / n;
    cos_phi[j] = std::cos(phi);
    sin_phi[j] = std::sin(phi);
  }

  // A ring of vertices at profile point p with profile normal (nr, ny).
  auto add_ring = [&](const ProfilePoint& p, double nr, double ny) -> Ring {
    const auto first = static_cast<std::uint32_t>(mesh.positions.size());
    if (p.r_m == 0.0) {
      mesh.positions.push_back(to_float({0.0, p.y_m, 0.0}));
      if (options.shading_normals) {
        mesh.normals.push_back({0.0f, ny >= 0.0 ? 1.0f : -1.0f, 0.0f});
        mesh.tangents.push_back({1.0f, 0.0f, 0.0f});
      }
      return {first, true};
    }
    for (int j = 0; j < n; ++j) {
      // A right-handed turn by φ about +Y takes +X to (cos φ, 0, −sin φ).
      mesh.positions.push_back(to_float({p.r_m * cos_phi[j], p.y_m, -p.r_m * sin_phi[j]}));
      if (options.shading_normals) {
        mesh.normals.push_back(to_float(normalize(Vec3{nr * cos_phi[j], ny, -nr * sin_phi[j]})));
        mesh.tangents.push_back(to_float({-sin_phi[j], 0.0, -cos_phi[j]}));
      }
    }
    return {first, false};
  };

  // For every profile point, the ring that ends the segment arriving at it
  // and the ring that starts the segment leaving it (the same ring unless the
  // point is a crease).
  std::vector<Ring> arriving(count), leaving(count);
  for (std::size_t i = 0; i < count; ++i) {
    const bool has_prev = i > 0 || options.closed_profile;
    const bool has_next = i + 1 < count || options.closed_profile;
    const ProfilePoint& p = profile[i];
    std::pair<double, double> n_prev{0.0, 0.0}, n_next{0.0, 0.0};
    if (has_prev) n_prev = segment_normal(profile[(i + count - 1) % count], p);
    if (has_next) n_next = segment_normal(p, profile[(i + 1) % count]);
    const bool crease = has_prev && has_next && options.shading_normals &&
                        n_prev.first * n_next.first + n_prev.second * n_next.second < cos_crease;
    if (crease && p.r_m > 0.0) {
      arriving[i] = add_ring(p, n_prev.first, n_prev.second);
      leaving[i] = add_ring(p, n_next.first, n_next.second);
    } else {
      double nr = n_prev.first + n_next.first, ny = n_prev.second + n_next.second;
      const double len = std::hypot(nr, ny);
      if (len > 0.0) {
        nr /= len;
        ny /= len;
      } else {
        nr = n_next.first;
        ny = n_next.second;
      }
      arriving[i] = leaving[i] = add_ring(p, nr, ny);
    }
  }

  for (std::size_t s = 0; s < segment_count; ++s) {
    const Ring a = leaving[s];
    const Ring b = arriving[(s + 1) % count];
    if (a.pole && b.pole) continue;  // a segment along the axis sweeps no area
    for (int j = 0; j < n; ++j) {
      const std::uint32_t j1 = static_cast<std::uint32_t>((j + 1) % n);
      const std::uint32_t aj = a.pole ? a.first : a.first + static_cast<std::uint32_t>(j);
      const std::uint32_t aj1 = a.pole ? a.first : a.first + j1;
      const std::uint32_t bj = b.pole ? b.first : b.first + static_cast<std::uint32_t>(j);
      const std::uint32_t bj1 = b.pole ? b.first : b.first + j1;
      if (!a.pole) mesh.indices.insert(mesh.indices.end(), {aj, aj1, bj});
      if (!b.pole) mesh.indices.insert(mesh.indices.end(), {aj1, bj1, bj});
    }
  }
  return mesh;
}

Mesh disc(double radius_m, int segments) {
  GONIO_CHECK_MSG(radius_m > 0.0, "disc radius must be positive");
  const ProfilePoint profile[] = {{radius_m, 0.0}, {0.0, 0.0}};
  LatheOptions options;
  options.segments = segments;
  Mesh mesh = lathe(profile, options);
  mesh.name = "disc";
  return mesh;
}

Mesh sphere(double radius_m, int segments, int rings) {
  GONIO_CHECK_MSG(radius_m > 0.0, "sphere radius must be positive");
  GONIO_CHECK_MSG(rings >= 2, "a sphere needs at least 2 rings");
  std::vector<ProfilePoint> profile(static_cast<std::size_t>(rings) + 1);
  for (int k = 0; k <= rings; ++k) {
    const double theta = std::numbers::pi * k / rings;  // from the south pole
    profile[k] = {k == 0 || k == rings ? 0.0 : radius_m * std::sin(theta),
                  -radius_m * std::cos(theta)};
  }
  LatheOptions options;
  options.segments = segments;
  Mesh mesh = lathe(profile, options);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    mesh.normals[v] = to_float(normalize(to_double(mesh.positions[v])));
  mesh.name = "sphere";
  return mesh;
}

Mesh box(double size_x_m, double size_y_m, double size_z_m) {
  GONIO_CHECK_MSG(size_x_m > 0.0 && size_y_m > 0.0 && size_z_m > 0.0,
                  "box sizes must be positive");
  const double hx = 0.5 * size_x_m, hy = 0.5 * size_y_m, hz = 0.5 * size_z_m;
  Mesh mesh;
  mesh.name = "box";
  // Vertex v has x = ±hx by bit 0, y by bit 1, z by bit 2.
  for (int v = 0; v < 8; ++v)
    mesh.positions.push_back(to_float({v & 1 ? hx : -hx, v & 2 ? hy : -hy, v & 4 ? hz : -hz}));
  // Each face as a quad, counter-clockwise seen from outside.
  const std::uint32_t quads[6][4] = {
      {1, 3, 7, 5},  // +X
      {0, 4, 6, 2},  // −X
      {2, 6, 7, 3},  // +Y
      {0, 1, 5, 4},  // −Y
      {4, 5, 7, 6},  // +Z
      {0, 2, 3, 1},  // −Z
  };
  for (const auto& q : quads)
    mesh.indices.insert(mesh.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  return mesh;
}

Mesh slab(double size_x_m, double size_z_m, double thickness_m) {
  Mesh mesh = box(size_x_m, thickness_m, size_z_m);
  mesh.name = "slab";
  return mesh;
}

Mesh paraboloid(double focal_length_m, double aperture_radius_m, double hole_radius_m, int rings,
                int segments) {
  const double f = focal_length_m;
  GONIO_CHECK_MSG(f > 0.0, "paraboloid focal length must be positive");
  GONIO_CHECK_MSG(hole_radius_m >= 0.0 && aperture_radius_m > hole_radius_m,
                  "paraboloid needs 0 <= hole radius < aperture radius");
  GONIO_CHECK_MSG(rings >= 1, "a paraboloid needs at least 1 ring");
  // Walked from the hole outwards, the front side (normal (dy, −dr)) faces
  // the focus.
  std::vector<ProfilePoint> profile(static_cast<std::size_t>(rings) + 1);
  for (int k = 0; k <= rings; ++k) {
    const double rho = hole_radius_m + (aperture_radius_m - hole_radius_m) * k / rings;
    profile[k] = {rho, f - rho * rho / (4.0 * f)};
  }
  LatheOptions options;
  options.segments = segments;
  Mesh mesh = lathe(profile, options);
  // The exact normal towards the focus side: −∇(y − f + ρ²/4f).
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3 p = to_double(mesh.positions[v]);
    mesh.normals[v] = to_float(normalize(Vec3{-p.x / (2.0 * f), -1.0, -p.z / (2.0 * f)}));
  }
  mesh.name = "paraboloid";
  return mesh;
}

void flip(Mesh& mesh) {
  for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
    std::swap(mesh.indices[i + 1], mesh.indices[i + 2]);
  for (Vec3f& n : mesh.normals) n = {-n.x, -n.y, -n.z};
}

namespace {
Vec3 triangle_cross(const Mesh& mesh, std::size_t t) {
  const Vec3 a = to_double(mesh.positions[mesh.indices[3 * t]]);
  const Vec3 b = to_double(mesh.positions[mesh.indices[3 * t + 1]]);
  const Vec3 c = to_double(mesh.positions[mesh.indices[3 * t + 2]]);
  return cross(b - a, c - a);
}
}  // namespace

double triangle_area_m2(const Mesh& mesh, std::size_t triangle) {
  return 0.5 * length(triangle_cross(mesh, triangle));
}

Vec3 triangle_normal(const Mesh& mesh, std::size_t triangle) {
  return normalize(triangle_cross(mesh, triangle));
}

double surface_area_m2(const Mesh& mesh) {
  double sum = 0.0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) sum += triangle_area_m2(mesh, t);
  return sum;
}

double enclosed_volume_m3(const Mesh& mesh) {
  double sum = 0.0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const Vec3 a = to_double(mesh.positions[mesh.indices[3 * t]]);
    const Vec3 b = to_double(mesh.positions[mesh.indices[3 * t + 1]]);
    const Vec3 c = to_double(mesh.positions[mesh.indices[3 * t + 2]]);
    sum += dot(a, cross(b, c));
  }
  return sum / 6.0;
}

}  // namespace gonio::sim
