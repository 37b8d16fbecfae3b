#include "sim/emitters/emission.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "photometry/angles.h"
#include "photometry/frame.h"
#include "sim/shapes.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
// Every sampler draws directions of the same density (sim/samplers/sampler.h): the
// Sobol' sampler by inversion inside a profile's cells, the random one by
// rejection.
constexpr SamplerKind kSamplers[] = {SamplerKind::Random, SamplerKind::Sobol};

photometry::Distribution type_c(std::vector<double> c_deg, std::vector<double> g_deg,
                                photometry::Symmetry symmetry,
                                const std::function<double(double, double)>& intensity) {
  photometry::Distribution d;
  d.type = photometry::PhotometricType::C;
  d.symmetry = symmetry;
  d.absolute = true;
  d.horizontal_deg = std::move(c_deg);
  d.vertical_deg = std::move(g_deg);
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg) d.candela.push_back(intensity(c, g));
  return d;
}

std::vector<double> range(double lo, double hi, double step) {
  std::vector<double> v;
  for (double x = lo; x <= hi + 1e-9; x += step) v.push_back(x);
  return v;
}

// ∫ f dΩ by the midpoint rule in (C, cos γ), which is exact in solid angle.
double integrate_sphere(const std::function<double(const Vec3&)>& f, int nc = 720, int nz = 720) {
  double sum = 0.0;
  for (int i = 0; i < nc; ++i) {
    const double c = (i + 0.5) * 2.0 * kPi / nc;
    for (int j = 0; j < nz; ++j) {
      const double z = -1.0 + (j + 0.5) * 2.0 / nz;
      const double s = std::sqrt(1.0 - z * z);
      sum += f({s * std::cos(c), s * std::sin(c), z});
    }
  }
  return sum * (2.0 * kPi / nc) * (2.0 / nz);
}

// An asymmetric profile on an irregular grid: a lobe towards C = 30°,
// γ = 60°, a weaker one towards C = 200°, γ = 150°, and a floor.
photometry::Distribution asymmetric() {
  std::vector<double> c = {0, 10, 20, 25, 30, 35, 40, 60, 90, 135, 180, 200, 225, 270, 315, 360};
  std::vector<double> g = {0, 5, 15, 30, 45, 55, 60, 65, 75, 90, 120, 150, 165, 180};
  return type_c(c, g, photometry::Symmetry::None, [](double cd, double gd) {
    const Vec3 d = photometry::direction_from_c_gamma(cd * kDeg, gd * kDeg);
    const Vec3 p1 = photometry::direction_from_c_gamma(30 * kDeg, 60 * kDeg);
    const Vec3 p2 = photometry::direction_from_c_gamma(200 * kDeg, 150 * kDeg);
    return 20.0 + 1000.0 * std::pow(std::max(0.0, dot(d, p1)), 8) +
           300.0 * std::pow(std::max(0.0, dot(d, p2)), 4);
  });
}

TEST(ProfileSampler, FluxIsTheIntegralOfTheInterpolant) {
  // Isotropic: exact.
  auto iso = ProfileSampler::create(
      type_c({0}, range(0, 180, 10), photometry::Symmetry::Rotational, [](double, double) { return 100.0; }));
  ASSERT_TRUE(iso.ok()) << iso.error().message;
  EXPECT_NEAR(iso->flux_lm(), 400.0 * kPi, 1e-9);
  EXPECT_NEAR(iso->pdf({0.3, -0.4, 0.2}), 1.0 / (4.0 * kPi), 1e-12);

  // Lambertian I0 cos γ on a 2.5° grid: Φ = π I0 to the grid's accuracy,
  // and exactly the interpolant's integral.
  auto lam = ProfileSampler::create(type_c({0}, range(0, 90, 2.5), photometry::Symmetry::Rotational,
                                           [](double, double g) { return 1000.0 * std::cos(g * kDeg); }));
  ASSERT_TRUE(lam.ok());
  EXPECT_NEAR(lam->flux_lm(), 1000.0 * kPi, 1000.0 * kPi * 1e-3);
  const auto& l = lam.value();
  EXPECT_NEAR(integrate_sphere([&](const Vec3& d) { return l.intensity_cd(d); }), l.flux_lm(),
              l.flux_lm() * 2e-5);

  auto asym = ProfileSampler::create(asymmetric());
  ASSERT_TRUE(asym.ok());
  const auto& a = asym.value();
  EXPECT_NEAR(integrate_sphere([&](const Vec3& d) { return a.intensity_cd(d); }), a.flux_lm(),
              a.flux_lm() * 2e-5);
  // The density integrates to 1.
  EXPECT_NEAR(integrate_sphere([&](const Vec3& d) { return a.pdf(d); }), 1.0, 2e-5);
}

TEST(ProfileSampler, SymmetriesExpandBeforeSampling) {
  // Quadrant symmetry: stored C 0…90, mirrored to the whole circle.
  auto q = ProfileSampler::create(type_c(range(0, 90, 15), range(0, 180, 15), photometry::Symmetry::Quadrant,
                                         [](double c, double) { return 10.0 + c; }));
  ASSERT_TRUE(q.ok());
  const auto& s = q.value();
  for (double c : {20.0, 160.0, 200.0, 340.0}) {
    // I(C) = I(180 − C) = I(360 − C): C and its mirror images agree.
    const Vec3 d = photometry::direction_from_c_gamma(c * kDeg, 70 * kDeg);
    EXPECT_NEAR(s.intensity_cd(d), 30.0, 1e-9) << "C = " << c;
  }
  EXPECT_NEAR(integrate_sphere([&](const Vec3& d) { return s.pdf(d); }), 1.0, 2e-5);
}

// χ² of n sampled directions against the interpolated profile
// (photometry::interpolate, independent of the sampler's cells) over nc bins
// in C × nz in cos γ; *dof gets the degrees of freedom.
double sampled_chi2(const photometry::Distribution& profile, int nc, int nz, int n, int* dof,
                    SamplerKind kind = SamplerKind::Random) {
  auto sampler = ProfileSampler::create(profile);
  EXPECT_TRUE(sampler.ok());
  if (!sampler.ok()) return 1e300;
  std::vector<double> obs(nc * nz, 0.0), exp(nc * nz, 0.0);
  const photometry::Distribution e = photometry::expand_symmetry(profile);
  const int sub = 40;
  double total = 0.0;
  for (int i = 0; i < nc * sub; ++i) {
    const double c = (i + 0.5) * 2.0 * kPi / (nc * sub);
    for (int j = 0; j < nz * sub; ++j) {
      const double z = -1.0 + (j + 0.5) * 2.0 / (nz * sub);
      const double g = std::acos(-z);  // local z = −cos γ
      const double w = photometry::interpolate(e, c / kDeg, g / kDeg);
      exp[(i / sub) * nz + j / sub] += w;
      total += w;
    }
  }
  for (double& x : exp) x *= n / total;
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(21, static_cast<std::uint64_t>(k), kind);
    const Vec3 d = sampler->sample(rng);
    EXPECT_NEAR(length(d), 1.0, 1e-12);
    double c = std::atan2(d.y, d.x);
    if (c < 0) c += 2 * kPi;
    const int bc = std::min(nc - 1, static_cast<int>(c / (2 * kPi) * nc));
    const int bz = std::min(nz - 1, static_cast<int>((d.z + 1.0) / 2.0 * nz));
    obs[bc * nz + bz] += 1;
  }
  double chi2 = 0.0;
  *dof = -1;
  for (std::size_t b = 0; b < obs.size(); ++b) {
    if (exp[b] < 5.0) continue;
    chi2 += (obs[b] - exp[b]) * (obs[b] - exp[b]) / exp[b];
    ++*dof;
  }
  return chi2;
}

TEST(ProfileSampler, SampledDirectionsReproduceTheProfile) {
  for (SamplerKind kind : kSamplers) {
    int dof = 0;
    const double chi2 = sampled_chi2(asymmetric(), 12, 12, 600000, &dof, kind);
    // χ² with ~143 dof: mean 143, σ ≈ 17; 5σ above the mean.
    EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof)) << "dof " << dof << ", " << to_string(kind);
  }
}

// Cells whose intensity is constant along γ (a hard-edged cone's one wide
// cell; a profile flat in γ that varies in C) take the exact inversion in μ
// rather than Newton steps; the density is the interpolant's either way.
TEST(ProfileSampler, CellsFlatInGammaKeepTheDensity) {
  // The peer's LED: 1000/π cd out to γ = 60°, nothing beyond (the KHR spot's
  // hard edge: a ramp a thousandth of a degree wide).
  const photometry::Distribution cone = type_c({0.0}, {0.0, 59.999, 60.0, 180.0}, photometry::Symmetry::Rotational,
                                               [](double, double g) { return g < 59.9995 ? 1000.0 / kPi : 0.0; });
  // Flat in γ to 90°, varying in C: the azimuthal draw inside the fast path.
  const photometry::Distribution in_c = type_c(range(0, 360, 30), {0.0, 90.0, 90.001, 180.0}, photometry::Symmetry::None,
                                               [](double c, double g) {
                                                 return g < 90.0005 ? 100.0 + 60.0 * std::cos(c * kDeg) : 0.0;
                                               });
  for (const photometry::Distribution* d : {&cone, &in_c}) {
    for (SamplerKind kind : kSamplers) {
      int dof = 0;
      // 48 bins in C resolve the linear variation inside in_c's 30° cells.
      const double chi2 = sampled_chi2(*d, d == &cone ? 12 : 48, 12, 400000, &dof, kind);
      EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof)) << "dof " << dof << ", " << to_string(kind);
    }
  }
}

TEST(ProfileSampler, CellsWiderThan45DegreesInCAreCutWithoutChangingTheDensity) {
  // Three C-planes 120° apart, the intensity linear in C between them, and a
  // rotational profile (one plane for the whole circle): the sampler cuts
  // such cells into parts of at most 45° in C. The flux and the sampled
  // histogram (24 bins in C resolve the cuts) must be the interpolant's.
  const photometry::Distribution three =
      type_c({0, 120, 240, 360}, range(0, 180, 15), photometry::Symmetry::None, [](double c, double g) {
        const double per_plane = c < 60 || c > 300 ? 50.0 : (c < 180 ? 400.0 : 150.0);
        return per_plane * (1.2 + std::cos(g * kDeg));
      });
  const photometry::Distribution rotational = type_c(
      {0}, range(0, 90, 5), photometry::Symmetry::Rotational,
      [](double, double g) { return 800.0 * std::pow(std::cos(g * kDeg), 1.5); });
  for (const auto* profile : {&three, &rotational}) {
    auto s = ProfileSampler::create(*profile);
    ASSERT_TRUE(s.ok());
    const auto& sampler = s.value();
    EXPECT_NEAR(integrate_sphere([&](const Vec3& d) { return sampler.intensity_cd(d); }),
                sampler.flux_lm(), sampler.flux_lm() * 2e-5);
    for (SamplerKind kind : kSamplers) {
      int dof = 0;
      const double chi2 = sampled_chi2(*profile, 24, 12, 600000, &dof, kind);
      EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof)) << "dof " << dof << ", " << to_string(kind);
    }
  }
}

// Types A and B: grids in (H, V) with their own frames (photometry/angles.h).
photometry::Distribution type_ab(photometry::PhotometricType type, photometry::Symmetry symmetry,
                                 std::vector<double> h_deg, std::vector<double> v_deg, const Vec3& peak) {
  photometry::Distribution d;
  d.type = type;
  d.symmetry = symmetry;
  d.absolute = true;
  d.horizontal_deg = std::move(h_deg);
  d.vertical_deg = std::move(v_deg);
  for (double h : d.horizontal_deg)
    for (double v : d.vertical_deg) {
      const Vec3 dir = photometry::direction_from_grid(type, h, v);
      d.candela.push_back(5.0 + 800.0 * std::pow(std::max(0.0, dot(dir, peak)), 6));
    }
  return d;
}

TEST(ProfileSampler, TypesAAndBFollowTheirFrames) {
  struct Case {
    photometry::PhotometricType type;
    photometry::Symmetry symmetry;
    std::vector<double> h, v;
    Vec3 peak;
  };
  const std::vector<Case> cases = {
      // Type B floodlight: beam towards (H 20°, V 30°), full H and V ranges.
      {photometry::PhotometricType::B, photometry::Symmetry::None,
       {-90, -60, -40, -30, -20, -10, 0, 10, 20, 30, 40, 60, 90},
       {-90, -70, -50, -30, -15, 0, 15, 30, 45, 60, 75, 90},
       photometry::direction_from_type_b(20 * kDeg, 30 * kDeg)},
      // Type B with lateral symmetry: H 0…90 mirrored.
      {photometry::PhotometricType::B, photometry::Symmetry::Lateral,
       {0, 10, 20, 30, 45, 60, 90},
       {-90, -60, -30, -15, 0, 15, 30, 60, 90},
       photometry::direction_from_type_b(0.0, -25 * kDeg)},
      // Type A: beam towards (H −35°, V 10°).
      {photometry::PhotometricType::A, photometry::Symmetry::None,
       {-90, -70, -50, -40, -30, -20, 0, 20, 45, 90},
       {-90, -60, -30, -10, 0, 10, 20, 40, 90},
       photometry::direction_from_type_a(-35 * kDeg, 10 * kDeg)},
  };
  for (std::size_t pass = 0; pass < 2 * cases.size(); ++pass) {
    const Case& k = cases[pass % cases.size()];
    const SamplerKind kind = kSamplers[pass / cases.size()];
    const photometry::Distribution d = type_ab(k.type, k.symmetry, k.h, k.v, k.peak);
    auto ps = ProfileSampler::create(d);
    ASSERT_TRUE(ps.ok()) << ps.error().message;
    const auto& s = ps.value();
    // The flux is the integral of the interpolant and the density sums to 1.
    EXPECT_NEAR(integrate_sphere([&](const Vec3& dir) { return s.intensity_cd(dir); }), s.flux_lm(),
                5e-5 * s.flux_lm());
    EXPECT_NEAR(integrate_sphere([&](const Vec3& dir) { return s.pdf(dir); }), 1.0, 5e-5);
    // Sampled directions follow the interpolated profile: χ² over 12 × 12
    // bins in local (azimuth about z, z).
    const int nc = 12, nz = 12, n = 300000, sub = 30;
    const photometry::Distribution e = photometry::expand_symmetry(d);
    std::vector<double> obs(nc * nz, 0.0), exp(nc * nz, 0.0);
    double total = 0.0;
    for (int i = 0; i < nc * sub; ++i) {
      const double c = (i + 0.5) * 2.0 * kPi / (nc * sub);
      for (int j = 0; j < nz * sub; ++j) {
        const double z = -1.0 + (j + 0.5) * 2.0 / (nz * sub);
        const double r = std::sqrt(1.0 - z * z);
        const double w = photometry::intensity_toward(e, {r * std::cos(c), r * std::sin(c), z});
        exp[(i / sub) * nz + j / sub] += w;
        total += w;
      }
    }
    for (double& x : exp) x *= n / total;
    Vec3 mean{};
    for (int q = 0; q < n; ++q) {
      PhotonRandom rng(31, static_cast<std::uint64_t>(q), kind);
      const Vec3 dir = s.sample(rng);
      ASSERT_NEAR(length(dir), 1.0, 1e-12);
      mean += dir;
      double c = std::atan2(dir.y, dir.x);
      if (c < 0) c += 2 * kPi;
      obs[std::min(nc - 1, static_cast<int>(c / (2 * kPi) * nc)) * nz +
          std::min(nz - 1, static_cast<int>((dir.z + 1.0) / 2.0 * nz))] += 1;
    }
    double chi2 = 0.0;
    int dof = -1;
    for (std::size_t b = 0; b < obs.size(); ++b) {
      if (exp[b] < 5.0) continue;
      chi2 += (obs[b] - exp[b]) * (obs[b] - exp[b]) / exp[b];
      ++dof;
    }
    EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof))
        << "Type " << photometry::to_string(k.type) << ", " << to_string(kind);
    // The beam points where the file's frame says.
    EXPECT_GT(dot(normalize(mean), k.peak), 0.9) << "Type " << photometry::to_string(k.type);
  }
}

TEST(ProfileSampler, PartialRangeEmitsNothingOutsideIt) {
  auto down = ProfileSampler::create(type_c({0}, range(0, 90, 5), photometry::Symmetry::Rotational,
                                            [](double, double) { return 50.0; }));
  ASSERT_TRUE(down.ok());
  EXPECT_NEAR(down->flux_lm(), 100.0 * kPi, 1e-9);  // 50 cd over 2π sr
  for (SamplerKind kind : kSamplers) {
    for (int k = 0; k < 20000; ++k) {
      PhotonRandom rng(2, static_cast<std::uint64_t>(k), kind);
      ASSERT_LE(down->sample(rng).z, 1e-12);  // γ ≤ 90°: the lower hemisphere
    }
  }
  EXPECT_EQ(down->pdf({0, 0, 1}), 0.0);
}

TEST(ProfileSampler, RejectsWhatItCannotSample) {
  auto zero = ProfileSampler::create(type_c({0}, range(0, 180, 10), photometry::Symmetry::Rotational,
                                            [](double, double) { return 0.0; }));
  ASSERT_FALSE(zero.ok());
  EXPECT_NE(zero.error().message.find("no flux"), std::string::npos);

  photometry::Distribution bad = type_c({0}, {0, 90}, photometry::Symmetry::Rotational,
                                        [](double, double) { return 1.0; });
  bad.candela.pop_back();
  EXPECT_FALSE(ProfileSampler::create(bad).ok());
}

TEST(AreaSampler, UniformInAreaCosineInDirection) {
  // Two triangles in the plane z = 0 facing +Z, areas 1 and 3.
  Mesh m;
  m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {10, 0, 0}, {13, 0, 0}, {10, 2, 0}};
  m.indices = {0, 1, 2, 3, 4, 5};
  auto s = AreaSampler::create(m, false);
  ASSERT_TRUE(s.ok());
  EXPECT_DOUBLE_EQ(s->area_m2(), 4.0);
  const int n = 200000, bins = 10;
  for (SamplerKind kind : kSamplers) {
  int second = 0;
  std::vector<double> obs(bins, 0.0);
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(4, static_cast<std::uint64_t>(k), kind);
    const AreaSampler::Sample a = s->sample(rng);
    ASSERT_NEAR(a.position.z, 0.0, 1e-12);
    ASSERT_NEAR(a.normal.z, 1.0, 1e-12);
    ASSERT_GT(a.direction.z, 0.0);
    second += a.triangle == 1;
    obs[std::min(bins - 1, static_cast<int>(a.direction.z * bins))] += 1;
  }
  EXPECT_NEAR(second / static_cast<double>(n), 0.75, 5 * std::sqrt(0.75 * 0.25 / n));
  double chi2 = 0.0;
  for (int b = 0; b < bins; ++b) {
    const double c0 = static_cast<double>(b) / bins, c1 = c0 + 1.0 / bins;
    const double e = n * (c1 * c1 - c0 * c0);
    chi2 += (obs[b] - e) * (obs[b] - e) / e;
  }
  EXPECT_LT(chi2, 27.9) << to_string(kind);  // 9 dof, p = 0.001
  }
  // ∫ over the area and the sphere of the density is 1.
  const double per_area = integrate_sphere([&](const Vec3& d) { return s->pdf({0, 0, 1}, d); });
  EXPECT_NEAR(per_area * s->area_m2(), 1.0, 1e-5);
}

TEST(AreaSampler, TwoSidedEmitsHalfEachWay) {
  Mesh m = disc(0.5, 16);
  auto s = AreaSampler::create(m, true);
  ASSERT_TRUE(s.ok());
  const int n = 100000;
  int down = 0;
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(6, static_cast<std::uint64_t>(k));
    const AreaSampler::Sample a = s->sample(rng);
    ASSERT_GT(dot(a.direction, a.normal), 0.0);
    down += a.direction.y < 0.0;
  }
  EXPECT_NEAR(down / static_cast<double>(n), 0.5, 5 * std::sqrt(0.25 / n));
  // (|cos| has a kink at the horizon: the midpoint rule is good to ~1e-5.)
  const double per_area = integrate_sphere([&](const Vec3& d) { return s->pdf({0, 1, 0}, d); });
  EXPECT_NEAR(per_area * s->area_m2(), 1.0, 5e-5);
}

TEST(AreaSampler, RejectsMeshesWithoutArea) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  m.indices = {0, 1, 2};
  EXPECT_FALSE(AreaSampler::create(m, false).ok());
  m.indices = {0, 1, 7};
  EXPECT_FALSE(AreaSampler::create(m, false).ok());
}

TEST(EmissionSampler, ChoosesEmittersByFlux) {
  SceneDesc scene;
  scene.materials.resize(1);
  scene.meshes = {disc(0.1, 8)};
  Emitter a, b, c;
  a.flux_lm = 1000.0;
  a.position = {1, 2, 3};
  b.flux_lm = 0.0;  // never emits
  c.kind = Emitter::Kind::Area;
  c.mesh = 0;
  c.flux_lm = 3000.0;
  scene.emitters = {a, b, c};
  auto s = EmissionSampler::create(scene);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_DOUBLE_EQ(s->total_flux_lm(), 4000.0);
  EXPECT_DOUBLE_EQ(s->emitter_probability(2), 0.75);
  int count[3] = {0, 0, 0};
  const int n = 100000;
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(8, static_cast<std::uint64_t>(k));
    const EmittedPhoton p = s->sample(rng);
    ++count[p.emitter];
    if (p.emitter == 0) {
      ASSERT_EQ(p.origin, (Vec3{1, 2, 3}));
      ASSERT_FALSE(p.on_surface);
    } else {
      ASSERT_TRUE(p.on_surface);
      ASSERT_GT(p.direction.y, 0.0);  // the disc faces +Y, one-sided
    }
  }
  EXPECT_EQ(count[1], 0);
  EXPECT_NEAR(count[2] / static_cast<double>(n), 0.75, 5 * std::sqrt(0.1875 / n));
}

TEST(EmissionSampler, ProfileFollowsTheEmitterFrame) {
  // A narrow beam at γ = 0 (local −z): in the default glTF frame it points
  // along −Y; in a frame whose zenith is +X, along −X.
  SceneDesc scene;
  Emitter e;
  e.flux_lm = 1.0;
  e.profile = std::make_shared<photometry::Distribution>(
      type_c({0}, range(0, 180, 1), photometry::Symmetry::Rotational,
             [](double, double g) { return g <= 2.0 ? 1.0 : 0.0; }));
  scene.emitters = {e};
  auto s = EmissionSampler::create(scene);
  ASSERT_TRUE(s.ok());
  PhotonRandom rng(1, 1);
  EXPECT_LT(s->sample(rng).direction.y, -0.998);  // within 3° (the interpolant reaches 0 at 3°)
  scene.emitters[0].frame = photometry::make_frame({1, 0, 0}, {0, 1, 0});
  auto t = EmissionSampler::create(scene);
  ASSERT_TRUE(t.ok());
  EXPECT_LT(t->sample(rng).direction.x, -0.998);
}

TEST(EmissionSampler, ErrorsNameTheEmitter) {
  SceneDesc scene;
  EXPECT_FALSE(EmissionSampler::create(scene).ok());  // no emitter
  Emitter e;
  e.name = "led";
  e.flux_lm = -1.0;
  scene.emitters = {e};
  auto r = EmissionSampler::create(scene);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("'led'"), std::string::npos);
  scene.emitters[0].flux_lm = std::nan("");
  EXPECT_FALSE(EmissionSampler::create(scene).ok());
  scene.emitters[0].flux_lm = 0.0;
  EXPECT_FALSE(EmissionSampler::create(scene).ok());  // no flux in total
  scene.emitters[0].flux_lm = 1.0;
  scene.emitters[0].frame.c0 = {2.0, 0.0, 0.0};
  r = EmissionSampler::create(scene);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("orthonormal"), std::string::npos);
  scene.emitters[0].frame = {};
  EXPECT_TRUE(EmissionSampler::create(scene).ok());
  scene.emitters[0].kind = Emitter::Kind::Area;
  scene.emitters[0].mesh = 3;
  r = EmissionSampler::create(scene);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("mesh 3"), std::string::npos);
}

}  // namespace
}  // namespace gonio::sim
