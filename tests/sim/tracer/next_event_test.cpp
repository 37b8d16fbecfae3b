#include "sim/tracer/next_event.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <utility>

#include "photometry/diagnostics.h"
#include "sim/bsdfs/tabulated_bsdf.h"
#include "sim/shapes.h"
#include "sim/simulation.h"
#include "sim/tracer/tracer.h"
#include "tests/sim/bsdfs/lobe_checks.h"
#include "tests/sim/scenes.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;

SimulationSettings run(NextEventMode mode, int threads, std::uint64_t per_iteration, int iterations,
                       std::uint64_t seed = 21) {
  SimulationSettings s = test_scenes::small_run(threads, per_iteration, iterations, seed);
  s.next_event = mode;
  return s;
}

// A point lamp inside an opal sphere (diffuse transmission t, reflection r
// inward): every escape follows a diffuse transmission, so with next-event
// estimation the far field is the connections alone. Escaped fraction
// t / (1 − r) (a closed sphere: each inward reflection lands on it again);
// the intensity is the same in every direction.
SceneDesc opal_sphere(double t, double r) {
  SceneDesc scene;
  Material opal{"opal", r, t, 0.0};
  scene.materials = {opal};
  scene.meshes = {sphere(0.1, 48, 24)};
  Emitter e;
  e.position = {0.0, 0.0, 0.0};
  e.flux_lm = 1000.0;
  scene.emitters = {e};
  return scene;
}

TEST(NextEvent, OpalSphereFarFieldIsIsotropicAtTheClosedFormFluxFromConnectionsAlone) {
  const double t = 0.6, r = 0.3, want = 1000.0 * t / (1.0 - r);
  SimulationSettings s = run(NextEventMode::On, 2, 100000, 2);
  s.next_event_connections = 8;
  auto sim = simulate(opal_sphere(t, r), s);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const NextEventSummary n = sim->next_event();
  ASSERT_TRUE(n.enabled);
  EXPECT_GT(n.connections, 0u);
  // Every escape is covered: nothing binned, the far field is the booked flux.
  const FarField f = sim->far_field();
  EXPECT_EQ(f.total_photons(), 0u);
  EXPECT_NEAR(f.total_flux_lm(), n.booked_lm, 1e-9 * want);
  // Booked and covered (the escapes they stand for) agree in expectation:
  // within 1 % at 2·10⁵ photons (each photon escapes with weight t/(1−r)
  // on average; the covered flux is binomial, σ ≈ 0.2 %).
  EXPECT_NEAR(n.booked_lm / want, 1.0, 0.01);
  EXPECT_NEAR(n.covered_lm / want, 1.0, 0.01);
  // Isotropic: each cube face carries a sixth of the flux. The connections
  // from a sphere's inside are cosine-distributed about its radial normal,
  // so a face sees an even spread; 1 % per face at this count.
  const std::size_t per_face = f.texel_count() / 6;
  for (std::size_t face = 0; face < 6; ++face) {
    double sum = 0.0;
    for (std::size_t i = face * per_face; i < (face + 1) * per_face; ++i) sum += f.flux_lm(i);
    EXPECT_NEAR(sum / (f.total_flux_lm() / 6.0), 1.0, 0.02) << "face " << face;
  }
  // The intensity per texel: I = Φ/(4π) everywhere, to the noise.
  double worst = 0.0;
  for (std::size_t i = 0; i < f.texel_count(); ++i)
    worst = std::max(worst, std::abs(f.intensity_cd(i) / (want / (4.0 * kPi)) - 1.0));
  EXPECT_LT(worst, 0.15);
}

TEST(NextEvent, BooksStayExactAndTheFarFieldsTotalIsBinnedPlusBooked) {
  // Every photon's fate is booked as without connections (emitted =
  // escaped + absorbed + cut off, exact); the escapes the connections stand
  // for are left out of the far field's photons, and its flux is the binned
  // escapes plus the booked connections.
  const SceneDesc scene = test_scenes::mixed_scene();
  auto on = simulate(scene, run(NextEventMode::On, 2, 20000, 2));
  ASSERT_TRUE(on.ok()) << on.error().message;
  const NextEventSummary n = on->next_event();
  ASSERT_TRUE(n.enabled);
  const Ledger b = on->ledger();
  EXPECT_TRUE(b.photons_close());
  EXPECT_NEAR(b.flux_imbalance_lm(), 0.0, 1e-9 * b.emitted.flux_lm);
  const FarField f = on->far_field();
  const double binned = static_cast<double>(f.total_photons()) * b.photon_power_lm;
  EXPECT_NEAR(binned + n.covered_lm, b.escaped.flux_lm, 1e-9 * b.escaped.flux_lm);
  EXPECT_NEAR(f.total_flux_lm(), binned + n.booked_lm, 1e-9 * b.escaped.flux_lm);
  EXPECT_GT(n.covered_lm, 0.0);
  // Booked and covered agree in expectation: within 2 % here.
  EXPECT_NEAR(n.booked_lm / n.covered_lm, 1.0, 0.02);
}

// Flux in 24 regions of the sphere (each cube face in four quadrants).
std::vector<double> regions(const FarField& f) {
  std::vector<double> out(24, 0.0);
  const int n = f.face_size();
  for (std::size_t i = 0; i < f.texel_count(); ++i) {
    const int face = static_cast<int>(i / static_cast<std::size_t>(n * n));
    const int rest = static_cast<int>(i % static_cast<std::size_t>(n * n));
    const int quad = (rest / n >= n / 2 ? 2 : 0) + (rest % n >= n / 2 ? 1 : 0);
    out[static_cast<std::size_t>(4 * face + quad)] += f.flux_lm(i);
  }
  return out;
}

TEST(NextEvent, FarFieldMeanIsThePhotonHistogramsOnEveryLobe) {
  // Unbiased: the mixed scene (diffuse reflection and transmission, mirror,
  // glossy, dielectric, two emitters) traced with and without connections,
  // flux in 24 regions against each other, within 4.5 standard deviations
  // of their difference (the histogram's Poisson variance, twice, as a
  // bound for both). A connection booking f·cos without /pdf, or an escape
  // counted twice, moves regions by far more.
  const SceneDesc scene = test_scenes::mixed_scene();
  SimulationSettings with = run(NextEventMode::On, 2, 150000, 2, 6);
  with.next_event_connections = 4;  // the estimator's mean does not depend on M; the test's time does
  auto off = simulate(scene, run(NextEventMode::Off, 2, 150000, 2, 5));
  auto on = simulate(scene, with);
  ASSERT_TRUE(off.ok());
  ASSERT_TRUE(on.ok());
  const FarField a = off->far_field(), b = on->far_field();
  const std::vector<double> ra = regions(a), rb = regions(b);
  const double per_photon = off->ledger().photon_power_lm;
  for (std::size_t k = 0; k < ra.size(); ++k) {
    const double sigma = std::sqrt(2.0 * std::max(ra[k], per_photon) * per_photon);
    EXPECT_NEAR(rb[k], ra[k], 4.5 * sigma + 1e-3 * ra[k]) << "region " << k;
  }
  EXPECT_NEAR(b.total_flux_lm() / a.total_flux_lm(), 1.0, 0.005);
}

// One lobe at a time (sim/bsdfs/lobes.h), each the only lobe of a disc
// under a point lamp, traced with and without connections: the far
// fields agree in 24 regions within their noise, and the connections'
// bytes are the same on one and two threads. A lobe whose value or
// density the connections took from anywhere but sim/bsdfs (a weight
// over incidence left out, the tabulated BSDF's side, the ABg lobe's
// normalisation, the compensated glossy lobe's second lobe) moves regions
// by far more than the noise.
struct LobeCase {
  const char* name;
  Material material;
};

std::vector<LobeCase> lobe_cases() {
  std::vector<LobeCase> cases;
  Material angular;  // diffuse reflection falling with incidence
  angular.diffuse_reflect = 0.9;
  angular.over_incidence[0] = {{0.0, 90.0}, {1.0, 0.2}};
  cases.push_back({"diffuse-reflect-over-incidence", angular});
  Material opal;
  opal.diffuse_transmit = 0.7;
  cases.push_back({"diffuse-transmit", opal});
  Material glossy;
  glossy.glossy = 0.9;
  glossy.glossy_mx = 0.35;
  glossy.glossy_my = 0.2;
  glossy.glossy_f0 = 0.8;
  glossy.glossy_compensation = true;
  cases.push_back({"glossy-compensated", glossy});
  Material abg_r;
  abg_r.abg_reflect = {0.7, 0.02, 1.5};
  cases.push_back({"abg-reflect", abg_r});
  Material abg_t;
  abg_t.abg_transmit = {0.6, 0.05, 1.2};
  cases.push_back({"abg-transmit", abg_t});
  auto table = test::non_lambertian_klems_sheet();
  Material tabulated;
  tabulated.tabulated = 0.9;
  tabulated.table = table;
  cases.push_back({"tabulated", tabulated});
  return cases;
}

SceneDesc lamp_over_disc(const Material& m) {
  SceneDesc scene;
  scene.materials = {m};
  scene.meshes = {disc(0.25, 48)};
  Emitter e;
  e.position = {0.0, 0.08, 0.0};
  e.flux_lm = 1000.0;
  scene.emitters = {e};
  return scene;
}

TEST(NextEvent, EachLobeKindAgreesWithPlainTracingAndKeepsItsBytes) {
  const std::vector<LobeCase> cases = lobe_cases();
  ASSERT_EQ(cases.size(), 6u);
  for (const LobeCase& c : cases) {
    SCOPED_TRACE(c.name);
    const SceneDesc scene = lamp_over_disc(c.material);
    SimulationSettings with = run(NextEventMode::On, 2, 100000, 2, 6);
    with.next_event_connections = 4;
    auto off = simulate(scene, run(NextEventMode::Off, 2, 100000, 2, 5));
    auto on = simulate(scene, with);
    ASSERT_TRUE(off.ok()) << off.error().message;
    ASSERT_TRUE(on.ok()) << on.error().message;
    ASSERT_TRUE(on->next_event().enabled);
    EXPECT_GT(on->next_event().escaped, 0u);
    const FarField a = off->far_field(), b = on->far_field();
    const std::vector<double> ra = regions(a), rb = regions(b);
    const double per_photon = off->ledger().photon_power_lm;
    for (std::size_t k = 0; k < ra.size(); ++k) {
      const double sigma = std::sqrt(2.0 * std::max(ra[k], per_photon) * per_photon);
      EXPECT_NEAR(rb[k], ra[k], 4.5 * sigma + 1e-3 * ra[k]) << "region " << k;
    }
    EXPECT_NEAR(b.total_flux_lm() / a.total_flux_lm(), 1.0, 0.01);
    // The same bytes on one thread and in another split.
    SimulationSettings one = with;
    one.threads = 1;
    one.photons_per_iteration = 200000;
    one.iterations = 1;
    auto single = simulate(scene, one);
    ASSERT_TRUE(single.ok());
    const FarField s = single->far_field();
    ASSERT_EQ(s.texel_count(), b.texel_count());
    EXPECT_EQ(std::memcmp(s.flux_lm().data(), b.flux_lm().data(), s.texel_count() * sizeof(double)), 0);
  }
}

// Issue 45, case 8: light scattered inside a volume after a connected
// surface vertex is no longer the direct escape the connections stood for,
// so the volume event clears the "covered" mark (sim/tracer/tracer.cpp).
// A lamp over a white disc (diffuse reflection, connected) under a volume
// diffuser open at the bottom: an index-matched (n = 1) scattering box
// without its −Y face, whose inside the tracer knows by the back faces it
// reaches. Light the disc sends up scatters in the box and leaves it
// downwards through the open face, past the disc, without crossing another
// surface. (In a closed part every way out crosses its surface, which sets
// the mark afresh: only an open volume shows a mark kept through a volume
// event.) Kept, those escapes are counted as covered and left out of the
// far field: several per cent of the flux go missing, and the covered flux
// grows far beyond what the connections book.
SceneDesc disc_under_open_volume() {
  SceneDesc scene;
  Material white{"white", 0.9, 0.0, 0.0};
  Material cloud;
  cloud.name = "cloud";
  cloud.dielectric = 1.0;
  cloud.ior = 1.0;
  cloud.scattering_per_m = 10.0;  // mean free path 0.1 m in a box 0.2 m tall
  cloud.scattering_g = 0.0;
  scene.materials = {white, cloud};
  Mesh floor = disc(0.25, 48);
  floor.material = 0;
  Mesh volume = box(0.6, 0.2, 0.6);
  // The quads come in the order +X, −X, +Y, −Y, +Z, −Z: drop the −Y face.
  volume.indices.erase(volume.indices.begin() + 18, volume.indices.begin() + 24);
  transform(volume, translation({0.0, 0.22, 0.0}));  // y from 0.12 to 0.32
  volume.material = 1;
  scene.meshes = {floor, volume};
  Emitter e;
  e.position = {0.0, 0.08, 0.0};
  e.flux_lm = 1000.0;
  scene.emitters = {e};
  return scene;
}

TEST(NextEvent, LightScatteredInAVolumeAfterAConnectedVertexIsBinnedNotCovered) {
  const SceneDesc scene = disc_under_open_volume();
  SimulationSettings with = run(NextEventMode::On, 2, 150000, 2, 6);
  with.next_event_connections = 4;
  auto off = simulate(scene, run(NextEventMode::Off, 2, 150000, 2, 5));
  auto on = simulate(scene, with);
  ASSERT_TRUE(off.ok()) << off.error().message;
  ASSERT_TRUE(on.ok()) << on.error().message;
  const NextEventSummary n = on->next_event();
  ASSERT_TRUE(n.enabled);
  // Closed books: every photon's fate, and the escaped flux is the binned
  // escapes plus the covered ones.
  const Ledger b = on->ledger();
  EXPECT_TRUE(b.photons_close());
  EXPECT_NEAR(b.flux_imbalance_lm(), 0.0, 1e-9 * b.emitted.flux_lm);
  const FarField fa = off->far_field(), fb = on->far_field();
  const double binned = static_cast<double>(fb.total_photons()) * b.photon_power_lm;
  EXPECT_NEAR(binned + n.covered_lm, b.escaped.flux_lm, 1e-9 * b.escaped.flux_lm);
  EXPECT_NEAR(fb.total_flux_lm(), binned + n.booked_lm, 1e-9 * b.escaped.flux_lm);
  // The covered escapes are the disc's direct ones, which the connections
  // book: they agree in expectation (a few per cent of the flux each, 3 %
  // is over 3 standard deviations here). Escapes after the volume counted
  // as covered would double the covered flux.
  ASSERT_GT(n.covered_lm, 0.0);
  std::printf("  disc under an open volume: booked %.3f lm, covered %.3f lm; far field %.3f lm with, %.3f lm "
              "without connections\n",
              n.booked_lm, n.covered_lm, fb.total_flux_lm(), fa.total_flux_lm());
  EXPECT_NEAR(n.booked_lm / n.covered_lm, 1.0, 0.03);
  // The far field's mean is the photon histogram's, region by region and
  // in total (the lost escapes would take several per cent of the flux).
  const std::vector<double> ra = regions(fa), rb = regions(fb);
  const double per_photon = off->ledger().photon_power_lm;
  for (std::size_t k = 0; k < ra.size(); ++k) {
    const double sigma = std::sqrt(2.0 * std::max(ra[k], per_photon) * per_photon);
    EXPECT_NEAR(rb[k], ra[k], 4.5 * sigma + 1e-3 * ra[k]) << "region " << k;
  }
  EXPECT_NEAR(fb.total_flux_lm() / fa.total_flux_lm(), 1.0, 0.01);
}

TEST(NextEvent, SameBytesWithOneOrTwoThreadsAndAnySplit) {
  const SceneDesc scene = test_scenes::mixed_scene();
  auto one = simulate(scene, run(NextEventMode::On, 1, 12000, 2));
  auto two = simulate(scene, run(NextEventMode::On, 2, 12000, 2));
  auto whole = simulate(scene, run(NextEventMode::On, 2, 24000, 1));
  ASSERT_TRUE(one.ok());
  ASSERT_TRUE(two.ok());
  ASSERT_TRUE(whole.ok());
  for (const auto* other : {&two, &whole}) {
    const FarField a = one->far_field(), b = (*other)->far_field();
    ASSERT_EQ(a.texel_count(), b.texel_count());
    EXPECT_EQ(std::memcmp(a.flux_lm().data(), b.flux_lm().data(), a.texel_count() * sizeof(double)), 0);
    EXPECT_EQ(one->next_event().connections, (*other)->next_event().connections);
    for (int r = 0; r < one->sobol_replicates(); ++r) {
      const FarField ra = one->replicate_far_field(r), rb = (*other)->replicate_far_field(r);
      EXPECT_EQ(std::memcmp(ra.flux_lm().data(), rb.flux_lm().data(), ra.texel_count() * sizeof(double)), 0);
    }
  }
}

TEST(NextEvent, ReplicatesCarryTheConnectionsUnderEitherSampler) {
  // The error estimate reads the replicates: with connections they must hold
  // them (their mean is the run's far field), also under the random sampler.
  for (SamplerKind sampler : {SamplerKind::Random, SamplerKind::Sobol}) {
    SimulationSettings s = run(NextEventMode::On, 2, 40000, 1);
    s.sampler = sampler;
    auto sim = simulate(opal_sphere(0.6, 0.3), s);
    ASSERT_TRUE(sim.ok());
    const int k = sim->sobol_replicates();
    ASSERT_EQ(k, kSobolReplicates);
    const FarField all = sim->far_field();
    double mean = 0.0;
    for (int r = 0; r < k; ++r) mean += sim->replicate_far_field(r).total_flux_lm() / k;
    EXPECT_NEAR(mean / all.total_flux_lm(), 1.0, 1e-9);
  }
}

TEST(NextEvent, AutoKeepsConnectionsWhereTheyEscapeAndOnlyWhereTheyPay) {
  // Inside a closed white box nothing escapes: the pilot keeps no mesh, and
  // auto stays off. The opal sphere: every escape covered, auto turns on.
  SceneDesc box_scene;
  Material white{"white", 0.8, 0.0, 0.0};
  box_scene.materials = {white};
  box_scene.meshes = {box(0.2, 0.2, 0.2)};
  Emitter e;
  e.flux_lm = 100.0;
  box_scene.emitters = {e};
  auto boxed = simulate(box_scene, run(NextEventMode::Auto, 2, 10000, 1));
  ASSERT_TRUE(boxed.ok());
  EXPECT_FALSE(boxed->next_event().enabled);
  ASSERT_EQ(boxed->next_event().mode, NextEventMode::Auto);
  auto opal = simulate(opal_sphere(0.6, 0.3), run(NextEventMode::Auto, 2, 10000, 1));
  ASSERT_TRUE(opal.ok());
  EXPECT_TRUE(opal->next_event().enabled);
  EXPECT_NEAR(opal->next_event().pilot_covered_share, 1.0, 1e-12);
  // A bare lamp: nothing to connect from.
  SceneDesc bare;
  bare.emitters = {e};
  auto lamp = simulate(bare, run(NextEventMode::Auto, 1, 1000, 1));
  ASSERT_TRUE(lamp.ok());
  EXPECT_FALSE(lamp->next_event().enabled);
}

TEST(NextEvent, RefusesGuidedEmissionAndBadCounts) {
  SimulationSettings s = run(NextEventMode::On, 1, 1000, 1);
  s.importance.enabled = true;
  auto guided = Simulation::create(opal_sphere(0.6, 0.3), s);
  ASSERT_FALSE(guided.ok());
  EXPECT_NE(guided.error().message.find("guided"), std::string::npos);
  s.next_event = NextEventMode::Auto;  // auto simply stays off
  auto quiet = Simulation::create(opal_sphere(0.6, 0.3), s);
  ASSERT_TRUE(quiet.ok());
  EXPECT_FALSE(quiet->next_event().enabled);
  SimulationSettings bad = run(NextEventMode::On, 1, 1000, 1);
  bad.next_event_connections = 0;
  EXPECT_FALSE(Simulation::create(opal_sphere(0.6, 0.3), bad).ok());
}

TEST(NextEvent, ModeNamesRoundTrip) {
  for (NextEventMode m : {NextEventMode::Off, NextEventMode::On, NextEventMode::Auto})
    EXPECT_EQ(parse_next_event_mode(to_string(m)), m);
  EXPECT_FALSE(parse_next_event_mode("yes").has_value());
}

}  // namespace
}  // namespace gonio::sim

namespace gonio::sim {
namespace {

// Issue 43: the photon's own escape from a connected vertex is one more
// sample of the vertex's direct escape, weighted against the M connections
// by the balance heuristic (both book power · f / (M·p + f)). The weights
// sum to one in every direction, so the far field keeps the photon
// histogram's mean for any M; a weight that does not (the connections
// booking f/p/M as before while the photon books its share, or the photon
// booking nothing) moves the reflected light by W/(M + W) of itself — a
// quarter to a half here. A Lambertian sheet (ρ = 0.8: W = ρ, the weights
// constant) and a rough mirror (the uncompensated glossy lobe, whose f/p
// varies with direction), each under a point lamp, M = 1 (where the photon's
// share is largest) and M = 3, on different seeds: 24 regions within 4.5σ
// of the histogram's Poisson noise (twice, bounding both), and the total
// flux within 4.5σ of its binomial noise (√2 for the two runs).
TEST(NextEvent, MisWeightedEstimateHasThePhotonHistogramsMeanOnASheetAndARoughMirror) {
  Material sheet;
  sheet.diffuse_reflect = 0.8;
  Material rough;
  rough.glossy = 0.9;
  rough.glossy_mx = 0.3;
  rough.glossy_my = 0.3;
  rough.glossy_f0 = 0.9;
  const std::pair<const char*, Material> cases[] = {{"lambertian sheet", sheet}, {"rough mirror", rough}};
  constexpr std::uint64_t kPerIteration = 60000;
  for (const auto& [name, material] : cases) {
    SCOPED_TRACE(name);
    const SceneDesc scene = lamp_over_disc(material);
    auto off = simulate(scene, run(NextEventMode::Off, 2, kPerIteration, 2, 5));
    ASSERT_TRUE(off.ok()) << off.error().message;
    const FarField a = off->far_field();
    const std::vector<double> ra = regions(a);
    const double per_photon = off->ledger().photon_power_lm;
    const double n = 2.0 * kPerIteration, escaped = a.total_flux_lm() / (per_photon * n);
    const double total_sigma = std::sqrt(2.0 * n * escaped * (1.0 - escaped)) * per_photon;
    for (int m : {1, 3}) {
      SCOPED_TRACE("M = " + std::to_string(m));
      SimulationSettings with = run(NextEventMode::On, 2, kPerIteration, 2, 6 + static_cast<std::uint64_t>(m));
      with.next_event_connections = m;
      auto on = simulate(scene, with);
      ASSERT_TRUE(on.ok()) << on.error().message;
      ASSERT_TRUE(on->next_event().enabled);
      const FarField b = on->far_field();
      const std::vector<double> rb = regions(b);
      for (std::size_t k = 0; k < ra.size(); ++k) {
        const double sigma = std::sqrt(2.0 * std::max(ra[k], per_photon) * per_photon);
        EXPECT_NEAR(rb[k], ra[k], 4.5 * sigma + 1e-3 * ra[k]) << "region " << k;
      }
      EXPECT_NEAR(b.total_flux_lm(), a.total_flux_lm(), 4.5 * total_sigma);
      // The photon's share is booked with the connections: booked and
      // covered agree in expectation (1 % at these counts).
      EXPECT_NEAR(on->next_event().booked_lm / on->next_event().covered_lm, 1.0, 0.01);
    }
  }
}

// The pilot's choice of M per mesh and side (choose_connections) on
// hand-made tallies: one side, slots as NextEventTally keeps them.
NextEventTally pilot_tally(std::uint64_t connections, std::uint64_t escaped, std::uint64_t covered,
                           std::uint64_t direct) {
  NextEventTally t;
  t.reset(6, 1, 1);
  const std::size_t slot = next_event_slot(0, false, Lobe::DiffuseReflect);
  t.slot_connections[slot] = connections;
  t.slot_escaped[slot] = escaped;
  t.slot_covered_units[slot] = covered;
  t.direct_units = direct;
  return t;
}

TEST(NextEvent, ConnectionsPerSideAreChosenByWhatTheyBuy) {
  // Every escape scattered there (a = 1), one vertex a photon at two rays
  // a photon (c·n = 0.5): T(M) = (1 + 0.5 M)/(M + 1) falls to the largest M.
  const std::uint64_t photons = 1000;
  ConnectionChoice all = choose_connections(pilot_tally(2000, 1500, 800, 0), 800, photons, 2, 2.0, 16);
  ASSERT_EQ(all.counts.size(), 2u);
  EXPECT_EQ(all.counts[0], 16);
  EXPECT_EQ(all.counts[1], 0);  // the back side: nothing there
  EXPECT_NEAR(all.variance_share, 1.0, 1e-12);
  EXPECT_NEAR(all.predicted_time, (1.0 + 0.5 * 16.0) / 17.0, 1e-12);
  EXPECT_TRUE(all.worthwhile);
  // The bell's pilot: a = 0.743 of the escaped power (a fifth straight from
  // the lamp, counted as noisy as the rest), c·n = 0.52: at best M = 1,
  // T = (0.257 + 0.743/2)·1.52 = 0.955 — not worth it (auto off).
  ConnectionChoice bell = choose_connections(pilot_tally(2080, 1800, 743, 200), 1000, photons, 2, 2.0, 16);
  EXPECT_EQ(bell.counts[0], 1);
  EXPECT_NEAR(bell.variance_share, 0.743, 1e-12);
  EXPECT_NEAR(bell.predicted_time, (0.257 + 0.743 / 2.0) * 1.52, 1e-9);
  EXPECT_FALSE(bell.worthwhile);
  // a = 0.95 at the same cost: T(M) = (0.05 + 0.95/(M + 1))·(1 + 0.52 M) is
  // least at M = 3 (0.736; 0.748 at 2, 0.739 at 4): on, with 3.
  ConnectionChoice most = choose_connections(pilot_tally(2080, 1800, 950, 0), 1000, photons, 2, 2.0, 16);
  EXPECT_EQ(most.counts[0], 3);
  EXPECT_NEAR(most.predicted_time, (0.05 + 0.95 / 4.0) * (1.0 + 3.0 * 0.52), 1e-9);
  EXPECT_TRUE(most.worthwhile);
  // Slots whose connections do not escape (under 5 %) get none; nothing
  // covered, nothing scattered, or a bare lamp: off.
  EXPECT_EQ(choose_connections(pilot_tally(2000, 50, 800, 0), 800, photons, 2, 2.0, 16).counts[0], 0);
  EXPECT_FALSE(choose_connections(pilot_tally(2000, 1500, 0, 0), 800, photons, 2, 2.0, 16).worthwhile);
  EXPECT_FALSE(choose_connections(pilot_tally(0, 0, 0, 800), 800, photons, 2, 1.0, 16).worthwhile);
  // Capped by --connections.
  EXPECT_EQ(choose_connections(pilot_tally(2000, 1500, 800, 0), 800, photons, 2, 2.0, 5).counts[0], 5);
}

// A side's own M (NextEventSettings::counts) weighs both its connections
// and the photon's share: the tracer with M = 1 on the disc's sides and 64
// elsewhere (--connections): the far field's power (binned + booked) has
// plain tracing's mean, booked and covered agree. Connections weighted with
// the 64 instead book 64·f/(64p + f) each against the photon's f/(p + f):
// 1.4× the covered power.
TEST(NextEvent, ASidesOwnConnectionCountWeighsItsConnectionsAndThePhotonsShare) {
  Material sheet;
  sheet.diffuse_reflect = 0.8;
  const SceneDesc scene = lamp_over_disc(sheet);
  TracerSettings ts;
  ts.sobol_replicates = 1;
  auto tracer = Tracer::create(scene, 8, ts);
  ASSERT_TRUE(tracer.ok()) << tracer.error().message;
  constexpr std::uint64_t kPhotons = 200000;
  const auto total_units = [&](const TracerTally& t) {
    double units = static_cast<double>(t.next_event.booked_units);
    for (std::size_t i = 0; i < t.texel_photons.size(); ++i)
      units += static_cast<double>(t.photons(i)) * static_cast<double>(kPowerUnits);
    return units;
  };
  TracerTally off = tracer->make_tally();
  tracer->trace_photons(3, 0, kPhotons, off);
  NextEventSettings ne;
  ne.enabled = true;
  ne.connections = 64;
  ne.counts = {1, 1};
  tracer->set_next_event(ne);
  TracerTally on = tracer->make_tally();
  tracer->trace_photons(4, 0, kPhotons, on);
  ASSERT_GT(on.next_event.connections, 0u);
  EXPECT_LE(on.next_event.connections, on.next_event.vertices);  // one a vertex
  const double p = total_units(off) / (static_cast<double>(kPhotons) * static_cast<double>(kPowerUnits));
  const double sigma = std::sqrt(2.0 * static_cast<double>(kPhotons) * p * (1.0 - p)) * static_cast<double>(kPowerUnits);
  EXPECT_NEAR(total_units(on), total_units(off), 4.5 * sigma);
  EXPECT_NEAR(static_cast<double>(on.next_event.booked_units) / static_cast<double>(on.next_event.covered_units), 1.0,
              0.02);
}

// Auto with M chosen per side: the lamp in the opal sphere (every escape
// scattered there: the largest M) and the mixed scene keep their closed
// form and the histogram's mean, with the connections and the photon's
// share weighted by the side's own M (a connection weighted with another
// side's M, or --connections', breaks the sum of the weights).
TEST(NextEvent, AutoWithConnectionsPerSideKeepsTheMean) {
  const double t = 0.6, r = 0.3, want = 1000.0 * t / (1.0 - r);
  SimulationSettings s = run(NextEventMode::Auto, 2, 100000, 2);
  s.next_event_connections = 24;
  auto sim = simulate(opal_sphere(t, r), s);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  ASSERT_TRUE(sim->next_event().enabled);
  EXPECT_EQ(sim->next_event().connections_per_vertex, 24);
  EXPECT_NEAR(sim->far_field().total_flux_lm() / want, 1.0, 0.005);

  const SceneDesc scene = test_scenes::mixed_scene();
  auto off = simulate(scene, run(NextEventMode::Off, 2, 80000, 2, 5));
  SimulationSettings a = run(NextEventMode::Auto, 2, 80000, 2, 6);
  a.next_event_connections = 40;
  auto on = simulate(scene, a);
  ASSERT_TRUE(off.ok());
  ASSERT_TRUE(on.ok());
  ASSERT_TRUE(on->next_event().enabled);
  EXPECT_LT(on->next_event().connections_per_vertex, 40);  // M chosen per side, not --connections
  std::printf("  mixed scene, auto: on %d, largest M %d, covered share %.3f\n", on->next_event().enabled ? 1 : 0,
              on->next_event().connections_per_vertex, on->next_event().pilot_covered_share);
  const std::vector<double> ra = regions(off->far_field()), rb = regions(on->far_field());
  const double per_photon = off->ledger().photon_power_lm;
  for (std::size_t k = 0; k < ra.size(); ++k) {
    const double sigma = std::sqrt(2.0 * std::max(ra[k], per_photon) * per_photon);
    EXPECT_NEAR(rb[k], ra[k], 4.5 * sigma + 1e-3 * ra[k]) << "region " << k;
  }
}

}  // namespace
}  // namespace gonio::sim
