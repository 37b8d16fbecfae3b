#include "sim/near_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

#include "sim/ledger.h"
#include "sim/shapes.h"
#include "sim/simulation.h"
#include "tests/sim/scenes.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;

SimulationSettings near_settings(int threads, std::uint64_t per_iteration, int iterations,
                                 std::vector<double> distances_m) {
  SimulationSettings s = test_scenes::small_run(threads, per_iteration, iterations, 77);
  s.near_field_distances_m = std::move(distances_m);
  return s;
}

// Photons in a pixel of illuminance e [lx] for a run of `photons` photons of
// `flux_lm` in all.
double photons_in_pixel(const NearFieldPlane& p, double e_lx, double flux_lm, double photons) {
  return e_lx * p.pixel_size_m * p.pixel_size_m / (flux_lm / photons);
}

TEST(NearField, LambertianDiscOnAxisIsTheClosedFormNotTheFarField) {
  // A black Lambertian disc of radius a facing the nadir, radiance L: on the
  // axis at distance D, E = πL·a²/(a² + D²) (the disc's configuration factor,
  // e.g. Modest, Radiative Heat Transfer, view factor of a disc to a
  // parallel element on its axis), while its far field, I(0) = L·πa², gives
  // πL·a²/D². The 64-gon has area A; a² is taken as A/π.
  const double a = 0.05, flux = 1000.0;
  SceneDesc scene;
  Material black;
  black.name = "black";
  scene.materials = {black};
  Mesh d = disc(a, 64);
  flip(d);  // facing −Y, the default frame's nadir
  scene.meshes = {d};
  Emitter e;
  e.kind = Emitter::Kind::Area;
  e.flux_lm = flux;
  scene.emitters = {e};
  const double area = 0.5 * 64 * std::sin(2.0 * kPi / 64) * a * a;
  const double a2 = area / kPi, radiance = flux / (kPi * area);
  const std::vector<double> distances = {0.5 * a, a, 2.0 * a, 4.0 * a};
  const std::uint64_t photons = 4'000'000;
  auto sim = simulate(scene, near_settings(2, photons / 2, 2, distances));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const std::vector<NearFieldPlane> planes = sim->near_field();
  ASSERT_EQ(planes.size(), distances.size());
  for (const NearFieldPlane& p : planes) {
    const double D = p.distance_m;
    const double near = kPi * radiance * a2 / (a2 + D * D), far = kPi * radiance * a2 / (D * D);
    // Tolerance: 4 standard deviations of the centre pixel's photon count,
    // plus 0.5 % for the pixel's average against its centre value.
    const double n = photons_in_pixel(p, near, flux, static_cast<double>(photons));
    const double tol = 4.0 / std::sqrt(n) + 0.005;
    std::printf("  D = %.3f m: near %.1f lx (closed form %.1f), far %.1f lx (closed form %.1f), %.0f photons\n", D,
                p.on_axis_lx, near, p.far_field_on_axis_lx, far, n);
    EXPECT_NEAR(p.on_axis_lx / near, 1.0, tol) << "D = " << D;
    EXPECT_NEAR(p.far_field_on_axis_lx / far, 1.0, tol) << "D = " << D;
  }
  // Near and far differ by (a² + D²)/D²: 5× at D = a/2, still 6 % at 4a.
  EXPECT_GT(planes[0].max_deviation_pct, 70.0);
  EXPECT_GT(planes[3].max_deviation_pct, 4.0);
  EXPECT_FALSE(far_field_distance_m(planes).has_value());
}

TEST(NearField, BarePointEmitterNearFieldIsItsFarFieldAtEveryDistance) {
  // Every photon leaves the point, which is the centre: both tallies bin the
  // same photons in the same pixels, at every distance.
  SceneDesc scene;
  Emitter e;
  e.kind = Emitter::Kind::Point;
  e.position = {0.1, 0.2, -0.3};
  e.flux_lm = 1000.0;
  scene.emitters = {e};
  const std::vector<double> distances = {0.001, 0.1, 3.0};
  const std::uint64_t photons = 400'000;
  auto sim = simulate(scene, near_settings(2, photons, 1, distances));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const std::vector<NearFieldPlane> planes = sim->near_field();
  ASSERT_EQ(planes.size(), 3u);
  for (const NearFieldPlane& p : planes) {
    EXPECT_EQ(p.near_lx, p.far_lx) << p.distance_m;
    EXPECT_EQ(p.max_deviation_pct, 0.0);
    // Isotropic: E on the axis = Φ/(4π D²), the centre pixel's photons' noise.
    const double want = 1000.0 / (4.0 * kPi * p.distance_m * p.distance_m);
    const double n = photons_in_pixel(p, want, 1000.0, static_cast<double>(photons));
    EXPECT_NEAR(p.on_axis_lx / want, 1.0, 4.0 / std::sqrt(n) + 0.005);
  }
  ASSERT_TRUE(far_field_distance_m(planes).has_value());
  EXPECT_EQ(*far_field_distance_m(planes), 0.001);
}

TEST(NearField, SameBytesWithOneOrTwoThreadsAndAnySplit) {
  const SceneDesc scene = test_scenes::mixed_scene();
  const std::vector<double> distances = {0.05, 0.3, 2.0};
  auto one = simulate(scene, near_settings(1, 30000, 2, distances));
  auto two = simulate(scene, near_settings(2, 30000, 2, distances));
  auto whole = simulate(scene, near_settings(2, 60000, 1, distances));
  ASSERT_TRUE(one.ok()) << one.error().message;
  ASSERT_TRUE(two.ok());
  ASSERT_TRUE(whole.ok());
  const auto a = one->near_field(), b = two->near_field(), c = whole->near_field();
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), 3u);
  ASSERT_EQ(c.size(), 3u);
  double total = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const std::size_t bytes = a[k].near_lx.size() * sizeof(double);
    ASSERT_EQ(b[k].near_lx.size(), a[k].near_lx.size());
    ASSERT_EQ(c[k].near_lx.size(), a[k].near_lx.size());
    EXPECT_EQ(std::memcmp(a[k].near_lx.data(), b[k].near_lx.data(), bytes), 0);
    EXPECT_EQ(std::memcmp(a[k].far_lx.data(), b[k].far_lx.data(), bytes), 0);
    EXPECT_EQ(std::memcmp(a[k].near_lx.data(), c[k].near_lx.data(), bytes), 0);
    EXPECT_EQ(std::memcmp(a[k].far_lx.data(), c[k].far_lx.data(), bytes), 0);
    EXPECT_EQ(a[k].max_deviation_bound_pct, b[k].max_deviation_bound_pct);
    for (double v : a[k].near_lx) total += v;
  }
  EXPECT_GT(total, 0.0);
}

TEST(NearField, NoPlanesAskedForNoneKept) {
  auto sim = simulate(test_scenes::mixed_scene(), near_settings(2, 10000, 1, {}));
  ASSERT_TRUE(sim.ok());
  EXPECT_TRUE(sim->near_field().empty());
  EXPECT_EQ(sim->near_field_planes(), nullptr);
}

TEST(NearField, FarFieldDistanceIsTheNearestOfAnUnbrokenRunOfPassingPlanes) {
  const auto plane = [](double d, double bound) {
    NearFieldPlane p;
    p.distance_m = d;
    p.max_deviation_bound_pct = bound;
    return p;
  };
  // Not sorted on input; 0.5 m passes but 1 m does not: from 2 m on.
  EXPECT_EQ(far_field_distance_m({plane(4.0, 0.2), plane(0.5, 0.9), plane(1.0, 1.5), plane(2.0, 0.8)}), 2.0);
  EXPECT_FALSE(far_field_distance_m({plane(1.0, 0.5), plane(4.0, 1.01)}).has_value());
  EXPECT_FALSE(far_field_distance_m({}).has_value());
  EXPECT_EQ(far_field_distance_m({plane(1.0, 1.0)}), 1.0);
}

}  // namespace
}  // namespace gonio::sim
