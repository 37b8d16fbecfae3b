// Simulation over the ranks of an MPI job, in process: every rank runs the
// job's simulation (SimulationSettings::ranks) and the same simulation alone
// (no ranks), and the two must be the same bytes — plain and importance-
// guided emission (whose guide learns from the summed counts), iterations
// of uneven sizes, more ranks than an iteration has chunks. Run by ctest
// under `mpirun -n 3` (label `mpi`); its own main joins the job, and every
// rank's result counts.
//
// Every rank must reach every collective: no ASSERT between them.
#include <gtest/gtest.h>

#include <cstdio>
#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "sim/distributed.h"
#include "sim/distributed_gather.h"
#include "sim/simulation.h"
#include "tests/sim/scenes.h"

namespace gonio::sim {
namespace {

const Ranks* g_ranks = nullptr;

SimulationSettings settings(int threads, std::uint64_t per_iteration, int iterations, bool guided) {
  SimulationSettings s = test_scenes::small_run(threads, per_iteration, iterations, 91);
  s.importance.enabled = guided;
  s.importance.emission_face_size = 8;
  s.near_field_distances_m = {0.05, 1.0};  // its counts are summed over the ranks too
  return s;
}

void expect_identical(const Simulation& job, const Simulation& alone) {
  const FarField a = job.far_field(), b = alone.far_field();
  ASSERT_EQ(a.texel_count(), b.texel_count());
  EXPECT_EQ(std::memcmp(a.flux_lm().data(), b.flux_lm().data(), a.texel_count() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(a.photons().data(), b.photons().data(), a.texel_count() * sizeof(std::uint64_t)), 0);
  // Sobol' replicates (the error estimate's): summed across the ranks too.
  ASSERT_EQ(job.sobol_replicates(), alone.sobol_replicates());
  for (int r = 0; r < job.sobol_replicates(); ++r) {
    const FarField ra = job.replicate_far_field(r), rb = alone.replicate_far_field(r);
    EXPECT_EQ(std::memcmp(ra.photons().data(), rb.photons().data(), ra.texel_count() * sizeof(std::uint64_t)), 0)
        << "replicate " << r;
  }
  const Ledger la = job.ledger(), lb = alone.ledger();
  EXPECT_EQ(la.emitted.photons, lb.emitted.photons);
  EXPECT_EQ(la.escaped.photons, lb.escaped.photons);
  EXPECT_EQ(la.absorbed.photons, lb.absorbed.photons);
  EXPECT_EQ(la.cutoff.photons, lb.cutoff.photons);
  EXPECT_EQ(std::memcmp(&la.escaped.flux_lm, &lb.escaped.flux_lm, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&la.emitted.flux_lm, &lb.emitted.flux_lm, sizeof(double)), 0);
  ASSERT_EQ(la.meshes.size(), lb.meshes.size());
  for (std::size_t i = 0; i < la.meshes.size(); ++i) {
    EXPECT_EQ(la.meshes[i].hits, lb.meshes[i].hits);
    EXPECT_EQ(la.meshes[i].absorbed.photons, lb.meshes[i].absorbed.photons);
    EXPECT_EQ(la.meshes[i].cutoff.photons, lb.meshes[i].cutoff.photons);
  }
  const std::vector<NearFieldPlane> na = job.near_field(), nb = alone.near_field();
  EXPECT_EQ(na.size(), 2u);
  EXPECT_EQ(na.size(), nb.size());
  for (std::size_t k = 0; k < std::min(na.size(), nb.size()); ++k) {
    EXPECT_EQ(na[k].near_lx, nb[k].near_lx);
    EXPECT_EQ(na[k].far_lx, nb[k].far_lx);
    EXPECT_EQ(na[k].upper_bound_pct, nb[k].upper_bound_pct);
    EXPECT_EQ(na[k].verdict, nb[k].verdict);
  }
  const SimulationStats sa = job.stats(), sb = alone.stats();
  EXPECT_EQ(sa.photons, sb.photons);
  EXPECT_EQ(sa.photons_traced, sb.photons_traced);
  EXPECT_EQ(sa.rays, sb.rays);
  EXPECT_EQ(sa.ranks, g_ranks->size());
}

// The ranks' shares add up to the run, each rank's its own.
void expect_shares_add_up(const Simulation& job) {
  std::uint64_t sum = 0;
  for (std::uint64_t p : g_ranks->gather(job.stats().rank_photons)) sum += p;
  EXPECT_EQ(sum, job.stats().photons);
  EXPECT_LT(job.stats().rank_photons, job.stats().photons);
}

// Iterations of 5000 (2 chunks: with 3 ranks one traces nothing), 70000
// (18 chunks) and 1 photon, over the ranks and in one process: the same
// bytes, and the ranks' shares add up.
void expect_uneven_iterations_alike(const SceneDesc& scene, SimulationSettings s) {
  auto alone = Simulation::create(scene, s);
  s.ranks = g_ranks;
  auto job = Simulation::create(scene, s);
  EXPECT_TRUE(alone.ok() && job.ok());
  if (!alone.ok() || !job.ok()) return;
  for (std::uint64_t n : {5000ull, 70000ull, 1ull}) {
    alone->run_iteration(n);
    job->run_iteration(n);
  }
  expect_identical(job.value(), alone.value());
  expect_shares_add_up(job.value());
}

TEST(DistributedSimulation, ThisIsAJobOfSeveralRanks) { EXPECT_GE(g_ranks->size(), 2); }

TEST(DistributedSimulation, PlainEmissionGivesTheBytesOfOneProcess) {
  const SceneDesc scene = test_scenes::mixed_scene();
  for (int threads : {1, 2}) {
    SimulationSettings s = settings(threads, 30000, 2, false);
    auto alone = simulate(scene, s);
    s.ranks = g_ranks;
    auto job = simulate(scene, s);
    EXPECT_TRUE(alone.ok() && job.ok());
    if (!alone.ok() || !job.ok()) continue;  // both fail on every rank alike
    expect_identical(job.value(), alone.value());
    expect_shares_add_up(job.value());
  }
}

TEST(DistributedSimulation, GuidedEmissionLearnsTheSameGuideOnEveryRank) {
  const SceneDesc scene = test_scenes::mixed_scene();
  SimulationSettings s = settings(2, 20000, 4, true);
  auto alone = simulate(scene, s);
  s.ranks = g_ranks;
  auto job = simulate(scene, s);
  EXPECT_TRUE(alone.ok() && job.ok());
  if (!alone.ok() || !job.ok()) return;
  expect_identical(job.value(), alone.value());
  // The guide after four updates: the same acceptance everywhere, and it
  // did learn (some texel below 1), so the comparison has teeth.
  const EmissionGuide* a = job->emission_guide();
  const EmissionGuide* b = alone->emission_guide();
  EXPECT_TRUE(a && b);
  if (!a || !b) return;
  double smallest = 1.0;
  for (std::uint32_t e = 0; e < a->emission_grid().texel_count(); ++e) {
    EXPECT_EQ(a->power_units(e), b->power_units(e)) << e;
    smallest = std::min(smallest, b->acceptance(e));
  }
  EXPECT_LT(smallest, 1.0);
  EXPECT_LT(job->stats().photons_traced, job->stats().photons);  // guided emission dropped some
}

// Next-event estimation and luminance images: their units (per texel, per
// replicate, per image pixel) and counts are summed across the ranks like
// the far field's; the pilot that chooses the slots is the same photons on
// every rank.
TEST(DistributedSimulation, NextEventAndLuminanceImagesGiveTheBytesOfOneProcess) {
  const SceneDesc scene = test_scenes::mixed_scene();
  SimulationSettings s = settings(2, 20000, 2, false);
  s.next_event = NextEventMode::On;
  s.luminance.views = ugr_luminance_views();
  s.luminance.pixel_m = 0.004;
  auto alone = simulate(scene, s);
  s.ranks = g_ranks;
  auto job = simulate(scene, s);
  EXPECT_TRUE(alone.ok() && job.ok());
  if (!alone.ok() || !job.ok()) return;
  expect_identical(job.value(), alone.value());
  EXPECT_TRUE(job->next_event().enabled);
  EXPECT_EQ(job->next_event().connections, alone->next_event().connections);
  EXPECT_EQ(job->next_event().booked_lm, alone->next_event().booked_lm);
  for (int r = 0; r < job->sobol_replicates(); ++r) {
    const FarField ra = job->replicate_far_field(r), rb = alone->replicate_far_field(r);
    EXPECT_EQ(std::memcmp(ra.flux_lm().data(), rb.flux_lm().data(), ra.texel_count() * sizeof(double)), 0) << r;
  }
  const std::vector<LuminanceImage> ia = job->luminance_images(), ib = alone->luminance_images();
  EXPECT_EQ(ia.size(), 4u);
  EXPECT_EQ(ia.size(), ib.size());
  double total = 0.0;
  for (std::size_t k = 0; k < std::min(ia.size(), ib.size()); ++k) {
    EXPECT_EQ(ia[k].cd_m2, ib[k].cd_m2) << k;
    total += ia[k].intensity_cd;
  }
  EXPECT_GT(total, 0.0);
}

TEST(DistributedSimulation, UnevenIterationsAndRanksWithoutChunks) {
  const SceneDesc scene = test_scenes::mixed_scene();
  expect_uneven_iterations_alike(scene, settings(1, 1, 1, false));
}

// The Sobol' sampler (sim/samplers/sampler.h): photon i is point ⌊i/K⌋ of replicate
// i mod K's scramble whichever rank and thread traces it — plain and guided,
// even and uneven iterations, the replicates' far fields as well.
TEST(DistributedSimulation, SobolSamplerGivesTheBytesOfOneProcess) {
  const SceneDesc scene = test_scenes::mixed_scene();
  for (int threads : {1, 2}) {
    for (bool guided : {false, true}) {
      SimulationSettings s = settings(threads, 30000, guided ? 4 : 2, guided);
      s.sampler = SamplerKind::Sobol;
      auto alone = simulate(scene, s);
      s.ranks = g_ranks;
      auto job = simulate(scene, s);
      EXPECT_TRUE(alone.ok() && job.ok());
      if (!alone.ok() || !job.ok()) continue;
      expect_identical(job.value(), alone.value());
      expect_shares_add_up(job.value());
      EXPECT_EQ(job->sobol_replicates(), guided ? 0 : kSobolReplicates);
    }
  }
  SimulationSettings s = settings(2, 1, 1, false);
  s.sampler = SamplerKind::Sobol;
  expect_uneven_iterations_alike(scene, s);
}

// gather_bytes in rounds of a few bytes (as a payload beyond 2³¹ bytes
// travels in rounds of kMaxBytesPerMpiCall): the bytes of one call, and of
// the payloads themselves — uneven sizes, an empty rank, sizes that are and
// are not a multiple of a rank's share of a round, zero bytes inside.
std::string payload(int rank, int pattern) {
  static const std::size_t sizes[3][5] = {{23, 0, 50, 21, 1}, {0, 21, 1, 6, 0}, {0, 0, 0, 0, 0}};
  const std::size_t n = sizes[pattern][rank % 5];
  std::string bytes(n, '\0');
  for (std::size_t i = 0; i < n; ++i)
    bytes[i] = static_cast<char>((i * 37 + static_cast<std::size_t>(rank) * 101 + 3) % 256);
  return bytes;
}

TEST(DistributedGather, PiecesOfAnySizeGiveTheBytesOfOneCall) {
  for (int pattern = 0; pattern < 3; ++pattern) {
    const std::string mine = payload(g_ranks->rank(), pattern);
    const std::vector<std::string> whole = gather_bytes(*g_ranks, mine);
    EXPECT_EQ(whole.size(), static_cast<std::size_t>(g_ranks->size()));
    for (int r = 0; r < std::min(g_ranks->size(), static_cast<int>(whole.size())); ++r)
      EXPECT_EQ(whole[static_cast<std::size_t>(r)], payload(r, pattern)) << "pattern " << pattern << ", rank " << r;
    for (std::size_t per_call : {1u, 2u, 3u, 7u, 8u, 21u, 64u, 1000u}) {
      const std::vector<std::string> pieces = gather_bytes(*g_ranks, mine, per_call);
      EXPECT_EQ(pieces, whole) << "pattern " << pattern << ", at most " << per_call << " bytes a call";
    }
  }
}

TEST(DistributedGather, SumsInPiecesOfAnySizeGiveTheSumsOfOneCall) {
  const std::size_t n = 29;
  std::vector<std::uint64_t> expected(n, 0);
  for (int r = 0; r < g_ranks->size(); ++r)
    for (std::size_t i = 0; i < n; ++i) expected[i] += (i + 1) * 1000003u + static_cast<std::uint64_t>(r) * 7919u;
  const auto mine = [&] {
    std::vector<std::uint64_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = (i + 1) * 1000003u + static_cast<std::uint64_t>(g_ranks->rank()) * 7919u;
    return v;
  };
  std::vector<std::uint64_t> whole = mine();
  g_ranks->sum(whole);
  EXPECT_EQ(whole, expected);
  for (std::size_t per_call : {1u, 4u, 7u, 28u, 29u, 100u}) {
    std::vector<std::uint64_t> pieces = mine();
    sum_in_pieces(*g_ranks, pieces, per_call);
    EXPECT_EQ(pieces, expected) << "at most " << per_call << " values a call";
  }
}

}  // namespace
}  // namespace gonio::sim

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  auto ranks = gonio::sim::Ranks::join_job();
  if (!ranks.ok()) {
    std::fprintf(stderr, "%s\n", ranks.error().message.c_str());
    return 1;
  }
  gonio::sim::g_ranks = &ranks.value();
  // Rank 0 prints; every rank's failures count.
  if (ranks->rank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int result = RUN_ALL_TESTS();
  const std::vector<std::uint64_t> results = ranks->gather(static_cast<std::uint64_t>(result != 0));
  for (std::size_t r = 0; r < results.size(); ++r)
    if (results[r] != 0) {
      if (ranks->rank() == 0) std::fprintf(stderr, "%s failed\n", ranks->name_of(static_cast<int>(r)).c_str());
      return 1;
    }
  return 0;
}
