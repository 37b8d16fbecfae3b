// Running a helper program (gnuplot for charts, a headless browser for PDF
// datasheets) as a separate process: no library state in Gonio's process, a
// time limit, and a missing or failing program as an error value.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::io {

// A private scratch directory under the system's temporary folder, removed
// with its contents when the object goes; path() is empty if it could not
// be created.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& prefix = "gonio");
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

struct ProcessOutput {
  int exit_code = -1;   // -1 if it did not exit normally
  int signal = 0;       // the signal that ended it, if one did
  std::string out;      // standard output (at most max_output_bytes)
  std::string err;      // standard error (at most 1 MiB)
};

// Runs argv[0] (looked up on PATH) with standard input from /dev/null, waits
// at most `timeout` (then kills it). Errors: the program cannot be started
// (the message names it and `missing_hint`), the time limit, an output
// larger than max_output_bytes. A non-zero exit is not an error here: the
// caller reads exit_code and err.
Result<ProcessOutput> run_program(const std::vector<std::string>& argv, std::chrono::seconds timeout,
                                  std::size_t max_output_bytes, const std::string& missing_hint);

// Where a file that ships with gonio (a module, a helper program) is looked
// for, in order: next to the running executable, in ../lib/gonio/ from it,
// then `built` (where the build wrote it, for the tests; empty: not).
std::vector<std::string> beside_executable(const std::string& name, const std::string& built);

// The last max_chars of a program's messages on one line (for error texts).
std::string last_lines(const std::string& text, std::size_t max_chars);

}  // namespace gonio::io
