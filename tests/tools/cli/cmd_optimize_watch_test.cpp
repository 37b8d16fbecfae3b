// gonio watch DIR following a running gonio optimize --out DIR, as a user
// runs the two side by side: while the optimisation runs, GET /state.json
// (the live page's route, through curl) carries the best merit, the merit
// history and the best's candela against the target, and each of them agrees
// with what the run finally writes (history.json, report.json); the finished
// state carries report.json's final figures. On the conic dish of
// cmd_optimize_test.cpp.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "design/reflector_design.h"
#include "io/photometric/photometric_file.h"
#include "tests/support/test_support.h"

extern char** environ;

namespace gonio {
namespace {

namespace fs = std::filesystem;

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

void write(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

std::string design_text(const std::string& conic) {
  return "length_unit = \"mm\"\n[materials.mirror]\nreflectance = 0.9\n[[emitters]]\nname = \"LED\"\n"
         "position = [0, 0, 0]\nprofile = \"up.ies\"\n[[reflectors]]\nname = \"dish\"\nmaterial = \"mirror\"\n"
         "profile = \"conic\"\nradius = 10\nconic = " + conic + "\nvertex = 5\naperture = [2, 30]\n";
}

// A program in the background, its stdout and stderr into `log`.
class Background {
 public:
  Background(std::vector<std::string> args, const fs::path& log) : log_(log) {
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    if (posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  ~Background() {
    if (pid_ > 0 && !done_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;
  bool started() const { return pid_ > 0; }
  std::string log() const { return test::read_file(log_); }
  // The exit code once it has ended (within `wait`), else -1.
  int wait(std::chrono::seconds wait, bool interrupt = false) {
    if (done_) return code_;
    if (interrupt) ::kill(pid_, SIGINT);
    const auto until = std::chrono::steady_clock::now() + wait;
    int status = 0;
    while (std::chrono::steady_clock::now() < until) {
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        done_ = true;
        code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        return code_;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return -1;
  }
  bool running() {
    if (done_) return false;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      done_ = true;
      code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    return !done_;
  }

 private:
  fs::path log_;
  pid_t pid_ = -1;
  bool done_ = false;
  int code_ = -1;
};

// curl on the PATH (empty: none).
std::string curl_program() {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(start, end - start)) / "curl";
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
    start = end + 1;
  }
  return {};
}

nlohmann::json get_json(const std::string& url) {
  const test::ProcessResult r = test::run_process({curl_program(), "-s", "--max-time", "5", url});
  if (r.exit_code != 0) return nullptr;
  return nlohmann::json::parse(r.out, nullptr, false);
}

// 100 · RMS(best − target) / target's peak over the served curves' C0 plane:
// the merit's candela RMS where the grid has one column (the default merit).
double served_rms_pct(const nlohmann::json& state) {
  const nlohmann::json& best = state.at("curves").at("c0");
  const nlohmann::json& target = state.at("previous_curves").at("c0");
  double sum = 0.0, peak = 0.0;
  for (std::size_t g = 0; g < best.size(); ++g) {
    const double d = best[g].get<double>() - target[g].get<double>();
    sum += d * d;
    peak = std::max(peak, target[g].get<double>());
  }
  return 100.0 * std::sqrt(sum / static_cast<double>(best.size())) / peak;
}

TEST(OptimizeWatch, TheServedStateFollowsTheRunAndMatchesWhatItWrites) {
  if (curl_program().empty()) GONIO_MISSING("curl on the PATH (to ask the live page's server)");
  test::TempDir dir;
  std::vector<double> g, c;
  for (int i = 0; i <= 72; ++i) {
    g.push_back(2.5 * i);
    c.push_back(g.back() <= 90.0 ? 0.0 : -318.31 * std::cos(g.back() * std::numbers::pi / 180.0));
  }
  ASSERT_TRUE(
      io::write_photometric_file((dir / "up.ies").string(), design::rotational_distribution(g, c), {}, nullptr).ok());
  write(dir / "truth.design.toml", design_text("-1.5"));
  write(dir / "start.design.toml", design_text("{ value = -2.6, min = -3, max = -1 }"));
  ASSERT_EQ(gonio({"simulate", (dir / "truth.design.toml").string(), "--out", (dir / "truth").string(), "--photons",
                   "200000", "--iterations", "1", "--gamma-step", "2.5", "--format", "ies", "--no-cache"})
                .exit_code,
            0);
  const fs::path out = dir / "out";
  fs::create_directories(out);
  // The page first, on the folder the optimisation will write into.
  Background watch({GONIO_EXECUTABLE, "watch", out.string(), "--port", "0"}, dir / "watch.log");
  ASSERT_TRUE(watch.started());
  std::string url;
  for (int i = 0; i < 400 && url.empty(); ++i) {
    std::smatch m;
    const std::string text = watch.log();
    if (std::regex_search(text, m, std::regex("live page: (\\S+)"))) url = m[1];
    else std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_FALSE(url.empty()) << watch.log();
  const nlohmann::json waiting = get_json(url + "state.json");
  ASSERT_TRUE(waiting.is_object()) << watch.log();
  EXPECT_EQ(waiting.value("kind", ""), "optimize");
  EXPECT_EQ(waiting.value("status", ""), "loading");
  // The same page as gonio watch of a model, with its optimisation panel.
  const test::ProcessResult page = test::run_process({curl_program(), "-s", "--max-time", "5", url});
  EXPECT_NE(page.out.find("id=\"optimize-panel\""), std::string::npos);

  Background run({GONIO_EXECUTABLE, "optimize", (dir / "start.design.toml").string(), "--target",
                  (dir / "truth" / "truth.ies").string(), "--out", out.string(), "--gamma-step", "5",
                  "--no-step", "--max-evals", "40", "--final-photons", "100000", "--threads", "1"},
                 dir / "optimize.log");
  ASSERT_TRUE(run.started());
  std::vector<nlohmann::json> running;
  nlohmann::json finished;
  const auto until = std::chrono::steady_clock::now() + std::chrono::minutes(4);
  while (std::chrono::steady_clock::now() < until) {
    const nlohmann::json s = get_json(url + "state.json");
    if (s.is_object() && s.value("status", "") == "running" && s.at("optimize").at("evaluation").get<int>() > 0 &&
        (running.empty() || running.back().at("version") != s.at("version")))
      running.push_back(s);
    if (s.is_object() && s.value("status", "") == "finished") {
      finished = s;
      break;
    }
    if (!run.running() && s.is_object() && s.value("status", "") != "running") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
  }
  ASSERT_EQ(run.wait(std::chrono::seconds(60)), 0) << run.log();
  ASSERT_TRUE(finished.is_object()) << watch.log() << run.log();
  ASSERT_GE(running.size(), 2u) << "the page saw too few states while the run went on";

  const nlohmann::json history = nlohmann::json::parse(test::read_file(out / "history.json"));
  const nlohmann::json report = nlohmann::json::parse(test::read_file(out / "report.json")).at("optimize");
  for (const nlohmann::json& s : running) {
    const nlohmann::json& o = s.at("optimize");
    const nlohmann::json& h = o.at("history");
    const int evaluation = o.at("evaluation").get<int>();
    ASSERT_EQ(h.size(), static_cast<std::size_t>(evaluation));
    // The served history is history.json's first rows, exactly.
    for (std::size_t i = 0; i < h.size(); ++i) ASSERT_EQ(h[i], history.at(i)) << "row " << i;
    // The page's iteration: the last evaluation of a stage (the noise
    // floor's traces come after the search).
    int searched = 0;
    for (const nlohmann::json& row : h)
      if (row.at("stage").is_number()) searched = row.at("index").get<int>();
    EXPECT_EQ(s.at("iteration").get<int>(), searched);
    // The best merit is that of the row it names, and that row's best.
    const int best = o.at("best_index").get<int>();
    ASSERT_GE(best, 1);
    ASSERT_LE(best, evaluation);
    EXPECT_EQ(o.at("best_merit").get<double>(), history.at(best - 1).at("merit").get<double>());
    EXPECT_EQ(o.at("best_merit").get<double>(), history.at(evaluation - 1).at("best").get<double>());
    EXPECT_EQ(o.at("best_values"), history.at(best - 1).at("values"));
    // The best's candela against the target are what the merit saw: their
    // RMS is the best's candela RMS, which is the default merit itself.
    ASSERT_TRUE(s.at("curves").is_object());
    EXPECT_NEAR(served_rms_pct(s), o.at("candela_rms_pct").get<double>(), 1e-9 * o.at("candela_rms_pct").get<double>());
    EXPECT_NEAR(o.at("candela_rms_pct").get<double>(), o.at("best_merit").get<double>(),
                1e-9 * o.at("best_merit").get<double>());
  }
  // Merits fall as the run goes on, as the page shows them.
  EXPECT_LE(running.back().at("optimize").at("best_merit").get<double>(),
            running.front().at("optimize").at("best_merit").get<double>());
  // Finished: the files are written, and the state says what they say.
  const nlohmann::json& f = finished.at("optimize");
  EXPECT_EQ(f.at("history"), history);
  EXPECT_EQ(f.at("final"), report.at("final"));
  EXPECT_EQ(f.at("stopped_by"), report.at("stopped_by"));
  EXPECT_EQ(f.at("noise_floor"), report.at("noise_floor"));
  EXPECT_EQ(f.at("best_merit"), report.at("best_merit"));
  for (const nlohmann::json& v : report.at("variables"))
    EXPECT_EQ(f.at("best_values").at(v.at("name").get<std::string>()), v.at("best"));
  EXPECT_NEAR(served_rms_pct(finished), report.at("best_merit").get<double>(),
              1e-9 * report.at("best_merit").get<double>());
  EXPECT_NE(watch.log().find("the optimisation has finished"), std::string::npos) << watch.log();
  EXPECT_EQ(watch.wait(std::chrono::seconds(20), true), 0) << watch.log();
}

}  // namespace
}  // namespace gonio
