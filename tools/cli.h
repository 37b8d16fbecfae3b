// The small command-line toolkit every `gonio` subcommand uses: option
// parsing with `--help`, typed values with range checks, and the message
// conventions (`gonio: FILE:LINE: message` on stderr).
//
// Exit codes shared by all subcommands (README "Exit codes"):
//   0  success
//   1  the work failed: unreadable or invalid input, a write error, a failed
//      energy check
//   2  usage error: unknown option, missing or malformed argument
// `gonio check` adds its own codes for findings (see cmd_check.cpp).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// Prints "gonio: <message>" to stderr.
void print_error(const std::string& message);
// Prints "gonio: <file>:<line>: <message>" to stderr.
void print_error(const Error& error);
// Prints "gonio: warning: <message>" to stderr.
void print_warning(const std::string& message);
// "<file>:<line>: <severity>: <message> [<code>]" (parts that are unknown
// left out), the form findings of readers, writers and checks take.
std::string format_finding(const Finding& finding);
// Prints "gonio: " + format_finding(finding) to stderr.
void print_finding(const Finding& finding);

// Whether standard error is a terminal (progress output goes there only then).
bool stderr_is_terminal();

class ArgParser {
 public:
  // `command` is the subcommand ("info"); `synopsis` the part of the usage
  // line after it ("FILE [--json]"); `description` a paragraph for --help.
  ArgParser(std::string command, std::string synopsis, std::string description);

  // --name (no value).
  void flag(const std::string& name, bool* out, const std::string& help);
  // --name VALUE or --name=VALUE, as text.
  void option(const std::string& name, std::string* out, const std::string& metavar,
              const std::string& help);
  // Integer and floating-point options with inclusive bounds.
  void option(const std::string& name, long long* out, long long min, long long max,
              const std::string& metavar, const std::string& help);
  void option(const std::string& name, double* out, double min, double max,
              const std::string& metavar, const std::string& help);
  // One of a fixed set of words.
  void choice(const std::string& name, std::string* out, std::vector<std::string> choices,
              const std::string& help);

  // Positional arguments, in order. A list takes all remaining positionals.
  void positional(const std::string& name, std::string* out, const std::string& help);
  void positional_list(const std::string& name, std::vector<std::string>* out,
                       std::size_t min_count, const std::string& help);

  enum class Outcome { Run, Help, Error };
  // Parses; on Help prints the help to stdout, on Error prints the problem and
  // the usage line to stderr. Callers return exit_code(outcome) unless Run.
  Outcome parse(const std::vector<std::string>& args);
  static int exit_code(Outcome outcome) { return outcome == Outcome::Help ? kExitOk : kExitUsage; }

  // Which options appeared on the command line.
  bool given(const std::string& name) const;

  std::string help() const;
  std::string usage() const;

 private:
  struct Option {
    std::string name;
    std::string metavar;  // empty for flags
    std::string help;
    std::function<std::optional<std::string>(const std::string&)> set;  // returns an error
    bool seen = false;
  };
  struct Positional {
    std::string name;
    std::string help;
    std::string* out = nullptr;
    std::vector<std::string>* list = nullptr;
    std::size_t min_count = 1;
  };

  Option* find(const std::string& name);

  std::string command_;
  std::string synopsis_;
  std::string description_;
  std::vector<Option> options_;
  std::vector<Positional> positionals_;
};

}  // namespace gonio::cli
