// The command line's option parser: every `gonio` subcommand parses its
// arguments with it, with `--help`, typed values and range checks. Messages
// and exit codes are tools/run/console.h's (included here for the commands).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "tools/run/console.h"

namespace gonio::cli {

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
