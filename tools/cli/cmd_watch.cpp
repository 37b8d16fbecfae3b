// gonio watch: the interactive loop. Runs the progressive simulation of a
// model, shows it on a local web page (tools/live/live_view.h), and starts again
// whenever the model, or a file it references, changes on disk (model_files,
// tools/run/model_input.h: a CAD model's sidecar and its profiles too).
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
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "io/support/cache_folder.h"
#include "io/support/file_io.h"
#include "tools/cli/cli.h"
#include "tools/cli/commands.h"
#include "tools/live/live_server.h"
#include "tools/live/live_view.h"
#include "tools/run/model_input.h"
#include "tools/run/progressive_run.h"
#include "tools/cli/simulate_command.h"
#include "tools/live/watch_files.h"

namespace gonio::cli {
namespace {

using namespace std::chrono_literals;

constexpr auto kPoll = 50ms;
constexpr auto kQuiet = 150ms;
constexpr std::uint64_t kFirstIterationPhotons = std::uint64_t{1} << 16;
constexpr long long kWatchPhotons = 1 << 18;
constexpr long long kWatchIterations = 1000;

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

}  // namespace

int run_watch(const Args& args) {
  std::string model, host = kLiveHost;
  long long port = kDefaultLivePort;
  SimulateOptions options;
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
  p.positional("MODEL", &model, "the luminaire model (.gltf, .glb, .step, .stp, .iges or .igs)");
  p.option("port", &port, 0, 65535, "P", "port of the page (default 8765; 0: any free port, printed)");
  p.option("host", &host, "ADDR", "address to listen on (default 127.0.0.1: this machine only)");
  p.option("out", &options.out_dir, "DIR", "write each finished run's files here (default: none)");
  add_simulate_options(p, &options);
  if (const auto outcome = p.parse(args); outcome != ArgParser::Outcome::Run)
    return ArgParser::exit_code(outcome);
  if (!p.given("photons")) options.photons = kWatchPhotons;
  if (!p.given("iterations")) options.iterations = kWatchIterations;
  std::optional<SimulatePlan> planned = plan_simulation("watch", model, options, p);
  if (!planned) return kExitUsage;
  SimulatePlan plan = *planned;
  plan.progressive.first_iteration_photons = kFirstIterationPhotons;
  if (!plan.out_dir.empty()) {
    if (Status s = io::make_directories(plan.out_dir); !s.ok()) {
      print_error(s.error());
      return kExitFailure;
    }
  }

  auto started = LiveView::start(host, static_cast<int>(port), plan);
  if (!started.ok()) {
    print_error(started.error());
    return kExitFailure;
  }
  LiveView& live = *started.value();
  std::printf("live page: %s\n", live.url().c_str());
  std::printf("watching %s (Ctrl-C to stop)\n", model.c_str());
  std::fflush(stdout);

  std::vector<std::string> files = model_files(model, plan.model_input);
  ChangeDebouncer debouncer(kQuiet);
  LoadRetry retry({250ms, 500ms, 1000ms});
  bool run_now = true;
  bool retry_pending = false;
  WatchClock::time_point retry_at{};
  WatchClock::time_point noticed = WatchClock::now();
  int exit_code = kExitOk;

  std::optional<ProgressiveOutcome> last;
  while (!interrupted()) {
    if (!run_now) {
      std::this_thread::sleep_for(kPoll);
      const auto now = WatchClock::now();
      if (debouncer.observe(snapshot_of(files), now)) {
        run_now = true;
        retry.reset();
        retry_pending = false;
        noticed = now;
      } else if (retry_pending && now >= retry_at) {
        run_now = true;
        retry_pending = false;
      }
      continue;
    }
    run_now = false;
    // What this run is loaded from: a change from here on restarts it.
    files = model_files(model, plan.model_input);
    debouncer.arm(snapshot_of(files));
    live.loading(model, noticed);
    ModelInputTimes input_times;
    ModelLoad loaded = load_model(model, plan.model_input, &input_times);
    if (loaded.error || loaded.has_errors) {
      const Error e = load_error(loaded, model);
      const std::optional<WatchClock::time_point> again = retry.failed(WatchClock::now());
      if (again) {
        retry_pending = true;
        retry_at = *again;
        live.note("cannot read the model (retry " + std::to_string(retry.failures()) + " of " +
                  std::to_string(retry.retries()) + "): it may still be being written");
        continue;
      }
      print_error(e);
      live.run_failed(e, loaded.findings);
      continue;
    }
    for (const Finding& f : loaded.findings)
      if (f.severity == Severity::Warning) print_warning(format_finding(f));
    retry.reset();
    const sim::SceneDesc& scene = *loaded.scene;
    const auto run_start = std::chrono::steady_clock::now();
    const sim::Resampler& resampler = live.resampler_for(scene);
    live.begin_run(model, scene, loaded.findings);
    bool changed = false;
    auto on_iteration = [&](const IterationReport& r, const sim::Simulation& s) {
      live.iteration(r, s);
      return true;
    };
    auto cancel = [&] {
      if (interrupted()) return true;
      if (debouncer.observe(snapshot_of(files), WatchClock::now())) changed = true;
      return changed;
    };
    // The last finished run's BVH serves this one if the geometry is the same
    // (a material, emitter or profile edited).
    Result<ProgressiveOutcome> run = run_progressive(scene, plan.progressive, &resampler, on_iteration, cancel,
                                                     last ? &last->simulation : nullptr);
    if (!run.ok()) {
      Error e = run.error();
      if (e.where.file.empty()) e.where.file = model;
      print_error(e);
      live.run_failed(e);
      continue;
    }
    if (changed) {
      run_now = true;
      retry.reset();
      noticed = WatchClock::now();
      last = std::move(run.value());  // its BVH may serve the next run
      continue;
    }
    if (run->stopped_by == StopReason::Cancelled) break;  // interrupted
    live.run_finished(run.value());
    if (!plan.out_dir.empty()) {
      exit_code = write_run_files(plan, run.value(), input_times, nullptr, run_start);
      if (exit_code != kExitOk) live.note("the run's files were written, but a check failed (see the terminal)");
      std::fflush(stdout);
    } else {
      io::trim_cache(plan.model_input.cache_dir, plan.cache_limit_bytes);  // write_run_files does it with --out
    }
    last = std::move(run.value());
  }
  std::printf("watch: stopped\n");
  return kExitOk;
}

}  // namespace gonio::cli
