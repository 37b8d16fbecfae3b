#include "photometry/frame.h"

#include <algorithm>
#include <numbers>

namespace gonio::photometry {

PhotometricFrame make_frame(const Vec3& up, const Vec3& c0) {
  PhotometricFrame f;
  f.up = normalize(up);
  f.c0 = normalize(c0 - dot(c0, f.up) * f.up);
  f.c90 = cross(f.up, f.c0);
  return f;
}

Vec3 direction_from_c_gamma(double c_rad, double gamma_rad) {
  const double s = std::sin(gamma_rad);
  return {s * std::cos(c_rad), s * std::sin(c_rad), -std::cos(gamma_rad)};
}

CGamma c_gamma_from_direction(const Vec3& local) {
  const double horizontal = std::hypot(local.x, local.y);
  const double gamma = std::atan2(horizontal, -local.z);
  double c = horizontal > 0.0 ? std::atan2(local.y, local.x) : 0.0;
  if (c < 0.0) c += 2.0 * std::numbers::pi;
  if (c >= 2.0 * std::numbers::pi) c = 0.0;
  return {c, std::clamp(gamma, 0.0, std::numbers::pi)};
}

}  // namespace gonio::photometry
