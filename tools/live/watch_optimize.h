// `gonio watch DIR`: the live page of a running `gonio optimize --out DIR`
// (docs/commands/watch.md "An optimisation"). The optimisation writes
// DIR/state.json atomically after every evaluation (tools/run/optimize_state.h);
// this follows that file (polled every 100 ms) and serves it on the live
// page's server (tools/live/live_server.h) as GET /state.json and /events,
// the page drawing the best so far against the target and the merit's
// history. No optimisation there yet: the page says it is waiting.
#pragma once

#include <functional>
#include <string>

#include "photometry/diagnostics.h"

namespace gonio::app {

// DIR/state.json: where gonio optimize writes its live state.
std::string optimize_state_path(const std::string& dir);

struct WatchOptimizeHooks {
  std::function<void(const std::string& url)> on_started;
  // Asked every poll: true ends watching. Empty: Ctrl-C or SIGTERM.
  std::function<bool()> stop;
  // The followed run has finished (or failed): its state's status.
  std::function<void(const std::string& status)> on_finished;
};

// Serves DIR's optimisation on host:port until hooks.stop says so. Errors:
// the page cannot be served (the port taken, the page's files missing).
Status watch_optimization(const std::string& dir, const std::string& host, int port,
                          const WatchOptimizeHooks& hooks = {});

}  // namespace gonio::app
