#include "io/report.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

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
  l.meshes = {{"shade", "opal", 1234, l.absorbed, l.cutoff}};
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
