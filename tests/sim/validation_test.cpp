// Physics validation of the photon tracer against closed forms
// (shared/design/VALIDATION.md, simulation table). Slow: ctest label
// `validation`; each case takes a few seconds on two cores.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <vector>

#include "photometry/frame.h"
#include "sim/bsdfs/material.h"
#include "sim/samplers/sampling.h"
#include "sim/shapes.h"
#include "sim/simulation.h"
#include "sim/tracer/tracer.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

Material named(const char* name) {
  Material m;
  m.name = name;
  return m;
}

Simulation run(const SceneDesc& scene, std::uint64_t photons, int iterations, int face_size,
               std::uint64_t seed = 1) {
  SimulationSettings s;
  s.photons_per_iteration = photons;
  s.iterations = iterations;
  s.face_size = face_size;
  s.seed = seed;
  s.threads = 2;
  auto sim = simulate(scene, s);
  EXPECT_TRUE(sim.ok()) << (sim.ok() ? "" : sim.error().message);
  return std::move(sim.value());
}

// ∫ f dΩ over one texel, by k × k sub-rectangles in face coordinates, each
// weighted by its exact solid angle and evaluated at its centre direction.
double texel_integral(const CubeMapGrid& grid, std::size_t texel,
                      const std::function<double(const Vec3&)>& f, int k = 6) {
  const int n = grid.face_size();
  const std::size_t per_face = static_cast<std::size_t>(n) * n;
  const int face = static_cast<int>(texel / per_face);
  const int y = static_cast<int>(texel % per_face) / n, x = static_cast<int>(texel % per_face) % n;
  const double step = 2.0 / n / k;
  double sum = 0.0;
  for (int j = 0; j < k; ++j) {
    for (int i = 0; i < k; ++i) {
      const double a0 = -1.0 + 2.0 * x / n + i * step, b0 = -1.0 + 2.0 * y / n + j * step;
      const double w = CubeMapGrid::solid_angle(a0, b0, a0 + step, b0 + step);
      sum += w * f(normalize(CubeMapGrid::direction(face, a0 + 0.5 * step, b0 + 0.5 * step)));
    }
  }
  return sum;
}

// Pearson's χ² of the far field's photon counts against expected intensity
// [cd] per texel (texels with fewer than `min_count` expected photons are
// pooled into one bin). Returns χ²/dof.
double reduced_chi_square(const FarField& f, const std::vector<double>& expected_cd,
                          double photon_power_lm, double min_count = 20.0, int* dof_out = nullptr) {
  double chi2 = 0.0, pooled_obs = 0.0, pooled_exp = 0.0;
  int dof = 0;
  for (std::size_t t = 0; t < f.texel_count(); ++t) {
    const double e = expected_cd[t] * f.grid().texel_solid_angle(t) / photon_power_lm;
    const double o = static_cast<double>(f.photons(t));
    if (e < min_count) {
      pooled_obs += o;
      pooled_exp += e;
      continue;
    }
    chi2 += (o - e) * (o - e) / e;
    ++dof;
  }
  if (pooled_exp >= min_count) {
    chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++dof;
  }
  if (dof_out) *dof_out = dof;
  return chi2 / dof;
}

// The χ²/dof of a correct model lies within a few σ = √(2/dof) of 1.
void expect_chi_square_ok(double reduced, int dof) {
  EXPECT_LT(reduced, 1.0 + 5.0 * std::sqrt(2.0 / dof)) << "dof " << dof;
  EXPECT_GT(reduced, 1.0 - 5.0 * std::sqrt(2.0 / dof)) << "dof " << dof;
}

photometry::Distribution asymmetric_profile() {
  photometry::Distribution d;
  d.type = photometry::PhotometricType::C;
  d.symmetry = photometry::Symmetry::None;
  d.absolute = true;
  d.horizontal_deg = {0, 10, 20, 25, 30, 35, 40, 60, 90, 135, 180, 200, 225, 270, 315, 360};
  d.vertical_deg = {0, 5, 15, 30, 45, 55, 60, 65, 75, 90, 120, 150, 165, 180};
  const Vec3 p1 = photometry::direction_from_c_gamma(30 * kDeg, 60 * kDeg);
  const Vec3 p2 = photometry::direction_from_c_gamma(200 * kDeg, 150 * kDeg);
  for (double c : d.horizontal_deg) {
    for (double g : d.vertical_deg) {
      const Vec3 v = photometry::direction_from_c_gamma(c * kDeg, g * kDeg);
      d.candela.push_back(20.0 + 1000.0 * std::pow(std::max(0.0, dot(v, p1)), 8) +
                          300.0 * std::pow(std::max(0.0, dot(v, p2)), 4));
    }
  }
  return d;
}

TEST(Validation, BareEmitterReproducesItsProfileAndFlux) {
  const photometry::Distribution profile = asymmetric_profile();
  const photometry::Distribution expanded = photometry::expand_symmetry(profile);
  SceneDesc scene;
  Emitter e;
  e.name = "measured";
  e.flux_lm = 1000.0;
  e.profile = std::make_shared<photometry::Distribution>(profile);
  // A tilted frame, so that the test also pins the profile's orientation.
  e.frame = photometry::make_frame({0.2, 1.0, 0.1}, {1.0, 0.0, 0.3});
  scene.emitters = {e};
  auto sampler = ProfileSampler::create(profile);
  ASSERT_TRUE(sampler.ok());
  const double scale = e.flux_lm / sampler->flux_lm();  // cd per profile cd

  const int face = 32;
  const CubeMapGrid grid(face);
  std::vector<double> expected(grid.texel_count());
  double mean = 0.0;
  for (std::size_t t = 0; t < grid.texel_count(); ++t) {
    expected[t] = scale *
                  texel_integral(grid, t, [&](const Vec3& d) {
                    const photometry::CGamma a = photometry::c_gamma_from_direction(e.frame.to_local(d));
                    return photometry::interpolate(expanded, a.c_rad / kDeg, a.gamma_rad / kDeg);
                  }) /
                  grid.texel_solid_angle(t);
    mean += expected[t] / static_cast<double>(grid.texel_count());
  }
  auto rms = [&](const FarField& f) {
    double sum = 0.0;
    for (std::size_t t = 0; t < f.texel_count(); ++t)
      sum += (f.intensity_cd(t) - expected[t]) * (f.intensity_cd(t) - expected[t]);
    return std::sqrt(sum / static_cast<double>(f.texel_count())) / mean;
  };

  Simulation sim = run(scene, 250000, 1, face, 3);
  const double rms1 = rms(sim.far_field());
  for (int k = 1; k < 16; ++k) sim.run_iteration();  // 16× the photons
  const FarField f = sim.far_field();
  const double rms16 = rms(f);
  std::printf("  profile: relative RMS error %.4f at 250k photons, %.4f at 4M\n", rms1, rms16);
  // Photon noise only: RMS error falls as 1/√N, here by 4.
  EXPECT_NEAR(rms1 / rms16, 4.0, 0.4) << rms1 << " " << rms16;
  int dof = 0;
  const double chi = reduced_chi_square(f, expected, sim.ledger().photon_power_lm, 20.0, &dof);
  std::printf("  chi^2/dof = %.3f (dof %d)\n", chi, dof);
  expect_chi_square_ok(chi, dof);
  // All of the flux, and the peak where the profile put it.
  EXPECT_NEAR(f.total_flux_lm(), 1000.0, 1e-9);
  std::size_t peak = 0;
  for (std::size_t t = 0; t < f.texel_count(); ++t)
    if (f.intensity_cd(t) > f.intensity_cd(peak)) peak = t;
  const Vec3 want = e.frame.to_world(photometry::direction_from_c_gamma(30 * kDeg, 60 * kDeg));
  EXPECT_GT(dot(grid.texel_direction(peak), want), std::cos(6 * kDeg));
}

TEST(Validation, LambertianDiscIsCosine) {
  // I(γ) = I0 cos γ about the disc's normal (−Y), I0 = Φ/π.
  SceneDesc scene;
  scene.materials = {named("black")};
  Mesh d = disc(0.05, 64);
  flip(d);
  scene.meshes = {d};
  Emitter e;
  e.kind = Emitter::Kind::Area;
  e.flux_lm = 1000.0;
  scene.emitters = {e};
  const int face = 32;
  Simulation sim = run(scene, 1000000, 2, face);
  const FarField f = sim.far_field();
  std::vector<double> expected(f.texel_count());
  for (std::size_t t = 0; t < f.texel_count(); ++t)
    expected[t] = 1000.0 / kPi *
                  texel_integral(f.grid(), t, [](const Vec3& v) { return std::max(0.0, -v.y); }) /
                  f.grid().texel_solid_angle(t);
  int dof = 0;
  const double chi = reduced_chi_square(f, expected, sim.ledger().photon_power_lm, 20.0, &dof);
  std::printf("  chi^2/dof = %.3f (dof %d)\n", chi, dof);
  expect_chi_square_ok(chi, dof);
  // Nothing above the horizon, and I0 at the nadir: the four texels round
  // −Y (within 2.5° of it) against I0 times their mean cos γ, within 5σ of
  // photon noise.
  for (std::size_t t = 0; t < f.texel_count(); ++t)
    if (expected[t] == 0.0) {
      ASSERT_EQ(f.photons(t), 0u);
    }
  double flux = 0.0, omega = 0.0, want = 0.0;
  for (int y = face / 2 - 1; y <= face / 2; ++y)
    for (int x = face / 2 - 1; x <= face / 2; ++x) {
      const std::size_t t = f.grid().index(3, x, y);
      flux += f.flux_lm(t);
      omega += f.grid().texel_solid_angle(t);
      want += expected[t] * f.grid().texel_solid_angle(t);
    }
  want /= omega;
  const double count = want * omega / sim.ledger().photon_power_lm;
  std::printf("  disc: nadir %.2f cd, expected %.2f cd (I0 = %.2f cd), %.0f photons\n", flux / omega, want,
              1000.0 / kPi, count);
  EXPECT_NEAR(flux / omega, want, 5.0 * want / std::sqrt(count));
  EXPECT_NEAR(want, 1000.0 / kPi, 2e-3 * 1000.0 / kPi);  // mean cos γ within 2.5°
  EXPECT_EQ(sim.ledger().escaped.photons, 2000000u);
}

TEST(Validation, UniformLuminanceSphereIsIsotropic) {
  // I = L·(projected area) = Lπr² in every direction; Φ = πL·4πr².
  const double r = 0.05;
  SceneDesc scene;
  scene.materials = {named("black")};
  const Mesh s = sphere(r, 128, 64);
  scene.meshes = {s};
  Emitter e;
  e.kind = Emitter::Kind::Area;
  e.flux_lm = 1000.0;
  scene.emitters = {e};
  const double luminance = e.flux_lm / (kPi * surface_area_m2(s));  // [cd/m²]
  // Projected area of the faceted sphere along d: Σ max(0, n·d)·A.
  auto projected = [&](const Vec3& d) {
    double a = 0.0;
    for (std::size_t t = 0; t < s.triangle_count(); ++t)
      a += std::max(0.0, dot(triangle_normal(s, t), d)) * triangle_area_m2(s, t);
    return a;
  };
  EXPECT_NEAR(projected({0, -1, 0}), kPi * r * r, 2e-3 * kPi * r * r);
  const int face = 16;
  Simulation sim = run(scene, 1000000, 2, face);
  const FarField f = sim.far_field();
  std::vector<double> expected(f.texel_count());
  for (std::size_t t = 0; t < f.texel_count(); ++t)
    expected[t] = luminance * projected(f.grid().texel_direction(t));
  int dof = 0;
  const double chi = reduced_chi_square(f, expected, sim.ledger().photon_power_lm, 20.0, &dof);
  std::printf("  chi^2/dof = %.3f (dof %d)\n", chi, dof);
  expect_chi_square_ok(chi, dof);
  // Per face, the mean intensity is L times the faceted sphere's projected
  // area (within 5σ of photon noise), and that is Lπr² within 0.2 %.
  const double target = luminance * kPi * r * r;
  for (int fc = 0; fc < kCubeFaces; ++fc) {
    double flux = 0.0, omega = 0.0, want = 0.0;
    for (int y = 0; y < face; ++y)
      for (int x = 0; x < face; ++x) {
        const std::size_t t = f.grid().index(fc, x, y);
        flux += f.flux_lm(t);
        omega += f.grid().texel_solid_angle(t);
        want += expected[t] * f.grid().texel_solid_angle(t);
      }
    const double count = want / sim.ledger().photon_power_lm;
    want /= omega;
    std::printf("  sphere face %d: %.3f cd, expected %.3f cd, L*pi*r^2 = %.3f cd\n", fc, flux / omega, want,
                target);
    EXPECT_NEAR(flux / omega, want, 5.0 * want / std::sqrt(count)) << "face " << fc;
    EXPECT_NEAR(want, target, 2e-3 * target) << "face " << fc;
  }
}

TEST(Validation, SourceAtTheFocusOfAParaboloid) {
  // A sphere of uniform luminance L (radius rs) at the focus of an ideal
  // paraboloid mirror of reflectance ρ opening downwards. Seen from far
  // below on the axis, every mirror point between the hole and the aperture
  // reflects a ray that came from the focus, so the mirror looks filled with
  // luminance ρL, and the source is seen directly:
  //   I(nadir) = L·A_src + ρ·L·(A_aperture − A_hole)
  // with the projected areas of the faceted parts (regular polygons for the
  // mirror's rims). The hole (radius > rs) holds the source's own shadow.
  // This holds within the angle the source subtends from the aperture rim,
  // atan(rs / 0.1 m) = 5.7° here; the measured texels are within 2.5°.
  const double f = 0.05, aperture = 0.1, hole = 0.02, rs = 0.01, rho = 0.9;
  const int segments = 256;
  SceneDesc scene;
  Material mirror = named("mirror");
  mirror.mirror = rho;
  scene.materials = {named("black"), mirror};
  Mesh src = sphere(rs, 64, 32);
  src.material = 0;
  Mesh refl = paraboloid(f, aperture, hole, 128, segments);
  refl.material = 1;
  scene.meshes = {src, refl};
  Emitter e;
  e.kind = Emitter::Kind::Area;
  e.mesh = 0;
  e.flux_lm = 1000.0;
  scene.emitters = {e};
  const double luminance = e.flux_lm / (kPi * surface_area_m2(src));
  double src_projected = 0.0;
  for (std::size_t t = 0; t < src.triangle_count(); ++t)
    src_projected += std::max(0.0, -triangle_normal(src, t).y) * triangle_area_m2(src, t);
  auto polygon = [&](double radius) { return 0.5 * segments * radius * radius * std::sin(2 * kPi / segments); };
  const double bare = luminance * src_projected;
  const double expected = bare + rho * luminance * (polygon(aperture) - polygon(hole));

  const int face = 64;
  Simulation sim = run(scene, 1000000, 2, face);
  const FarField ff = sim.far_field();
  double flux = 0.0, omega = 0.0;
  for (int y = face / 2 - 1; y <= face / 2; ++y)
    for (int x = face / 2 - 1; x <= face / 2; ++x) {
      flux += ff.flux_lm(ff.grid().index(3, x, y));
      omega += ff.grid().texel_solid_angle(ff.grid().index(3, x, y));
    }
  const double measured = flux / omega;
  std::printf("  paraboloid: on-axis %.1f cd, expected %.1f cd (bare %.2f cd), %.0f photons\n", measured,
              expected, bare, flux / sim.ledger().photon_power_lm);
  EXPECT_NEAR(measured, expected, 0.02 * expected) << "bare " << bare;
  // The reflector multiplies the on-axis intensity.
  EXPECT_GT(measured, 20.0 * bare);
  EXPECT_TRUE(sim.ledger().photons_close());
}

TEST(Validation, GlossyPlaneUnderACollimatedBeam) {
  // A beam (all of it within 0.4° of its axis) onto a large brushed plane:
  // anisotropic lobe (mx along the mesh's tangent +X), f0 < 1, at 70° from
  // the normal, where Walter's weights would exceed 1 for half the samples.
  // The books close with no light created, the reflected fraction is
  // ks · albedo (the lobe's ∫ f cos θo dωo by quadrature), and the far field
  // is ks · f · cos θo per texel.
  Material brushed = named("brushed");
  brushed.glossy = 0.85;
  brushed.glossy_mx = 0.3;
  brushed.glossy_my = 0.1;
  brushed.glossy_f0 = 0.6;
  // The single-scattering lobe this test pins down; the compensated one
  // (the default) is checked in tests/sim/bsdfs/ (lobes, integrating sphere).
  brushed.glossy_compensation = false;
  SceneDesc scene;
  scene.materials = {brushed};
  Mesh plane = disc(5.0, 64);  // y = 0, facing +Y
  plane.normals.assign(plane.positions.size(), Vec3f{0.0f, 1.0f, 0.0f});
  plane.tangents.assign(plane.positions.size(), Vec3f{1.0f, 0.0f, 0.0f});
  scene.meshes = {plane};
  // The lobe's frame in the world: x = tangent (+X), y = n × x (−Z), z = n.
  auto to_local = [](const Vec3& w) { return Vec3{w.x, -w.z, w.y}; };
  auto to_world = [](const Vec3& l) { return Vec3{l.x, l.z, -l.y}; };
  const Vec3 wi_local = normalize(Vec3{std::sin(70 * kDeg) * std::cos(30 * kDeg),
                                       std::sin(70 * kDeg) * std::sin(30 * kDeg), std::cos(70 * kDeg)});
  const Vec3 towards_source = to_world(wi_local);

  photometry::Distribution beam;
  beam.type = photometry::PhotometricType::C;
  beam.symmetry = photometry::Symmetry::Rotational;
  beam.absolute = true;
  beam.horizontal_deg = {0.0};
  beam.vertical_deg = {0.0, 0.2, 0.4, 90.0, 180.0};
  beam.candela = {1e6, 1e6, 0.0, 0.0, 0.0};
  Emitter e;
  e.name = "beam";
  e.flux_lm = 1000.0;
  e.position = 0.3 * towards_source;
  e.frame = photometry::make_frame(towards_source, cross(towards_source, Vec3{0, 0, 1}));  // nadir onto the plane
  e.profile = std::make_shared<photometry::Distribution>(beam);
  scene.emitters = {e};

  const int face = 32;
  Simulation sim = run(scene, 500000, 2, face, 5);
  const Ledger l = sim.ledger();
  EXPECT_TRUE(l.photons_close());
  // Every photon keeps its nominal power through the lobe (survival, not gain).
  EXPECT_NEAR(l.escaped.flux_lm, static_cast<double>(l.escaped.photons) * l.photon_power_lm,
              1e-9 * l.emitted.flux_lm);
  EXPECT_EQ(l.cutoff.photons, 0u);
  EXPECT_EQ(l.escaped.photons + l.absorbed.photons, l.emitted.photons);
  EXPECT_NEAR(l.escaped.flux_lm + l.absorbed.flux_lm, l.emitted.flux_lm, 1e-9 * l.emitted.flux_lm);
  EXPECT_NEAR(l.flux_imbalance_lm(), 0.0, 1e-9);
  EXPECT_EQ(l.meshes[0].hits, l.emitted.photons);  // every photon reached the plane once

  double albedo = 0.0;
  {
    const int nz = 2000, np = 2000;
    for (int i = 0; i < nz; ++i) {
      const double z = (i + 0.5) / nz, r = std::sqrt(1.0 - z * z);
      for (int j = 0; j < np; ++j) {
        const double p = (j + 0.5) * 2.0 * kPi / np;
        const Vec3 o{r * std::cos(p), r * std::sin(p), z};
        albedo += glossy_brdf(brushed, wi_local, o) * z;
      }
    }
    albedo *= (1.0 / nz) * (2.0 * kPi / np);
  }
  const double n = static_cast<double>(l.emitted.photons);
  const double reflected = l.escaped.photons / n, expected_reflected = brushed.glossy * albedo;
  std::printf("  glossy plane at 70 deg: reflected %.5f, ks * albedo %.5f (albedo %.5f)\n", reflected,
              expected_reflected, albedo);
  EXPECT_NEAR(reflected, expected_reflected, 5.0 * std::sqrt(expected_reflected * (1.0 - expected_reflected) / n));

  const FarField f = sim.far_field();
  std::vector<double> expected(f.texel_count());
  for (std::size_t t = 0; t < f.texel_count(); ++t)
    expected[t] = e.flux_lm * brushed.glossy *
                  texel_integral(f.grid(), t, [&](const Vec3& d) {
                    const Vec3 o = to_local(d);
                    return glossy_brdf(brushed, wi_local, o) * std::max(0.0, o.z);
                  }) /
                  f.grid().texel_solid_angle(t);
  int dof = 0;
  const double chi = reduced_chi_square(f, expected, l.photon_power_lm, 20.0, &dof);
  std::printf("  glossy plane: chi^2/dof = %.3f (dof %d)\n", chi, dof);
  EXPECT_GT(dof, 100);
  expect_chi_square_ok(chi, dof);
}

// Transmittance of a non-absorbing slab n = 1.52 for a beam at θ:
// the mean over s and p of (1 − R)/(1 + R), with multiple reflections.
TEST(Validation, DielectricSlabTransmittance) {
  SceneDesc scene;
  Material glass = named("glass");
  glass.dielectric = 1.0;
  glass.ior = 1.52;
  scene.materials = {glass};
  scene.meshes = {slab(4.0, 4.0, 0.01)};  // top face at y = 0.005
  Emitter unused;
  unused.flux_lm = 1.0;
  unused.position = {0, 1, 0};
  scene.emitters = {unused};
  TracerSettings settings;
  settings.max_bounces = 200;
  auto tracer = Tracer::create(scene, 8, settings);
  ASSERT_TRUE(tracer.ok());
  const int n = 200000;
  auto transmitted = [&](const std::function<Vec3(PhotonRandom&)>& direction, std::uint64_t seed) {
    int through = 0;
    for (int k = 0; k < n; ++k) {
      PhotonRandom rng(seed, static_cast<std::uint64_t>(k));
      const Vec3 d = direction(rng);
      // Start 1 mm above the top face, aimed at its centre.
      const Vec3 o = Vec3{0, 0.005, 0} - d * (0.001 / -d.y);
      const TraceResult r = tracer->trace(o, d, rng);
      EXPECT_EQ(r.fate, Fate::Escaped);
      through += r.direction.y < 0.0;
    }
    return through / static_cast<double>(n);
  };
  const double angles[] = {0, 30, 45, 60, 75};
  const double expected[] = {0.9183, 0.9160, 0.9025, 0.8435, 0.6148};
  for (int i = 0; i < 5; ++i) {
    const double t = angles[i] * kDeg;
    const Vec3 d{std::sin(t), -std::cos(t), 0.0};
    const double T = transmitted([&](PhotonRandom&) { return d; }, 10 + i);
    std::printf("  slab T(%2.0f deg) = %.4f, expected %.4f\n", angles[i], T, expected[i]);
    EXPECT_NEAR(T, expected[i], 0.005) << angles[i] << "°";
  }
  const Basis down = basis_from_normal({0, -1, 0});
  const double diffuse =
      transmitted([&](PhotonRandom& rng) { return down.to_world(sample_cosine_hemisphere(rng)); }, 20);
  std::printf("  slab T(diffuse) = %.4f, expected 0.8464\n", diffuse);
  EXPECT_NEAR(diffuse, 0.8464, 0.005) << "diffuse";
}

TEST(Validation, SingleInterfaceAndAbsorbingSlab) {
  const double n_glass = 1.52;
  const double R = std::pow((n_glass - 1) / (n_glass + 1), 2);
  EXPECT_NEAR(R, 0.0426, 5e-5);
  auto fraction_through = [&](double thickness, double attenuation, bool* any_cut) {
    SceneDesc scene;
    Material glass = named("glass");
    glass.dielectric = 1.0;
    glass.ior = n_glass;
    glass.attenuation_per_m = attenuation;
    scene.materials = {glass};
    scene.meshes = {slab(1.0, 1.0, thickness)};
    Emitter unused;
    unused.flux_lm = 1.0;
    scene.emitters = {unused};
    auto tracer = Tracer::create(scene, 8);
    EXPECT_TRUE(tracer.ok());
    const int n = 400000;
    int up = 0, down = 0;
    for (int k = 0; k < n; ++k) {
      PhotonRandom rng(5, static_cast<std::uint64_t>(k));
      const TraceResult r = tracer->trace({0.0, thickness, 0.0}, {0, -1, 0}, rng);
      if (r.fate == Fate::CutOff) *any_cut = true;
      if (r.fate != Fate::Escaped) continue;
      (r.direction.y > 0 ? up : down) += 1;
    }
    return std::pair{up / static_cast<double>(n), down / static_cast<double>(n)};
  };
  bool cut = false;
  // One interface: a thick block that swallows whatever enters it.
  const auto [reflected, through] = fraction_through(0.5, 1000.0, &cut);
  const double sigma = std::sqrt(R * (1 - R) / 400000);
  EXPECT_NEAR(reflected, R, 5 * sigma);
  EXPECT_EQ(through, 0.0);
  // Internal transmittance τ = 1/2: T = (1 − R)²τ / (1 − R²τ²).
  const double thickness = 0.01, tau = 0.5;
  const auto [r2, t2] = fraction_through(thickness, std::log(2.0) / thickness, &cut);
  const double T = (1 - R) * (1 - R) * tau / (1 - R * R * tau * tau);
  const double Rs = R + (1 - R) * (1 - R) * R * tau * tau / (1 - R * R * tau * tau);
  std::printf("  interface R = %.5f (%.5f); absorbing slab T = %.5f (%.5f), R = %.5f (%.5f)\n",
              reflected, R, t2, T, r2, Rs);
  EXPECT_NEAR(t2, T, 5 * std::sqrt(T * (1 - T) / 400000));
  EXPECT_NEAR(r2, Rs, 5 * std::sqrt(Rs * (1 - Rs) / 400000));
  EXPECT_FALSE(cut);
}

TEST(Validation, IntegratingSphere) {
  // Isotropic source at the centre of a diffuse sphere (reflectance ρ) with
  // a port of area fraction f: escaped fraction f/(1 − ρ(1 − f)), mean wall
  // hits per photon (1 − f)/(1 − ρ(1 − f)).
  const double radius = 0.1, rho = 0.8;
  const int segments = 128, rings = 64;
  // A closed sphere's profile, cut at polar angle α from the top: cos α = 0.9.
  const double alpha = std::acos(0.9);
  std::vector<ProfilePoint> profile;
  for (int k = 0; k <= rings; ++k) {
    const double theta = (kPi - alpha) * k / rings;  // from the south pole
    profile.push_back({k == 0 ? 0.0 : radius * std::sin(theta), -radius * std::cos(theta)});
  }
  LatheOptions options;
  options.segments = segments;
  Mesh wall = lathe(profile, options);
  // The missing cap, faceted alike, for the port's area.
  std::vector<ProfilePoint> cap_arc;
  for (int k = 0; k <= 16; ++k) {
    const double theta = kPi - alpha + alpha * k / 16;
    cap_arc.push_back({k == 16 ? 0.0 : radius * std::sin(theta), -radius * std::cos(theta)});
  }
  const double port_area = surface_area_m2(lathe(cap_arc, options));
  const double f = port_area / (port_area + surface_area_m2(wall));
  EXPECT_NEAR(f, 0.05, 1e-3);

  SceneDesc scene;
  Material white = named("white");
  white.diffuse_reflect = rho;
  scene.materials = {white};
  scene.meshes = {wall};
  Emitter e;
  e.flux_lm = 1000.0;
  scene.emitters = {e};
  const std::uint64_t n = 1000000;
  Simulation sim = run(scene, n / 2, 2, 8);
  const Ledger l = sim.ledger();
  EXPECT_TRUE(l.photons_close());
  const double escaped = l.escaped.photons / static_cast<double>(n);
  const double expect_escaped = f / (1 - rho * (1 - f));
  EXPECT_NEAR(escaped, expect_escaped, 0.01 * expect_escaped);
  const double hits = l.meshes[0].hits / static_cast<double>(n);
  const double expect_hits = (1 - f) / (1 - rho * (1 - f));
  std::printf("  integrating sphere f = %.5f: escaped %.5f (%.5f), wall hits %.4f (%.4f)\n", f, escaped,
              expect_escaped, hits, expect_hits);
  EXPECT_NEAR(hits, expect_hits, 0.01 * expect_hits);
  EXPECT_NEAR(l.escaped.flux_lm + l.absorbed.flux_lm + l.cutoff.flux_lm, 1000.0, 1e-9);
}

}  // namespace
}  // namespace gonio::sim
