#include "sim/simulation.h"

#include <gtest/gtest.h>

#include <cstring>

#include "sim/shapes.h"
#include "tests/sim/scenes.h"

namespace gonio::sim {
namespace {

using test_scenes::mixed_scene;

SimulationSettings settings(int threads, std::uint64_t per_iteration, int iterations) {
  return test_scenes::small_run(threads, per_iteration, iterations, 77);
}

void expect_identical(const Simulation& a, const Simulation& b) {
  const FarField fa = a.far_field(), fb = b.far_field();
  ASSERT_EQ(fa.texel_count(), fb.texel_count());
  EXPECT_EQ(std::memcmp(fa.flux_lm().data(), fb.flux_lm().data(), fa.texel_count() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(fa.photons().data(), fb.photons().data(),
                        fa.texel_count() * sizeof(std::uint64_t)), 0);
  ASSERT_EQ(a.sobol_replicates(), b.sobol_replicates());
  for (int r = 0; r < a.sobol_replicates(); ++r) {
    const FarField ra = a.replicate_far_field(r), rb = b.replicate_far_field(r);
    EXPECT_EQ(std::memcmp(ra.photons().data(), rb.photons().data(), ra.texel_count() * sizeof(std::uint64_t)), 0)
        << "replicate " << r;
    EXPECT_EQ(std::memcmp(ra.flux_lm().data(), rb.flux_lm().data(), ra.texel_count() * sizeof(double)), 0)
        << "replicate " << r;
  }
  const Ledger la = a.ledger(), lb = b.ledger();
  EXPECT_EQ(la.escaped.photons, lb.escaped.photons);
  EXPECT_EQ(std::memcmp(&la.escaped.flux_lm, &lb.escaped.flux_lm, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&la.absorbed.flux_lm, &lb.absorbed.flux_lm, sizeof(double)), 0);
  ASSERT_EQ(la.meshes.size(), lb.meshes.size());
  for (std::size_t i = 0; i < la.meshes.size(); ++i) {
    EXPECT_EQ(la.meshes[i].hits, lb.meshes[i].hits);
    EXPECT_EQ(la.meshes[i].absorbed.photons, lb.meshes[i].absorbed.photons);
    EXPECT_EQ(std::memcmp(&la.meshes[i].absorbed.flux_lm, &lb.meshes[i].absorbed.flux_lm, sizeof(double)), 0);
  }
}

TEST(Simulation, SameBytesWithOneOrTwoThreadsAndAnySplit) {
  const SceneDesc scene = mixed_scene();
  auto one = simulate(scene, settings(1, 30000, 2));
  auto two = simulate(scene, settings(2, 30000, 2));
  auto whole = simulate(scene, settings(2, 60000, 1));
  ASSERT_TRUE(one.ok()) << one.error().message;
  ASSERT_TRUE(two.ok());
  ASSERT_TRUE(whole.ok());
  expect_identical(one.value(), two.value());
  expect_identical(one.value(), whole.value());
  EXPECT_EQ(two->stats().threads, 2);
  // A different seed gives a different far field.
  SimulationSettings other = settings(2, 30000, 2);
  other.seed = 78;
  auto three = simulate(scene, other);
  ASSERT_TRUE(three.ok());
  EXPECT_NE(three->ledger().escaped.photons, one->ledger().escaped.photons);
}

TEST(Simulation, SobolSamplerGivesTheSameBytesForAnyThreadsAndSplit) {
  // Photon i is Sobol' point ⌊i/K⌋ of replicate i mod K (sim/samplers/sampler.h): no
  // state crosses photons; the replicates' far fields are the same bytes too.
  const SceneDesc scene = mixed_scene();
  auto with = [](int threads, std::uint64_t per_iteration, int iterations) {
    SimulationSettings s = settings(threads, per_iteration, iterations);
    s.sampler = SamplerKind::Sobol;
    return s;
  };
  auto one = simulate(scene, with(1, 30000, 2));
  auto two = simulate(scene, with(2, 30000, 2));
  auto whole = simulate(scene, with(2, 60000, 1));
  ASSERT_TRUE(one.ok()) << one.error().message;
  ASSERT_TRUE(two.ok());
  ASSERT_TRUE(whole.ok());
  expect_identical(one.value(), two.value());
  expect_identical(one.value(), whole.value());
  // Uneven iterations (as progressive schedules and slices run them).
  auto uneven = Simulation::create(scene, with(2, 1, 1));
  ASSERT_TRUE(uneven.ok());
  for (std::uint64_t n : {std::uint64_t{1}, std::uint64_t{4095}, std::uint64_t{10000}, std::uint64_t{45904}})
    uneven->run_iteration(n);
  expect_identical(one.value(), uneven.value());
  // Another sampler, another far field; the ledger closes under both.
  auto random = simulate(scene, settings(2, 60000, 1));
  ASSERT_TRUE(random.ok());
  EXPECT_NE(random->ledger().escaped.photons, one->ledger().escaped.photons);
  EXPECT_TRUE(one->ledger().photons_close());
  EXPECT_EQ(one->ledger().emitted.photons, 60000u);
  // The replicates split the photons: their counts add up to the far
  // field's, texel by texel, and each carries the flux of its own photons.
  EXPECT_EQ(random->sobol_replicates(), 0);
  ASSERT_EQ(one->sobol_replicates(), kSobolReplicates);
  const FarField all = one->far_field();
  std::vector<std::uint64_t> sum(all.texel_count(), 0);
  double flux = 0.0;
  for (int r = 0; r < kSobolReplicates; ++r) {
    const FarField f = one->replicate_far_field(r);
    for (std::size_t t = 0; t < f.texel_count(); ++t) sum[t] += f.photons(t);
    flux += f.total_flux_lm();
  }
  EXPECT_EQ(std::memcmp(sum.data(), all.photons().data(), sum.size() * sizeof(std::uint64_t)), 0);
  // 60000 = 8 · 7500: equal shares, so the replicates' mean flux is the field's.
  EXPECT_NEAR(flux / kSobolReplicates, all.total_flux_lm(), 1e-9 * all.total_flux_lm());
  // One replicate: no replicates counted, photon i is point i.
  SimulationSettings single = with(2, 60000, 1);
  single.sobol_replicates = 1;
  auto k1 = simulate(scene, single);
  ASSERT_TRUE(k1.ok());
  EXPECT_EQ(k1->sobol_replicates(), 0);
  EXPECT_NE(k1->ledger().escaped.photons, one->ledger().escaped.photons);
  single.sobol_replicates = kMaxSobolReplicates + 1;
  EXPECT_FALSE(Simulation::create(scene, single).ok());
}

TEST(Simulation, LedgerClosesAndTheFarFieldHoldsTheEscapedFlux) {
  auto r = simulate(mixed_scene(), settings(2, 40000, 2));
  ASSERT_TRUE(r.ok());
  const Ledger l = r->ledger();
  EXPECT_TRUE(l.photons_close());
  EXPECT_EQ(l.emitted.photons, 80000u);
  EXPECT_NEAR(l.emitted.flux_lm, 1000.0, 1e-9);
  EXPECT_NEAR(l.flux_imbalance_lm(), 0.0, 1e-9);
  // The glossy lobe never changes a photon's power: every escape carries
  // the nominal power.
  EXPECT_NEAR(l.escaped.flux_lm, static_cast<double>(l.escaped.photons) * l.photon_power_lm,
              1e-9 * l.emitted.flux_lm);
  EXPECT_GT(l.absorbed.photons, 0u);
  // Per emitter: chosen by flux (800 : 200), each closing.
  ASSERT_EQ(l.emitters.size(), 2u);
  EXPECT_NEAR(l.emitters[0].emitted.photons / 80000.0, 0.8, 0.01);
  for (const EmitterLedger& e : l.emitters)
    EXPECT_EQ(e.emitted.photons, e.escaped.photons + e.absorbed.photons + e.cutoff.photons);
  // Per mesh and per material the absorbed photons add up to the total.
  std::uint64_t mesh_absorbed = 0, material_absorbed = 0;
  for (const MeshLedger& m : l.meshes) mesh_absorbed += m.absorbed.photons;
  for (const MaterialLedger& m : l.materials) material_absorbed += m.absorbed.photons;
  EXPECT_EQ(mesh_absorbed, l.absorbed.photons);
  EXPECT_EQ(material_absorbed, l.absorbed.photons);
  EXPECT_EQ(l.meshes[1].material, "brushed");
  const FarField f = r->far_field();
  EXPECT_EQ(f.total_photons(), l.escaped.photons);
  EXPECT_NEAR(f.total_flux_lm(), l.escaped.flux_lm, 1e-9 * l.escaped.flux_lm);
  const SimulationStats st = r->stats();
  EXPECT_EQ(st.photons, 80000u);
  EXPECT_EQ(st.iterations_done, 2);
  EXPECT_GE(st.rays, st.photons);
}

TEST(Simulation, ProgressAfterEveryIteration) {
  std::vector<int> seen;
  auto r = simulate(mixed_scene(), settings(1, 5000, 3),
                    [&](const SimulationProgress& p, const Simulation& s) {
                      seen.push_back(p.iteration);
                      EXPECT_EQ(p.iterations, 3);
                      EXPECT_EQ(p.photons_done, 5000u * p.iteration);
                      EXPECT_EQ(p.photons_total, 15000u);
                      EXPECT_EQ(s.stats().photons, p.photons_done);
                      EXPECT_GE(p.remaining_s, 0.0);
                    });
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(seen, (std::vector<int>{1, 2, 3}));
}

TEST(Simulation, DefaultFaceSizeServesA2Point5DegreeGrid) {
  EXPECT_EQ(SimulationSettings{}.face_size, CubeMapGrid::face_size_for_step(2.5));
}

TEST(Simulation, RejectsBadSettings) {
  EXPECT_FALSE(Simulation::create(mixed_scene(), settings(1, 0, 1)).ok());
  EXPECT_FALSE(Simulation::create(mixed_scene(), settings(1, 10, 0)).ok());
  EXPECT_FALSE(Simulation::create(mixed_scene(), settings(-1, 10, 1)).ok());
  SimulationSettings s = settings(1, 10, 1);
  s.max_bounces = -1;
  EXPECT_FALSE(Simulation::create(mixed_scene(), s).ok());
  s = settings(1, 10, 1);
  s.face_size = 0;
  EXPECT_FALSE(Simulation::create(mixed_scene(), s).ok());
}

// gonio watch's reuse: a simulation of the same geometry shares an earlier
// one's BVH (same hits, so the same far field), whatever else changed;
// other geometry or Embree options build their own.
TEST(Simulation, AnEarlierSimulationsBvhServesTheSameGeometry) {
  const SceneDesc scene = mixed_scene();
  auto first = Simulation::create(scene, settings(2, 20000, 1));
  ASSERT_TRUE(first.ok());
  EXPECT_FALSE(first->stats().tracer_setup.bvh_reused);
  first->run_iteration();

  auto again = Simulation::create(scene, settings(2, 20000, 1), &first.value());
  ASSERT_TRUE(again.ok());
  EXPECT_TRUE(again->stats().tracer_setup.bvh_reused);
  EXPECT_EQ(&again->tracer().embree(), &first->tracer().embree());
  again->run_iteration();
  const FarField a = first->far_field(), b = again->far_field();
  for (std::size_t t = 0; t < a.texel_count(); ++t) ASSERT_EQ(a.photons(t), b.photons(t)) << t;

  SceneDesc material = scene;
  material.materials[0].diffuse_reflect = 0.05;
  material.emitters[0].flux_lm = 400.0;
  auto edited = Simulation::create(material, settings(2, 20000, 1), &first.value());
  ASSERT_TRUE(edited.ok());
  EXPECT_TRUE(edited->stats().tracer_setup.bvh_reused);
  edited->run_iteration();
  EXPECT_NE(edited->ledger().escaped.photons, first->ledger().escaped.photons);

  SceneDesc moved = scene;
  moved.meshes[1].positions[0].x += 1e-4f;
  auto rebuilt = Simulation::create(moved, settings(2, 20000, 1), &first.value());
  ASSERT_TRUE(rebuilt.ok());
  EXPECT_FALSE(rebuilt->stats().tracer_setup.bvh_reused);
  EXPECT_NE(&rebuilt->tracer().embree(), &first->tracer().embree());

  SimulationSettings fragile = settings(2, 20000, 1);
  fragile.robust_embree = false;
  auto other = Simulation::create(scene, fragile, &first.value());
  ASSERT_TRUE(other.ok());
  EXPECT_FALSE(other->stats().tracer_setup.bvh_reused);
}

// The escapes kept (capture_escaped_photons) come out in photon order and
// the same whatever the threads and the split into iterations (iterations
// that do not start at a multiple of kChunkPhotons included): the merge puts
// the threads' chunks in order instead of sorting every escape (issue 40).
TEST(Simulation, KeptEscapesAreInPhotonOrderWhateverTheThreadsAndSplit) {
  const SceneDesc scene = mixed_scene();
  const auto run = [&](int threads, const std::vector<std::uint64_t>& split) {
    SimulationSettings s = settings(threads, split.front(), 1);
    s.capture_escaped_photons = 50'000;
    Result<Simulation> sim = Simulation::create(scene, s);
    EXPECT_TRUE(sim.ok());
    for (std::uint64_t n : split) sim->run_iteration(n);
    return sim->escaped_rays();
  };
  const std::vector<EscapedRay> one = run(1, {60'000});
  ASSERT_GT(one.size(), 10'000u);
  EXPECT_LT(one.back().photon, 50'000u);
  for (std::size_t i = 1; i < one.size(); ++i) ASSERT_LT(one[i - 1].photon, one[i].photon) << i;
  for (const auto& [threads, split] : {std::pair<int, std::vector<std::uint64_t>>{2, {60'000}},
                                       {3, {7'000, 13'001, 39'999}}, {2, {5'000, 5'000, 50'000}}}) {
    const std::vector<EscapedRay> other = run(threads, split);
    ASSERT_EQ(other.size(), one.size()) << threads << " threads";
    for (std::size_t i = 0; i < one.size(); ++i) {
      ASSERT_EQ(other[i].photon, one[i].photon) << i;
      ASSERT_EQ(std::memcmp(&other[i].origin, &one[i].origin, sizeof(Vec3)), 0) << i;
      ASSERT_EQ(std::memcmp(&other[i].direction, &one[i].direction, sizeof(Vec3)), 0) << i;
      ASSERT_EQ(other[i].power_units, one[i].power_units) << i;
    }
  }
}

}  // namespace
}  // namespace gonio::sim
