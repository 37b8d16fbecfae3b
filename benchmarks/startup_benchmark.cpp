// Whole-process runs of the gonio executable: what a user running `gonio
// info` over a catalogue of files pays per file, start-up included (the
// dynamic loader, static initialisers, the command, exit). The baseline in
// the same run is spawning /bin/true, the floor of any process here.
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

extern char** environ;

namespace {

// Runs argv with stdout and stderr to /dev/null; the exit status.
int run(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The executables timed: the build's gonio, or --gonio=PATH; and with
// --gonio-before=PATH a second build timed in the same run, each command
// right after the first build's (cases named before_…), so that a change's
// before and after share the machine's load.
std::string g_gonio = GONIO_EXECUTABLE;
std::string g_gonio_before;

// User + system CPU time of every child waited for so far [s].
double children_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_CHILDREN, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

void BM_Process(benchmark::State& state, std::vector<std::string> args, const std::string& gonio) {
  if (args[0] == "gonio") args[0] = gonio;
  const double cpu_before = children_cpu_s();
  for (auto _ : state) {
    if (run(args) != 0) {
      state.SkipWithError(("'" + args[0] + " " + (args.size() > 1 ? args[1] : "") + "' failed").c_str());
      break;
    }
  }
  // CPU time of the child processes (user + system) per run: on a loaded
  // machine the wall time includes waiting for a core, this does not.
  state.counters["child_cpu_ms"] = benchmark::Counter(
      1e3 * (children_cpu_s() - cpu_before) / static_cast<double>(state.iterations()));
}

const std::string kGonio = "gonio";
const std::string kCurves = GONIO_CURVES_DIR;
const std::string kName = "gonio-startup-" + std::to_string(getpid()) + ".ldt";
// convert writes atomically and fsyncs (io/support/file_io.h): on a disk that costs
// what the disk takes, so the start-up figure writes to memory (/dev/shm)
// and a second one to the temporary folder shows the fsync.
const std::string kOut =
    (std::filesystem::is_directory("/dev/shm") ? std::filesystem::path("/dev/shm") / kName
                                               : std::filesystem::temp_directory_path() / kName)
        .string();
const std::string kOutDisk = (std::filesystem::temp_directory_path() / kName).string();

struct Case {
  std::string name;
  std::vector<std::string> args;
};

const std::vector<Case>& cases() {
  static const std::vector<Case> all = {
      {"gonio_version", {kGonio, "--version"}},
      {"gonio_info", {kGonio, "info", kCurves + "/downlight.ies"}},
      {"gonio_check", {kGonio, "check", kCurves + "/downlight.ldt"}},
      {"gonio_convert", {kGonio, "convert", kCurves + "/downlight.ies", kOut, "--quiet"}},
      {"gonio_convert_fsync_to_disk", {kGonio, "convert", kCurves + "/downlight.ies", kOutDisk, "--quiet"}},
      {"gonio_compare", {kGonio, "compare", kCurves + "/downlight.ies", kCurves + "/downlight.ldt"}},
  };
  return all;
}

void register_all() {
  const auto add = [](const std::string& name, const std::vector<std::string>& args, const std::string& gonio) {
    benchmark::RegisterBenchmark(("BM_Process/" + name).c_str(),
                                 [args, gonio](benchmark::State& s) { BM_Process(s, args, gonio); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  };
  add("true_baseline", {"/bin/true"}, g_gonio);
  for (const Case& c : cases()) {
    add(c.name, c.args, g_gonio);
    if (!g_gonio_before.empty()) add("before_" + c.name, c.args, g_gonio_before);
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--gonio=", 0) == 0) g_gonio = a.substr(8);
    if (a.rfind("--gonio-before=", 0) == 0) g_gonio_before = a.substr(15);
  }
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::filesystem::remove(kOut);
  std::filesystem::remove(kOutDisk);
  return 0;
}
