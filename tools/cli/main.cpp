// gonio: the command line. Thin by design: each subcommand parses its
// arguments, calls the libraries, prints, and chooses the exit code.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "gonio/version.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"

namespace gonio::cli {
namespace {

// Subcommands in the order `gonio --help` lists them.
const std::vector<Command> kCommands = {
    {"info", "Show what a photometric file holds: grid, lamps, flux, LOR, beam angles", run_info},
    {"check", "Check photometric files for format and plausibility problems", run_check},
    {"convert", "Convert between IES, LDT, TM-33 and GLDF, or to another version", run_convert},
    {"simulate", "Trace a luminaire model (glTF) into photometric, EXR and ray files", run_simulate},
    {"watch", "Simulate a model live in the browser, again whenever it changes on disk", run_watch},
    {"plot", "Draw the intensity diagram of a photometric file (SVG or PNG)", run_plot},
    {"report", "Write the datasheet of photometric files: UGR, CU, SC, BUG (HTML or PDF)", run_report},
    {"compare", "Compare two photometric files: RMS, peak, flux and beam differences", run_compare},
    {"bench", "Measure speed against accuracy on luminaire models (error vs time and photons)", run_bench},
    {"design", "Design a reflector from a target distribution and trace it", run_design},
    {"optimize", "Optimise a design's variables toward a target distribution", run_optimize},
    {"tolerance", "How robust a luminaire is: sensitivities, noise floor, Monte Carlo yield", run_tolerance},
};

void print_help() {
  std::printf(
      "Usage: gonio COMMAND [ARGS...]\n\n"
      "Gonio %s, a virtual goniophotometer: reads, checks and converts IES LM-63,\n"
      "EULUMDAT, IES TM-33 and GLDF files (and IES TM-25 ray files), and simulates\n"
      "luminaire models into them.\n\n"
      "Commands:\n",
      kVersion);
  for (const Command& c : commands()) std::printf("  %-10s %s\n", c.name, c.summary);
  std::printf(
      "\nOptions:\n  --help     Show this help.\n  --version  Show the version.\n\n"
      "Run 'gonio COMMAND --help' for a command's options.\n");
}

int run(int argc, char** argv) {
  if (argc < 2) {
    print_help();
    return kExitUsage;
  }
  const std::string first = argv[1];
  if (first == "--help" || first == "-h" || first == "help") {
    print_help();
    return kExitOk;
  }
  if (first == "--version") {
    std::printf("gonio %s\n", kVersion);
    return kExitOk;
  }
  for (const Command& c : commands()) {
    if (first == c.name) return c.run(Args(argv + 2, argv + argc));
  }
  print_error("unknown command '" + first + "'; see 'gonio --help'");
  return kExitUsage;
}

// Every command prints to stdout (buffered) and returns its exit code; this
// one check makes sure what it printed was written: a full disk or
// `> /dev/full` is an error on stderr and exit code 1 (what the command
// found is lost with its output), never silence.
int checked_stdout(int code) {
  errno = 0;
  const bool flushed = std::fflush(stdout) == 0;
  const int flush_errno = errno;
  if (flushed && !std::ferror(stdout)) return code;
  print_error(std::string("cannot write the standard output") +
              (flush_errno != 0 ? std::string(": ") + std::strerror(flush_errno) : std::string()));
  return kExitFailure;  // the output is lost, whatever the command found
}

}  // namespace

std::span<const Command> commands() { return kCommands; }

}  // namespace gonio::cli

int main(int argc, char** argv) {
  using namespace gonio::cli;
  return checked_stdout(run(argc, argv));
}
