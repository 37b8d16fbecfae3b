// The glossy lobes' energy tables kept on disk: what comes back is the table
// built, bit for bit; a damaged or foreign file is rebuilt, never trusted.
#include "tools/run/glossy_energy_cache.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "sim/bsdfs/lobes.h"
#include "tests/support/test_support.h"

namespace gonio::app {
namespace {

namespace fs = std::filesystem;

// Every byte of the table: the nodes, e_avg and the cdf.
void expect_same_bytes(const sim::GlossyEnergy& a, const sim::GlossyEnergy& b) {
  EXPECT_EQ(std::memcmp(&a.mx, &b.mx, sizeof a.mx), 0);
  EXPECT_EQ(std::memcmp(&a.my, &b.my, sizeof a.my), 0);
  EXPECT_EQ(std::memcmp(a.e.data(), b.e.data(), sizeof a.e), 0);
  EXPECT_EQ(std::memcmp(&a.e_avg, &b.e_avg, sizeof a.e_avg), 0);
  EXPECT_EQ(std::memcmp(a.cdf.data(), b.cdf.data(), sizeof a.cdf), 0);
}

// A one-material scene with a compensated glossy lobe of roughness mx, my.
sim::SceneDesc glossy_scene(double mx, double my) {
  sim::SceneDesc scene;
  sim::Material m;
  m.glossy = 0.5;
  m.glossy_mx = mx;
  m.glossy_my = my;
  m.glossy_compensation = true;
  scene.materials = {m, m};  // the same roughness twice: one table
  return scene;
}

TEST(GlossyEnergyCache, WhatComesBackIsTheTableBuilt) {
  test::TempDir dir;
  const std::string cache = (dir / "cache").string();  // made when first needed
  for (auto [mx, my] : {std::pair{0.3, 0.3}, std::pair{0.2, 0.6}}) {
    const auto built = sim::build_glossy_energy(mx, my);
    EXPECT_EQ(read_cached_glossy_energy(mx, my, cache), nullptr);
    ASSERT_TRUE(store_glossy_energy(*built, cache));
    EXPECT_TRUE(fs::is_regular_file(dir / "cache" / glossy_energy_cache_name(mx, my)));
    const auto read = read_cached_glossy_energy(mx, my, cache);
    ASSERT_NE(read, nullptr);
    expect_same_bytes(*read, *built);
  }
  EXPECT_EQ(read_cached_glossy_energy(0.3, 0.3, ""), nullptr);  // --no-cache
}

TEST(GlossyEnergyCache, EveryRoughnessNamesItsOwnFile) {
  const std::string name = glossy_energy_cache_name(0.3, 0.3);
  EXPECT_EQ(name.rfind("glossy-energy-", 0), 0u);
  EXPECT_NE(glossy_energy_cache_name(0.3, 0.30000000000000004), name);
  EXPECT_NE(glossy_energy_cache_name(0.2, 0.6), glossy_energy_cache_name(0.6, 0.2));
  EXPECT_NE(glossy_energy_cache_name(0.2, 0.6), glossy_energy_cache_name(0.2, 0.7));
  EXPECT_NE(glossy_energy_cache_name(0.2, 0.6), glossy_energy_cache_name(0.3, 0.6));
}

// Another roughness's table under this roughness's name (a file copied in
// by hand, or a name clash) is not used.
TEST(GlossyEnergyCache, AForeignFileIsNotUsed) {
  test::TempDir dir;
  const std::string cache = dir.path().string();
  ASSERT_TRUE(store_glossy_energy(*sim::build_glossy_energy(0.25, 0.25), cache));
  fs::copy_file(dir / glossy_energy_cache_name(0.25, 0.25), dir / glossy_energy_cache_name(0.45, 0.45));
  EXPECT_EQ(read_cached_glossy_energy(0.45, 0.45, cache), nullptr);
  EXPECT_NE(read_cached_glossy_energy(0.25, 0.25, cache), nullptr);
}

// A damaged file (a flipped bit in a node, cut short, grown, emptied) is
// rebuilt and rewritten by the loader, and the process gets the built table.
TEST(GlossyEnergyCache, ADamagedFileIsRebuiltNotTrusted) {
  test::TempDir dir;
  const std::string cache = dir.path().string();
  // A roughness no other test of this process asks for: the loader's table
  // is then its own (sim::glossy_energy keeps one per process).
  constexpr double kMx = 0.4375, kMy = 0.4375;
  const auto built = sim::build_glossy_energy(kMx, kMy);
  ASSERT_TRUE(store_glossy_energy(*built, cache));
  const fs::path file = dir / glossy_energy_cache_name(kMx, kMy);
  const std::string good = test::read_file(file);
  std::string flipped = good;
  flipped[16 + 8 + 16 + 8 * 10] ^= 0x01;  // the 11th node's lowest bit
  for (const std::string& bad : {flipped, good.substr(0, good.size() - 1), good + "x", std::string()}) {
    test::write_file(file, bad);
    EXPECT_EQ(read_cached_glossy_energy(kMx, kMy, cache), nullptr);
  }
  test::write_file(file, flipped);
  const GlossyEnergySource s = load_glossy_energy_tables(glossy_scene(kMx, kMy), cache);
  EXPECT_EQ(s.from_cache, 0);
  EXPECT_EQ(s.built, 1);
  EXPECT_EQ(s.stored, 1);
  EXPECT_EQ(test::read_file(file), good);  // rewritten
  expect_same_bytes(*sim::glossy_energy(kMx, kMy), *built);
  // Read back now.
  const GlossyEnergySource again = load_glossy_energy_tables(glossy_scene(kMx, kMy), cache);
  EXPECT_EQ(again.from_cache, 1);
  EXPECT_EQ(again.built, 0);
}

// A table read from the cache is the one the tracer's materials get
// (sim::glossy_energy, through sim::prepare): none is built again.
TEST(GlossyEnergyCache, TheTableReadIsTheOneTheProcessShares) {
  test::TempDir dir;
  const std::string cache = dir.path().string();
  constexpr double kMx = 0.3125, kMy = 0.5625;  // asked for by no other test
  ASSERT_TRUE(store_glossy_energy(*sim::build_glossy_energy(kMx, kMy), cache));
  const GlossyEnergySource s = load_glossy_energy_tables(glossy_scene(kMx, kMy), cache);
  EXPECT_EQ(s.from_cache, 1);
  EXPECT_EQ(s.built, 0);
  const auto shared = sim::glossy_energy(kMx, kMy);
  sim::Material m = glossy_scene(kMx, kMy).materials[0];
  sim::prepare(m);
  ASSERT_NE(m.tables, nullptr);
  EXPECT_EQ(m.tables->glossy, shared);
  // The same object as a second read offers: the first offered is kept.
  EXPECT_EQ(sim::offer_glossy_energy(read_cached_glossy_energy(kMx, kMy, cache)), shared);
}

// A folder that cannot be written only costs the build.
TEST(GlossyEnergyCache, AnUnwritableFolderIsNoError) {
  test::TempDir dir;
  test::write_file(dir / "file", "not a folder");
  const std::string cache = (dir / "file" / "cache").string();
  EXPECT_FALSE(store_glossy_energy(*sim::build_glossy_energy(0.3, 0.3), cache));
  const GlossyEnergySource s = load_glossy_energy_tables(glossy_scene(0.3, 0.3), cache);
  EXPECT_EQ(s.built, 1);
  EXPECT_EQ(s.stored, 0);
  EXPECT_NE(sim::glossy_energy(0.3, 0.3), nullptr);
}

}  // namespace
}  // namespace gonio::app
