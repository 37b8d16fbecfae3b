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

// The subcommands (tools/cmd_<name>.cpp). Each returns the process exit code.
int run_info(const Args& args);      // gonio info FILE [--json]
int run_convert(const Args& args);   // gonio convert IN OUT
int run_check(const Args& args);     // gonio check FILE...
int run_simulate(const Args& args);  // gonio simulate MODEL --out DIR
int run_plot(const Args& args);      // gonio plot FILE
int run_compare(const Args& args);   // gonio compare A B
int run_bench(const Args& args);     // gonio bench MODEL... --out DIR
int run_watch(const Args& args);     // gonio watch MODEL
int run_report(const Args& args);    // gonio report FILE... --out X.html|X.pdf
int run_design(const Args& args);    // gonio design reflector --emitter FILE --target FILE --out DIR
int run_optimize(const Args& args);  // gonio optimize DESIGN.design.toml --target FILE --out DIR
int run_tolerance(const Args& args);  // gonio tolerance MODEL --tolerances FILE --out DIR

}  // namespace gonio::cli
