// `gonio tolerance` over the ranks of an MPI job (docs/tolerance.md, "Trials
// over MPI ranks"): the noise, sensitivity and Monte Carlo traces split over
// the ranks, rank 0 writing DIR. report.json must be the bytes of one process
// for any rank count and any --parallel-trials, and a run resumed from the
// journal of an interrupted MPI run too. Runs Open MPI's mpirun (label `mpi`).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;

// As MpiRun (distributed_run_test.cpp): root's consent, --oversubscribe and
// no binding on a machine with fewer cores than ranks.
class MpiTolerance : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(GONIO_MPIRUN))
      GONIO_MISSING(std::string(GONIO_MPIRUN) + " (scripts/setup.sh installs openmpi-bin)");
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  }

  // `gonio tolerance` of the sample downlight as `ranks` ranks (0: one plain
  // process): the LED's x, the reflector's reflectance, 2 noise seeds, 7
  // trials, three limits that the reflectance crosses (three bisections of
  // the traced inverse, 1 step each; the LED's x is below the noise).
  static test::ProcessResult tolerance(int ranks, const fs::path& dir, const std::string& out,
                                       const std::vector<std::string>& extra = {}) {
    std::vector<std::string> argv;
    if (ranks > 0)
      argv = {GONIO_MPIRUN, "--oversubscribe", "--bind-to", "none", "-n", std::to_string(ranks)};
    for (const std::string& a :
         {std::string(GONIO_EXECUTABLE), std::string("tolerance"),
          std::string(GONIO_SAMPLES_DIR) + "/downlight/downlight.gltf", std::string("--tolerances"),
          (dir / "t.toml").string(), std::string("--out"), (dir / out).string(), std::string("--threads"),
          std::string("1"), std::string("--photons"), std::string("20000"), std::string("--trials"),
          std::string("7"), std::string("--noise-seeds"), std::string("2"), std::string("--spec"),
          std::string("flux>=975,lor>=0.975,flux<=981"), std::string("--inverse-steps"), std::string("1")})
      argv.push_back(a);
    argv.insert(argv.end(), extra.begin(), extra.end());
    return test::run_process(argv);
  }
};

// DIR/journal.jsonl as key → figures (the order of its lines, and the
// seconds, depend on the split; which trace gave which figures must not).
std::map<std::string, std::string> journal_figures(const fs::path& dir) {
  std::map<std::string, std::string> out;
  std::istringstream lines(test::read_file(dir / "journal.jsonl"));
  for (std::string line; std::getline(lines, line);) {
    const nlohmann::json j = nlohmann::json::parse(line);
    if (j.contains("key")) out[j["key"].get<std::string>()] = j["figures"].dump();
  }
  return out;
}

std::size_t count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

// Rank 0 gathers every rank's traces by their place in the run, not by the
// order they come in: a rank that put its share of a round in another order
// (or another rank's place) would give other trials other figures.
TEST_F(MpiTolerance, AnyRankCountGivesTheReportBytesOfOneProcessAndResumes) {
  test::TempDir dir;
  test::write_file(dir / "t.toml",
                   "[emitter.LED]\nx = { uniform = 0.5 }\n"
                   "[material.\"semi-specular aluminium\"]\nreflectance = { uniform = 2 }\n");
  test::ProcessResult r = tolerance(0, dir.path(), "one");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string one = test::read_file(dir / "one" / "report.json");
  const nlohmann::json report = nlohmann::json::parse(one);
  ASSERT_EQ(report["monte_carlo"]["trials"].size(), 7u);
  // The trials differ from each other (a split that lost or swapped them shows).
  for (std::size_t n = 1; n < 7; ++n)
    EXPECT_NE(report["monte_carlo"]["trials"][n]["figures"], report["monte_carlo"]["trials"][n - 1]["figures"]);

  struct Split {
    int ranks;
    std::string parallel;
  };
  for (const Split& s : {Split{1, "1"}, Split{2, "1"}, Split{3, "1"}, Split{2, "3"}}) {
    const std::string out = "n" + std::to_string(s.ranks) + "p" + s.parallel;
    r = tolerance(s.ranks, dir.path(), out, {"--parallel-trials", s.parallel});
    ASSERT_EQ(r.exit_code, 0) << out << ": " << r.err;
    EXPECT_EQ(one, test::read_file(dir / out / "report.json")) << out;
    // Every trace, the inverse sensitivity's too, under its own key.
    EXPECT_EQ(journal_figures(dir / "one"), journal_figures(dir / out)) << out;
    for (const char* f : {"nominal.ies", "best.ies", "worst.ldt", "sensitivity.txt"})
      EXPECT_EQ(test::read_file(dir / "one" / f), test::read_file(dir / out / f)) << out << ": " << f;
    // Rank 0 alone reports.
    EXPECT_EQ(count(r.out, "traces, "), 1u) << r.out;
    if (s.ranks > 1) {
      EXPECT_EQ(count(r.out, "over " + std::to_string(s.ranks) + " MPI ranks: 13 of 13 traces"), 1u) << r.out;
      EXPECT_EQ(count(r.out, "MPI ranks: the inverse sensitivity's 3 bisections"), 1u) << r.out;
    }
  }

  // An interrupted 3-rank run: its journal cut after 6 traces and half a line.
  const std::string journal = test::read_file(dir / "n3p1" / "journal.jsonl");
  std::vector<std::size_t> ends;
  for (std::size_t i = 0; i < journal.size(); ++i)
    if (journal[i] == '\n') ends.push_back(i + 1);
  ASSERT_GE(ends.size(), 10u);
  fs::create_directories(dir / "resumed");
  test::write_file(dir / "resumed" / "journal.jsonl",
                   journal.substr(0, ends[6]) + journal.substr(ends[6], (ends[7] - ends[6]) / 2));
  r = tolerance(2, dir.path(), "resumed", {"--resume"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(one, test::read_file(dir / "resumed" / "report.json"));
  EXPECT_EQ(journal_figures(dir / "one"), journal_figures(dir / "resumed"));
  // The header and the nominal are lines 1 and 2: 5 of the 13 split traces read back.
  EXPECT_EQ(count(r.out, "resume: 6 traces read back from the journal"), 1u) << r.out;
  EXPECT_EQ(count(r.out, "over 2 MPI ranks: 8 of 13 traces to make (5 from the journal)"), 1u) << r.out;
  // The resumed journal is whole again: a second resume traces nothing more.
  r = tolerance(3, dir.path(), "resumed", {"--resume"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(one, test::read_file(dir / "resumed" / "report.json"));
  EXPECT_EQ(count(r.out, "0 of 13 traces to make"), 1u) << r.out;
}

// Ranks that trace another nominal (here rank 1 with other --photons, as a
// rank with another model or file would) stop every rank before the split,
// rank 0 naming the rank, and DIR gets no report.
TEST_F(MpiTolerance, ARankWithAnotherNominalStopsEveryRank) {
  test::TempDir dir;
  test::write_file(dir / "t.toml", "[emitter.LED]\nx = { uniform = 0.5 }\n");
  const test::ProcessResult r = test::run_process(
      {GONIO_MPIRUN, "--oversubscribe", "--bind-to", "none", "-n", "2", "sh", "-c",
       "exec \"$0\" tolerance \"$1\" --tolerances \"$2\" --out \"$3\" --threads 1 --trials 2 --noise-seeds 1 "
       "--photons $((20000 + OMPI_COMM_WORLD_RANK))",
       GONIO_EXECUTABLE, std::string(GONIO_SAMPLES_DIR) + "/downlight/downlight.gltf", (dir / "t.toml").string(),
       (dir / "out").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(count(r.err, "tolerance: rank 1 of 2 traced another nominal than rank 0"), 1u) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "report.json"));
  EXPECT_EQ(count(r.out, "traces to make"), 0u) << r.out;
}

}  // namespace
}  // namespace gonio
