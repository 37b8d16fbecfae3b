#include "sim/near_field.h"

#include <gtest/gtest.h>

#include <algorithm>
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

// The planes of a run of `photons` photons (two threads, two iterations).
std::vector<NearFieldPlane> planes_of(const SceneDesc& scene, std::uint64_t photons,
                                      const std::vector<double>& distances) {
  auto sim = simulate(scene, near_settings(2, photons / 2, 2, distances));
  EXPECT_TRUE(sim.ok()) << sim.error().message;
  if (!sim.ok()) return {};
  std::vector<NearFieldPlane> planes = sim->near_field();
  EXPECT_EQ(planes.size(), distances.size());
  return planes;
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
  const std::vector<NearFieldPlane> planes = planes_of(scene, photons, distances);
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

// A black Lambertian disc of radius a facing the nadir (a 64-gon; a² taken
// as its area / π) with `flux` lm, its centre at `at`.
Mesh lambertian_disc(double a, const Vec3& at) {
  Mesh d = disc(a, 64);
  flip(d);  // facing −Y, the default frame's nadir
  transform(d, translation(at));
  d.material = 0;
  return d;
}

// A speck of black geometry (a triangle of 0.1 mm) at `at`: it moves the
// luminaire's bounding box, and so the planes' reference, without shading.
Mesh speck(const Vec3& at) {
  Mesh m = disc(1e-4, 3);
  transform(m, translation(at));
  m.material = 0;
  return m;
}

// Issue 34, case 5: the sign of the start point's depth. The disc sits h
// above the bottom of the luminaire's bounding box (two specks at the side
// hold the bottom down), where the planes are measured from: at D below the
// bottom, the disc is D + h away, and on the axis E = πL·a²/(a² + (D + h)²).
// A start depth taken with the wrong sign puts the disc at D − h (at D = h
// that is a pole: E = πL; at 2h, 5 × the right value).
TEST(NearField, DiscRaisedAboveTheBoxBottomIsLitFromItsOwnHeight) {
  const double a = 0.05, h = 0.05, flux = 1000.0;
  SceneDesc scene;
  Material black;
  black.name = "black";
  scene.materials = {black};
  scene.meshes = {lambertian_disc(a, {0.0, 0.0, 0.0}), speck({0.5, -h, 0.0}), speck({-0.5, -h, 0.0})};
  Emitter e;
  e.kind = Emitter::Kind::Area;
  e.mesh = 0;
  e.flux_lm = flux;
  scene.emitters = {e};
  const Vec3 centre = luminaire_centre(scene);
  EXPECT_NEAR(centre.y, -h, 1e-9);
  EXPECT_NEAR(centre.x, 0.0, 1e-4);  // the specks' triangles are not quite symmetric
  const double area = 0.5 * 64 * std::sin(2.0 * kPi / 64) * a * a;
  const double a2 = area / kPi, radiance = flux / (kPi * area);
  const std::vector<double> distances = {h, 2.0 * h, 4.0 * h};
  const std::uint64_t photons = 400'000;
  const std::vector<NearFieldPlane> planes = planes_of(scene, photons, distances);
  ASSERT_EQ(planes.size(), distances.size());
  for (const NearFieldPlane& p : planes) {
    const double D = p.distance_m;
    const double want = kPi * radiance * a2 / (a2 + (D + h) * (D + h));
    const double n = photons_in_pixel(p, want, flux, static_cast<double>(photons));
    const double tol = 4.0 / std::sqrt(n) + 0.005;
    std::printf("  raised disc, D = %.2f m: near %.1f lx, closed form %.1f lx (with the depth's sign flipped %.1f)\n",
                D, p.on_axis_lx, want, kPi * radiance * a2 / (a2 + (D - h) * (D - h)));
    EXPECT_NEAR(p.on_axis_lx / want, 1.0, tol) << "D = " << D;
  }
}

// Issue 34, case 5: the image's orientation. Rows run along C90 from +C90 at
// the top (row 0) to −C90 at the bottom (near_field.h, and the EXR written
// from it); columns along C0 from −C0 at the left. A small Lambertian disc
// 5 cm toward +C90 and 3 cm toward +C0 of the luminaire's centre (a speck
// opposite keeps the centre between them) lights, 5 cm below, the rows
// about row 10 of 41 most ((0.1 − 0.05) / 0.2 × 41 = 10.25) and the columns
// about 26 ((0.1 + 0.03) / 0.2 × 41 = 26.65); the image's centroid lies
// toward +C90 and +C0. The far field's prediction, from the centre, is
// centred. An image flipped along C90, or C90 taken the wrong way round,
// puts the brightest row at 30 (and flipped along C0, the column at 14).
TEST(NearField, EmitterTowardC90AndC0LightsTheTopRightOfTheImage) {
  SceneDesc scene;
  Material black;
  black.name = "black";
  scene.materials = {black};
  const Vec3 toward_c90 = scene.frame.c90;
  const Vec3 offset = 0.05 * toward_c90 + 0.03 * scene.frame.c0;
  scene.meshes = {lambertian_disc(0.005, offset), speck(-1.0 * offset)};
  Emitter e;
  e.kind = Emitter::Kind::Area;
  e.mesh = 0;
  e.flux_lm = 1000.0;
  scene.emitters = {e};
  auto sim = simulate(scene, near_settings(2, 100000, 1, {0.05}));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const std::vector<NearFieldPlane> planes = sim->near_field();
  ASSERT_EQ(planes.size(), 1u);
  const NearFieldPlane& p = planes[0];
  const auto n = static_cast<std::size_t>(p.pixels);
  // Per image: the brightest row and column, and the centroid along C0 and C90 [m].
  struct Shape {
    std::size_t brightest_row, brightest_column;
    double c0_m, c90_m;
  };
  const auto shape = [&](const std::vector<double>& lx) {
    std::vector<double> rows(n, 0.0), columns(n, 0.0);
    double sum = 0.0, c0 = 0.0, c90 = 0.0;
    for (std::size_t r = 0; r < n; ++r)
      for (std::size_t c = 0; c < n; ++c) {
        const double v = lx[r * n + c];
        rows[r] += v;
        columns[c] += v;
        sum += v;
        c0 += v * (-p.half_width_m + (static_cast<double>(c) + 0.5) * p.pixel_size_m);
        c90 += v * (p.half_width_m - (static_cast<double>(r) + 0.5) * p.pixel_size_m);
      }
    const auto brightest = [](const std::vector<double>& v) {
      return static_cast<std::size_t>(std::max_element(v.begin(), v.end()) - v.begin());
    };
    return Shape{brightest(rows), brightest(columns), c0 / sum, c90 / sum};
  };
  const Shape near = shape(p.near_lx), far = shape(p.far_lx);
  std::printf("  emitter toward C90 and C0: near field brightest row %zu, column %zu, centroid C0 %+.4f m, C90 "
              "%+.4f m; far field centroid C0 %+.4f m, C90 %+.4f m\n",
              near.brightest_row, near.brightest_column, near.c0_m, near.c90_m, far.c0_m, far.c90_m);
  EXPECT_EQ(near.brightest_row, 10u);
  EXPECT_EQ(near.brightest_column, 26u);
  EXPECT_GT(near.c90_m, 0.02);
  EXPECT_GT(near.c0_m, 0.01);
  EXPECT_NEAR(far.c90_m, 0.0, 0.003);
  EXPECT_NEAR(far.c0_m, 0.0, 0.003);
  EXPECT_EQ(far.brightest_row, 20u);
  EXPECT_EQ(far.brightest_column, 20u);
}

// Issue 34, case 6: the far-field criterion's constants on a hand-made
// tally. Pinned here (re-pin both when the criterion changes):
//   kPixelCut   a pixel counts where the far field reaches this fraction of
//               its maximum (near_field.h: "≥ 10 %");
//   kNoiseSigmas the bound is the deviation plus this many standard
//               deviations of photon noise, σ = √moved / photons.
// Pixels (far-field photons of nominal power): A 100 (the maximum), B
// 100·(kPixelCut + 0.01) and C 100·(kPixelCut − 0.01), each with its near
// count and `moved`. The largest deviation and bound are B's, exactly; C
// (a 9 % pixel with a 122 % deviation) must be left out, B (11 %) counted.
// A cut at 9 % counts C (deviation 122 %), one at 12 % drops B (3 %); one
// or three σ give a bound of 36.4 % or 72.7 % instead of 54.5 %.
constexpr double kPixelCut = 0.10;
constexpr double kNoiseSigmas = 2.0;

TEST(NearField, CriterionConstantsOnAHandMadeTally) {
  NearFieldPlanes planes;
  planes.centre = {0.0, 0.0, 0.0};
  planes.distances_m = {1.0};
  NearFieldTally t;
  t.reset(planes);
  const std::size_t a = 100, b = 300, c = 1000;  // any three pixels
  const double far_a = 100.0, far_b = 100.0 * (kPixelCut + 0.01), far_c = 100.0 * (kPixelCut - 0.01);
  const double near_a = 103.0, near_b = far_b + 2.0, near_c = 20.0;
  const auto units = [](double photons) { return static_cast<std::uint64_t>(std::llround(photons * kPowerUnits)); };
  t.far_units[a] = units(far_a);
  t.near_units[a] = units(near_a);
  t.moved[a] = 9;
  t.far_units[b] = units(far_b);
  t.near_units[b] = units(near_b);
  t.moved[b] = 4;
  t.far_units[c] = units(far_c);
  t.near_units[c] = units(near_c);
  t.moved[c] = 0;
  const double lm_per_unit = 1e-6;
  const std::vector<NearFieldPlane> out = near_field_planes(planes, t, lm_per_unit);
  ASSERT_EQ(out.size(), 1u);
  const NearFieldPlane& p = out[0];
  // Illuminance: units × lm per unit / pixel area (4 m / 41 a side at 1 m).
  const double pixel = 4.0 / 41.0;
  EXPECT_DOUBLE_EQ(p.pixel_size_m, pixel);
  EXPECT_NEAR(p.far_lx[a], far_a * kPowerUnits * lm_per_unit / (pixel * pixel), 1e-9);
  // A: deviation 3 %, σ = √9 / 100 = 3 %. B: deviation 2 / far_b, σ = √4 / far_b.
  const double dev_a = 3.0, dev_b = 2.0 / far_b * 100.0;
  const double bound_a = dev_a + kNoiseSigmas * 3.0, bound_b = dev_b + kNoiseSigmas * 2.0 / far_b * 100.0;
  EXPECT_NEAR(p.max_deviation_pct, std::max(dev_a, dev_b), 1e-9);
  EXPECT_NEAR(p.max_deviation_bound_pct, std::max(bound_a, bound_b), 1e-9);
  EXPECT_EQ(p.min_photons, static_cast<std::uint64_t>(far_b)) << "the fewest photons of a counted pixel (B's)";
  // With today's constants: 18.18 % and 54.55 %.
  EXPECT_NEAR(p.max_deviation_pct, 200.0 / 11.0, 1e-9);
  EXPECT_NEAR(p.max_deviation_bound_pct, 600.0 / 11.0, 1e-9);
  EXPECT_EQ(p.on_axis_lx, 0.0);  // nothing in the middle pixel
  // The plane passes a limit just above its bound and fails one just below.
  EXPECT_EQ(far_field_distance_m(out, p.max_deviation_bound_pct + 1e-9), 1.0);
  EXPECT_FALSE(far_field_distance_m(out, p.max_deviation_bound_pct - 1e-9).has_value());
}

}  // namespace
}  // namespace gonio::sim
