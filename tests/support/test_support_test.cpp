// The test helpers themselves: a missing prerequisite skips, or fails under
// CI=true, and says what is missing; fuzz seeds land where
// $GONIO_FUZZ_SEEDS says, and nowhere otherwise.
#include "tests/support/test_support.h"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace gonio {
namespace {

using test::ScopedEnv;

// A test body that lacks something.
void lacks_the_tool() { GONIO_MISSING("the frobnicator (not on PATH)"); }

// What GONIO_MISSING reports, intercepted so that it does not end this test.
testing::TestPartResult outcome_of_missing() {
  testing::TestPartResultArray results;
  {
    testing::ScopedFakeTestPartResultReporter reporter(
        testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &results);
    lacks_the_tool();
  }
  EXPECT_EQ(results.size(), 1);
  return results.GetTestPartResult(0);
}

TEST(Missing, OnlyCiTrueOrOneMakesAMissingPrerequisiteFail) {
  {
    const ScopedEnv ci("CI", nullptr);
    EXPECT_FALSE(test::missing_prerequisite_fails());
  }
  for (const char* value : {"true", "1"}) {
    const ScopedEnv ci("CI", value);
    EXPECT_TRUE(test::missing_prerequisite_fails()) << value;
  }
  for (const char* value : {"", "false", "0", "no"}) {
    const ScopedEnv ci("CI", value);
    EXPECT_FALSE(test::missing_prerequisite_fails()) << value;
  }
}

TEST(Missing, OutsideCiItSkipsAndSaysWhatIsMissing) {
  const ScopedEnv ci("CI", nullptr);
  const testing::TestPartResult r = outcome_of_missing();
  EXPECT_TRUE(r.skipped());
  EXPECT_NE(std::string(r.message()).find("the frobnicator (not on PATH)"), std::string::npos) << r.message();
}

TEST(Missing, UnderCiTrueItFailsAndSaysWhatIsMissing) {
  const ScopedEnv ci("CI", "true");
  const testing::TestPartResult r = outcome_of_missing();
  EXPECT_TRUE(r.fatally_failed());
  EXPECT_FALSE(r.skipped());
  EXPECT_NE(std::string(r.message()).find("the frobnicator (not on PATH)"), std::string::npos) << r.message();
  EXPECT_NE(std::string(r.message()).find("CI=true"), std::string::npos) << r.message();
}

TEST(Missing, TheCorpusCheckUsesIt) {
  // With $GONIO_CORPUS naming a folder that does not exist, the corpus is
  // missing: under CI=true that is a failure naming the corpus.
  const ScopedEnv corpus("GONIO_CORPUS", "/nonexistent/gonio-corpus");
  const ScopedEnv ci("CI", "true");
  EXPECT_TRUE(test::corpus_dir().empty());
  EXPECT_FATAL_FAILURE(
      [] { GONIO_REQUIRE_CORPUS(); }(), "missing under CI=true (a skip would pass unseen): the photometric corpus");
}

TEST(FuzzSeeds, KeptOnlyWhereTheVariableNamesAFolder) {
  test::TempDir dir;
  {
    const ScopedEnv seeds("GONIO_FUZZ_SEEDS", nullptr);
    test::offer_fuzz_seed("ies", "nothing is kept");
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
  const ScopedEnv seeds("GONIO_FUZZ_SEEDS", dir.path().c_str());
  test::offer_fuzz_seed("ies", "IESNA:LM-63-2002");
  test::offer_fuzz_seed("ies", "IESNA:LM-63-2002");  // the same bytes: one file
  test::offer_fuzz_seed("ldt", std::string("a\0b", 3));
  int files = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir.path()))
    if (e.is_regular_file()) ++files;
  EXPECT_EQ(files, 2);
  for (const auto& e : std::filesystem::directory_iterator(dir / "ldt"))
    EXPECT_EQ(test::read_file(e.path()), std::string("a\0b", 3));
  for (const auto& e : std::filesystem::directory_iterator(dir / "ies"))
    EXPECT_EQ(test::read_file(e.path()), "IESNA:LM-63-2002");
}

}  // namespace
}  // namespace gonio
