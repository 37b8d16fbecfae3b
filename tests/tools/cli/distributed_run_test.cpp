// `gonio simulate` and `gonio bench` over the ranks of an MPI job (mpirun;
// tools/run/distributed_run.h, sim/distributed.h), against one process: the
// same bytes whatever the rank and thread counts, and faults (a rank
// without its model, a rank with another model, a rank that dies) that end
// the whole run with a message naming the rank and leave nothing in the
// output folder. Runs Open MPI's mpirun (ctest label `mpi`).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;

const std::string kSamples = GONIO_SAMPLES_DIR;

// mpirun as root needs its consent; several ranks on two cores need
// --oversubscribe, and no binding (a rank bound to one core would starve
// its threads).
class MpiRun : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(GONIO_MPIRUN))
      GONIO_MISSING(std::string(GONIO_MPIRUN) + " (scripts/setup.sh installs openmpi-bin)");
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  }

  static std::vector<std::string> mpirun(int ranks) {
    return {GONIO_MPIRUN, "--oversubscribe", "--bind-to", "none", "-n", std::to_string(ranks)};
  }

  // `gonio simulate MODEL --out OUT` with the run's options, as `ranks`
  // ranks of an MPI job, or as one plain process when ranks == 0.
  static test::ProcessResult simulate(int ranks, const std::string& model, const fs::path& out,
                                      const std::string& threads,
                                      const std::vector<std::string>& extra = {}) {
    std::vector<std::string> argv = ranks > 0 ? mpirun(ranks) : std::vector<std::string>{};
    for (const std::string& a : {std::string(GONIO_EXECUTABLE), std::string("simulate"), model,
                                std::string("--out"), out.string(), std::string("--photons"),
                                std::string("30000"), std::string("--iterations"), std::string("2"),
                                std::string("--seed"), std::string("7"), std::string("--threads"), threads})
      argv.push_back(a);
    argv.insert(argv.end(), extra.begin(), extra.end());
    return test::run_process(argv);
  }

  // Per-rank copies of the bell (glTF and its buffer) in dir/rank<R>/,
  // for a launcher line that names each rank's own model.
  static void copy_bell(const fs::path& dir, int rank) {
    const fs::path to = dir / ("rank" + std::to_string(rank));
    fs::create_directories(to);
    for (const char* f : {"bell.gltf", "bell.bin"}) fs::copy_file(fs::path(kSamples) / "bell" / f, to / f);
  }

  // mpirun -n N sh -c '... gonio simulate DIR/rank$RANK/bell.gltf --out OUT ...'
  // with `before` run by the shell first (the same shell process then
  // becomes gonio: $$ is gonio's process id).
  static test::ProcessResult simulate_per_rank(int ranks, const fs::path& dir, const fs::path& out,
                                               const std::string& before, const std::string& iterations) {
    std::vector<std::string> argv = mpirun(ranks);
    argv.insert(argv.end(),
                {"sh", "-c",
                 before + "exec \"$0\" simulate \"$1/rank$OMPI_COMM_WORLD_RANK/bell.gltf\" --out \"$2\" "
                          "--photons 100000 --iterations " + iterations + " --threads 1",
                 GONIO_EXECUTABLE, dir.string(), out.string()});
    return test::run_process(argv);
  }
};

nlohmann::json read_report(const fs::path& dir) {
  return nlohmann::json::parse(test::read_file(dir / "report.json"));
}

// The files and the photon counts must be the bytes of the plain run.
void expect_same_run(const fs::path& one, const fs::path& many, const std::string& what) {
  for (const char* f : {"farfield.exr", "bell.ies", "bell.ldt", "farfield-latlong.exr"})
    EXPECT_TRUE(test::read_file(one / f) == test::read_file(many / f)) << what << ": " << f << " differs";
  const nlohmann::json a = read_report(one), b = read_report(many);
  for (const char* key : {"photons_emitted", "photons_escaped", "photons_absorbed", "photons_cutoff",
                          "rays", "emitted_lm", "escaped_lm", "meshes", "materials", "emitters"})
    EXPECT_EQ(a[key], b[key]) << what << ": " << key;
}

bool folder_is_empty(const fs::path& dir) { return !fs::exists(dir) || fs::is_empty(dir); }

std::size_t entries(const fs::path& dir) {
  return fs::exists(dir) ? static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), {})) : 0;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST_F(MpiRun, ThreeRanksWriteTheBytesOfOneProcess) {
  test::TempDir dir;
  const std::string bell = kSamples + "/bell/bell.gltf";
  auto one = simulate(0, bell, dir / "one", "2", {"--preview"});
  ASSERT_EQ(one.exit_code, 0) << one.err;
  auto three = simulate(3, bell, dir / "three", "1", {"--preview", "--progress"});
  ASSERT_EQ(three.exit_code, 0) << three.err;
  expect_same_run(dir / "one", dir / "three", "3 ranks x 1 thread");
  // Rank 0's preview filters the summed far field: the same images.
  for (const char* f : {"preview.exr", "preview.png"})
    EXPECT_TRUE(test::read_file(dir / "one" / f) == test::read_file(dir / "three" / f)) << f << " differs";

  // Rank 0 alone printed the summary, and the report has each rank's share:
  // 2 iterations of 30000 photons in chunks of 4096 (8 per iteration: 3, 3
  // and 2 chunks to the ranks).
  EXPECT_TRUE(contains(three.out, "60000 photons in 2 iterations")) << three.out;
  EXPECT_TRUE(contains(three.out, "on 3 MPI ranks")) << three.out;
  std::size_t summaries = 0;
  for (std::size_t at = three.out.find("photons in 2 iterations"); at != std::string::npos;
       at = three.out.find("photons in 2 iterations", at + 1))
    ++summaries;
  EXPECT_EQ(summaries, 1u) << three.out;
  // --progress: rank 0 alone shows each iteration (the job's rate: photons
  // of every rank over rank 0's time).
  for (const char* line : {"simulate: iteration 1/2, ", "simulate: iteration 2/2, "}) {
    const std::size_t at = three.err.find(line);
    EXPECT_NE(at, std::string::npos) << three.err;
    EXPECT_EQ(three.err.find(line, at + 1), std::string::npos) << three.err;
  }
  const nlohmann::json mpi = read_report(dir / "three")["mpi"];
  ASSERT_EQ(mpi["ranks"], 3);
  ASSERT_EQ(mpi["per_rank"].size(), 3u);
  const std::uint64_t expected[] = {2 * 3 * 4096, 2 * 3 * 4096, 60000 - 2 * 6 * 4096};
  for (int r = 0; r < 3; ++r) {
    const nlohmann::json& pr = mpi["per_rank"][static_cast<std::size_t>(r)];
    EXPECT_EQ(pr["rank"], r);
    EXPECT_EQ(pr["photons"].get<std::uint64_t>(), expected[r]) << pr.dump();
    EXPECT_GT(pr["photons_per_s"].get<double>(), 0.0) << pr.dump();
  }
  const nlohmann::json single = read_report(dir / "one")["mpi"];
  EXPECT_EQ(single["ranks"], 1);
  EXPECT_EQ(single["per_rank"][0]["photons"], 60000);
}

// --sampler sobol: photon i is Sobol' point i of the seed's scramble on
// whichever rank traces it, so 3 ranks write one process's bytes too.
TEST_F(MpiRun, SobolSamplerThreeRanksWriteTheBytesOfOneProcess) {
  test::TempDir dir;
  const std::string bell = kSamples + "/bell/bell.gltf";
  auto one = simulate(0, bell, dir / "one", "2", {"--sampler", "sobol"});
  ASSERT_EQ(one.exit_code, 0) << one.err;
  auto three = simulate(3, bell, dir / "three", "1", {"--sampler", "sobol"});
  ASSERT_EQ(three.exit_code, 0) << three.err;
  expect_same_run(dir / "one", dir / "three", "sobol, 3 ranks x 1 thread");
  EXPECT_EQ(read_report(dir / "three")["settings"]["sampler"], "sobol");
}

// Slower (five MPI jobs): every rank count, more ranks than an iteration has
// chunks among them (7 ranks, 8 chunks: uneven shares), threads 1 and 2.
TEST_F(MpiRun, EveryRankAndThreadCountWritesTheSameBytes) {
  test::TempDir dir;
  const std::string bell = kSamples + "/bell/bell.gltf";
  auto one = simulate(0, bell, dir / "one", "1");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  for (int n : {1, 2, 3, 4, 7}) {
    const std::string threads = n % 2 == 0 ? "2" : "1";
    const fs::path out = dir / ("n" + std::to_string(n));
    auto r = simulate(n, bell, out, threads);
    ASSERT_EQ(r.exit_code, 0) << n << " ranks: " << r.err;
    expect_same_run(dir / "one", out, std::to_string(n) + " ranks x " + threads + " threads");
    EXPECT_EQ(read_report(out)["mpi"]["ranks"], n);
  }
}

TEST_F(MpiRun, ARankWithoutItsModelStopsEveryRankBeforeTracing) {
  test::TempDir dir;
  copy_bell(dir.path(), 0);
  copy_bell(dir.path(), 1);  // rank 2 has no model
  const fs::path out = dir / "out";
  auto r = simulate_per_rank(3, dir.path(), out, "", "2");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.err, "rank2/bell.gltf")) << r.err;  // rank 2's own error
  EXPECT_TRUE(contains(r.err, "gonio: simulate: rank 2 of 3 could not get ready")) << r.err;
  EXPECT_FALSE(contains(r.err, "rank 1 of 3")) << r.err;
  EXPECT_TRUE(contains(r.err, "nothing was traced")) << r.err;
  EXPECT_TRUE(folder_is_empty(out)) << entries(out);
}

TEST_F(MpiRun, RanksWithDifferentModelsAreRefusedBeforeTracing) {
  test::TempDir dir;
  for (int rank : {0, 1, 2}) copy_bell(dir.path(), rank);
  // Rank 1's buffer differs from the others' by one ulp of one vertex
  // coordinate strictly inside the bounds (a model that still loads and
  // passes its checks).
  const fs::path bin = dir / "rank1" / "bell.bin";
  std::string bytes = test::read_file(bin);
  bool nudged = false;
  for (std::size_t at = 0; at + 4 <= 12672 && !nudged; at += 4) {
    float v;
    std::memcpy(&v, bytes.data() + at, 4);
    if (std::abs(v) > 1e-3f && std::abs(v) < 0.1f) {
      v = std::nextafter(v, 0.0f);
      std::memcpy(bytes.data() + at, &v, 4);
      nudged = true;
    }
  }
  ASSERT_TRUE(nudged);
  test::write_file(bin, bytes);
  const fs::path out = dir / "out";
  auto r = simulate_per_rank(3, dir.path(), out, "", "2");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.err, "gonio: simulate: rank 1 of 3 holds another model")) << r.err;
  EXPECT_FALSE(contains(r.err, "rank 2 of 3")) << r.err;
  EXPECT_TRUE(folder_is_empty(out)) << entries(out);
}

TEST_F(MpiRun, ARankThatDiesEndsTheRunAndNamesTheRank) {
  test::TempDir dir;
  for (int rank : {0, 1, 2}) copy_bell(dir.path(), rank);
  const fs::path out = dir / "out";
  // Rank 1 is killed (SIGKILL) two seconds in, well before its 1000
  // iterations are done; the others are waiting for it in a reduction.
  auto r = simulate_per_rank(
      3, dir.path(), out, "if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then (sleep 2; kill -KILL $$) & fi; ", "1000");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.out + r.err, "rank 1")) << r.out << r.err;
  EXPECT_TRUE(contains(r.out + r.err, "signal 9")) << r.out << r.err;
  EXPECT_TRUE(folder_is_empty(out)) << entries(out);
}

// --target-error: every rank holds the summed far field, so every rank's
// estimate and its decision to stop are the same; the run stops where one
// process stops, with the same bytes. --serve is one process only.
TEST_F(MpiRun, TargetErrorStopsEveryRankWhereOneProcessStops) {
  test::TempDir dir;
  const std::string bell = kSamples + "/bell/bell.gltf";
  const std::vector<std::string> target = {"--iterations", "50", "--target-error", "2"};
  auto one = simulate(0, bell, dir / "one", "2", target);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  auto three = simulate(3, bell, dir / "three", "1", target);
  ASSERT_EQ(three.exit_code, 0) << three.err;
  expect_same_run(dir / "one", dir / "three", "3 ranks, target error");
  const nlohmann::json a = read_report(dir / "one"), b = read_report(dir / "three");
  EXPECT_EQ(a["stopped_by"], "target-error");
  EXPECT_EQ(b["stopped_by"], "target-error");
  EXPECT_EQ(a["iterations_done"], b["iterations_done"]);
  EXPECT_LT(a["iterations_done"].get<int>(), 50);

  auto serve = simulate(2, bell, dir / "serve", "1", {"--serve"});
  EXPECT_EQ(serve.exit_code, 2);
  EXPECT_TRUE(contains(serve.err, "--serve runs in one process")) << serve.err;
}

// gonio bench's reference run is shared by the ranks: the same reference
// bytes (and its noise, measured from its halves) as one process traces.
TEST_F(MpiRun, BenchSharesItsReferenceRunAcrossRanks) {
  test::TempDir dir;
  const std::string bell = kSamples + "/bell/bell.gltf";
  auto bench = [&](int ranks, const fs::path& out) {
    std::vector<std::string> argv = ranks > 0 ? mpirun(ranks) : std::vector<std::string>{};
    for (const std::string& a : {std::string(GONIO_EXECUTABLE), std::string("bench"), bell, std::string("--out"),
                                 out.string(), std::string("--photons"), std::string("32768"),
                                 std::string("--reference"), std::string("200000"), std::string("--threads"),
                                 std::string("1"), std::string("--no-png")})
      argv.push_back(a);
    return test::run_process(argv);
  };
  auto one = bench(0, dir / "one");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  auto three = bench(3, dir / "three");
  ASSERT_EQ(three.exit_code, 0) << three.err;
  EXPECT_TRUE(test::read_file(dir / "one" / "reference.exr") == test::read_file(dir / "three" / "reference.exr"));
  const auto a = nlohmann::json::parse(test::read_file(dir / "one" / "reference.json"));
  const auto b = nlohmann::json::parse(test::read_file(dir / "three" / "reference.json"));
  EXPECT_EQ(a["key"], b["key"]);
  EXPECT_EQ(a["noise"], b["noise"]);
  // Rank 0 alone ran the series and printed its summary.
  std::size_t summaries = 0;
  for (std::size_t at = three.out.find("reference 200000 photons"); at != std::string::npos;
       at = three.out.find("reference 200000 photons", at + 1))
    ++summaries;
  EXPECT_EQ(summaries, 1u) << three.out;
  EXPECT_TRUE(fs::exists(dir / "three" / "bench.json"));
}

}  // namespace
}  // namespace gonio
