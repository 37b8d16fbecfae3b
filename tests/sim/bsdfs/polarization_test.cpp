#include "sim/bsdfs/polarization.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sim/bsdfs/material.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;

Polarization linear(const Vec3& e) {
  Polarization p;
  p.polarized = true;
  p.e[0] = e.x;
  p.e[1] = e.y;
  p.e[2] = e.z;
  return p;
}

// Incident direction at angle θ in the xz plane onto the surface z = 0
// (normal +z on the incident side): s is along ∓y, p in the xz plane.
Vec3 incoming(double theta) { return {std::sin(theta), 0.0, -std::cos(theta)}; }

void expect_unit_and_transverse(const Polarization& p, const Vec3& k) {
  const double norm = std::norm(p.e[0]) + std::norm(p.e[1]) + std::norm(p.e[2]);
  EXPECT_NEAR(norm, 1.0, 1e-12);
  EXPECT_NEAR(std::abs(p.e[0] * k.x + p.e[1] * k.y + p.e[2] * k.z), 0.0, 1e-12);
}

TEST(Polarization, AmplitudesConserveEnergy) {
  for (double deg : {0.0, 20.0, 45.0, 56.0, 70.0, 85.0}) {
    for (auto [n1, n2] : {std::pair{1.0, 1.52}, std::pair{1.52, 1.0}}) {
      const double ci = std::cos(deg * kPi / 180.0);
      const FresnelAmplitudes a = fresnel_amplitudes(ci, n1, n2);
      if (a.total_internal_reflection) {
        EXPECT_NEAR(std::abs(a.rs), 1.0, 1e-12);
        EXPECT_NEAR(std::abs(a.rp), 1.0, 1e-12);
        continue;
      }
      const double k = n2 * a.cos_t / (n1 * ci);
      EXPECT_NEAR(std::norm(a.rs) + k * std::norm(a.ts), 1.0, 1e-12) << deg;
      EXPECT_NEAR(std::norm(a.rp) + k * std::norm(a.tp), 1.0, 1e-12) << deg;
      EXPECT_NEAR(0.5 * (std::norm(a.rs) + std::norm(a.rp)), fresnel_dielectric(ci, n1, n2), 1e-12);
    }
  }
}

TEST(Polarization, TotalInternalReflectionPhase) {
  // Born & Wolf: the phase difference δ = δp − δs of totally reflected light
  // obeys tan(δ/2) = cos θ √(sin²θ − n²) / sin²θ with n = n2/n1.
  const double n = 1.0 / 1.5, theta = 55.0 * kPi / 180.0;
  const FresnelAmplitudes a = fresnel_amplitudes(std::cos(theta), 1.5, 1.0);
  ASSERT_TRUE(a.total_internal_reflection);
  const double delta = std::arg(a.rp / a.rs);
  const double s2 = std::sin(theta) * std::sin(theta);
  EXPECT_NEAR(std::abs(std::tan(delta / 2.0)), std::cos(theta) * std::sqrt(s2 - n * n) / s2, 1e-12);
}

TEST(Polarization, BrewsterAngleReflectsNoPLight) {
  const double tb = std::atan(1.5);
  const Vec3 k = incoming(tb), n{0, 0, 1};
  // p lies in the plane of incidence, perpendicular to k.
  const Polarization p = linear({std::cos(tb), 0.0, std::sin(tb)});
  const Polarization s = linear({0.0, 1.0, 0.0});
  const FresnelAmplitudes a = fresnel_amplitudes(std::cos(tb), 1.0, 1.5);
  for (double u : {0.0, 1e-9, 0.5}) {
    const InterfaceOutcome o = interface_event(p, k, n, 1.0, 1.5, u);
    EXPECT_FALSE(o.reflected);
    EXPECT_NEAR(o.reflectance, 0.0, 1e-15);
    expect_unit_and_transverse(o.state, o.direction);
    // The refracted field stays p: in the plane of incidence.
    EXPECT_NEAR(std::abs(o.state.e[1]), 0.0, 1e-12);
  }
  const InterfaceOutcome os = interface_event(s, k, n, 1.0, 1.5, 0.5);
  EXPECT_NEAR(os.reflectance, std::norm(a.rs), 1e-14);
  const InterfaceOutcome refl = interface_event(s, k, n, 1.0, 1.5, 0.0);
  ASSERT_TRUE(refl.reflected);
  EXPECT_NEAR(std::abs(refl.state.e[1]), 1.0, 1e-12);  // stays s
  EXPECT_NEAR(refl.direction.z, std::cos(tb), 1e-12);
}

TEST(Polarization, RandomLinearStatesAreUnpolarised) {
  // Averaged over photons, R is the unpolarised mean (Rs + Rp)/2, and after
  // one reflection the light is partly polarised towards s.
  const double theta = 70.0 * kPi / 180.0;
  const Vec3 k = incoming(theta), n{0, 0, 1};
  const int count = 200000;
  double r_sum = 0.0, s_after = 0.0;
  for (int i = 0; i < count; ++i) {
    PhotonRandom rng(3, static_cast<std::uint64_t>(i));
    Polarization p;
    polarize_randomly(p, k, rng);
    expect_unit_and_transverse(p, k);
    const InterfaceOutcome o = interface_event(p, k, n, 1.0, 1.52, 0.0);  // u = 0: always reflect
    r_sum += o.reflectance;
    s_after += std::norm(o.state.e[1]);
  }
  const double mean = fresnel_dielectric(std::cos(theta), 1.0, 1.52);
  EXPECT_NEAR(r_sum / count, mean, 3e-3 * mean);
  const FresnelAmplitudes a = fresnel_amplitudes(std::cos(theta), 1.0, 1.52);
  // Per photon (renormalised) the s share after reflection is
  // Rs cos²ψ / (Rs cos²ψ + Rp sin²ψ), whose mean over uniform ψ is
  // √Rs / (√Rs + √Rp): partly polarised towards s.
  const double rs = std::abs(a.rs), rp = std::abs(a.rp);
  EXPECT_NEAR(s_after / count, rs / (rs + rp), 3e-3);
}

TEST(Polarization, MirrorKeepsTheFieldTransverse) {
  Polarization p = linear(normalize(Vec3{1, 1, 0}));
  const Vec3 k{0, 0, -1}, n = normalize(Vec3{0.2, 0, 1});
  reflect_field(p, n);
  const Vec3 out = k - 2.0 * dot(k, n) * n;
  expect_unit_and_transverse(p, out);
}

TEST(Polarization, ScatterUpdatesOrForgetsTheState) {
  const SurfaceFrame f{{0, 0, 1}, {0, 0, 1}, {}};
  Material glass;
  glass.dielectric = 1.0;
  glass.ior = 1.5;
  Material opal;
  opal.diffuse_transmit = 1.0;
  PhotonRandom rng(5, 5);
  Polarization p;
  const ScatterResult r = scatter(glass, f, normalize(Vec3{0.5, 0.1, -1}), rng, &p);
  EXPECT_TRUE(p.polarized);
  expect_unit_and_transverse(p, r.direction);
  scatter(opal, f, r.direction.z < 0 ? -r.direction : r.direction, rng, &p);
  EXPECT_FALSE(p.polarized);
}

}  // namespace
}  // namespace gonio::sim
