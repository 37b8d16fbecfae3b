#include "photometry/diagnostics.h"
#include "photometry/error_at.h"

#include <gtest/gtest.h>

namespace gonio {
namespace {

TEST(Diagnostics, LocationFormatsWhatIsKnown) {
  EXPECT_EQ(to_string(SourceLoc{"a.ies", 0, 0}), "a.ies");
  EXPECT_EQ(to_string(SourceLoc{"a.ies", 12, 0}), "a.ies:12");
  EXPECT_EQ(to_string(SourceLoc{"a.ies", 12, 5}), "a.ies:12:5");
  EXPECT_EQ(to_string(Error{{"b.ldt", 3, 0}, "bad number"}), "b.ldt:3: bad number");
}

TEST(Diagnostics, ResultHoldsValueOrError) {
  Result<int> good = 7;
  ASSERT_TRUE(good.ok());
  EXPECT_EQ(*good, 7);
  Result<int> bad = Error{{"f", 1, 0}, "nope"};
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "nope");
}

TEST(Diagnostics, WorstSeverity) {
  EXPECT_EQ(worst({}), Severity::Info);
  std::vector<Finding> f = {{Severity::Warning, "w", "", {}}, {Severity::Info, "i", "", {}}};
  EXPECT_EQ(worst(f), Severity::Warning);
  f.push_back({Severity::Error, "e", "", {}});
  EXPECT_EQ(worst(f), Severity::Error);
}

TEST(DiagnosticsDeathTest, CheckStopsOnBrokenInvariant) {
  EXPECT_DEATH(GONIO_CHECK_MSG(1 + 1 == 3, "arithmetic"), "check failed: 1 \\+ 1 == 3: arithmetic");
}

TEST(Diagnostics, AnErrorAtALineNamesTheFileAndTheLine) {
  const Error e = make_error("design.toml", 7, "'points' is missing");
  EXPECT_EQ(e.where.file, "design.toml");
  EXPECT_EQ(e.where.line, 7);
  EXPECT_EQ(e.where.column, 0);
  EXPECT_EQ(e.message, "'points' is missing");
  EXPECT_EQ(to_string(e), "design.toml:7: 'points' is missing");
  // Line 0: the whole file, as make_error(file, message).
  EXPECT_EQ(to_string(make_error("design.toml", 0, "empty")), to_string(make_error("design.toml", "empty")));
}

}  // namespace
}  // namespace gonio
