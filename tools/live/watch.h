// The interactive loop of `gonio watch`, for any front end: runs the
// progressive simulation of a model, shows it on the live page
// (tools/live/live_view.h), and starts again whenever the model, or a file it
// references, changes on disk.
//
// Changes are polled every 50 ms and debounced (tools/live/watch_files.h:
// 150 ms without a further change); a run in progress is stopped between
// slices of 16384 photons. The first iteration of every run is 65536 photons
// (a first preview soon after a change). A model that cannot be read is
// retried after 250, 500 and 1000 ms (a modeller may still be saving), then
// its error is shown while the last good result stays on the page. Where the
// plan names a folder, every run that finishes (all iterations, or the
// target error reached) writes what `gonio simulate` writes
// (tools/run/simulation_run.h). The last finished run's BVH serves the next
// one where the geometry is the same (a material, emitter or profile edited).
#pragma once

#include <functional>
#include <string>

#include "photometry/diagnostics.h"
#include "tools/live/live_server.h"
#include "tools/run/console.h"
#include "tools/run/progressive_run.h"
#include "tools/run/simulation_run.h"

namespace gonio::app {

// What watching defaults to where simulate's options are not given: a page
// update every few tenths of a second, and a run that goes on until the
// target error, the last iteration or the next change.
inline constexpr long long kWatchPhotons = 1 << 18;
inline constexpr long long kWatchIterations = 1000;

struct WatchHooks {
  // The model's warnings and errors, and each run's error (tools/run/console.h;
  // empty: printed to stderr).
  MessageSink on_message;
  // The page is up at `url`.
  std::function<void(const std::string& url)> on_started;
  // Asked while waiting and between slices of photons: true ends watching.
  // Empty: Ctrl-C or SIGTERM (interrupted()).
  std::function<bool()> stop;
  // A finished run's files were written (plan.out_dir): returns whether they
  // passed every check (the page says so where not). Empty: files.passed().
  std::function<bool(const ProgressiveOutcome& run, const RunFiles& files)> on_files;
};

// Serves the live page on host:port (port 0: any free port) and watches
// plan.model until hooks.stop says so. Errors: the output folder cannot be
// made, or the page cannot be served (e.g. the port is taken); a model that
// cannot be read or run is not an error (it is shown, and told).
Status watch(SimulatePlan plan, const std::string& host, int port, const WatchHooks& hooks = {});

}  // namespace gonio::app
