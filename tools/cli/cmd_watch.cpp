// gonio watch: the interactive loop (tools/live/watch.h). Runs the
// progressive simulation of a model, shows it on a local web page
// (tools/live/live_view.h), and starts again whenever the model, or a file it
// references (model_files, tools/run/model_input.h: a CAD model's sidecar and
// its profiles too), changes on disk. This file parses the options into a plan,
// calls app::watch, and prints.
//
//   gonio watch MODEL [--port P] [--host ADDR] [--out DIR] [simulate options]
//
// Changes are polled every 50 ms and debounced (tools/live/watch_files.h: 150 ms
// without a further change); a run in progress is stopped between slices of
// 16384 photons. Unless given, --photons is 262144 and --iterations 1000 (a
// page update every few tenths of a second; the run goes on until the target
// error, the last iteration or the next change), and the first iteration of
// every run is 65536 photons (a first preview soon after a change). A model that cannot be read is retried after 250, 500 and
// 1000 ms (a modeller may still be saving), then its error is shown while the
// last good result stays on the page. With --out, every run that finishes
// (all iterations, or --target-error reached) writes what `gonio simulate`
// writes. Ends on Ctrl-C (exit 0).
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/cli/simulate_command.h"
#include "tools/live/watch.h"
#include "tools/live/watch_optimize.h"

namespace gonio::cli {

int run_watch(const Args& args) {
  std::string model, host = app::kLiveHost;
  long long port = app::kDefaultLivePort;
  app::SimulateOptions options;
  ArgParser p("watch", "MODEL [--port P] [--out DIR] [simulate options]",
              "Simulates a luminaire model progressively and shows the light on a local web\n"
              "page (http://127.0.0.1:P/): the filtered far field as an unfolded cube and on a\n"
              "sphere, the C0-C180 and C90-C270 curves (the previous run's dashed), flux, LOR,\n"
              "beam and field angles, peak, speed, the estimated candela error, the model's\n"
              "check findings and the last error. GET /state.json gives the same numbers to\n"
              "scripts. Whenever MODEL or a file it references (buffers, profiles; a CAD model's\n"
              "sidecar and the sidecar's profiles and ray files) changes,\n"
              "the run starts again (debounced; a half-written file is retried; the last good\n"
              "result stays up while the model cannot be read). With --out DIR, each run that\n"
              "finishes writes the files and report.json of `gonio simulate`. Ctrl-C ends it.\n"
              "Unlike simulate, --photons defaults to 262144 and --iterations to 1000 here.");
  p.positional("MODEL", &model,
               "the luminaire model (.gltf, .glb, .step, .stp, .iges or .igs), or the --out DIR of a running\n"
               "gonio optimize: its best design against the target and its merit history, followed live");
  p.option("port", &port, 0, 65535, "P", "port of the page (default 8765; 0: any free port, printed)");
  p.option("host", &host, "ADDR", "address to listen on (default 127.0.0.1: this machine only)");
  p.option("out", &options.out_dir, "DIR", "write each finished run's files here (default: none)");
  options.photons = app::kWatchPhotons;  // before the options, so that --help shows them
  options.iterations = app::kWatchIterations;
  add_simulate_options(p, &options);
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run)
    return ArgParser::exit_code(outcome);
  // A folder: follow the optimisation writing into it (gonio optimize --out DIR).
  std::error_code ec;
  if (std::filesystem::is_directory(model, ec)) {
    app::WatchOptimizeHooks follow;
    follow.on_started = [&model](const std::string& url) {
      std::printf("live page: %s\n", url.c_str());
      std::printf("following the optimisation in %s (%s; Ctrl-C to stop)\n", model.c_str(),
                  app::optimize_state_path(model).c_str());
      std::fflush(stdout);
    };
    follow.on_finished = [](const std::string& status) {
      std::printf("watch: the optimisation has %s\n", status == "finished" ? "finished" : "failed");
      std::fflush(stdout);
    };
    if (Status s = app::watch_optimization(model, host, static_cast<int>(port), follow); !s.ok()) {
      print_error(s.error());
      return kExitFailure;
    }
    std::printf("watch: stopped\n");
    return kExitOk;
  }
  std::optional<app::SimulatePlan> plan = plan_or_usage("watch", model, options, p);
  if (!plan) return kExitUsage;
  app::WatchHooks hooks;
  hooks.on_started = [&model](const std::string& url) {
    std::printf("live page: %s\n", url.c_str());
    std::printf("watching %s (Ctrl-C to stop)\n", model.c_str());
    std::fflush(stdout);
  };
  hooks.on_files = [&plan](const app::ProgressiveOutcome& run, const app::RunFiles& files) {
    const int code = print_run_files(*plan, run, files);
    std::fflush(stdout);
    return code == kExitOk;
  };
  if (Status s = app::watch(*plan, host, static_cast<int>(port), hooks); !s.ok()) {
    print_error(s.error());
    return kExitFailure;
  }
  std::printf("watch: stopped\n");
  return kExitOk;
}

}  // namespace gonio::cli
