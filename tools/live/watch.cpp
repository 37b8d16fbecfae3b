#include "tools/live/watch.h"

#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "io/support/cache_folder.h"
#include "io/support/file_io.h"
#include "tools/live/live_view.h"
#include "tools/live/watch_files.h"
#include "tools/run/glossy_energy_cache.h"
#include "tools/run/model_input.h"

namespace gonio::app {
namespace {

using namespace std::chrono_literals;

constexpr auto kPoll = 50ms;
constexpr auto kQuiet = 150ms;
// The first iteration is small so that the first filtered preview comes
// soon after the model is read (issue 43: 2¹⁶ photons took 0.26–0.34 s of
// the bell's 1.3–1.5 s on the loaded 2-core machine; docs/validation.md).
constexpr std::uint64_t kFirstIterationPhotons = std::uint64_t{1} << 14;

// Why a load failed: the reader's error, or the check findings' verdict.
[[gnu::noinline]] Error load_error(const ModelLoad& loaded, const std::string& model) {
  Error e;
  e.where.file = model;
  e.message = "the model has errors (see the findings); not simulated";
  if (loaded.error) {
    e.message = loaded.error->message;
    if (!loaded.error->where.file.empty()) e.where = loaded.error->where;
  }
  return e;
}

// One watch: its page, the files it follows and the state between runs.
class Watcher {
 public:
  Watcher(SimulatePlan plan, LiveView& live, const WatchHooks& hooks)
      : plan_(std::move(plan)), live_(live), hooks_(hooks), files_(model_files(plan_.model, plan_.model_input)) {}

  // Runs until stopped.
  void loop() {
    while (!stopped()) {
      if (!run_now_) {
        wait();
        continue;
      }
      run_now_ = false;
      run();
    }
  }

 private:
  bool stopped() const { return hooks_.stop ? hooks_.stop() : interrupted(); }

  // One poll: a change (debounced) or a retry that is due starts a run.
  void wait() {
    std::this_thread::sleep_for(kPoll);
    const auto now = WatchClock::now();
    if (debouncer_.observe(snapshot_of(files_), now)) {
      run_now_ = true;
      retry_.reset();
      retry_pending_ = false;
      noticed_ = now;
    } else if (retry_pending_ && now >= retry_at_) {
      run_now_ = true;
      retry_pending_ = false;
    }
  }

  // Loads the model (or schedules a retry), runs it, and writes its files.
  void run() {
    const std::string& model = plan_.model;
    // What this run is loaded from: a change from here on restarts it.
    files_ = model_files(model, plan_.model_input);
    debouncer_.arm(snapshot_of(files_));
    live_.loading(model, noticed_);
    ModelInputTimes input_times;
    ModelLoad loaded = load_model(model, plan_.model_input, &input_times);
    if (loaded.error || loaded.has_errors) {
      load_failed(loaded);
      return;
    }
    live_.model_read();
    for (const Finding& f : loaded.findings)
      if (f.severity == Severity::Warning) tell(hooks_.on_message, Severity::Warning, "warning: " + format_finding(f));
    retry_.reset();
    const sim::SceneDesc& scene = *loaded.scene;
    const auto run_start = std::chrono::steady_clock::now();
    const sim::Resampler& resampler = live_.resampler_for(scene);
    live_.begin_run(model, scene, loaded.findings);
    bool changed = false;
    auto on_iteration = [&](const IterationReport& r, const sim::Simulation& s) {
      live_.iteration(r, s);
      return true;
    };
    auto cancel = [&] {
      if (stopped()) return true;
      if (debouncer_.observe(snapshot_of(files_), WatchClock::now())) changed = true;
      return changed;
    };
    // The glossy lobes' energy tables from the cache folder where it has
    // them (~0.3 s of the bell's first preview when built, issue 43).
    (void)load_glossy_energy_tables(scene, plan_.model_input.cache_dir);
    Result<ProgressiveOutcome> run = run_progressive(scene, plan_.progressive, &resampler, on_iteration, cancel,
                                                     last_ ? &last_->simulation : nullptr);
    if (!run.ok()) {
      Error e = run.error();
      if (e.where.file.empty()) e.where.file = model;
      tell(hooks_.on_message, e);
      live_.run_failed(e);
      return;
    }
    if (changed) {
      run_now_ = true;
      retry_.reset();
      noticed_ = WatchClock::now();
      last_ = std::move(run.value());  // its BVH may serve the next run
      return;
    }
    if (run->stopped_by == StopReason::Cancelled) return;  // stopped
    live_.run_finished(run.value());
    finished(run.value(), input_times, run_start);
    last_ = std::move(run.value());
  }

  // A model that cannot be read is tried again a few times, then shown.
  void load_failed(const ModelLoad& loaded) {
    const Error e = load_error(loaded, plan_.model);
    const std::optional<WatchClock::time_point> again = retry_.failed(WatchClock::now());
    if (again) {
      retry_pending_ = true;
      retry_at_ = *again;
      live_.note("cannot read the model (retry " + std::to_string(retry_.failures()) + " of " +
                 std::to_string(retry_.retries()) + "): it may still be being written");
      return;
    }
    tell(hooks_.on_message, e);
    live_.run_failed(e, loaded.findings);
  }

  // A finished run: its files where the plan names a folder, and the cache
  // kept to its limit (write_run_files does that with a folder).
  void finished(const ProgressiveOutcome& run, const ModelInputTimes& input_times,
                std::chrono::steady_clock::time_point run_start) {
    if (plan_.out_dir.empty()) {
      io::trim_cache(plan_.model_input.cache_dir, plan_.cache_limit_bytes);
      return;
    }
    const RunFiles files = write_run_files(plan_, run, input_times, nullptr, run_start);
    const bool passed = hooks_.on_files ? hooks_.on_files(run, files) : files.passed();
    if (!passed) live_.note("the run's files were written, but a check failed (see the terminal)");
  }

  SimulatePlan plan_;
  LiveView& live_;
  const WatchHooks& hooks_;
  std::vector<std::string> files_;
  ChangeDebouncer debouncer_{kQuiet};
  LoadRetry retry_{{250ms, 500ms, 1000ms}};
  bool run_now_ = true;
  bool retry_pending_ = false;
  WatchClock::time_point retry_at_{};
  WatchClock::time_point noticed_ = WatchClock::now();
  std::optional<ProgressiveOutcome> last_;
};

}  // namespace

Status watch(SimulatePlan plan, const std::string& host, int port, const WatchHooks& hooks) {
  plan.progressive.first_iteration_photons = kFirstIterationPhotons;
  if (!plan.out_dir.empty())
    if (Status s = io::make_directories(plan.out_dir); !s.ok()) return s;
  auto started = LiveView::start(host, port, plan);
  if (!started.ok()) return started.error();
  LiveView& live = *started.value();
  if (hooks.on_started) hooks.on_started(live.url());
  Watcher(std::move(plan), live, hooks).loop();
  return Ok{};
}

}  // namespace gonio::app
