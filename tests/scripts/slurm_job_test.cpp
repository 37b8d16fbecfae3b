// scripts/slurm/gonio-simulate.sbatch, the job script the docs give for
// runs over many nodes, submitted with sbatch to a real one-node Slurm
// (Debian's slurmctld, slurmd and munge, started in a scratch folder under
// the build tree by scripts/slurm/local-cluster.sh and stopped after each
// test, also when it fails; a watcher stops them if this process dies).
// The file itself is submitted, scaled to this machine by sbatch's own
// options (1 node, 2 tasks of 1 core), and its files are compared byte for
// byte with one `gonio simulate` process; then the errors a user meets: a
// rank that dies, a node without the model, a node list the cluster cannot
// give. Label `slurm`; without Slurm or munge it skips, and fails under
// CI=true (scripts/setup.sh installs them).
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;

const fs::path kScript = fs::path(GONIO_SOURCE_DIR) / "scripts/slurm/gonio-simulate.sbatch";
const fs::path kCluster = fs::path(GONIO_SOURCE_DIR) / "scripts/slurm/local-cluster.sh";
const fs::path kGonio = GONIO_EXECUTABLE;
const fs::path kBell = fs::path(GONIO_SAMPLES_DIR) / "bell";

// `name` on $PATH, or empty.
fs::path on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "";
  for (std::size_t start = 0; start <= dirs.size();) {
    const std::size_t colon = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(start, colon - start)) / name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
    start = colon + 1;
  }
  return {};
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

bool folder_is_empty(const fs::path& dir) { return !fs::exists(dir) || fs::is_empty(dir); }

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The photons of every job: 2 iterations of 40000 photons of the bell, seed 7.
const std::vector<std::string> kRun = {"--photons", "40000", "--iterations", "2", "--seed", "7"};

class SlurmJob : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* tool : {"munged", "mungekey", "slurmctld", "slurmd", "sbatch", "srun", "sinfo", "squeue", "scontrol"})
      if (on_path(tool).empty())
        GONIO_MISSING(std::string(tool) + " on PATH (scripts/setup.sh installs munge, slurmctld, slurmd and "
                                          "slurm-client)");
    // A short folder: munge's socket path must fit a sockaddr_un.
    const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    dir_ = fs::path(GONIO_SLURM_DIR) / name.substr(0, 24);
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "work");
    const test::ProcessResult started =
        test::run_process({"/bin/bash", kCluster.string(), "start", (dir_ / "cluster").string(),
                           std::to_string(getpid())});
    if (started.exit_code == 3) GONIO_MISSING(started.err);
    ASSERT_EQ(started.exit_code, 0) << "the one-node cluster did not start:\n" << started.err;
    started_ = true;
    conf_.emplace("SLURM_CONF", (dir_ / "cluster" / "slurm.conf").c_str());
    // The job finds `gonio` on PATH, as on a cluster: dir_/bin holds a link
    // to the build's (or, in the fault tests, a wrapper around it).
    fs::create_directories(dir_ / "bin");
    const std::string path = (dir_ / "bin").string() + ":" + (std::getenv("PATH") ? std::getenv("PATH") : "");
    path_.emplace("PATH", path.c_str());
  }

  void TearDown() override {
    conf_.reset();
    path_.reset();
    if (started_) {
      const test::ProcessResult stopped =
          test::run_process({"/bin/bash", kCluster.string(), "stop", (dir_ / "cluster").string()});
      EXPECT_EQ(stopped.exit_code, 0) << stopped.err;
    }
  }

  // `gonio` on the job's PATH: the build's, or a shell script that runs
  // `prelude` first and then becomes the build's gonio ($$ stays its pid).
  void install_gonio(const std::string& prelude = "") {
    const fs::path to = dir_ / "bin" / "gonio";
    fs::remove(to);
    if (prelude.empty()) {
      fs::create_symlink(kGonio, to);
      return;
    }
    test::write_file(to, "#!/bin/sh\n" + prelude + "\nexec \"" + kGonio.string() + "\" \"$@\"\n");
    fs::permissions(to, fs::perms::owner_all);
  }

  // sbatch of the job script with `sbatch_options` before it and MODEL OUT
  // and the run's options after it, from dir_/work, its stdout and stderr
  // in dir_/job.out; then waits for the job to end (polling squeue: sbatch
  // --wait polls only every few seconds). exit_code: the job's exit code
  // (scontrol's ExitCode), or sbatch's where it refused the job; err:
  // sbatch's stderr.
  test::ProcessResult submit(const std::vector<std::string>& sbatch_options, const std::string& model,
                             const std::string& out, const std::vector<std::string>& extra = {}) {
    std::vector<std::string> argv = {on_path("sbatch").string(), "--parsable",
                                     "--output=" + (dir_ / "job.out").string(),
                                     "--chdir=" + (dir_ / "work").string()};
    argv.insert(argv.end(), sbatch_options.begin(), sbatch_options.end());
    argv.insert(argv.end(), {kScript.string(), model, out});
    argv.insert(argv.end(), kRun.begin(), kRun.end());
    argv.insert(argv.end(), extra.begin(), extra.end());
    test::ProcessResult r = test::run_process(argv);
    if (r.exit_code != 0) return r;
    job_ = r.out.substr(0, r.out.find_first_of(";\n"));
    // Every job here asks for --time=10 (minutes); Slurm ends it by then.
    const auto submitted = std::chrono::steady_clock::now();
    for (;;) {
      const test::ProcessResult q = test::run_process({on_path("squeue").string(), "-h", "-j", job_, "-o", "%T"});
      if (q.exit_code != 0 || q.out.empty()) break;
      if (seconds_since(submitted) > 720.0) {
        ADD_FAILURE() << "job " << job_ << " still " << q.out << " after 12 minutes";
        break;
      }
      usleep(200'000);
    }
    const test::ProcessResult shown = test::run_process({on_path("scontrol").string(), "show", "job", job_});
    const std::size_t at = shown.out.find(" ExitCode=");
    r.exit_code = at == std::string::npos ? -1 : std::atoi(shown.out.c_str() + at + 10);
    return r;
  }

  std::string job_log() const { return fs::exists(dir_ / "job.out") ? test::read_file(dir_ / "job.out") : ""; }

  // This machine's two cores as two tasks of one core each (the script's own
  // directives ask for 8 nodes of 32 cores).
  static std::vector<std::string> two_tasks() {
    return {"--nodes=1", "--ntasks-per-node=2", "--cpus-per-task=1", "--time=10"};
  }

  fs::path dir_;
  std::string job_;  // the last job's id
  bool started_ = false;
  std::optional<test::ScopedEnv> conf_, path_;
};

nlohmann::json read_report(const fs::path& dir) {
  return nlohmann::json::parse(test::read_file(dir / "report.json"));
}

TEST_F(SlurmJob, TwoTasksWriteTheBytesOfOneProcess) {
  install_gonio();
  const fs::path one = dir_ / "one", job = dir_ / "job";
  std::vector<std::string> argv = {kGonio.string(), "simulate", (kBell / "bell.gltf").string(), "--out",
                                   one.string(), "--threads", "2"};
  argv.insert(argv.end(), kRun.begin(), kRun.end());
  const auto t_one = std::chrono::steady_clock::now();
  const test::ProcessResult single = test::run_process(argv);
  const double one_s = seconds_since(t_one);
  ASSERT_EQ(single.exit_code, 0) << single.err;

  const auto t_job = std::chrono::steady_clock::now();
  const test::ProcessResult r = submit(two_tasks(), (kBell / "bell.gltf").string(), job.string());
  const double job_s = seconds_since(t_job);
  const std::string log = job_log();
  ASSERT_EQ(r.exit_code, 0) << r.err << log;

  // Every file one process wrote, byte for byte (report.json holds times).
  int compared = 0;
  for (const auto& entry : fs::directory_iterator(one)) {
    const std::string name = entry.path().filename().string();
    if (name == "report.json") continue;
    ASSERT_TRUE(fs::exists(job / name)) << name << " missing from the job's files\n" << log;
    EXPECT_TRUE(test::read_file(entry.path()) == test::read_file(job / name)) << name << " differs";
    ++compared;
  }
  EXPECT_GE(compared, 5);  // bell.ies, bell.ldt, farfield.exr, farfield-latlong.exr, bell.svg
  const nlohmann::json a = read_report(one), b = read_report(job);
  for (const char* key : {"photons_emitted", "photons_escaped", "photons_absorbed", "photons_cutoff", "rays",
                          "emitted_lm", "escaped_lm"})
    EXPECT_EQ(a[key], b[key]) << key;
  // Two ranks of one thread each (srun started both; --threads came from
  // $SLURM_CPUS_PER_TASK), and the job said what it did.
  ASSERT_EQ(b["mpi"]["ranks"], 2) << b["mpi"].dump();
  for (const auto& rank : b["mpi"]["per_rank"]) EXPECT_EQ(rank["threads"], 1) << rank.dump();
  EXPECT_TRUE(contains(log, "gonio-simulate.sbatch: job " + job_ + ": " + (kBell / "bell.gltf").string() +
                                " traced in"))
      << log;
  EXPECT_TRUE(contains(log, "by 2 ranks x 1 threads")) << log;
  // The wall times, for docs/slurm.md (not asserted: the machine is shared).
  std::printf("one process (2 threads): %.2f s wall; the 2-task job from sbatch to its end: %.2f s wall\n", one_s,
              job_s);
  std::printf("job log:\n%s\n", log.c_str());
}

TEST_F(SlurmJob, ARankThatDiesEndsTheJobWithAReport) {
  // Rank 1 is killed (SIGKILL) three seconds in, long before its 1000
  // iterations are done; srun must stop rank 0, which waits for it in a
  // reduction, instead of leaving the job to hang until its time limit.
  install_gonio("if [ \"$SLURM_PROCID\" = 1 ]; then (sleep 3; kill -KILL $$) & fi");
  const fs::path out = dir_ / "out";
  const auto t = std::chrono::steady_clock::now();
  const test::ProcessResult r =
      submit(two_tasks(), (kBell / "bell.gltf").string(), out.string(), {"--iterations", "1000"});
  const double s = seconds_since(t);
  const std::string log = job_log();
  EXPECT_NE(r.exit_code, 0) << log;
  EXPECT_LT(s, 120.0) << log;  // not the 10 minutes of --time
  EXPECT_TRUE(contains(log, "task 1: Killed")) << log;  // srun names the task
  EXPECT_TRUE(contains(log, "gonio-simulate.sbatch: job ")) << log;
  EXPECT_TRUE(contains(log, ": the run failed (srun exit status ")) << log;
  // The report repeats srun's line that names the task that died.
  EXPECT_TRUE(std::regex_search(log, std::regex("gonio-simulate\\.sbatch:   srun: error: [^ ]+: task 1: Killed")))
      << log;
  EXPECT_TRUE(contains(log, "of 1000 iterations") || contains(log, "done before it failed: no iteration")) << log;
  EXPECT_TRUE(contains(log, "nothing written to " + out.string())) << log;
  EXPECT_TRUE(folder_is_empty(out));
}

TEST_F(SlurmJob, ANodeWithoutTheModelStopsTheJobBeforeTracing) {
  // The model is named relative to the job's folder; rank 1 runs from an
  // empty folder, as on a node without the shared file system.
  fs::copy(kBell, dir_ / "work" / "bell");
  fs::create_directories(dir_ / "elsewhere");
  install_gonio("if [ \"$SLURM_PROCID\" = 1 ]; then cd \"" + (dir_ / "elsewhere").string() + "\"; fi");
  const test::ProcessResult r = submit(two_tasks(), "bell/bell.gltf", "out");
  const std::string log = job_log();
  EXPECT_NE(r.exit_code, 0) << log;
  EXPECT_TRUE(contains(log, "gonio: simulate: rank 1 of 2 could not get ready")) << log;
  EXPECT_TRUE(contains(log, "done before it failed: no iteration")) << log;
  EXPECT_TRUE(contains(log, "nothing written to out")) << log;
  EXPECT_TRUE(folder_is_empty(dir_ / "work" / "out"));
}

// srun exits 0 for a step whose tasks never launched (seen here when two
// clusters on one machine shared job ids: "task 0 launch failed"); the
// script must not call that a success. Ranks that exit 0 without running
// stand in for it.
TEST_F(SlurmJob, AStepThatLeavesNoReportIsAFailure) {
  install_gonio("exit 0");
  const fs::path out = dir_ / "out";
  const test::ProcessResult r = submit(two_tasks(), (kBell / "bell.gltf").string(), out.string());
  const std::string log = job_log();
  EXPECT_NE(r.exit_code, 0) << log;
  EXPECT_TRUE(contains(log, "srun exited 0 but no report.json was written to " + out.string())) << log;
  EXPECT_TRUE(contains(log, ": the run failed (srun exit status 0)")) << log;
  EXPECT_FALSE(contains(log, "traced in")) << log;
}

TEST_F(SlurmJob, ANodeListTheClusterDoesNotHaveIsRefusedAtSubmission) {
  install_gonio();
  std::vector<std::string> options = two_tasks();
  options.push_back("--nodelist=gonio-no-such-node");
  const fs::path out = dir_ / "out";
  const test::ProcessResult r = submit(options, (kBell / "bell.gltf").string(), out.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.err, "Invalid node name specified")) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "job.out"));  // no job ran
  EXPECT_TRUE(folder_is_empty(out));
}

// The script's own directives (8 nodes) on a cluster of one: sbatch would
// queue the job for ever (reason PartitionNodeLimit, unless the cluster sets
// EnforcePartLimits); sbatch --test-only, which docs/slurm.md advises
// before a first submission, refuses it at once.
TEST_F(SlurmJob, MoreNodesThanTheClusterHasAreRefusedByATestSubmission) {
  install_gonio();
  const test::ProcessResult r = test::run_process(
      {on_path("sbatch").string(), "--test-only", "--chdir=" + (dir_ / "work").string(), kScript.string(),
       (kBell / "bell.gltf").string(), (dir_ / "out").string()});
  EXPECT_NE(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "Requested node configuration is not available")) << r.err;
}

}  // namespace
}  // namespace gonio
