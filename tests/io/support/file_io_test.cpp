#include "io/support/file_io.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

TEST(FileIo, ReadsRegularFilesAndNamesWhatIsWrong) {
  test::TempDir dir;
  test::write_file(dir / "a.txt", "hello");
  auto ok = read_file((dir / "a.txt").string(), 100);
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ(*ok, "hello");

  auto missing = read_file((dir / "missing.ies").string(), 100);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().where.file, (dir / "missing.ies").string());

  auto directory = read_file(dir.path().string(), 100);
  ASSERT_FALSE(directory.ok());
  EXPECT_NE(directory.error().message.find("directory"), std::string::npos);

  auto too_big = read_file((dir / "a.txt").string(), 4);
  ASSERT_FALSE(too_big.ok());
  EXPECT_NE(too_big.error().message.find("too large"), std::string::npos);
}

TEST(FileIo, AtomicWriteReplacesWholeAndLeavesNoTemporaries) {
  test::TempDir dir;
  const auto target = dir / "out.ies";
  test::write_file(target, "old contents");
  ASSERT_TRUE(write_file_atomic(target.string(), "new").ok());
  EXPECT_EQ(test::read_file(target), "new");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(FileIo, FailedWriteLeavesTargetUntouched) {
  test::TempDir dir;
  Status s = write_file_atomic((dir / "no-such-dir" / "x.ies").string(), "data");
  ASSERT_FALSE(s.ok());
  EXPECT_FALSE(std::filesystem::exists(dir / "no-such-dir"));
}

TEST(FileIo, MakesDirectories) {
  test::TempDir dir;
  ASSERT_TRUE(make_directories((dir / "a" / "b").string()).ok());
  EXPECT_TRUE(std::filesystem::is_directory(dir / "a" / "b"));
  test::write_file(dir / "f", "x");
  EXPECT_FALSE(make_directories((dir / "f").string()).ok());
}

}  // namespace
}  // namespace gonio::io
