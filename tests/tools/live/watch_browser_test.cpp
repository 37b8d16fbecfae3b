// gonio watch and its live page in a real browser: Debian's headless
// Chromium driven by puppeteer-core (npm, pinned below, installed into the
// build tree at test time) through watch_page.mjs, which
//   - starts `gonio watch` on the bell sample packed as a .glb (--port 0,
//     --out), opens the page, and waits for two iterations pushed over
//     server-sent events;
//   - when the run finishes, checks the page's numbers (flux, emitted flux,
//     LOR, photons, iterations) against report.json, and the estimated error,
//     peak and beam angle against GET /state.json;
//   - moves the shade up 0.2 m in the model file and sees a new run whose
//     curves differ (nadir intensity), with the first run's curves kept as the
//     dashed previous run; measures save → first preview on the page;
//   - writes a truncated .glb and sees the error on the page, naming the
//     file, while the server answers and the last good result stays; then a
//     good model again and the page recovers;
//   - ends gonio with SIGINT (exit 0);
//   - then, without the browser, watches the downlight sample and rewrites
//     the IES profile its model references: GET /state.json shows a new run.
//   - watches a spectral bell (a 2856 K blackbody lamp): the page shows its
//     colour as state.json and report.json give it, CCT 2856 K.
//   - and (watch_optimize_page.mjs) follows a running gonio optimize through
//     gonio watch DIR: the optimisation panel, the merit history, the best
//     against the target, as report.json and history.json give them.
// Screenshots: build/test-artifacts/watch-page.png (and -run1, -error, -colour),
// watch-optimize.png (and -running).
// Needs node, npm (the registry once) and chromium: skips without them,
// fails under CI=true. ctest label `browser`.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace gonio {
namespace {

constexpr const char* kPuppeteerVersion = "24.43.1";

std::filesystem::path puppeteer_dir() {
  return std::filesystem::path(GONIO_BROWSER_DIR) / "node_modules" / "puppeteer-core";
}

// An exclusive lock on a file while it lives (one npm install at a time).
class FileLock {
 public:
  explicit FileLock(const std::filesystem::path& path) : fd_(::open(path.c_str(), O_CREAT | O_RDWR, 0644)) {
    if (fd_ >= 0) ::flock(fd_, LOCK_EX);
  }
  ~FileLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

// What is missing to run the browser test; empty when everything is there.
std::string ensure_browser_tools() {
  if (std::string(GONIO_NODE).empty() || std::string(GONIO_NPM).empty())
    return "node and npm were not found when the build was configured";
  if (std::string(GONIO_CHROMIUM).empty() || !std::filesystem::exists(GONIO_CHROMIUM))
    return "chromium was not found (scripts/setup.sh installs it)";
  std::filesystem::create_directories(GONIO_BROWSER_DIR);
  const FileLock lock(std::filesystem::path(GONIO_BROWSER_DIR) / "install.lock");
  if (std::filesystem::exists(puppeteer_dir() / "package.json")) {
    const auto pkg = nlohmann::json::parse(test::read_file(puppeteer_dir() / "package.json"));
    if (pkg.value("version", "") == kPuppeteerVersion) return {};
  }
  const auto r = test::run_process({GONIO_NPM, "install", "--no-save", "--no-audit", "--no-fund", "--prefix",
                                    GONIO_BROWSER_DIR, std::string("puppeteer-core@") + kPuppeteerVersion});
  if (r.exit_code != 0 || !std::filesystem::exists(puppeteer_dir() / "package.json"))
    return "npm could not install puppeteer-core@" + std::string(kPuppeteerVersion) + ": " + r.err;
  return {};
}

TEST(WatchBrowser, ThePageFollowsTheModelShowsErrorsAndMatchesTheReport) {
  if (const std::string why = ensure_browser_tools(); !why.empty()) GONIO_MISSING("the browser test's tools: " + why);
  test::TempDir work;
  std::filesystem::create_directories(GONIO_ARTIFACTS_DIR);
  const auto r = test::run_process({GONIO_NODE, std::string(GONIO_SOURCE_DIR) + "/tests/tools/live/watch_page.mjs",
                                    puppeteer_dir().string(), GONIO_CHROMIUM, GONIO_EXECUTABLE, GONIO_SAMPLES_DIR,
                                    work.path().string(), GONIO_ARTIFACTS_DIR});
  ASSERT_EQ(r.exit_code, 0) << r.out << "\n" << r.err;
  // The measurements, for the record (ctest -V shows them).
  std::printf("%s", r.out.c_str());
  const auto m = nlohmann::json::parse(r.out.substr(r.out.rfind('{')));
  EXPECT_GT(m["page_updates"].get<int>(), 1);
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(GONIO_ARTIFACTS_DIR) / "watch-page.png"));
}

// gonio watch DIR on a running gonio optimize --out DIR (watch_optimize_page.mjs):
// the optimisation panel while it runs, then the page's best merit, final
// RMS, best variable, history and curves as report.json, history.json and
// state.json give them.
TEST(WatchBrowser, ThePageFollowsARunningOptimisation) {
  if (const std::string why = ensure_browser_tools(); !why.empty()) GONIO_MISSING("the browser test's tools: " + why);
  test::TempDir work;
  std::filesystem::create_directories(GONIO_ARTIFACTS_DIR);
  const auto r = test::run_process({GONIO_NODE,
                                    std::string(GONIO_SOURCE_DIR) + "/tests/tools/live/watch_optimize_page.mjs",
                                    puppeteer_dir().string(), GONIO_CHROMIUM, GONIO_EXECUTABLE,
                                    work.path().string(), GONIO_ARTIFACTS_DIR});
  ASSERT_EQ(r.exit_code, 0) << r.out << "\n" << r.err;
  std::printf("%s", r.out.c_str());
  const auto m = nlohmann::json::parse(r.out.substr(r.out.rfind('{')));
  EXPECT_GE(m["drawn_while_running"].get<int>(), 3);
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(GONIO_ARTIFACTS_DIR) / "watch-optimize.png"));
}

}  // namespace
}  // namespace gonio
