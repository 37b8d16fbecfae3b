// Issue 42's tolerances on a volume's scattering coefficient and on the
// position and tilt of ray-set and area emitters (design/tolerance_spec.h):
// round trips against the model edited or placed there itself, and the
// slab's transmittance against an independent trace (sim::slab_optics).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "design/tolerance_spec.h"
#include "io/model/gltf.h"
#include "io/photometric/tm25.h"
#include "sim/bsdfs/slab.h"
#include "sim/shapes.h"
#include "sim/simulation.h"
#include "tests/support/test_support.h"

namespace gonio::design {
namespace {

ToleranceSpec parse_ok(const std::string& text) {
  Result<ToleranceSpec> s = parse_tolerances(text, "t.toml");
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : to_string(s.error()));
  return s.ok() ? s.value() : ToleranceSpec{};
}

sim::SimulationSettings run(std::uint64_t photons) {
  sim::SimulationSettings s;
  s.threads = 1;
  s.photons_per_iteration = photons;
  s.iterations = 1;
  s.face_size = 16;
  s.seed = 7;
  return s;
}

// A 2 mm slab of an index-matched (n = 1) volume diffuser, 0.4 m square,
// lit at normal incidence by a ray set: 400 rays straight down (−Y) from a
// 10 mm square 10 mm above it.
sim::SceneDesc lit_slab(double mu_s) {
  sim::SceneDesc scene;
  sim::Material clear;
  clear.name = "clear";
  clear.dielectric = 1.0;
  clear.ior = 1.0;
  sim::Material diffuser = clear;
  diffuser.name = "diffuser";
  diffuser.scattering_per_m = mu_s;
  diffuser.scattering_g = 0.6;
  diffuser.attenuation_per_m = 20.0;
  scene.materials = {clear, diffuser};
  sim::Mesh slab = sim::slab(0.4, 0.4, 0.002);
  slab.material = 1;
  scene.meshes = {slab};
  auto rays = std::make_shared<sim::RaySet>();
  for (int i = 0; i < 20; ++i)
    for (int k = 0; k < 20; ++k) {
      rays->position_m.push_back(sim::to_float(Vec3{(i - 9.5) * 5e-4, 0.01, (k - 9.5) * 5e-4}));
      rays->direction.push_back(sim::to_float(Vec3{0.0, -1.0, 0.0}));
      rays->flux_lm.push_back(1.0f);
    }
  sim::Emitter e;
  e.kind = sim::Emitter::Kind::RaySet;
  e.name = "beam";
  e.flux_lm = 100.0;
  e.position = {0.0, 0.01, 0.0};
  e.rays = std::move(rays);
  scene.emitters = {e};
  return scene;
}

// The fraction of the emitted flux that leaves downwards (−Y).
double transmitted(const sim::FarField& f, double emitted_lm) {
  double sum = 0.0;
  for (std::size_t t = 0; t < f.texel_count(); ++t)
    if (f.grid().texel_direction(t).y < 0.0) sum += f.flux_lm(t);
  return sum / emitted_lm;
}

TEST(ToleranceScattering, NamesAClearMaterialAndZeroChangesNothing) {
  const sim::SceneDesc scene = lit_slab(500.0);
  const Status clear = check_tolerances(parse_ok("[material.clear]\nscattering = { uniform = 5 }\n"), scene);
  ASSERT_FALSE(clear.ok());
  EXPECT_EQ(to_string(clear.error()).rfind("t.toml:2: clear.scattering: the material does not scatter in volume", 0),
            0u)
      << to_string(clear.error());
  const ToleranceSpec s = parse_ok("[material.diffuser]\nscattering = { normal = 10 }\n");
  ASSERT_TRUE(check_tolerances(s, scene).ok());
  EXPECT_STREQ(s.tolerances[0].unit(), "%");
  sim::SceneDesc zero = scene;
  apply_tolerances(s, std::vector<double>{0.0}, zero);
  auto a = sim::simulate(scene, run(20000));
  auto b = sim::simulate(zero, run(20000));
  ASSERT_TRUE(a.ok() && b.ok());
  const sim::FarField fa = a->far_field(), fb = b->far_field();
  EXPECT_EQ(std::memcmp(fa.flux_lm().data(), fb.flux_lm().data(), fa.texel_count() * sizeof(double)), 0);
}

// μs at +50 %: the far field is, byte for byte, that of the model with
// μs = 750 /m written in it (the absorption coefficient stays 20 /m), and
// the transmittance falls as an independent trace of the sheet
// (sim::slab_optics, the same medium as an infinite slab) says, for both.
TEST(ToleranceScattering, PlusFiftyPercentIsTheModelWithMuSEditedAndTheSlabsTransmittance) {
  const ToleranceSpec s = parse_ok("[material.diffuser]\nscattering = { uniform = 50 }\n");
  sim::SceneDesc tolerated = lit_slab(500.0);
  ASSERT_TRUE(check_tolerances(s, tolerated).ok());
  apply_tolerances(s, std::vector<double>{50.0}, tolerated);
  EXPECT_EQ(tolerated.materials[1].attenuation_per_m, 20.0);
  const std::uint64_t n = 200000;
  auto nominal = sim::simulate(lit_slab(500.0), run(n));
  auto moved = sim::simulate(tolerated, run(n));
  auto edited = sim::simulate(lit_slab(750.0), run(n));
  ASSERT_TRUE(nominal.ok() && moved.ok() && edited.ok());
  const sim::FarField f0 = nominal->far_field(), f1 = moved->far_field(), f2 = edited->far_field();
  ASSERT_EQ(f1.texel_count(), f2.texel_count());
  EXPECT_EQ(std::memcmp(f1.flux_lm().data(), f2.flux_lm().data(), f1.texel_count() * sizeof(double)), 0);
  const double t0 = transmitted(f0, 100.0), t1 = transmitted(f1, 100.0);
  sim::SlabMedium m;
  m.absorption_per_m = 20.0;
  m.g = 0.6;
  m.ior = 1.0;
  m.thickness_m = 0.002;
  m.scattering_per_m = 500.0;
  const double s0 = sim::slab_optics(m, 0.0, n, 3).transmittance;
  m.scattering_per_m = 750.0;
  const double s1 = sim::slab_optics(m, 0.0, n, 3).transmittance;
  std::printf("  slab transmittance: traced %.4f -> %.4f, slab_optics %.4f -> %.4f\n", t0, t1, s0, s1);
  const auto sigma = [n](double t) { return std::sqrt(t * (1.0 - t) / static_cast<double>(n)); };
  EXPECT_NEAR(t0, s0, 4.0 * std::hypot(sigma(t0), sigma(s0)));
  EXPECT_NEAR(t1, s1, 4.0 * std::hypot(sigma(t1), sigma(s1)));
  EXPECT_LT(t1, t0 - 0.02);  // more scattering, less transmitted (more back-scattered)
  EXPECT_NEAR(t1 - t0, s1 - s0, 4.0 * std::hypot(std::hypot(sigma(t0), sigma(t1)), std::hypot(sigma(s0), sigma(s1))));
}

// A ray file of rays in a 30° cone about the file's −Y from a 1 mm disc in
// its XZ plane (a Fibonacci lattice and its mirror images in x and z:
// symmetric, the mean direction −Y).
io::Tm25RaySet cone_rays() {
  const int n = 1000;
  const double golden = (std::sqrt(5.0) - 1.0) / 2.0, s30 = 0.5;
  std::vector<float> rays;
  for (int i = 0; i < n; ++i) {
    const double u1 = (i + 0.5) / n, u2 = std::fmod(i * golden, 1.0);
    const double r = s30 * std::sqrt(u1), phi = 2.0 * std::numbers::pi * u2;
    const double pr = std::sqrt(u2), pphi = 2.0 * std::numbers::pi * u1;
    for (double sx : {-1.0, 1.0})
      for (double sz : {-1.0, 1.0})
        for (double v : {sx * pr * std::cos(pphi), 0.0, sz * pr * std::sin(pphi), sx * r * std::cos(phi),
                         -std::sqrt(1.0 - r * r), sz * r * std::sin(phi), 1.0})
          rays.push_back(static_cast<float>(v));
  }
  return io::make_luminous_ray_set(std::move(rays));
}

// A glTF of one node carrying the ray file, at `t` [m], turned by `q` (x, y, z, w).
sim::SceneDesc placed(const test::TempDir& dir, const std::string& stem, Vec3 t, std::array<double, 4> q) {
  const std::string path = (dir / (stem + ".gltf")).string();
  const auto format_number = [](double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return std::string(b);
  };
  std::ofstream(path) << "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{"
                         "\"name\":\"led\",\"translation\":["
                      << format_number(t.x) << "," << format_number(t.y) << "," << format_number(t.z)
                      << "],\"rotation\":[" << format_number(q[0]) << "," << format_number(q[1]) << ","
                      << format_number(q[2]) << "," << format_number(q[3])
                      << "],\"extras\":{\"gonio\":{\"ray_file\":\"cone.tm25ray\",\"flux_lm\":1000}}}]}";
  Result<sim::SceneDesc> s = io::load_gltf(path, nullptr);
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : to_string(s.error()));
  return s.ok() ? std::move(s.value()) : sim::SceneDesc{};
}

Vec3 mean_direction(const sim::RaySet& r) {
  Vec3 m{};
  for (std::size_t i = 0; i < r.size(); ++i) m = m + static_cast<double>(r.flux_lm[i]) * sim::to_double(r.direction[i]);
  return normalize(m);
}

// The LED 0.1 mm off along C0 and C90 and tilted by 3° about C0: the
// tolerances on the ray file's emitter give the rays (and the far field) of
// the glTF with the node placed and turned there itself; the tilt turns
// the symmetric beam's axis by 3° about C0, through the ray file's origin.
TEST(ToleranceRaySet, MovedAndTurnedLikeTheNodePlacedThere) {
  test::TempDir dir;
  ASSERT_TRUE(io::write_tm25_file((dir / "cone.tm25ray").string(), cone_rays()).ok());
  const double a = 3.0 * std::numbers::pi / 180.0;
  sim::SceneDesc tolerated = placed(dir, "nominal", {0.0, 0.05, 0.0}, {0.0, 0.0, 0.0, 1.0});
  // The glTF frame: C0 +X, C90 −Z, up +Y.
  const sim::SceneDesc there =
      placed(dir, "there", {1e-4, 0.05, -1e-4}, {std::sin(a / 2), 0.0, 0.0, std::cos(a / 2)});
  ASSERT_EQ(tolerated.emitters.size(), 1u);
  ASSERT_EQ(there.emitters.size(), 1u);
  const ToleranceSpec s = parse_ok(
      "[emitter.\"" + tolerated.emitters[0].name + "\"]\nx = { uniform = 0.1 }\ny = { uniform = 0.1 }\n"
      "tilt_x = { uniform = 3 }\n");
  ASSERT_TRUE(check_tolerances(s, tolerated).ok());
  const std::shared_ptr<const sim::RaySet> before = tolerated.emitters[0].rays;
  std::vector<double> values;
  for (const Tolerance& t : s.tolerances) values.push_back(t.quantity == "tilt_x" ? 3.0 : 0.1);
  apply_tolerances(s, values, tolerated);
  const sim::Emitter &e = tolerated.emitters[0], &w = there.emitters[0];
  EXPECT_NEAR(length(e.position - w.position), 0.0, 1e-12);
  ASSERT_EQ(e.rays->size(), w.rays->size());
  double dp = 0.0, dd = 0.0;
  for (std::size_t i = 0; i < e.rays->size(); ++i) {
    dp = std::max(dp, length(sim::to_double(e.rays->position_m[i]) - sim::to_double(w.rays->position_m[i])));
    dd = std::max(dd, length(sim::to_double(e.rays->direction[i]) - sim::to_double(w.rays->direction[i])));
  }
  EXPECT_LT(dp, 1e-8);  // float rounding of metres near 0.05 m
  EXPECT_LT(dd, 1e-6);
  // The beam's axis: from −Y to (0, −cos 3°, −sin 3°), a right-handed turn about +X (C0).
  const Vec3 m0 = mean_direction(*before), m1 = mean_direction(*e.rays);
  EXPECT_NEAR(m0.y, -1.0, 1e-6);
  EXPECT_NEAR(m1.x, 0.0, 1e-6);
  EXPECT_NEAR(m1.y, -std::cos(a), 1e-6);
  EXPECT_NEAR(m1.z, -std::sin(a), 1e-6);
  // Traced with the same photons: the same far field, photon for photon
  // but for a direction that float rounding puts across a texel edge.
  auto ft = sim::simulate(tolerated, run(100000));
  auto fw = sim::simulate(there, run(100000));
  ASSERT_TRUE(ft.ok() && fw.ok());
  const sim::FarField x = ft->far_field(), y = fw->far_field();
  double diff = 0.0;
  for (std::size_t t = 0; t < x.texel_count(); ++t) diff += std::abs(x.flux_lm(t) - y.flux_lm(t));
  EXPECT_LT(diff, 1e-3 * x.total_flux_lm());
  // A zero move leaves the rays as they were (the same object).
  sim::SceneDesc zero = placed(dir, "nominal", {0.0, 0.05, 0.0}, {0.0, 0.0, 0.0, 1.0});
  const sim::RaySet* own = zero.emitters[0].rays.get();
  apply_tolerances(s, std::vector<double>(s.tolerances.size(), 0.0), zero);
  EXPECT_EQ(zero.emitters[0].rays.get(), own);
}

// An area emitter (a 10 mm disc) tilted by 90° about C90 through its
// bounding-box centre and moved 1 mm up: its vertices are where the turn
// and the move put them.
TEST(ToleranceAreaEmitter, TurnsAboutItsCentreAndMoves) {
  sim::SceneDesc scene;
  sim::Material m;
  m.name = "black";
  scene.materials = {m};
  sim::Mesh panel = sim::disc(0.01, 8);
  panel.name = "panel";
  sim::transform(panel, sim::translation({0.1, 0.05, 0.0}));
  scene.meshes = {panel};
  sim::Emitter e;
  e.kind = sim::Emitter::Kind::Area;
  e.name = "panel";
  e.flux_lm = 10.0;
  e.mesh = 0;
  scene.emitters = {e};
  const ToleranceSpec s = parse_ok("[emitter.panel]\nz = { uniform = 1 }\ntilt_y = { uniform = 90 }\n");
  ASSERT_TRUE(check_tolerances(s, scene).ok());
  std::vector<double> values;
  for (const Tolerance& t : s.tolerances) values.push_back(t.quantity == "z" ? 1.0 : 90.0);
  const sim::Mesh before = scene.meshes[0];
  apply_tolerances(s, values, scene);
  // A right-handed turn by 90° about C90 (−Z) takes (px, py, pz) about the
  // centre (0.1, 0.05, 0) to (py, −px, pz); then +1 mm along up (+Y).
  for (std::size_t i = 0; i < before.positions.size(); ++i) {
    const Vec3 p = sim::to_double(before.positions[i]) - Vec3{0.1, 0.05, 0.0};
    const Vec3 want = Vec3{0.1 + p.y, 0.05 + 1e-3 - p.x, p.z};
    EXPECT_NEAR(length(sim::to_double(scene.meshes[0].positions[i]) - want), 0.0, 1e-7) << i;
  }
}

}  // namespace
}  // namespace gonio::design
