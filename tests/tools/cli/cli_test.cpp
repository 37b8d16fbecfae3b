// Runs the gonio executable as a user would: what every subcommand shares.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/tools/cli/cli_fixtures.h"

namespace gonio {
namespace {

using test::contains;
using test::gonio;

const char* const kSubcommands[] = {"info", "check", "convert", "report"};

TEST(Cli, VersionAndHelp) {
  auto v = gonio({"--version"});
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_EQ(v.out.rfind("gonio ", 0), 0u);
  auto h = gonio({"--help"});
  EXPECT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("Usage: gonio COMMAND"), std::string::npos);
  for (const char* c : kSubcommands) EXPECT_TRUE(contains(h.out, std::string("  ") + c + " ")) << c;
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

TEST(Cli, EverySubcommandHasHelp) {
  for (const char* c : kSubcommands) {
    SCOPED_TRACE(c);
    for (const char* flag : {"--help", "-h"}) {
      auto r = gonio({c, flag});
      EXPECT_EQ(r.exit_code, 0);
      EXPECT_EQ(r.out.rfind(std::string("Usage: gonio ") + c + " ", 0), 0u) << r.out;
      EXPECT_TRUE(contains(r.out, "Exit status")) << r.out;
      EXPECT_TRUE(contains(r.out, "--ldt-isym3")) << r.out;
      EXPECT_TRUE(r.err.empty()) << r.err;
      // Fits an 80-column terminal, but for the usage line.
      std::size_t start = r.out.find('\n') + 1;
      while (start < r.out.size()) {
        const std::size_t end = r.out.find('\n', start);
        EXPECT_LE(end - start, 80u) << r.out.substr(start, end - start);
        start = end + 1;
      }
    }
    // --help wins over anything else on the line.
    EXPECT_EQ(gonio({c, "no-such-file.ies", "--help"}).exit_code, 0);
  }
}

TEST(Cli, UsageErrorsExitWith2AndSayWhy) {
  struct Case {
    std::vector<std::string> args;
    const char* says;
  };
  const std::vector<Case> cases = {
      {{"info"}, "missing FILE"},
      {{"info", "a.ies", "b.ies"}, "unexpected argument 'b.ies'"},
      {{"info", "a.ies", "--frob"}, "unknown option '--frob'"},
      {{"info", "a.ies", "--json=yes"}, "takes no value"},
      {{"info", "a.ies", "--ldt-isym3", "sideways"}, "must be one of standard|qlumedit"},
      {{"info", "a.ies", "--ldt-isym3"}, "needs a value"},
      {{"check"}, "missing FILE"},
      {{"convert", "a.ies"}, "missing OUT"},
      {{"convert", "a.ies", "b.ldt", "c.ldt"}, "unexpected argument 'c.ldt'"},
      {{"convert", "a.ies", "b.txt"}, "extension must be .ies, .ldt, .xml or .gldf"},
      {{"convert", "a.ies", "b"}, "extension must be .ies, .ldt, .xml or .gldf"},
      {{"convert", "a.ies", "b.ies", "--ies-version", "1995"}, "must be one of 2002|2019"},
      {{"convert", "a.ies", "b.ldt", "--ies-version", "2002"}, "applies to .ies output only"},
      {{"convert", "a.ldt", "b.ies", "--ldt-isym3-out", "qlumedit"}, "applies to .ldt output only"},
      {{"convert", "a.ies", "b.ldt", "--c-step", "0"}, "--c-step must be between"},
      {{"convert", "a.ies", "b.ldt", "--c-step", "five"}, "--c-step needs a number"},
      {{"convert", "a.ies", "b.ldt", "--gamma-step", "nan"}, "--gamma-step needs a number"},
      {{"convert", "a.ies", "b.ldt", "-x"}, "unknown option '-x'"},
  };
  for (const Case& c : cases) {
    std::string line;
    for (const auto& a : c.args) line += a + " ";
    SCOPED_TRACE(line);
    auto r = gonio(c.args);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(contains(r.err, c.says)) << r.err;
    EXPECT_EQ(r.err.rfind("gonio: ", 0), 0u) << r.err;
    EXPECT_TRUE(contains(r.err, "Usage: gonio ")) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

// Standard output that cannot be written (here /dev/full, as on a full
// disk) is an error on stderr and exit code 1, whatever the command; the
// same commands succeed with a writable stdout.
TEST(Cli, AStandardOutputThatCannotBeWrittenIsAnErrorForEveryCommand) {
  test::TempDir dir;
  const auto ies = dir / "downlight.ies";
  test::write_distribution(ies, test::lambertian_downlight());
  const std::vector<std::vector<std::string>> commands = {
      {"--version"},
      {"--help"},
      {"info", ies.string()},
      {"info", ies.string(), "--json"},
      {"check", ies.string()},
      {"convert", ies.string(), (dir / "downlight.ldt").string()},
      {"compare", ies.string(), ies.string()},
      {"simulate", "--help"},
      {"bench", "--help"},
  };
  for (const auto& args : commands) {
    std::string command = std::string("exec '") + GONIO_EXECUTABLE + "'";
    for (const std::string& a : args) command += " '" + a + "'";
    SCOPED_TRACE(command);
    const auto ok = test::run_process({"/bin/sh", "-c", command});
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    ASSERT_FALSE(ok.out.empty());  // it does print: the failure below is the write's
    const auto full = test::run_process({"/bin/sh", "-c", command + " > /dev/full"});
    EXPECT_EQ(full.exit_code, 1);
    EXPECT_TRUE(contains(full.err, "gonio: cannot write the standard output")) << full.err;
  }
}

}  // namespace
}  // namespace gonio
