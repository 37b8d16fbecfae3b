#include "io/outputs/report.h"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

TEST(Report, GivesTheSetupPhasesAndTheMemoryHighWaterMark) {
  SimulationReport r;
  r.setup.load_s = 0.25;
  r.setup.check_s = 1.5;
  r.setup.validate_s = 0.01;
  r.setup.emission_tables_s = 0.02;
  r.setup.bvh_s = 0.75;
  r.setup.shading_s = 0.125;
  r.setup.meshes = 7;
  r.setup.meshes_from_cache = 7;
  r.setup.max_rss_after_load_bytes = 100;
  r.setup.max_rss_after_checks_bytes = 200;
  r.max_rss_bytes = 300;
  const nlohmann::json j = to_json(r);
  EXPECT_EQ(j["setup"]["load_s"], 0.25);
  EXPECT_EQ(j["setup"]["check_s"], 1.5);
  EXPECT_EQ(j["setup"]["validate_s"], 0.01);
  EXPECT_EQ(j["setup"]["emission_tables_s"], 0.02);
  EXPECT_EQ(j["setup"]["bvh_s"], 0.75);
  EXPECT_EQ(j["setup"]["shading_s"], 0.125);
  EXPECT_EQ(j["setup"]["meshes"], 7);
  EXPECT_EQ(j["setup"]["meshes_from_cache"], 7);
  EXPECT_EQ(j["setup"]["max_rss_after_load_bytes"], 100);
  EXPECT_EQ(j["setup"]["max_rss_after_checks_bytes"], 200);
  EXPECT_EQ(j["max_rss_bytes"], 300);
}

// The high-water mark rises by what is touched, and never falls.
TEST(Report, PeakMemoryFollowsWhatTheProcessTouches) {
  const std::uint64_t before = peak_memory_bytes();
  EXPECT_GT(before, 0u);
  constexpr std::size_t kBytes = std::size_t{256} << 20;
  {
    auto block = std::make_unique<char[]>(kBytes);
    std::memset(block.get(), 1, kBytes);  // make every page resident
    volatile char sink = block[kBytes - 1];
    (void)sink;
  }
  const std::uint64_t after = peak_memory_bytes();
  // The block may reuse pages the process held before its old peak.
  EXPECT_GE(after, before);
  EXPECT_GE(after, kBytes);
  EXPECT_LE(after, before + kBytes + (std::uint64_t{64} << 20));
  EXPECT_GE(peak_memory_bytes(), after);
}

TEST(Report, HoldsTheLedgerSettingsAndSpeed) {
  SimulationReport r;
  r.program_version = "9.9.9";
  r.model = "bell.gltf";
  r.photons_per_iteration = 1000;
  r.iterations = 2;
  r.seed = 18446744073709551615ull;  // the full 64-bit range survives JSON
  r.threads = 2;
  r.max_bounces = 50;
  r.face_size = 128;
  r.iterations_done = 2;
  r.photons = 2000;
  r.rays = 5000;
  r.trace_s = 0.5;
  r.wall_s = 0.75;
  sim::Ledger& l = r.ledger;
  l.photon_power_lm = 0.5;
  l.emitted = {2000, 1000.0};
  l.escaped = {1500, 750.0};
  l.absorbed = {400, 200.0};
  l.cutoff = {100, 50.0};
  l.emitters = {{"lamp", l.emitted, l.escaped, l.absorbed, l.cutoff}};
  l.meshes = {{"shade", "opal", 1, 1234, l.absorbed, l.cutoff}};
  l.materials = {{"opal", 1234, l.absorbed, l.cutoff}};

  const nlohmann::json j = to_json(r);
  EXPECT_EQ(j["program"]["version"], "9.9.9");
  EXPECT_EQ(j["seed"].get<std::uint64_t>(), 18446744073709551615ull);
  EXPECT_EQ(j["emitted_lm"], 1000.0);
  EXPECT_EQ(j["escaped_lm"], 750.0);
  EXPECT_EQ(j["absorbed_lm"], 200.0);
  EXPECT_EQ(j["cutoff_lm"], 50.0);
  EXPECT_EQ(j["photons_emitted"], 2000);
  EXPECT_EQ(j["photons_escaped"], 1500);
  EXPECT_EQ(j["photons_absorbed"], 400);
  EXPECT_EQ(j["photons_cutoff"], 100);
  EXPECT_EQ(j["photons_per_s"], 4000.0);
  EXPECT_EQ(j["rays_per_s"], 10000.0);
  EXPECT_EQ(j["rays_per_photon"], 2.5);
  EXPECT_EQ(j["wall_s"], 0.75);
  EXPECT_EQ(j["ledger"]["photons_close"], true);
  EXPECT_EQ(j["ledger"]["flux_imbalance_lm"], 0.0);
  EXPECT_EQ(j["settings"]["max_bounces"], 50);
  EXPECT_EQ(j["emitters"][0]["name"], "lamp");
  EXPECT_EQ(j["emitters"][0]["escaped_lm"], 750.0);
  EXPECT_EQ(j["meshes"][0]["material"], "opal");
  EXPECT_EQ(j["meshes"][0]["hits"], 1234);
  EXPECT_EQ(j["meshes"][0]["placements"], 1);
  EXPECT_EQ(j["materials"][0]["photons_absorbed"], 400);

  test::TempDir dir;
  const std::string path = (dir / "report.json").string();
  ASSERT_TRUE(write_json(path, j).ok());
  const std::string text = test::read_file(path);
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(nlohmann::json::parse(text), j);
  EXPECT_FALSE(write_json((dir / "no" / "report.json").string(), j).ok());
}

}  // namespace
}  // namespace gonio::io
