// gonio simulate --target-error and gonio watch's command line, run as a
// user would on the sample luminaires. The live page itself is tested in a
// real browser (watch_browser_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace gonio {
namespace {

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

std::string sample(const std::string& name) {
  return std::string(GONIO_SAMPLES_DIR) + "/" + name + "/" + name + ".gltf";
}

nlohmann::json report(const std::filesystem::path& dir) {
  return nlohmann::json::parse(test::read_file(dir / "report.json"));
}

// The LED array's die is one mesh placed by nine nodes: simulate keeps it
// once (nine instances); --no-instancing stores nine copies. The same
// photons, the same light within photon noise.
TEST(SimulateInstancing, TheLedArraysDiesAreInstancedAndNoInstancingFlattensThem) {
  test::TempDir dir;
  auto run = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {"simulate", sample("led-array"), "--out", (dir.path() / out).string(),
                                     "--photons", "100000", "--iterations", "1", "--format", "ies", "--no-cache"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = gonio(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return report(dir.path() / out);
  };
  const auto inst = run("instanced", {});
  const auto flat = run("flat", {"--no-instancing"});
  EXPECT_EQ(inst["setup"]["instances"], 9);
  EXPECT_EQ(flat["setup"]["instances"], 0);
  EXPECT_EQ(inst["setup"]["triangles_placed"], flat["setup"]["triangles_placed"]);
  EXPECT_EQ(inst["setup"]["triangles_unique"].get<std::size_t>() + 8 * 16,
            flat["setup"]["triangles_unique"].get<std::size_t>());  // eight more 16-triangle dies
  EXPECT_EQ(inst["setup"]["meshes"], 3);
  EXPECT_EQ(flat["setup"]["meshes"], 11);
  ASSERT_EQ(inst["meshes"].size(), 3u);
  ASSERT_EQ(flat["meshes"].size(), 11u);
  std::uint64_t die_hits = 0;
  for (const auto& m : flat["meshes"])
    if (m["name"].get<std::string>().ends_with("/LED die/0")) die_hits += m["hits"].get<std::uint64_t>();
  for (const auto& m : inst["meshes"]) {
    if (m["name"] != "LED die/0") continue;
    EXPECT_EQ(m["placements"], 9);
    const double hits = m["hits"].get<double>();
    EXPECT_NEAR(hits, static_cast<double>(die_hits), 3.0 * std::sqrt(static_cast<double>(die_hits)));
  }
  EXPECT_EQ(inst["photons_emitted"], flat["photons_emitted"]);
  const double escaped = flat["escaped_lm"].get<double>();
  EXPECT_NEAR(inst["escaped_lm"].get<double>(), escaped, 3.0 * escaped / std::sqrt(100000.0));
}

TEST(SimulateTargetError, StopsUnderTheTargetAndSaysSoInTheReport) {
  test::TempDir dir;
  const double target = 4.0;
  // Without next-event estimation: with it (auto turns it on for the LED
  // array) the first 20000 photons are already at 1.6 %, and the stop's
  // timing is not what this test looks at.
  const auto r = gonio({"simulate", sample("led-array"), "--out", dir.path().string(), "--photons", "20000",
                        "--iterations", "500", "--target-error", "4", "--format", "ies", "--threads", "2",
                        "--next-event", "off"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = report(dir.path());
  EXPECT_EQ(j["stopped_by"], "target-error");
  ASSERT_TRUE(j["estimated_rms_error_pct"].is_number());
  EXPECT_LE(j["estimated_rms_error_pct"].get<double>(), target);
  EXPECT_GT(j["estimated_rms_error_pct"].get<double>(), 0.5 * target) << "stopped much later than needed";
  EXPECT_EQ(j["target_error_pct"].get<double>(), target);
  const int done = j["iterations_done"];
  EXPECT_LT(done, 500);
  EXPECT_EQ(j["photons_emitted"].get<std::uint64_t>(), static_cast<std::uint64_t>(done) * 20000u);
  EXPECT_TRUE(j["energy"]["passed"].get<bool>());
  EXPECT_TRUE(test::read_file(dir.path() / "led-array.ies").find("TILT=NONE") != std::string::npos);
  EXPECT_NE(r.out.find("stopped at the target error"), std::string::npos) << r.out;
}

TEST(SimulateTargetError, WithoutATargetEveryIterationRuns) {
  test::TempDir dir;
  const auto r = gonio({"simulate", sample("led-array"), "--out", dir.path().string(), "--photons", "20000",
                        "--iterations", "3", "--format", "ies"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = report(dir.path());
  EXPECT_EQ(j["stopped_by"], "iterations");
  EXPECT_EQ(j["iterations_done"], 3);
  EXPECT_TRUE(j["target_error_pct"].is_null());
}

TEST(SimulateTargetError, BadTargetsAreUsageErrors) {
  test::TempDir dir;
  for (const char* bad : {"-1", "101", "abc"}) {
    const auto r = gonio({"simulate", sample("led-array"), "--out", dir.path().string(), "--target-error", bad});
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find("target-error"), std::string::npos) << r.err;
  }
}

TEST(Watch, UsageErrorsAndHelp) {
  const auto none = gonio({"watch"});
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("MODEL"), std::string::npos) << none.err;
  EXPECT_EQ(gonio({"watch", sample("bell"), "--port", "70000"}).exit_code, 2);
  EXPECT_EQ(gonio({"watch", sample("bell"), "--c-step", "7"}).exit_code, 2);
  const auto help = gonio({"watch", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  for (const char* option : {"--port", "--host", "--out", "--target-error", "--photons", "--filter"})
    EXPECT_NE(help.out.find(option), std::string::npos) << option;
  const auto top = gonio({"--help"});
  EXPECT_NE(top.out.find("watch"), std::string::npos);
}

// watch's defaults differ from simulate's; the shared option texts once
// printed simulate's (1000000, 10) under watch as well.
TEST(Watch, HelpStatesWatchsOwnDefaults) {
  const auto watch = gonio({"watch", "--help"});
  EXPECT_NE(watch.out.find("(default 262144)"), std::string::npos) << watch.out;
  EXPECT_NE(watch.out.find("iterations (default 1000)"), std::string::npos) << watch.out;
  EXPECT_EQ(watch.out.find("per iteration (default 1000000)"), std::string::npos) << watch.out;
  const auto simulate = gonio({"simulate", "--help"});
  EXPECT_NE(simulate.out.find("per iteration (default 1000000)"), std::string::npos) << simulate.out;
  EXPECT_NE(simulate.out.find("iterations (default 10)"), std::string::npos) << simulate.out;
}

TEST(Watch, SimulateServeAndWatchShareTheOptions) {
  const auto help = gonio({"simulate", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  for (const char* option : {"--serve", "--port", "--target-error"})
    EXPECT_NE(help.out.find(option), std::string::npos) << option;
}

}  // namespace
}  // namespace gonio
