// The `gonio` subcommands. Each lives in tools/cmd_<name>.cpp, parses its own
// arguments with cli::ArgParser and returns the process exit code.
#pragma once

#include <span>
#include <string>
#include <vector>

namespace gonio::cli {

using Args = std::vector<std::string>;

struct Command {
  const char* name;
  const char* summary;  // one line for `gonio --help`
  int (*run)(const Args& args);
};

// Every subcommand, in the order `gonio --help` lists them.
std::span<const Command> commands();

// The subcommands' entry points (tools/cmd_<name>.cpp).
int run_simulate(const Args& args);
int run_plot(const Args& args);
int run_compare(const Args& args);

}  // namespace gonio::cli
