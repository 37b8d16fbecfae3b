#include "sim/detectors/cube_map.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>

#include "photometry/diagnostics.h"

namespace gonio::sim {
namespace {

// Solid angle of the face rectangle [0, a] × [0, b] (signed): the classic
// closed form atan(ab / √(a² + b² + 1)).
double corner_integral(double a, double b) {
  return std::atan2(a * b, std::sqrt(a * a + b * b + 1.0));
}

// One face's texel solid angles for face size n (4 atan2 a texel).
std::vector<double> face_solid_angles(int n) {
  std::vector<double> out(static_cast<std::size_t>(n) * n);
  const double step = 2.0 / n;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const double a0 = -1.0 + x * step, b0 = -1.0 + y * step;
      out[static_cast<std::size_t>(y) * n + x] = CubeMapGrid::solid_angle(a0, b0, a0 + step, b0 + step);
    }
  }
  return out;
}

}  // namespace

// The face's solid angles are computed once per face size in the process
// (up to kCachedFaceSize, 8 MB) and copied: a far field, each Sobol'
// replicate's and each resampling builds a grid, and one evaluation of a
// design built seven at face size 128 (6 % of its time, issue 40;
// docs/design.md "Speed of one evaluation"). The copy holds the same values.
CubeMapGrid::CubeMapGrid(int face_size) : n_(face_size) {
  GONIO_CHECK_MSG(face_size >= 1 && face_size <= 16384, "cube-map face size out of range");
  constexpr int kCachedFaceSize = 1024;
  if (n_ > kCachedFaceSize) {
    face_solid_angle_ = face_solid_angles(n_);
    return;
  }
  static std::mutex mutex;
  static std::map<int, std::shared_ptr<const std::vector<double>>> cache;
  std::shared_ptr<const std::vector<double>> angles;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (auto it = cache.find(n_); it != cache.end()) angles = it->second;
  }
  if (!angles) {
    angles = std::make_shared<const std::vector<double>>(face_solid_angles(n_));
    const std::lock_guard<std::mutex> lock(mutex);
    angles = cache.emplace(n_, angles).first->second;
  }
  face_solid_angle_ = *angles;
}

CubePoint CubeMapGrid::locate(const Vec3& d) {
  const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
  if (ax >= ay && ax >= az) {
    const double inv = 1.0 / ax;
    return d.x > 0 ? CubePoint{0, d.z * inv, -d.y * inv} : CubePoint{1, -d.z * inv, -d.y * inv};
  }
  if (ay >= az) {
    const double inv = 1.0 / ay;
    return d.y > 0 ? CubePoint{2, d.x * inv, -d.z * inv} : CubePoint{3, d.x * inv, d.z * inv};
  }
  const double inv = 1.0 / az;
  return d.z > 0 ? CubePoint{4, -d.x * inv, -d.y * inv} : CubePoint{5, d.x * inv, -d.y * inv};
}

Vec3 CubeMapGrid::direction(int face, double a, double b) {
  switch (face) {
    case 0: return {1.0, -b, a};
    case 1: return {-1.0, -b, -a};
    case 2: return {a, 1.0, -b};
    case 3: return {a, -1.0, b};
    case 4: return {-a, -b, 1.0};
    default: return {a, -b, -1.0};
  }
}

double CubeMapGrid::solid_angle(double a0, double b0, double a1, double b1) {
  return corner_integral(a1, b1) - corner_integral(a0, b1) - corner_integral(a1, b0) +
         corner_integral(a0, b0);
}

std::size_t CubeMapGrid::texel_of(const Vec3& d) const {
  const CubePoint p = locate(d);
  const double half = 0.5 * n_;
  const int x = std::clamp(static_cast<int>((p.a + 1.0) * half), 0, n_ - 1);
  const int y = std::clamp(static_cast<int>((p.b + 1.0) * half), 0, n_ - 1);
  return index(p.face, x, y);
}

Vec3 CubeMapGrid::texel_direction(std::size_t texel) const {
  const std::size_t per_face = static_cast<std::size_t>(n_) * n_;
  const int face = static_cast<int>(texel / per_face);
  const std::size_t in_face = texel % per_face;
  const int y = static_cast<int>(in_face / n_), x = static_cast<int>(in_face % n_);
  const double a = 2.0 * (x + 0.5) / n_ - 1.0, b = 2.0 * (y + 0.5) / n_ - 1.0;
  return normalize(direction(face, a, b));
}

int CubeMapGrid::face_size_for_step(double step_deg, double texels_per_step) {
  GONIO_CHECK(step_deg > 0.0 && texels_per_step > 0.0);
  const double texel_rad = step_deg / texels_per_step * std::numbers::pi / 180.0;
  int n = 1;
  // The centre texel of a face of size n spans 2·atan(1/n) radians.
  while (n < 16384 && 2.0 * std::atan(1.0 / n) > texel_rad) n *= 2;
  return n;
}

}  // namespace gonio::sim
