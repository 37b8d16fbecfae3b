// What several test suites need: the corpus folder, scratch directories and
// running the gonio executable.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace gonio::test {

// ../shared/corpus beside the checkout (or $GONIO_CORPUS); empty if absent.
// Tests that need it call GONIO_REQUIRE_CORPUS() first.
std::filesystem::path corpus_dir();

// Every file in the corpus whose extension (case-insensitive) is one of
// `extensions` (e.g. {".ies"}), sorted.
std::vector<std::filesystem::path> corpus_files(const std::vector<std::string>& extensions);

// The repository root.
std::filesystem::path source_dir();

// A fresh empty directory, removed with everything in it when the object dies.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// Writes a file whole (binary), creating nothing else.
void write_file(const std::filesystem::path& path, const std::string& bytes);
std::string read_file(const std::filesystem::path& path);

struct ProcessResult {
  int exit_code = -1;  // -1 if it did not exit normally
  std::string out;
  std::string err;
};

// Runs a program with arguments, standard input from /dev/null, and returns
// its exit code and captured output.
ProcessResult run_process(const std::vector<std::string>& argv);

}  // namespace gonio::test

#define GONIO_REQUIRE_CORPUS()                                                               \
  do {                                                                                       \
    if (::gonio::test::corpus_dir().empty())                                                 \
      GTEST_SKIP() << "photometric corpus not found (../shared/corpus beside the checkout, " \
                      "or $GONIO_CORPUS): skipping";                                         \
  } while (false)
