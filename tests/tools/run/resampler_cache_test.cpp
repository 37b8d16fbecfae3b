// The outputs' resamplers kept on disk: what comes back is what was built,
// and a damaged, foreign or unwritable cache only costs the build.
#include "tools/run/resampler_cache.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>

#include "tests/support/test_support.h"

namespace gonio::app {
namespace {

constexpr int kFace = 16;
const sim::CGammaGrid kGrid{15.0, 10.0};

photometry::PhotometricFrame tilted() { return photometry::make_frame({0.3, 1.0, 0.2}, {1.0, 0.1, -0.4}); }

sim::FarField random_field() {
  sim::FarField field(kFace);
  std::mt19937_64 rng(7);
  std::exponential_distribution<double> e(1.0);
  for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, e(rng), 1 + rng() % 40);
  return field;
}

// Same rows, and so the same binned field, bit for bit.
void expect_same(const sim::Resampler& a, const sim::Resampler& b) {
  const sim::Resampler::Rows ra = a.rows(), rb = b.rows();
  EXPECT_EQ(ra.row_start, rb.row_start);
  EXPECT_EQ(ra.texel, rb.texel);
  EXPECT_EQ(ra.fraction, rb.fraction);
  EXPECT_EQ(ra.solid_angle_sr, rb.solid_angle_sr);
  const sim::FarField field = random_field();
  EXPECT_EQ(a.bin(field).flux_lm, b.bin(field).flux_lm);
  EXPECT_EQ(a.bin(field).variance_lm2, b.bin(field).variance_lm2);
}

TEST(ResamplerCache, WhatComesBackIsWhatWasBuilt) {
  test::TempDir dir;
  const std::string cache = (dir / "cache").string();  // made when first needed
  const sim::Resampler fresh(kFace, tilted(), kGrid);
  ResamplerSource first, second;
  const sim::Resampler built = cached_resampler(kFace, tilted(), kGrid, cache, &first);
  EXPECT_FALSE(first.from_cache);
  EXPECT_TRUE(first.stored);
  EXPECT_TRUE(std::filesystem::is_regular_file(dir / "cache" / resampler_cache_name(kFace, tilted(), kGrid)));
  const sim::Resampler read = cached_resampler(kFace, tilted(), kGrid, cache, &second);
  EXPECT_TRUE(second.from_cache);
  EXPECT_FALSE(second.stored);
  expect_same(built, fresh);
  expect_same(read, fresh);
  EXPECT_EQ(read.face_size(), kFace);
  EXPECT_EQ(read.grid().c_step_deg, kGrid.c_step_deg);
}

TEST(ResamplerCache, EveryParameterNamesItsOwnFile) {
  const std::string name = resampler_cache_name(kFace, tilted(), kGrid);
  EXPECT_EQ(name.rfind("resampler-", 0), 0u);
  EXPECT_NE(resampler_cache_name(2 * kFace, tilted(), kGrid), name);
  EXPECT_NE(resampler_cache_name(kFace, {}, kGrid), name);
  EXPECT_NE(resampler_cache_name(kFace, tilted(), sim::CGammaGrid{15.0, 5.0}), name);
  EXPECT_NE(resampler_cache_name(kFace, tilted(), sim::CGammaGrid{10.0, 10.0}), name);
  EXPECT_EQ(resampler_cache_name(kFace, tilted(), kGrid), name);
}

TEST(ResamplerCache, DamagedOrForeignFilesAreRebuiltAndRewritten) {
  test::TempDir dir;
  const std::string cache = dir.path().string();
  const std::filesystem::path file = dir / resampler_cache_name(kFace, tilted(), kGrid);
  const sim::Resampler fresh(kFace, tilted(), kGrid);
  cached_resampler(kFace, tilted(), kGrid, cache);
  const std::string good = test::read_file(file);
  ASSERT_GT(good.size(), 100u);

  // Another grid's file under this name (a copied or colliding entry).
  cached_resampler(kFace, tilted(), sim::CGammaGrid{30.0, 10.0}, cache);
  const std::string foreign =
      test::read_file(dir / resampler_cache_name(kFace, tilted(), sim::CGammaGrid{30.0, 10.0}));

  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 0x10);
  std::string flipped_digest = good;
  flipped_digest.back() = static_cast<char>(flipped_digest.back() ^ 1);
  const std::vector<std::pair<std::string, std::string>> damaged = {
      {"empty", ""},
      {"truncated", good.substr(0, good.size() / 3)},
      {"one byte short", good.substr(0, good.size() - 1)},
      {"one byte more", good + "x"},
      {"a bit flipped", flipped},
      {"its digest flipped", flipped_digest},
      {"text", "gonio-resampler\nnot really\n"},
      {"another grid's", foreign}};
  for (const auto& [what, bytes] : damaged) {
    test::write_file(file, bytes);
    ResamplerSource source;
    const sim::Resampler r = cached_resampler(kFace, tilted(), kGrid, cache, &source);
    EXPECT_FALSE(source.from_cache) << what;
    EXPECT_TRUE(source.stored) << what;
    expect_same(r, fresh);
    EXPECT_EQ(test::read_file(file), good) << what << ": rewritten";
  }
}

TEST(ResamplerCache, NoFolderOrAnUnwritableOneOnlyCostsTheBuild) {
  test::TempDir dir;
  const sim::Resampler fresh(kFace, tilted(), kGrid);
  ResamplerSource none;
  expect_same(cached_resampler(kFace, tilted(), kGrid, "", &none), fresh);
  EXPECT_FALSE(none.from_cache);
  EXPECT_FALSE(none.stored);
  // A file where the folder should be.
  test::write_file(dir / "file", "x");
  ResamplerSource blocked;
  expect_same(cached_resampler(kFace, tilted(), kGrid, (dir / "file").string(), &blocked), fresh);
  EXPECT_FALSE(blocked.from_cache);
  EXPECT_FALSE(blocked.stored);
  EXPECT_EQ(test::read_file(dir / "file"), "x");
}

TEST(ResamplerCache, StoredRowsOfTheWrongShapeAreRefused) {
  const sim::Resampler fresh(kFace, {}, kGrid);
  const sim::Resampler::Rows good = fresh.rows();
  ASSERT_TRUE(sim::Resampler::from_rows(kFace, kGrid, good).ok());
  auto refused = [&](const char* what, auto change, int face = kFace, sim::CGammaGrid grid = kGrid) {
    sim::Resampler::Rows rows = good;
    change(rows);
    EXPECT_FALSE(sim::Resampler::from_rows(face, grid, std::move(rows)).ok()) << what;
  };
  refused("rows out of order", [](sim::Resampler::Rows& r) { std::swap(r.row_start[3], r.row_start[4]); });
  refused("a row missing", [](sim::Resampler::Rows& r) { r.row_start.pop_back(); });
  refused("an entry missing", [](sim::Resampler::Rows& r) { r.fraction.pop_back(); });
  refused("texel past the map", [](sim::Resampler::Rows& r) { r.texel[5] = 6 * kFace * kFace; });
  refused("fraction above 1", [](sim::Resampler::Rows& r) { r.fraction[5] = 1.5; });
  refused("fraction not a number", [](sim::Resampler::Rows& r) { r.fraction[5] = std::nan(""); });
  refused("bin without solid angle", [](sim::Resampler::Rows& r) { r.solid_angle_sr[2] = 0.0; });
  refused("another grid", [](sim::Resampler::Rows&) {}, kFace, sim::CGammaGrid{30.0, 10.0});
  refused("a face too small for its texels", [](sim::Resampler::Rows&) {}, kFace / 2);
}

// The resamplers kept in memory (issue 40): the same object again for the
// same folder and parameters, its rows those built; other parameters or
// another folder get their own; no folder keeps nothing.
TEST(ResamplerCache, SharedResamplersAreKeptPerFolderAndParameters) {
  test::TempDir dir;
  const std::string cache = (dir / "cache").string();
  const std::shared_ptr<const sim::Resampler> a = shared_resampler(kFace, tilted(), kGrid, cache);
  const std::shared_ptr<const sim::Resampler> again = shared_resampler(kFace, tilted(), kGrid, cache);
  EXPECT_EQ(a.get(), again.get());
  expect_same(*a, sim::Resampler(kFace, tilted(), kGrid));
  const std::shared_ptr<const sim::Resampler> other = shared_resampler(kFace, {}, kGrid, cache);
  EXPECT_NE(other.get(), a.get());
  expect_same(*other, sim::Resampler(kFace, {}, kGrid));
  EXPECT_NE(shared_resampler(kFace, tilted(), kGrid, (dir / "elsewhere").string()).get(), a.get());
  EXPECT_NE(shared_resampler(kFace, tilted(), kGrid, std::string()).get(),
            shared_resampler(kFace, tilted(), kGrid, std::string()).get());
}

}  // namespace
}  // namespace gonio::app
