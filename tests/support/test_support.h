// What several test suites need: the corpus folder, scratch directories and
// running the gonio executable.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gonio::test {

// Whether a missing prerequisite (data such as ../shared/corpus, a tool such
// as node or npm) fails a test instead of skipping it: when $CI is "true" or
// "1" (CI services set CI=true; so does .ci/run). Tests do not call this;
// they use GONIO_MISSING below.
bool missing_prerequisite_fails();

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

// Sets (or, with nullptr, removes) an environment variable for one scope and
// restores it after; child processes (run_process) inherit it.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value);
  ~ScopedEnv();
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string name_;
  std::optional<std::string> old_;
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

// Where $GONIO_FUZZ_SEEDS names a folder (scripts/fuzz.sh sets it while it
// runs the reader suites), keeps `bytes` there as a seed for the fuzzer
// `harness` ("ies", "ldt", "gltf"): FOLDER/HARNESS/<hash of the bytes>.
// Does nothing otherwise. The hand-made hostile inputs of the reader tests
// pass through it.
void offer_fuzz_seed(const std::string& harness, std::string_view bytes);

}  // namespace gonio::test

// Ends the test because `what` (a std::string: which data or tool, and where
// it was looked for) is missing: a skip that says so, or, under CI=true
// (missing_prerequisite_fails()), a failure that says so, because a skipped
// test counts as passed and would hide the missing piece.
#define GONIO_MISSING(what)                                                                       \
  do {                                                                                            \
    const std::string gonio_missing_what_ = (what);                                               \
    if (::gonio::test::missing_prerequisite_fails())                                              \
      GTEST_FAIL() << "missing under CI=true (a skip would pass unseen): " << gonio_missing_what_; \
    GTEST_SKIP() << "missing: " << gonio_missing_what_ << " (skipped; under CI=true this fails)";  \
  } while (false)

#define GONIO_REQUIRE_CORPUS()                                                        \
  do {                                                                                \
    if (::gonio::test::corpus_dir().empty())                                          \
      GONIO_MISSING("the photometric corpus (../shared/corpus beside the checkout, or " \
                    "$GONIO_CORPUS)");                                                \
  } while (false)
