#include "sim/bsdfs/bsdf_eval.h"
#include "sim/bsdfs/bsdf_eval_pair.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "photometry/diagnostics.h"
#include "sim/bsdfs/lobes.h"
#include "sim/bsdfs/tabulated_bsdf.h"
#include "sim/samplers/random.h"
#include "sim/samplers/sampling.h"
#include "tests/sim/bsdfs/lobe_checks.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;

SurfaceFrame tilted_frame() {
  const Vec3 ng = normalize(Vec3{0.2, 1.0, -0.1});
  const Vec3 ns = normalize(Vec3{0.25, 1.0, 0.0});
  return {ng, ns, normalize(Vec3{1.0, -0.2, 0.3})};
}

// ∫ g dω over the sphere by uniform directions (independent of the
// connection sampler under test).
template <class G>
double sphere_integral(G&& g, int n) {
  double sum = 0.0;
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(5, static_cast<std::uint64_t>(k));
    sum += g(sample_uniform_sphere(rng)) / uniform_sphere_pdf();
  }
  return sum / n;
}

TEST(BsdfEval, DiffuseLobesSendTheirWeightOverTheSphere) {
  // ∫ kd·cos/π over the reflection side + kt·cos/π over the other = kd + kt,
  // whatever the incidence: a missing cosine or 1/π fails.
  Material m{"opal", 0.3, 0.6, 0.1};
  const SurfaceFrame f = tilted_frame();
  const Vec3 wi = normalize(Vec3{0.5, 0.7, 0.2});
  const double total = sphere_integral([&](const Vec3& wo) { return non_delta_f_cos(m, f, wi, wo); }, 400000);
  EXPECT_NEAR(total, 0.9, 0.01);
  // From the back side the sides swap; the sum stays.
  const double back = sphere_integral([&](const Vec3& wo) { return non_delta_f_cos(m, f, -1.0 * wi, wo); }, 400000);
  EXPECT_NEAR(back, 0.9, 0.01);
  // Reflection only on wi's side: a wo on that side gets kd cos/π.
  const Vec3 ng = f.geometric_normal;
  EXPECT_NEAR(non_delta_f_cos(m, f, wi, ng), 0.3 / kPi, 1e-12);
  EXPECT_NEAR(non_delta_f_cos(m, f, wi, -1.0 * ng), 0.6 / kPi, 1e-12);
}

// Every non-delta lobe of sim/bsdfs at once, with a weight over incidence.
Material every_lobe() {
  Material m;
  m.diffuse_reflect = 0.1;
  m.diffuse_transmit = 0.12;
  m.glossy = 0.2;
  m.glossy_mx = 0.3;
  m.glossy_my = 0.15;
  m.glossy_f0 = 0.8;
  m.abg_reflect = {0.15, 0.02, 1.5};
  m.abg_transmit = {0.1, 0.05, 1.2};
  m.tabulated = 0.2;
  m.table = test::non_lambertian_klems_sheet();
  m.over_incidence[0] = {{0.0, 90.0}, {1.0, 0.3}};  // diffuse reflection falls with incidence
  prepare(m);
  return m;
}

TEST(BsdfEval, EachLobeSendsItsWeightTimesItsAlbedo) {
  // With the shading normal on the geometric one nothing is lost to the
  // geometry, so ∫ f_cos dω of each lobe alone is weight_at(θi) ·
  // lobe_albedo (sim/bsdfs): a lobe evaluated in the wrong frame, on the
  // wrong side, without its weight over incidence or without the glossy
  // lobe's compensation fails.
  const Material m = every_lobe();
  const Vec3 n = normalize(Vec3{0.2, 1.0, -0.1});
  const SurfaceFrame f{n, n, normalize(Vec3{1.0, 0.2, 0.0} - dot(Vec3{1.0, 0.2, 0.0}, n) * n)};
  const Vec3 wi = normalize(n + Vec3{0.6, 0.0, 0.3});
  const double cos_i = dot(wi, n);
  // The glossy lobe reads the tangent; the ABg and tabulated lobes build
  // their basis from the normal alone (as scatter() hands them the frame).
  const Basis with_tangent = basis_from_normal_tangent(n, f.tangent), without = basis_from_normal_tangent(n, Vec3{});
  for (Lobe lobe : {Lobe::DiffuseReflect, Lobe::DiffuseTransmit, Lobe::Glossy, Lobe::AbgReflect, Lobe::AbgTransmit,
                    Lobe::Tabulated}) {
    const double integral = test::integrate_sphere(
        [&](const Vec3& wo) { return non_delta_f_cos(m, f, wi, wo, lobe_bit(lobe)); }, 1200, 600);
    const Basis& b = lobe == Lobe::Glossy ? with_tangent : without;
    const double want = weight_at(m, lobe, cos_i) * lobe_albedo(m, lobe, b.to_local(wi), true);
    EXPECT_NEAR(integral / want, 1.0, 0.01) << to_string(lobe);
  }
  // From the back the tabulated lobe reads the back's data (none here:
  // the table's back mirrors the front's or is empty; either way the sum
  // is what lobe_albedo says for front = false).
  const double back = test::integrate_sphere(
      [&](const Vec3& wo) { return non_delta_f_cos(m, f, -1.0 * wi, wo, lobe_bit(Lobe::Tabulated)); }, 1200, 600);
  EXPECT_NEAR(back, weight_at(m, Lobe::Tabulated, cos_i) *
                        lobe_albedo(m, Lobe::Tabulated, basis_from_normal_tangent(-1.0 * n, Vec3{}).to_local(-1.0 * wi),
                                    false),
              0.01 * std::max(back, 0.01));
}

TEST(BsdfEval, ConnectionDensityIsNormalisedAndItsWeightsIntegrateTheLobes) {
  // A wrong mixture density (forgetting a lobe, a Jacobian) breaks either
  // ∫ pdf = 1 or E[f_cos / pdf] = ∫ f_cos.
  const Material m = every_lobe();
  const SurfaceFrame f = tilted_frame();
  const Vec3 wi = normalize(Vec3{-0.4, 0.8, 0.3});
  // Under the sampler's own draws E[f_cos/pdf] is the integral of f_cos;
  // the density itself integrates to 1 over the sphere.
  double weight = 0.0;
  const int n = 1 << 18;
  for (int k = 0; k < n; ++k) {
    PhotonRandom rng(3, static_cast<std::uint64_t>(k));
    const ConnectionDirection c = connection_direction(m, f, wi, rng.uniform(), rng.uniform());
    if (!(c.pdf > 0.0)) continue;
    EXPECT_NEAR(c.f_cos, non_delta_f_cos(m, f, wi, c.wo), 1e-12);
    EXPECT_NEAR(length(c.wo), 1.0, 1e-12);
    EXPECT_NEAR(c.pdf, connection_pdf(m, f, wi, c.wo), 1e-12 * c.pdf);
    weight += c.f_cos / c.pdf;
  }
  weight /= n;
  const double want =
      sphere_integral([&](const Vec3& wo) { return non_delta_f_cos(m, f, wi, wo); }, 1'000'000);
  EXPECT_NEAR(weight / want, 1.0, 0.015);
  EXPECT_NEAR(sphere_integral([&](const Vec3& wo) { return connection_pdf(m, f, wi, wo); }, 1'000'000), 1.0, 0.015);
  // And a histogram check of the density: the draws' share of the upper
  // hemisphere about the geometric normal against ∫ pdf over it.
  int up = 0;
  for (int k = 0; k < 200000; ++k) {
    PhotonRandom rng(4, static_cast<std::uint64_t>(k));
    if (dot(connection_direction(m, f, wi, rng.uniform(), rng.uniform()).wo, f.geometric_normal) > 0.0) ++up;
  }
  const double upper = sphere_integral(
      [&](const Vec3& wo) { return dot(wo, f.geometric_normal) > 0.0 ? connection_pdf(m, f, wi, wo) : 0.0; }, 1'000'000);
  EXPECT_NEAR(up / 200000.0, upper, 0.01);
}

TEST(BsdfEval, StratifiedPairsGiveStratifiedDiffuseDirections) {
  // A pure reflector: u1 in [k/M, (k+1)/M) lands in the k-th ring of equal
  // projected solid angle (sin²θ in [k/M, (k+1)/M)).
  Material m{"white", 0.8, 0.0, 0.0};
  const SurfaceFrame f{{0.0, 1.0, 0.0}, {0.0, 1.0, 0.0}, {}};
  const Vec3 wi{0.0, 1.0, 0.0};
  const int M = 8;
  for (int k = 0; k < M; ++k) {
    const double u1 = (k + 0.5) / M;
    const ConnectionDirection c = connection_direction(m, f, wi, u1, 0.3);
    const double sin2 = 1.0 - c.wo.y * c.wo.y;
    EXPECT_NEAR(sin2, u1, 1e-9) << k;
    EXPECT_NEAR(c.f_cos / c.pdf, 0.8, 1e-12);  // kd exactly: no variance in the weight
  }
}

// The batched draw of one vertex's connections (the vertex's bases and the
// lobes' weights computed once) gives connection_direction's answers bit for
// bit, from the front and the back, for every lobe subset the tracer hands
// over. Mistakes it catches: the weights computed for every lobe instead of
// the vertex's subset, a basis kept from the front for a back incidence, a
// draw's pair read from the wrong index.
TEST(BsdfEval, ConnectionDirectionsOfOneVertexAreThoseDrawnOneByOne) {
  const Material m = every_lobe();
  const SurfaceFrame f = tilted_frame();
  const unsigned subsets[] = {
      kNonDeltaLobes, lobe_bit(Lobe::DiffuseReflect) | lobe_bit(Lobe::Glossy),
      lobe_bit(Lobe::DiffuseTransmit) | lobe_bit(Lobe::AbgTransmit) | lobe_bit(Lobe::Tabulated)};
  std::vector<double> u1(37), u2(37);
  for (std::size_t i = 0; i < u1.size(); ++i) {
    PhotonRandom rng(11, i);
    u1[i] = rng.uniform();
    u2[i] = rng.uniform();
  }
  for (const Vec3& wi : {normalize(Vec3{-0.4, 0.8, 0.3}), normalize(Vec3{0.3, -0.7, 0.2})})
    for (const unsigned lobes : subsets)
      for (const std::size_t n : {std::size_t{0}, std::size_t{1}, u1.size()}) {
        std::vector<ConnectionDirection> got(n + 1);
        got[n].pdf = -7.0;  // one past the end stays untouched
        connection_directions(m, f, wi, u1.data(), u2.data(), n, got.data(), lobes);
        int booked = 0;
        for (std::size_t i = 0; i < n; ++i) {
          const ConnectionDirection one = connection_direction(m, f, wi, u1[i], u2[i], lobes);
          EXPECT_EQ(got[i].wo.x, one.wo.x) << i;
          EXPECT_EQ(got[i].wo.y, one.wo.y) << i;
          EXPECT_EQ(got[i].wo.z, one.wo.z) << i;
          EXPECT_EQ(got[i].pdf, one.pdf) << i;
          EXPECT_EQ(got[i].f_cos, one.f_cos) << i;
          EXPECT_EQ(got[i].lobe, one.lobe) << i;
          if (one.pdf > 0.0) ++booked;
        }
        EXPECT_EQ(got[n].pdf, -7.0);
        if (n == u1.size()) {
          EXPECT_GT(booked, 20) << lobes;  // not a comparison of empty draws
        }
      }
}

}  // namespace
}  // namespace gonio::sim

namespace gonio::sim {
namespace {

// The pair the balance heuristic reads at a photon's escape
// (sim/bsdfs/bsdf_eval_pair.h) is the two single queries bit for bit, for
// every lobe subset and both sides (the far field's bytes rest on it).
TEST(BsdfEval, ValueAndDensityTogetherAreTheSingleQueriesBitForBit) {
  const Material m = every_lobe();
  const SurfaceFrame f = tilted_frame();
  const unsigned subsets[] = {kNonDeltaLobes, lobe_bit(Lobe::DiffuseReflect) | lobe_bit(Lobe::Glossy),
                              lobe_bit(Lobe::DiffuseTransmit) | lobe_bit(Lobe::AbgTransmit) | lobe_bit(Lobe::Tabulated)};
  int nonzero = 0;
  for (const Vec3& wi : {normalize(Vec3{-0.4, 0.8, 0.3}), normalize(Vec3{0.3, -0.7, 0.2})})
    for (const unsigned lobes : subsets)
      for (std::uint64_t i = 0; i < 64; ++i) {
        PhotonRandom rng(13, i);
        const Vec3 wo = sample_uniform_sphere(rng);
        const FCosAndPdf both = non_delta_f_cos_and_pdf(m, f, wi, wo, lobes);
        EXPECT_EQ(both.f_cos, non_delta_f_cos(m, f, wi, wo, lobes)) << i;
        EXPECT_EQ(both.pdf, connection_pdf(m, f, wi, wo, lobes)) << i;
        if (both.f_cos > 0.0 && both.pdf > 0.0) ++nonzero;
      }
  EXPECT_GT(nonzero, 100);
}

// A vertex prepared once for its connections and the photon's own share
// (ConnectionVertex, issue 43's cheaper connections) answers as the single
// queries do, bit for bit: its draws (value and density at the drawn
// direction) and its value and density towards any direction — on the
// diffuse lobes alone (where the value and density are read in one pass,
// and the shading bases are never built) as on the other lobes.
TEST(BsdfEval, APreparedVertexAnswersAsTheSingleQueriesBitForBit) {
  const Material every = every_lobe();
  Material opal;  // the bell's opal: diffuse transmission and reflection
  opal.diffuse_reflect = 0.3;
  opal.diffuse_transmit = 0.6;
  opal.over_incidence[1] = {{0.0, 90.0}, {1.0, 0.5}};
  prepare(opal);
  const SurfaceFrame f = tilted_frame();
  const unsigned diffuse = lobe_bit(Lobe::DiffuseReflect) | lobe_bit(Lobe::DiffuseTransmit);
  struct Case {
    const Material* m;
    unsigned lobes;
  };
  const Case cases[] = {{&opal, kNonDeltaLobes},     {&opal, lobe_bit(Lobe::DiffuseTransmit)},
                        {&every, diffuse},           {&every, lobe_bit(Lobe::DiffuseReflect)},
                        {&every, kNonDeltaLobes},    {&every, lobe_bit(Lobe::DiffuseTransmit) | lobe_bit(Lobe::Glossy)}};
  int drawn = 0, towards = 0;
  for (const Case& c : cases)
    for (const Vec3& wi : {normalize(Vec3{-0.4, 0.8, 0.3}), normalize(Vec3{0.3, -0.7, 0.2})}) {
      const ConnectionVertex v(*c.m, f, wi, c.lobes);
      EXPECT_EQ(v.diffuse_only, (c.lobes & kShadingFrameLobes & (c.m == &opal ? 0u : ~0u)) == 0) << c.lobes;
      std::array<double, 16> u1{}, u2{};
      for (std::size_t k = 0; k < u1.size(); ++k) {
        u1[k] = (static_cast<double>(k) + 0.37) / 16.0;
        u2[k] = std::fmod(0.81 + 0.618 * static_cast<double>(k), 1.0);
      }
      std::array<ConnectionDirection, 16> got;
      connection_directions(*c.m, v, u1.data(), u2.data(), u1.size(), got.data());
      for (std::size_t k = 0; k < got.size(); ++k) {
        const ConnectionDirection one = connection_direction(*c.m, f, wi, u1[k], u2[k], c.lobes);
        EXPECT_EQ(got[k].wo.x, one.wo.x);
        EXPECT_EQ(got[k].wo.y, one.wo.y);
        EXPECT_EQ(got[k].wo.z, one.wo.z);
        EXPECT_EQ(got[k].pdf, one.pdf);
        EXPECT_EQ(got[k].f_cos, one.f_cos);
        if (!(got[k].pdf > 0.0)) continue;
        // The drawn direction's value and density are the single queries'.
        EXPECT_EQ(got[k].f_cos, non_delta_f_cos(*c.m, f, wi, got[k].wo, c.lobes)) << c.lobes << " " << k;
        EXPECT_EQ(got[k].pdf, connection_pdf(*c.m, f, wi, got[k].wo, c.lobes)) << c.lobes << " " << k;
        ++drawn;
      }
      for (std::uint64_t i = 0; i < 64; ++i) {
        PhotonRandom rng(29, i);
        const Vec3 wo = sample_uniform_sphere(rng);
        const FCosAndPdf at = non_delta_f_cos_and_pdf(*c.m, v, wo);
        EXPECT_EQ(at.f_cos, non_delta_f_cos(*c.m, f, wi, wo, c.lobes)) << c.lobes << " " << i;
        EXPECT_EQ(at.pdf, connection_pdf(*c.m, f, wi, wo, c.lobes)) << c.lobes << " " << i;
        if (at.f_cos > 0.0 && at.pdf > 0.0) ++towards;
      }
    }
  EXPECT_GT(drawn, 150);
  EXPECT_GT(towards, 300);
}

}  // namespace
}  // namespace gonio::sim
