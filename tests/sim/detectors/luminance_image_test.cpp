#include "sim/detectors/luminance_image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include "sim/shapes.h"
#include "sim/simulation.h"
#include "tests/sim/scenes.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

SimulationSettings image_run(std::vector<LuminanceView> views, std::uint64_t photons, int threads = 2,
                             double cone_deg = kLuminanceConeDeg, double pixel_m = 0.002) {
  SimulationSettings s = test_scenes::small_run(threads, photons, 1, 13);
  s.luminance.views = std::move(views);
  s.luminance.cone_deg = cone_deg;
  s.luminance.pixel_m = pixel_m;
  return s;
}

// Pixel centre of image `img` in world space.
Vec3 pixel_centre(const LuminanceImage& img, std::size_t i) {
  const ImagePlane& p = img.plane;
  const double half = 0.5 * p.pixel_m * p.pixels;
  const double u = (static_cast<double>(i % static_cast<std::size_t>(p.pixels)) + 0.5) * p.pixel_m - half;
  const double v = half - (static_cast<double>(i / static_cast<std::size_t>(p.pixels)) + 0.5) * p.pixel_m;
  return p.centre + u * p.right + v * p.up;
}

TEST(LuminanceImage, ViewsParseAndTheUgrSetIsCie232s) {
  std::vector<LuminanceView> v;
  EXPECT_EQ(parse_luminance_views("0:65,90:50,0:65", &v), "");
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[1].c_deg, 90.0);
  EXPECT_EQ(v[1].gamma_deg, 50.0);
  EXPECT_EQ(parse_luminance_views("ugr", &v), "");
  ASSERT_EQ(v.size(), 4u);  // γ 65° and 50° (25° and 40° above the plane), C0 and C90
  for (const LuminanceView& w : v) EXPECT_TRUE(w.gamma_deg == 65.0 || w.gamma_deg == 50.0);
  EXPECT_NE(parse_luminance_views("0:181", &v), "");
  EXPECT_NE(parse_luminance_views("360:10", &v), "");
  EXPECT_NE(parse_luminance_views("a:b", &v), "");
  EXPECT_NE(parse_luminance_views("", &v), "");
  EXPECT_NE(parse_luminance_views("5", &v), "");
}

TEST(LuminanceImage, AxesFollowTheFrameAndTurnContinuouslyThroughTheNadir) {
  photometry::PhotometricFrame f;  // up +Y, C0 +X, C90 −Z
  LuminanceImageSettings s;
  s.views = {{0.0, 60.0}, {0.0, 0.0}, {0.0, 0.001}, {90.0, 180.0}};
  const LuminanceCamera cam = make_luminance_camera(s, {-0.1, -0.1, -0.1}, {0.1, 0.1, 0.1}, f, false);
  ASSERT_EQ(cam.planes.size(), 4u);
  // γ 60° in C0: the light goes down and along +X to the observer.
  EXPECT_NEAR(cam.planes[0].toward.x, std::sin(60 * kDeg), 1e-12);
  EXPECT_NEAR(cam.planes[0].toward.y, -std::cos(60 * kDeg), 1e-12);
  EXPECT_GT(cam.planes[0].up.y, 0.0);  // the zenith shows up
  for (const ImagePlane& p : cam.planes) {
    EXPECT_NEAR(dot(cross(p.right, p.up), p.toward), 1.0, 1e-12);
    EXPECT_NEAR(dot(p.up, p.toward), 0.0, 1e-11);
  }
  // Straight below, `up` is the limit of the nearby views'.
  EXPECT_NEAR(dot(cam.planes[1].up, cam.planes[2].up), 1.0, 1e-6);
  // The bounding sphere fits: diameter √12·0.1 ≈ 0.35 m.
  EXPECT_GE(cam.planes[0].pixels * cam.planes[0].pixel_m, std::sqrt(0.12));
  EXPECT_EQ(cam.planes[0].pixels % 2, 1);
}

TEST(LuminanceImage, LambertianDiscIsUniformAtItsLuminanceFromAnyDirection) {
  // A black disc emitting Φ, Lambertian: L = Φ / (πA) everywhere on it,
  // from every direction in front; the image's integral is I(γ) = L·A·cos γ.
  const double a = 0.05, flux = 100.0;
  SceneDesc scene;
  Material black;
  black.name = "black";
  scene.materials = {black};
  Mesh d = disc(a, 128);
  flip(d);  // facing the nadir
  scene.meshes = {d};
  Emitter e;
  e.kind = Emitter::Kind::Area;
  e.flux_lm = flux;
  scene.emitters = {e};
  const double area = 0.5 * 128 * std::sin(2.0 * kPi / 128) * a * a;
  const double l = flux / (kPi * area);
  auto sim = simulate(scene, image_run({{0.0, 0.0}, {30.0, 60.0}, {0.0, 120.0}}, 400000));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const std::vector<LuminanceImage> images = sim->luminance_images();
  ASSERT_EQ(images.size(), 3u);
  for (int k = 0; k < 2; ++k) {
    const LuminanceImage& img = images[static_cast<std::size_t>(k)];
    const double gamma = img.plane.view.gamma_deg * kDeg;
    EXPECT_NEAR(img.intensity_cd / (l * area * std::cos(gamma)), 1.0, 0.01) << k;
    // Pixels wholly inside the disc (centre within a − 1.5 pixels on it).
    double sum = 0.0, sum2 = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < img.cd_m2.size(); ++i) {
      const Vec3 c = pixel_centre(img, i);
      // Back along the view onto the disc's plane y = 0.
      const Vec3 on = c - (c.y / img.plane.toward.y) * img.plane.toward;
      if (std::hypot(on.x, on.z) > a - 1.5 * img.plane.pixel_m / std::cos(gamma)) continue;
      sum += img.cd_m2[i];
      sum2 += img.cd_m2[i] * img.cd_m2[i];
      ++n;
    }
    ASSERT_GT(n, 100);
    const double mean = sum / n, sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
    EXPECT_NEAR(mean / l, 1.0, 0.01) << k;
    EXPECT_LT(sd / l, 0.2) << k;  // each pixel holds ~100 emission connections
  }
  // From above (γ 120°) the disc's back faces the observer: dark.
  EXPECT_EQ(images[2].intensity_cd, 0.0);
}

// Issue 45, case 10: a two-sided Lambertian sheet of luminance L on each
// face sends 2πLA in all, half of its photons to each side; its image from
// either side reads L, as a one-sided sheet of the same luminance does
// (πLA, every photon to the front). The emission connection of a two-sided
// emitter weighs |cos|/π by the half of the photons that leave on the
// observer's side: left whole, the sheet reads 2L.
TEST(LuminanceImage, TwoSidedSheetReadsItsLuminanceFromEitherSideAsAOneSidedOneDoes) {
  const double a = 0.05, l = 5000.0;  // [m], [cd/m²]
  const double area = 0.5 * 128 * std::sin(2.0 * kPi / 128) * a * a;
  for (const bool two_sided : {false, true}) {
    SCOPED_TRACE(two_sided ? "two-sided" : "one-sided");
    SceneDesc scene;
    Material black;
    black.name = "black";
    scene.materials = {black};
    Mesh d = disc(a, 128);
    flip(d);  // the front faces the nadir
    scene.meshes = {d};
    Emitter e;
    e.kind = Emitter::Kind::Area;
    e.two_sided = two_sided;
    e.flux_lm = (two_sided ? 2.0 : 1.0) * kPi * l * area;
    scene.emitters = {e};
    // Face-on from below (the front) and from above (the back).
    auto sim = simulate(scene, image_run({{0.0, 0.0}, {0.0, 180.0}}, 400000));
    ASSERT_TRUE(sim.ok()) << sim.error().message;
    const std::vector<LuminanceImage> images = sim->luminance_images();
    ASSERT_EQ(images.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      const LuminanceImage& img = images[k];
      if (k == 1 && !two_sided) {
        EXPECT_EQ(img.intensity_cd, 0.0);  // a one-sided sheet's back is dark
        continue;
      }
      // I = L·A face-on, on either lit side.
      EXPECT_NEAR(img.intensity_cd / (l * area), 1.0, 0.01) << k;
      double sum = 0.0;
      int n = 0;
      for (std::size_t i = 0; i < img.cd_m2.size(); ++i) {
        const Vec3 c = pixel_centre(img, i);
        if (std::hypot(c.x, c.z) > a - 1.5 * img.plane.pixel_m) continue;
        sum += img.cd_m2[i];
        ++n;
      }
      ASSERT_GT(n, 100);
      EXPECT_NEAR(sum / n / l, 1.0, 0.01) << k;
    }
  }
}

TEST(LuminanceImage, MirrorShowsThePointSourcesImageWhereItsReflectionLies) {
  // An isotropic point 5 cm above a mirror (ρ = 1, facing up), seen from
  // γ = 150° in C0 (from above): the light reaches the observer only via
  // the mirror, whose image of the point lies 5 cm below it. Its projection
  // along the view is where the image's light must be, and the image
  // carries I = Φ/(4π) (averaged over the 10° cone), by binned escapes
  // alone (a mirror makes no connections).
  SceneDesc scene;
  Material mirror;
  mirror.name = "mirror";
  mirror.mirror = 1.0;
  scene.materials = {mirror};
  scene.meshes = {disc(0.3, 64)};  // facing +Y
  Emitter e;
  e.position = {0.0, 0.05, 0.0};
  e.flux_lm = 1000.0;
  scene.emitters = {e};
  auto sim = simulate(scene, image_run({{0.0, 150.0}}, 2'000'000, 2, 10.0, 0.004));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const LuminanceImage img = sim->luminance_images().at(0);
  // The direct light also reaches the observer (the point is in front of
  // the mirror, seen from above): two spots, the point and its image, each
  // I = Φ/(4π). Their flux-weighted positions: the point's projection and
  // the image's.
  const Vec3 point{0.0, 0.05, 0.0}, image{0.0, -0.05, 0.0};
  const ImagePlane& p = img.plane;
  const auto project = [&](const Vec3& w) { return std::pair{dot(w - p.centre, p.right), dot(w - p.centre, p.up)}; };
  const auto [pu, pv] = project(point);
  const auto [iu, iv] = project(image);
  double near_point = 0.0, near_image = 0.0;
  for (std::size_t i = 0; i < img.cd_m2.size(); ++i) {
    const auto [u, v] = project(pixel_centre(img, i));
    const double flux = img.cd_m2[i] * p.pixel_m * p.pixel_m;
    // 2 cm: the image point lies ~6 cm behind the mirror, so an escape 10°
    // off the view lands up to 1 cm from its projection (the cone's depth
    // blur, as a camera aperture's); the two spots are 5 cm apart.
    if (std::hypot(u - pu, v - pv) < 0.02) near_point += flux;
    else if (std::hypot(u - iu, v - iv) < 0.02) near_image += flux;
  }
  const double want = 1000.0 / (4.0 * kPi);
  // ~2·10⁶ · Ω/(4π) = 1.5·10⁴ photons each: 1 % noise; 5 % allowed.
  EXPECT_NEAR(near_point / want, 1.0, 0.05);
  EXPECT_NEAR(near_image / want, 1.0, 0.05);
  EXPECT_NEAR(img.intensity_cd / (2.0 * want), 1.0, 0.05);
}

TEST(LuminanceImage, OpalDiscIsItsTransmittedIlluminanceOverPiAndItsFarFieldOverProjectedArea) {
  // A point of intensity I₀ = Φ/4π a height h above an opal disc (diffuse
  // transmission t, facing down): the disc's underside has
  // L(r) = t·E(r)/π = t·I₀·h / (π (h² + r²)^{3/2}); the image seen from γ
  // averages it, and its integral is the far field's intensity towards γ.
  const double h = 0.05, radius = 0.1, t = 0.5, flux = 1000.0;
  SceneDesc scene;
  Material opal{"opal", 0.0, t, 0.0};
  scene.materials = {opal};
  Mesh d = disc(radius, 96);
  flip(d);
  scene.meshes = {d};
  Emitter e;
  e.position = {0.0, h, 0.0};
  e.flux_lm = flux;
  scene.emitters = {e};
  SimulationSettings s = image_run({{0.0, 0.0}, {0.0, 40.0}}, 1'000'000, 2, 5.0, 0.004);
  s.face_size = 32;
  auto sim = simulate(scene, s);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const std::vector<LuminanceImage> images = sim->luminance_images();
  const double i0 = flux / (4.0 * kPi);
  // Straight below, ring by ring against the closed form averaged over the
  // same pixels (a ring of ~100 pixels: ~1 % noise).
  const LuminanceImage& below = images[0];
  for (double r0 : {0.0, 0.02, 0.04, 0.06}) {
    double got = 0.0, want = 0.0;
    for (std::size_t i = 0; i < below.cd_m2.size(); ++i) {
      const Vec3 c = pixel_centre(below, i);
      const double r = std::hypot(c.x, c.z);
      if (r < r0 || r >= r0 + 0.015) continue;
      got += below.cd_m2[i];
      want += t * i0 * h / (kPi * std::pow(h * h + r * r, 1.5));
    }
    EXPECT_NEAR(got / want, 1.0, 0.04) << "ring from " << r0 << " m";
  }
  // The disc catches Φ(1 − cos θ)/2, θ = atan(r/h) (r of the 96-gon's
  // area), and sends t of it out Lambertian: I(γ) = tΦ_disc cos γ / π, so
  // the mean luminance over the disc is I(γ) / (A cos γ) = tΦ_disc / (πA).
  const double r_eff = radius * std::sqrt(0.5 * 96 * std::sin(2.0 * kPi / 96) / kPi);
  const double caught = flux * 0.5 * (1.0 - h / std::hypot(h, r_eff));
  for (const LuminanceImage& img : images) {
    const double gamma = img.plane.view.gamma_deg * kDeg;
    EXPECT_NEAR(img.intensity_cd / (t * caught * std::cos(gamma) / kPi), 1.0, 0.015) << img.plane.view.gamma_deg;
  }
  // And against the run's own far field: texels within 12° of the view
  // (~5000 photons: 1.5 % noise; the cone's average of cos differs from
  // the centre's by under 1.2 %).
  const FarField far = sim->far_field();
  for (const LuminanceImage& img : images) {
    double flux_sum = 0.0, omega = 0.0;
    for (std::size_t i = 0; i < far.texel_count(); ++i)
      if (dot(far.grid().texel_direction(i), img.plane.toward) > std::cos(12.0 * kDeg)) {
        flux_sum += far.flux_lm(i);
        omega += far.grid().texel_solid_angle(i);
      }
    ASSERT_GT(omega, 0.0);
    EXPECT_NEAR(img.intensity_cd / (flux_sum / omega), 1.0, 0.07) << img.plane.view.gamma_deg;
  }
}

TEST(LuminanceImage, SameBytesWithOneOrTwoThreadsAndTheSameMeanWithNextEventOnTheFarField) {
  const SceneDesc scene = test_scenes::mixed_scene();
  auto one = simulate(scene, image_run(ugr_luminance_views(), 30000, 1));
  auto two = simulate(scene, image_run(ugr_luminance_views(), 30000, 2));
  SimulationSettings with_nee = image_run(ugr_luminance_views(), 30000, 2);
  with_nee.next_event = NextEventMode::On;
  auto nee = simulate(scene, with_nee);
  ASSERT_TRUE(one.ok() && two.ok() && nee.ok());
  const auto a = one->luminance_images(), b = two->luminance_images(), c = nee->luminance_images();
  ASSERT_EQ(a.size(), 4u);
  double total = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const std::size_t bytes = a[k].cd_m2.size() * sizeof(double);
    EXPECT_EQ(std::memcmp(a[k].cd_m2.data(), b[k].cd_m2.data(), bytes), 0);
    // The far field's connections neither add to nor take from the images
    // (they shift the photons' later numbers, so the bytes differ).
    EXPECT_NEAR(c[k].intensity_cd / a[k].intensity_cd, 1.0, 0.05) << k;
    total += a[k].intensity_cd;
  }
  EXPECT_GT(total, 0.0);
}

}  // namespace
}  // namespace gonio::sim
