#include "io/support/process.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>

namespace gonio::io {
namespace {

TEST(Process, CapturesOutputAndExitCode) {
  auto r = run_program({"/bin/sh", "-c", "echo out; echo err >&2; exit 3"}, std::chrono::seconds(30), 1024, "hint");
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_EQ(r.value().exit_code, 3);
  EXPECT_EQ(r.value().out, "out\n");
  EXPECT_EQ(r.value().err, "err\n");
}

TEST(Process, MissingProgramNamesItAndTheHint) {
  auto r = run_program({"gonio-no-such-program"}, std::chrono::seconds(5), 1024, "install it with X");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("gonio-no-such-program"), std::string::npos);
  EXPECT_NE(r.error().message.find("install it with X"), std::string::npos);
}

TEST(Process, TimeLimitKills) {
  const auto start = std::chrono::steady_clock::now();
  auto r = run_program({"/bin/sh", "-c", "sleep 30"}, std::chrono::seconds(1), 1024, "");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("did not finish within 1 s"), std::string::npos);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
}

TEST(Process, OutputOverTheLimitIsAnError) {
  auto r = run_program({"/bin/sh", "-c", "head -c 5000 /dev/zero"}, std::chrono::seconds(30), 1000, "");
  EXPECT_FALSE(r.ok());
}

TEST(Process, ScratchDirGoesAwayWithItsContents) {
  std::filesystem::path kept;
  {
    ScratchDir d("gonio-test");
    ASSERT_FALSE(d.path().empty());
    kept = d.path();
    std::ofstream(d.path() / "f") << "x";
    EXPECT_TRUE(std::filesystem::exists(kept / "f"));
  }
  EXPECT_FALSE(std::filesystem::exists(kept));
}

}  // namespace
}  // namespace gonio::io
