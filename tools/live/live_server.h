// The HTTP side of the live page (`gonio watch`, `gonio simulate --serve`):
// a small local server (cpp-httplib; this header keeps its types out) that
// serves the page's files and what the simulation publishes.
//
// Routes:
//   GET /               the page (web dir's index.html), and the web dir's
//                       other files (app.js, node_modules/three/…)
//   GET /state.json     the latest published state (application/json)
//   GET /field.f32      the latest filtered far field: float32 intensities
//                       [cd], little-endian, in cube-map texel order
//                       (sim/detectors/cube_map.h); header X-Gonio-Version
//   GET /events         server-sent events: one `data: <state JSON>` event
//                       per publish (and the current state on connect)
// The web dir is $GONIO_WEB_DIR, else `web/` beside the gonio executable
// (the build puts index.html, app.js and three there: tools/CMakeLists.txt).
// Handlers never throw out of the server; a client that goes away ends only
// its own stream.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "photometry/diagnostics.h"

namespace gonio::app {

inline constexpr const char* kLiveHost = "127.0.0.1";
inline constexpr int kDefaultLivePort = 8765;

// The folder of the page's files (see above).
std::string live_web_dir();

class LiveServer {
 public:
  // Binds host:port (port 0: any free port) and serves on its own threads.
  // Errors: the web dir lacks index.html, or the port cannot be bound.
  static Result<std::unique_ptr<LiveServer>> start(const std::string& host, int port);
  ~LiveServer();  // stops serving and joins its threads
  LiveServer(const LiveServer&) = delete;
  LiveServer& operator=(const LiveServer&) = delete;

  int port() const;
  std::string url() const;  // http://host:port/

  // Replaces the state (and, when `field_f32` is not empty, the field) and
  // wakes every /events stream. Thread-safe.
  void publish(std::string state_json, std::string field_f32);

 private:
  struct Impl;
  explicit LiveServer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Ctrl-C and SIGTERM: installs handlers that set a flag (first call), and
// reads it. wait_for_interrupt() sleeps until it is set.
void install_interrupt_handlers();
bool interrupted();
void wait_for_interrupt();

}  // namespace gonio::app
