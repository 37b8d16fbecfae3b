// gonio watch DIR: follows a running optimisation (tools/live/watch_optimize.h).
#include "tools/live/watch_optimize.h"

#include <chrono>
#include <filesystem>
#include <memory>
#include <thread>

#include <nlohmann/json.hpp>

#include "io/support/file_io.h"
#include "tools/live/live_server.h"

namespace gonio::app {

std::string optimize_state_path(const std::string& dir) {
  return (std::filesystem::path(dir) / "state.json").string();
}

Status watch_optimization(const std::string& dir, const std::string& host, int port,
                          const WatchOptimizeHooks& hooks) {
  if (!hooks.stop) install_interrupt_handlers();
  Result<std::unique_ptr<LiveServer>> server = LiveServer::start(host, port);
  if (!server.ok()) return server.error();
  const std::string path = optimize_state_path(dir);
  // Until the optimisation has written its first state.
  const nlohmann::json waiting = {{"kind", "optimize"},
                                  {"run", 0},
                                  {"model", dir},
                                  {"status", "loading"},
                                  {"status_text", "waiting for " + path + " (gonio optimize … --out " + dir + ")"},
                                  {"curves", nullptr},
                                  {"previous_curves", nullptr},
                                  {"findings", nlohmann::json::array()},
                                  {"last_error", nullptr}};
  (*server)->publish(waiting.dump(), {});
  if (hooks.on_started) hooks.on_started((*server)->url());
  std::string last;
  std::string last_status;
  long long run = 0, last_version = -1;
  const auto stopped = [&] { return hooks.stop ? hooks.stop() : interrupted(); };
  while (!stopped()) {
    // The optimisation replaces the file whole (a rename): a read sees one
    // state or the next, never half of one.
    Result<std::string> text = io::read_file(path, std::size_t{256} << 20);
    if (text.ok() && *text != last) {
      nlohmann::json state = nlohmann::json::parse(*text, nullptr, false);
      if (state.is_object()) {
        last = *text;
        // A new optimisation into the same DIR starts its versions again.
        const long long version = state.value("version", 0LL);
        if (version <= last_version || run == 0) ++run;
        last_version = version;
        state["run"] = run;
        (*server)->publish(state.dump(), {});
        const std::string status = state.value("status", std::string());
        if (status != last_status && (status == "finished" || status == "error") && hooks.on_finished)
          hooks.on_finished(status);
        last_status = status;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return Ok{};
}

}  // namespace gonio::app
