// Runs the gonio executable as a user would.
#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace gonio {
namespace {

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

TEST(Cli, VersionAndHelp) {
  auto v = gonio({"--version"});
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_EQ(v.out.rfind("gonio ", 0), 0u);
  auto h = gonio({"--help"});
  EXPECT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("Usage: gonio COMMAND"), std::string::npos);
}

TEST(Cli, UnknownCommandIsAUsageError) {
  auto r = gonio({"frobnicate"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("gonio: unknown command 'frobnicate'"), std::string::npos);
  EXPECT_TRUE(r.out.empty());
}

TEST(Cli, NoArgumentsPrintsUsage) {
  auto r = gonio({});
  EXPECT_EQ(r.exit_code, 2);
}

}  // namespace
}  // namespace gonio
