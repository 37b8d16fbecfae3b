// gonio watch's change detection: stamps, the debounce and the retries of a
// half-written model, driven with a clock of the test's own.
#include "tools/live/watch_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "tests/support/test_support.h"

namespace gonio::cli {
namespace {

using namespace std::chrono_literals;
using T = WatchClock::time_point;

FileStamp stamp(std::uint64_t size, std::int64_t mtime, std::uint64_t inode = 1) {
  return FileStamp{true, size, mtime, inode};
}

TEST(FileStamp, SeesSizeTimeRenameAndDeletion) {
  test::TempDir dir;
  const std::string path = (dir.path() / "model.gltf").string();
  EXPECT_FALSE(stamp_of(path).exists);
  test::write_file(path, "{}");
  const FileStamp a = stamp_of(path);
  EXPECT_TRUE(a.exists);
  EXPECT_EQ(a.size, 2u);
  // Rewritten with the same size and the same time: a rename changes the inode.
  test::write_file((dir.path() / "tmp").string(), "[]");
  std::filesystem::rename(dir.path() / "tmp", path);
  const FileStamp b = stamp_of(path);
  EXPECT_EQ(b.size, 2u);
  EXPECT_NE(a, b);
  std::filesystem::remove(path);
  EXPECT_FALSE(stamp_of(path).exists);
  EXPECT_EQ(snapshot_of({path, path}).size(), 2u);
}

TEST(ChangeDebouncer, FiresOnceTheFilesHaveBeenQuietLongEnough) {
  ChangeDebouncer d(150ms);
  const Snapshot base{stamp(10, 1)};
  d.arm(base);
  const T t0{};
  EXPECT_FALSE(d.observe(base, t0 + 1s)) << "nothing changed";
  const Snapshot written{stamp(20, 2)};
  EXPECT_FALSE(d.observe(written, t0 + 2s)) << "just changed: not quiet yet";
  EXPECT_FALSE(d.observe(written, t0 + 2s + 149ms));
  EXPECT_TRUE(d.observe(written, t0 + 2s + 150ms));
  EXPECT_TRUE(d.observe(written, t0 + 3s)) << "stays ready until re-armed";
  d.arm(written);
  EXPECT_FALSE(d.observe(written, t0 + 4s)) << "the new run was loaded from these files";
}

TEST(ChangeDebouncer, AFileWrittenInBurstsTriggersOnceAfterTheLastWrite) {
  ChangeDebouncer d(150ms);
  d.arm({stamp(0, 0)});
  const T t0{};
  // A modeller writing for half a second, a burst every 100 ms.
  for (int k = 1; k <= 5; ++k)
    EXPECT_FALSE(d.observe({stamp(100u * static_cast<unsigned>(k), k)}, t0 + k * 100ms)) << k;
  EXPECT_FALSE(d.observe({stamp(500, 5)}, t0 + 600ms));
  EXPECT_TRUE(d.observe({stamp(500, 5)}, t0 + 650ms));
}

TEST(ChangeDebouncer, AChangeUndoneBeforeItSettlesIsNoChange) {
  ChangeDebouncer d(150ms);
  const Snapshot base{stamp(10, 1), stamp(5, 1, 7)};
  d.arm(base);
  const T t0{};
  EXPECT_FALSE(d.observe({stamp(10, 1), stamp(6, 2, 7)}, t0));
  EXPECT_FALSE(d.observe(base, t0 + 50ms));
  EXPECT_FALSE(d.observe(base, t0 + 1s));
}

TEST(ChangeDebouncer, AReferencedFileCountsAsMuchAsTheModel) {
  ChangeDebouncer d(100ms);
  d.arm({stamp(10, 1), stamp(5, 1)});
  const T t0{};
  EXPECT_FALSE(d.observe({stamp(10, 1), stamp(5, 9)}, t0));
  EXPECT_TRUE(d.observe({stamp(10, 1), stamp(5, 9)}, t0 + 100ms));
}

TEST(LoadRetry, RetriesAfterEachDelayThenGivesUpUntilTheNextChange) {
  LoadRetry r({250ms, 500ms, 1000ms});
  const T t0{};
  EXPECT_EQ(r.failed(t0), t0 + 250ms);
  EXPECT_EQ(r.failed(t0 + 250ms), t0 + 750ms);
  EXPECT_EQ(r.failed(t0 + 750ms), t0 + 1750ms);
  EXPECT_EQ(r.failures(), 3);
  EXPECT_FALSE(r.failed(t0 + 1750ms).has_value()) << "retries spent: show the error";
  EXPECT_FALSE(r.failed(t0 + 2s).has_value());
  r.reset();  // the file changed again
  EXPECT_EQ(r.failed(t0 + 5s), t0 + 5s + 250ms);
}

}  // namespace
}  // namespace gonio::cli
