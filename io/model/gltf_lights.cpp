#include "io/model/gltf_lights.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace gonio::io {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;
constexpr int kFalloffSteps = 128;

bool hard_edge(double inner_rad, double outer_rad) { return !(inner_rad < outer_rad); }

}  // namespace

double isotropic_flux_lm(double intensity_cd) { return 4.0 * std::numbers::pi * intensity_cd; }

double khr_spot_falloff(double theta_rad, double inner_rad, double outer_rad) {
  const double c = std::cos(theta_rad);
  const double co = std::cos(outer_rad);
  if (hard_edge(inner_rad, outer_rad)) return theta_rad < outer_rad ? 1.0 : 0.0;
  const double s = std::clamp((c - co) / (std::cos(inner_rad) - co), 0.0, 1.0);
  return s * s;
}

double khr_spot_flux_lm(double intensity_cd, double inner_rad, double outer_rad) {
  const double co = std::cos(outer_rad);
  if (hard_edge(inner_rad, outer_rad)) return 2.0 * std::numbers::pi * intensity_cd * (1.0 - co);
  const double ci = std::cos(inner_rad);
  // ∫ s² dμ over μ = cos θ from cos θo to cos θi, with s linear in μ, is
  // (cos θi − cos θo)/3.
  return 2.0 * std::numbers::pi * intensity_cd * ((1.0 - ci) + (ci - co) / 3.0);
}

photometry::Distribution khr_spot_distribution(double intensity_cd, double inner_rad,
                                               double outer_rad) {
  GONIO_CHECK(intensity_cd >= 0.0 && inner_rad >= 0.0 && outer_rad > 0.0 &&
              outer_rad <= std::numbers::pi / 2 + 1e-12);
  photometry::Distribution d;
  d.type = photometry::PhotometricType::C;
  d.symmetry = photometry::Symmetry::Rotational;
  d.horizontal_deg = {0.0};
  d.absolute = true;
  d.lamps = {photometry::LampSet{}};
  d.lamps[0].type = "KHR_lights_punctual spot";

  std::vector<double> gamma = {0.0};
  std::vector<double> candela = {intensity_cd};
  if (hard_edge(inner_rad, outer_rad)) {
    // A step becomes a ramp a thousandth of a degree wide: the grid stays
    // strictly increasing and the flux error stays below 1e-4.
    const double edge = outer_rad * kDeg;
    gamma.push_back(std::max(edge - 1e-3, 0.5 * edge));
    candela.push_back(intensity_cd);
    gamma.push_back(edge);
    candela.push_back(0.0);
  } else {
    if (inner_rad > 0.0) {
      gamma.push_back(inner_rad * kDeg);
      candela.push_back(intensity_cd);
    }
    for (int i = 1; i <= kFalloffSteps; ++i) {
      const double theta = inner_rad + (outer_rad - inner_rad) * i / kFalloffSteps;
      gamma.push_back(theta * kDeg);
      candela.push_back(intensity_cd * khr_spot_falloff(theta, inner_rad, outer_rad));
    }
  }
  if (gamma.back() < 180.0) {
    gamma.push_back(180.0);
    candela.push_back(0.0);
  }
  d.vertical_deg = std::move(gamma);
  d.candela = std::move(candela);
  return d;
}

photometry::PhotometricFrame light_frame(const Vec3& node_x, const Vec3& node_z) {
  return photometry::make_frame(node_z, node_x);
}

}  // namespace gonio::io
