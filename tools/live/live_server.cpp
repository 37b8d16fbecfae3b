#include "tools/live/live_server.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <thread>
#include <vector>

#include <httplib.h>

namespace gonio::app {
namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void on_signal(int) { g_interrupted.store(true); }

std::filesystem::path executable_dir() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path(".") : exe.parent_path();
}

// Where the page's files are looked for, in order: web/ beside the
// executable (the build tree: build/tools/gonio and build/tools/web/), then
// ../share/gonio/web/ from it (installed: PREFIX/bin/gonio and
// PREFIX/share/gonio/web/, packaging/CMakeLists.txt).
std::vector<std::filesystem::path> web_dir_candidates() {
  const std::filesystem::path exe_dir = executable_dir();
  return {exe_dir / "web", exe_dir.parent_path() / "share" / "gonio" / "web"};
}

}  // namespace

std::string live_web_dir() {
  if (const char* dir = std::getenv("GONIO_WEB_DIR"); dir && *dir) return dir;
  const auto candidates = web_dir_candidates();
  for (const auto& dir : candidates)
    if (std::filesystem::is_regular_file(dir / "index.html")) return dir.string();
  return candidates.front().string();
}

struct LiveServer::Impl {
  httplib::Server server;
  std::thread thread;
  std::string host;
  int port = 0;

  std::mutex mutex;
  std::condition_variable changed;
  std::uint64_t version = 0;
  bool stopping = false;
  std::string state = "{}";
  std::string field;
};

LiveServer::LiveServer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

LiveServer::~LiveServer() {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->stopping = true;
  }
  impl_->changed.notify_all();
  impl_->server.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

int LiveServer::port() const { return impl_->port; }
std::string LiveServer::url() const { return "http://" + impl_->host + ":" + std::to_string(impl_->port) + "/"; }

void LiveServer::publish(std::string state_json, std::string field_f32) {
  {
    std::lock_guard lock(impl_->mutex);
    impl_->state = std::move(state_json);
    if (!field_f32.empty()) impl_->field = std::move(field_f32);
    ++impl_->version;
  }
  impl_->changed.notify_all();
}

Result<std::unique_ptr<LiveServer>> LiveServer::start(const std::string& host, int port) {
  const std::string web = live_web_dir();
  if (!std::filesystem::is_regular_file(std::filesystem::path(web) / "index.html")) {
    const char* env_dir = std::getenv("GONIO_WEB_DIR");
    const auto candidates = web_dir_candidates();
    return make_error("the live page's files are not installed: " +
                      (env_dir && *env_dir ? web + "/index.html (GONIO_WEB_DIR) is missing"
                                           : "neither " + candidates.front().string() + "/index.html nor " +
                                                 candidates.back().string() + "/index.html exists") +
                      " (build the target gonio, install gonio, or set GONIO_WEB_DIR)");
  }
  auto impl = std::make_unique<Impl>();
  Impl* s = impl.get();
  s->host = host;
  httplib::Server& server = s->server;
  // No compression: httplib would compress every response (brotli or gzip,
  // as the browser allows) on the fly, which takes seconds for three.js on
  // two busy cores and would hold back the event stream. The page is local.
  server.set_pre_routing_handler([](const httplib::Request& req, httplib::Response&) {
    const_cast<httplib::Request&>(req).headers.erase("Accept-Encoding");  // the server's own object
    return httplib::Server::HandlerResponse::Unhandled;
  });
  server.set_mount_point("/", web);
  server.set_file_extension_and_mimetype_mapping("js", "text/javascript");
  server.set_file_extension_and_mimetype_mapping("mjs", "text/javascript");
  server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
    res.status = 500;
    res.set_content("internal error", "text/plain");
  });
  server.Get("/state.json", [s](const httplib::Request&, httplib::Response& res) {
    std::lock_guard lock(s->mutex);
    res.set_header("Cache-Control", "no-store");
    res.set_content(s->state, "application/json");
  });
  server.Get("/field.f32", [s](const httplib::Request&, httplib::Response& res) {
    std::lock_guard lock(s->mutex);
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Gonio-Version", std::to_string(s->version));
    res.set_content(s->field, "application/octet-stream");
  });
  server.Get("/events", [s](const httplib::Request&, httplib::Response& res) {
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider(
        "text/event-stream", [s, sent = std::uint64_t{0}](std::size_t, httplib::DataSink& sink) mutable {
          std::unique_lock lock(s->mutex);
          s->changed.wait_for(lock, std::chrono::seconds(10), [&] { return s->stopping || s->version != sent; });
          if (s->stopping) {
            sink.done();
            return false;
          }
          std::string message;
          if (s->version == sent) {
            message = ": keep-alive\n\n";  // a comment: tells a dead client apart
          } else {
            sent = s->version;
            message = "data: " + s->state + "\n\n";
          }
          lock.unlock();
          return sink.write(message.data(), message.size());
        });
  });
  if (port == 0) {
    s->port = server.bind_to_any_port(host);
    if (s->port <= 0) return make_error("cannot listen on " + host + " (any port)");
  } else {
    if (!server.bind_to_port(host, port))
      return make_error("cannot listen on " + host + ":" + std::to_string(port) +
                        " (in use? choose another with --port)");
    s->port = port;
  }
  s->thread = std::thread([s] { s->server.listen_after_bind(); });
  return std::unique_ptr<LiveServer>(new LiveServer(std::move(impl)));
}

void install_interrupt_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    std::signal(SIGPIPE, SIG_IGN);  // a client gone mid-write is an error return, not death
  });
}

bool interrupted() { return g_interrupted.load(); }

void wait_for_interrupt() {
  install_interrupt_handlers();
  while (!interrupted()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
}

}  // namespace gonio::app
