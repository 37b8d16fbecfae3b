#include "io/support/process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "io/support/file_io.h"

extern char** environ;

namespace gonio::io {
namespace {

namespace fs = std::filesystem;

Error error(std::string message) {
  Error e;
  e.message = std::move(message);
  return e;
}

}  // namespace

ScratchDir::ScratchDir(const std::string& prefix) {
  std::string pattern = (fs::temp_directory_path() / (prefix + "-XXXXXX")).string();
  if (::mkdtemp(pattern.data()) != nullptr) path_ = pattern;
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  if (!path_.empty()) fs::remove_all(path_, ec);
}

std::vector<std::string> beside_executable(const std::string& name, const std::string& built) {
  std::vector<std::string> paths;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    paths.push_back((exe.parent_path() / name).string());
    paths.push_back((exe.parent_path().parent_path() / "lib" / "gonio" / name).string());
  }
  if (!built.empty()) paths.push_back(built);
  return paths;
}

std::string last_lines(const std::string& text, std::size_t max_chars) {
  std::string t = text;
  while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
  if (t.size() > max_chars) t = "…" + t.substr(t.size() - max_chars);
  for (char& c : t)
    if (c == '\n') c = ' ';
  return t;
}

Result<ProcessOutput> run_program(const std::vector<std::string>& args, std::chrono::seconds timeout,
                                  std::size_t max_output_bytes, const std::string& missing_hint) {
  if (args.empty()) return error("run_program: no program given");
  ScratchDir dir("gonio-run");
  if (dir.path().empty())
    return error(std::string("cannot create a scratch directory: ") + std::strerror(errno));
  const std::string out_path = (dir.path() / "out").string();
  const std::string err_path = (dir.path() / "err").string();
  const std::string& program = args.front();

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0600);
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = ::posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return error("cannot run '" + program + "' (" + std::strerror(rc) + "): " + missing_hint);

  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR)
      return error("waiting for " + program + ": " + std::strerror(errno));
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      return error(program + " did not finish within " + std::to_string(timeout.count()) + " s");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ProcessOutput result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  const Result<std::string> err = read_file(err_path, 1u << 20);
  if (err.ok()) result.err = err.value();
  Result<std::string> out = read_file(out_path, max_output_bytes);
  if (!out.ok()) return out.error();
  result.out = std::move(out.value());
  return result;
}

}  // namespace gonio::io
