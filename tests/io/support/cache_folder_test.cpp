// The cache folder's limit: least recently used entries go first, a used
// entry counts as new, other files stay, interrupted writes' leftovers go
// once an hour old.
#include "io/support/cache_folder.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

namespace fs = std::filesystem;
using std::chrono::hours;
using std::chrono::minutes;

std::string entry(int i) {
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016x", i);
  return "resampler-" + std::string(hex) + ".bin";
}

// A file of `bytes` bytes whose modification time is `age` ago.
void put(const fs::path& path, std::size_t bytes, fs::file_time_type::duration age) {
  test::write_file(path, std::string(bytes, 'x'));
  fs::last_write_time(path, fs::file_time_type::clock::now() - age);
}

TEST(CacheFolder, EntryNames) {
  EXPECT_TRUE(is_cache_entry_name("mesh-check-0123456789abcdef.json"));
  EXPECT_TRUE(is_cache_entry_name("resampler-0123456789abcdef.bin"));
  EXPECT_FALSE(is_cache_entry_name("resampler-0123456789ABCDEF.bin"));   // to_hex writes lower case
  EXPECT_FALSE(is_cache_entry_name("resampler-0123456789abcde.bin"));    // 15 digits
  EXPECT_FALSE(is_cache_entry_name("resampler-0123456789abcdef.json"));  // another owner's suffix
  EXPECT_FALSE(is_cache_entry_name("mesh-check-0123456789abcdef.json.bak"));
  EXPECT_FALSE(is_cache_entry_name(".mesh-check-0123456789abcdef.json.tmp12"));
  EXPECT_FALSE(is_cache_entry_name("notes.txt"));
}

TEST(CacheFolder, TrimsLeastRecentlyUsedFirstDownToNineTenthsAndLeavesOtherFiles) {
  test::TempDir dir;
  for (int i = 0; i < 10; ++i) put(dir / entry(i), 1000, hours(100 - i));  // entry 0 the oldest
  put(dir / "notes.txt", 5000, hours(200));
  put(dir / "resampler-old.bin", 5000, hours(200));
  fs::create_directory(dir / entry(99));  // a folder under an entry's name

  const CacheTrim t = trim_cache(dir.path().string(), 6000);
  EXPECT_EQ(t.removed_entries, 5u);  // 10,000 bytes down to ≤ 5,400
  EXPECT_EQ(t.removed_bytes, 5000u);
  EXPECT_EQ(t.entries, 5u);
  EXPECT_EQ(t.bytes, 5000u);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(fs::exists(dir / entry(i)), i >= 5) << i;
  EXPECT_TRUE(fs::exists(dir / "notes.txt"));
  EXPECT_TRUE(fs::exists(dir / "resampler-old.bin"));
  EXPECT_TRUE(fs::is_directory(dir / entry(99)));

  // Within the limit: nothing more goes.
  const CacheTrim again = trim_cache(dir.path().string(), 6000);
  EXPECT_EQ(again.removed_entries, 0u);
  EXPECT_EQ(again.entries, 5u);
}

TEST(CacheFolder, AnEntryReadCountsAsNew) {
  test::TempDir dir;
  for (int i = 0; i < 4; ++i) put(dir / entry(i), 1000, hours(10 - i));
  mark_cache_entry_used((dir / entry(0)).string());  // the oldest, read now
  const CacheTrim t = trim_cache(dir.path().string(), 3000);
  EXPECT_EQ(t.removed_entries, 2u);  // 4,000 down to ≤ 2,700
  EXPECT_TRUE(fs::exists(dir / entry(0)));
  EXPECT_FALSE(fs::exists(dir / entry(1)));
  EXPECT_FALSE(fs::exists(dir / entry(2)));
  EXPECT_TRUE(fs::exists(dir / entry(3)));
  mark_cache_entry_used((dir / "missing").string());  // no error
}

TEST(CacheFolder, LeftoversOfInterruptedWritesGoOnceAnHourOld) {
  test::TempDir dir;
  const std::string name = "mesh-check-0123456789abcdef.json";
  put(dir / ("." + name + ".tmp123"), 100, hours(2));
  put(dir / ("." + name + ".tmp456"), 100, minutes(10));  // perhaps being written now
  put(dir / ".notes.txt.tmp1", 100, hours(2));            // not a leftover of ours
  const CacheTrim t = trim_cache(dir.path().string(), 0);
  EXPECT_FALSE(fs::exists(dir / ("." + name + ".tmp123")));
  EXPECT_TRUE(fs::exists(dir / ("." + name + ".tmp456")));
  EXPECT_TRUE(fs::exists(dir / ".notes.txt.tmp1"));
  EXPECT_EQ(t.removed_entries, 0u);
  EXPECT_EQ(t.entries, 0u);
}

TEST(CacheFolder, NoLimitAndNoFolder) {
  test::TempDir dir;
  for (int i = 0; i < 3; ++i) put(dir / entry(i), 1000, hours(1));
  const CacheTrim t = trim_cache(dir.path().string(), 0);
  EXPECT_EQ(t.removed_entries, 0u);
  EXPECT_EQ(t.entries, 3u);
  EXPECT_EQ(t.bytes, 3000u);
  const CacheTrim none = trim_cache((dir / "missing").string(), 1);
  EXPECT_EQ(none.entries, 0u);
  EXPECT_EQ(trim_cache("", 1).entries, 0u);
}

}  // namespace
}  // namespace gonio::io
