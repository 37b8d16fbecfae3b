// `gonio optimize` over the ranks of an MPI job (mpirun; tools/run/optimize_run.h,
// docs/mpi.md "Optimisation"): BOBYQA's evaluations share their photons
// over the ranks as gonio simulate does, CMA-ES deals a generation's points
// to the ranks (point i to rank i mod K) and puts their merits back in the
// points' order. Either way 1, 2 and 3 ranks (and 2 ranks of 2 jobs) give
// the history, the best design and its IES of the run without mpirun, and
// rank 0 alone writes. Runs Open MPI's mpirun (ctest label `mpi`).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

// A point source shining up (1000 lm, Lambertian toward the zenith) under a
// conic dish whose spread depends strongly on its conic constant (the dish
// of cmd_optimize_test.cpp).
std::string design_text(const std::string& conic) {
  return "length_unit = \"mm\"\n[materials.mirror]\nreflectance = 0.9\n[[emitters]]\nname = \"LED\"\n"
         "position = [0, 0, 0]\nprofile = \"up.ies\"\n[[reflectors]]\nname = \"dish\"\nmaterial = \"mirror\"\n"
         "profile = \"conic\"\nradius = 10\nconic = " + conic + "\nvertex = 5\naperture = [2, 30]\n";
}

std::string up_ies() {
  // IES LM-63-2002, rotational, γ 0 … 180 every 2.5°: 318.31 · (−cos γ) above 90°.
  std::string text = "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 73 1 1 2 0 0 0\n1 1 0\n";
  for (int i = 0; i <= 72; ++i) text += std::to_string(2.5 * i) + (i % 8 == 7 ? "\n" : " ");
  text += "\n0\n";
  for (int i = 0; i <= 72; ++i) {
    const double g = 2.5 * i;
    const double cd = g <= 90.0 ? 0.0 : -318.31 * std::cos(g * std::numbers::pi / 180.0);
    text += std::to_string(cd) + (i % 8 == 7 ? "\n" : " ");
  }
  return text + "\n";
}

nlohmann::json without_times(nlohmann::json history) {
  for (nlohmann::json& e : history) e.erase("time_s");
  return history;
}

// What DIR/state.json (gonio watch DIR) shows of the best evaluation: its
// candela curves and figures, and which evaluation it is. Rank 0 writes it,
// so the best's candela must reach rank 0 whichever rank traced it.
nlohmann::json best_state(const fs::path& out) {
  const nlohmann::json s = nlohmann::json::parse(test::read_file(out / "state.json"));
  const nlohmann::json& o = s.at("optimize");
  return {{"curves", s.at("curves")},
          {"lor", s.at("lor")},
          {"max_cd", s.at("max_cd")},
          {"flux_lm", s.at("flux_lm")},
          {"best_index", o.at("best_index")},
          {"best_merit", o.at("best_merit")},
          {"candela_rms_pct", o.at("candela_rms_pct")},
          {"beam_angle_deg", o.at("beam_angle_deg")}};
}

class OptimizeMpi : public ::testing::Test {
 protected:
  test::TempDir dir;
  std::string target;

  void SetUp() override {
    if (!fs::exists(GONIO_MPIRUN))
      GONIO_MISSING(std::string(GONIO_MPIRUN) + " (scripts/setup.sh installs openmpi-bin)");
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    write(dir / "up.ies", up_ies());
    write(dir / "truth.design.toml", design_text("-1.5"));
    write(dir / "start.design.toml", design_text("{ value = -2.6, min = -3, max = -1 }"));
    const test::ProcessResult t = test::run_process(
        {GONIO_EXECUTABLE, "simulate", (dir / "truth.design.toml").string(), "--out", (dir / "truth").string(),
         "--photons", "200000", "--iterations", "1", "--gamma-step", "2.5", "--format", "ies", "--no-cache"});
    ASSERT_EQ(t.exit_code, 0) << t.out << t.err;
    target = (dir / "truth" / "truth.ies").string();
  }

  // gonio optimize with `ranks` ranks of mpirun (0: without mpirun).
  test::ProcessResult optimize(int ranks, const fs::path& out, const std::vector<std::string>& more,
                               const std::string& design = "start") const {
    std::vector<std::string> argv;
    if (ranks > 0) argv = {GONIO_MPIRUN, "--oversubscribe", "--bind-to", "none", "-n", std::to_string(ranks)};
    for (const std::string& a :
         {std::string(GONIO_EXECUTABLE), std::string("optimize"), (dir / (design + ".design.toml")).string(),
          std::string("--target"), target, std::string("--out"), out.string(), std::string("--gamma-step"),
          std::string("5"), std::string("--no-step"), std::string("--stages"), std::string("2"),
          std::string("--final-photons"), std::string("20000"), std::string("--threads"), std::string("1")})
      argv.push_back(a);
    argv.insert(argv.end(), more.begin(), more.end());
    return test::run_process(argv);
  }

  // Runs the method without mpirun and with 1, 2 and 3 ranks (and 2 ranks
  // of 2 jobs where `jobs`): the same history (times aside), best design
  // and IES bytes; the other ranks' files are gone.
  void same_for_any_split(const std::string& method, const std::vector<std::string>& more, bool jobs,
                          const std::string& design = "start", std::vector<int> rank_counts = {1, 2, 3}) {
    std::vector<std::string> args = {"--method", method};
    args.insert(args.end(), more.begin(), more.end());
    const fs::path plain = dir / (method + "-" + design + "-plain");
    const test::ProcessResult p = optimize(0, plain, args, design);
    ASSERT_EQ(p.exit_code, 0) << p.out << p.err;
    const nlohmann::json history = without_times(nlohmann::json::parse(test::read_file(plain / "history.json")));
    ASSERT_GE(history.size(), 8u);
    const std::string best = test::read_file(plain / (design + ".design.toml"));
    const std::string ies = test::read_file(plain / (design + ".ies"));
    const nlohmann::json state = best_state(plain);
    ASSERT_FALSE(state.at("curves").is_null());
    struct Split {
      int ranks;
      std::string jobs;
    };
    std::vector<Split> splits;
    for (int k : rank_counts) splits.push_back({k, "1"});
    if (jobs) splits.push_back({2, "2"});
    for (const Split& s : splits) {
      const fs::path out = dir / (method + "-" + design + "-" + std::to_string(s.ranks) + "x" + s.jobs);
      std::vector<std::string> a = args;
      if (jobs) a.insert(a.end(), {"--jobs", s.jobs});
      const test::ProcessResult r = optimize(s.ranks, out, a, design);
      ASSERT_EQ(r.exit_code, 0) << s.ranks << " ranks\n" << r.out << r.err;
      EXPECT_EQ(without_times(nlohmann::json::parse(test::read_file(out / "history.json"))), history)
          << method << ", " << s.ranks << " ranks × " << s.jobs << " jobs";
      EXPECT_EQ(test::read_file(out / (design + ".design.toml")), best) << s.ranks << " ranks";
      EXPECT_EQ(test::read_file(out / (design + ".ies")), ies) << s.ranks << " ranks";
      EXPECT_EQ(best_state(out), state) << method << ", " << s.ranks << " ranks × " << s.jobs << " jobs: state.json";
      const nlohmann::json report = nlohmann::json::parse(test::read_file(out / "report.json")).at("optimize");
      EXPECT_EQ(report.at("ranks").get<int>(), s.ranks);
      // Rank 0 alone wrote; every rank's own evaluation files are gone.
      for (const auto& e : fs::directory_iterator(out))
        EXPECT_EQ(e.path().filename().string().rfind(".evaluation", 0), std::string::npos) << e.path();
      EXPECT_FALSE(fs::exists(out / ".best-r1-main.design.toml"));
    }
  }
};

TEST_F(OptimizeMpi, BobyqaSharesEachEvaluationsPhotonsWithTheSameResultForAnySplit) {
  same_for_any_split("bobyqa", {"--max-evals", "12"}, false);
}

// A UGR limit: the merit needs where the photons leave (the opening of the
// downward exits), which travel with the directions; 2 ranks.
TEST_F(OptimizeMpi, AUgrLimitsOpeningIsTheSameOverRanks) {
  write(dir / "ugr.design.toml",
        design_text("{ value = -2.6, min = -3, max = -1 }") + "[merit]\nugr = { limit = 18, room = [8, 6] }\n");
  same_for_any_split("bobyqa", {"--max-evals", "8"}, false, "ugr", {2});
}

TEST_F(OptimizeMpi, CmaesDealsAGenerationsPointsWithTheSameResultForAnySplit) {
  same_for_any_split("cmaes", {"--max-evals", "16", "--population", "5"}, true);
}

// Every rank exits with the job's code (docs/mpi.md): a run that cannot
// improve exits 3 on both ranks; the same run where rank 0 cannot write
// history.json (a folder there) exits 1 on both, not 3 on rank 1 while rank
// 0 failed (mpirun may report either).
TEST_F(OptimizeMpi, EveryRankExitsWithTheJobsCode) {
  write(dir / "pinned.design.toml", design_text("{ value = -2, min = -3, max = -2 }"));
  for (const bool blocked : {false, true}) {
    const fs::path out = dir / (blocked ? "blocked" : "pinned");
    if (blocked) fs::create_directories(out / "history.json");
    const test::ProcessResult r = test::run_process(
        {GONIO_MPIRUN, "--oversubscribe", "--bind-to", "none", "-n", "2", "sh", "-c",
         "\"$0\" optimize \"$1\" --target \"$2\" --out \"$3\" --gamma-step 5 --no-step --stages 1 --max-evals 3 "
         "--final-photons 20000 --threads 1 --photons-per-bin 200; echo \"rank $OMPI_COMM_WORLD_RANK exit $?\"",
         GONIO_EXECUTABLE, (dir / "pinned.design.toml").string(), target, out.string()});
    const std::string code = blocked ? "1" : "3";
    EXPECT_NE(r.out.find("rank 0 exit " + code), std::string::npos) << blocked << "\n" << r.out << r.err;
    EXPECT_NE(r.out.find("rank 1 exit " + code), std::string::npos) << blocked << "\n" << r.out << r.err;
  }
}

}  // namespace
}  // namespace gonio
