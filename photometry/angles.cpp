#include "photometry/angles.h"

#include <cmath>
#include <numbers>

#include "photometry/frame.h"

namespace gonio::photometry {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

Vec3 direction_from_type_a(double h_rad, double v_rad) {
  const double cv = std::cos(v_rad);
  return {cv * std::cos(h_rad), -cv * std::sin(h_rad), std::sin(v_rad)};
}

HV type_a_from_direction(const Vec3& local) {
  const double horizontal = std::hypot(local.x, local.y);
  const double v = std::atan2(local.z, horizontal);
  const double h = horizontal > 0.0 ? std::atan2(-local.y, local.x) : 0.0;
  return {h, v};
}

Vec3 direction_from_type_b(double h_rad, double v_rad) {
  const double ch = std::cos(h_rad);
  return {ch * std::sin(v_rad), -std::sin(h_rad), -ch * std::cos(v_rad)};
}

HV type_b_from_direction(const Vec3& local) {
  const double across = std::hypot(local.x, local.z);
  const double h = std::atan2(-local.y, across);
  const double v = across > 0.0 ? std::atan2(local.x, -local.z) : 0.0;
  return {h, v};
}

Vec3 direction_from_grid(PhotometricType type, double horizontal_deg, double vertical_deg) {
  switch (type) {
    case PhotometricType::A:
      return direction_from_type_a(horizontal_deg * kDeg, vertical_deg * kDeg);
    case PhotometricType::B:
      return direction_from_type_b(horizontal_deg * kDeg, vertical_deg * kDeg);
    case PhotometricType::C:
      break;
  }
  return direction_from_c_gamma(horizontal_deg * kDeg, vertical_deg * kDeg);
}

GridAngles grid_from_direction(PhotometricType type, const Vec3& local) {
  switch (type) {
    case PhotometricType::A: {
      const HV a = type_a_from_direction(local);
      return {a.h_rad / kDeg, a.v_rad / kDeg};
    }
    case PhotometricType::B: {
      const HV b = type_b_from_direction(local);
      return {b.h_rad / kDeg, b.v_rad / kDeg};
    }
    case PhotometricType::C:
      break;
  }
  const CGamma c = c_gamma_from_direction(local);
  return {c.c_rad / kDeg, c.gamma_rad / kDeg};
}

double solid_angle_jacobian(PhotometricType type, double horizontal_rad, double vertical_rad) {
  switch (type) {
    case PhotometricType::A:
      return std::cos(vertical_rad);
    case PhotometricType::B:
      return std::cos(horizontal_rad);
    case PhotometricType::C:
      break;
  }
  return std::sin(vertical_rad);
}

double intensity_toward(const Distribution& expanded, const Vec3& local) {
  const GridAngles a = grid_from_direction(expanded.type, local);
  return interpolate(expanded, a.horizontal_deg, a.vertical_deg);
}

}  // namespace gonio::photometry
