// The application's one way to simulate (tools/run/simulate.h), called as a
// front end without argv calls it (the Python module, tests): the files it
// writes are the command's bytes, its hooks see every iteration and stop the
// run, and its checks meet plain options the command line's parser never
// sees.
#include "tools/run/simulate.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/test_support.h"

namespace gonio::app {
namespace {

std::string bell() { return std::string(GONIO_SAMPLES_DIR) + "/bell/bell.gltf"; }

SimulateOptions small_run(const std::string& out) {
  SimulateOptions o;
  o.out_dir = out;
  o.photons = 20000;
  o.iterations = 2;
  o.seed = 7;
  o.threads = 2;
  o.no_cache = true;
  o.format_list = "ies,ldt";
  return o;
}

// Messages collected instead of printed.
struct Messages {
  std::vector<std::pair<Severity, std::string>> told;
  MessageSink sink() {
    return [this](Severity s, const std::string& text) { told.emplace_back(s, text); };
  }
};

// A plan that differs from the command's (a default resolved otherwise, a
// setting dropped on the way from the options to the plan) gives other
// bytes here; so does a write_run_files that depends on the front end.
TEST(AppSimulate, WritesTheCommandsBytesAndReportsEveryIteration) {
  ASSERT_TRUE(std::filesystem::exists(bell())) << bell();
  test::TempDir dir;
  const std::string out = (dir / "app").string();
  Result<SimulatePlan> plan = plan_simulation(bell(), small_run(out));
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  std::vector<int> iterations;
  Messages messages;
  SimulateHooks hooks;
  hooks.on_message = messages.sink();
  hooks.on_iteration = [&](const IterationReport& r, const sim::Simulation&) {
    iterations.push_back(r.progress.iteration);
    return true;
  };
  bool traced = false;
  hooks.on_traced = [&](const ProgressiveOutcome& run) { traced = run.stopped_by == StopReason::Iterations; };
  std::optional<SimulateResult> result = simulate(plan.value(), hooks);
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(iterations, (std::vector<int>{1, 2}));
  EXPECT_TRUE(traced);
  EXPECT_TRUE(result->lead);
  EXPECT_EQ(result->run.simulation.stats().photons, 40000u);
  ASSERT_TRUE(result->files.has_value());
  EXPECT_TRUE(result->files->passed());
  EXPECT_EQ(result->files->report_path, out + "/report.json");
  EXPECT_EQ(result->files->written.size(), 2u);
  EXPECT_EQ(result->files->report["photons_emitted"], 40000);
  for (const auto& [severity, text] : messages.told) EXPECT_NE(severity, Severity::Error) << text;

  const auto cli = test::run_process({GONIO_EXECUTABLE, "simulate", bell(), "--out", (dir / "cli").string(),
                                      "--photons", "20000", "--iterations", "2", "--seed", "7", "--threads", "2",
                                      "--no-cache", "--format", "ies,ldt"});
  ASSERT_EQ(cli.exit_code, 0) << cli.err;
  for (const char* name : {"bell.ies", "bell.ldt"})
    EXPECT_EQ(test::read_file(dir / "app" / name), test::read_file(dir / "cli" / name)) << name;
}

// The iteration hook's false and the cancel check both stop the run as
// cancelled, and nothing is written (the folder is made before tracing, for
// the preview, and stays empty). A simulate() that ignored either hook would
// run every iteration; one that wrote on cancel would leave report.json.
TEST(AppSimulate, AHookStopsTheRunAndNothingIsWritten) {
  test::TempDir dir;
  SimulateOptions o = small_run((dir / "stopped").string());
  o.iterations = 50;
  Result<SimulatePlan> plan = plan_simulation(bell(), o);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  {
    SimulateHooks hooks;
    int seen = 0;
    hooks.on_iteration = [&](const IterationReport&, const sim::Simulation&) { return ++seen < 2; };
    std::optional<SimulateResult> result = simulate(plan.value(), hooks);
    ASSERT_TRUE(result.has_value());
    EXPECT_EQ(seen, 2);
    EXPECT_EQ(result->run.stopped_by, StopReason::Cancelled);
    EXPECT_FALSE(result->files.has_value());
  }
  {
    SimulateHooks hooks;
    hooks.cancel = [] { return true; };
    std::optional<SimulateResult> result = simulate(plan.value(), hooks);
    ASSERT_TRUE(result.has_value());
    EXPECT_EQ(result->run.stopped_by, StopReason::Cancelled);
    EXPECT_EQ(result->run.iterations_done, 0);
    EXPECT_FALSE(result->files.has_value());
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir / "stopped"));
}

// keep_when_stopped (the Python module's callback returning False): a run
// stopped after its second iteration keeps what was traced and writes the
// bytes of a two-iteration run (photon i draws from (seed, i) alone). A
// simulate() that ignored the hook would write nothing; one that wrote the
// plan's iteration count, or traced on, would give other bytes.
TEST(AppSimulate, AStoppedRunKeptWritesWhatWasTraced) {
  test::TempDir dir;
  SimulateOptions o = small_run((dir / "kept").string());
  o.iterations = 10;
  Result<SimulatePlan> plan = plan_simulation(bell(), o);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  SimulateHooks hooks;
  int seen = 0;
  hooks.on_iteration = [&](const IterationReport&, const sim::Simulation&) { return ++seen < 2; };
  int asked = 0;
  hooks.keep_when_stopped = [&] { return ++asked > 0; };
  std::optional<SimulateResult> result = simulate(plan.value(), hooks);
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(asked, 1);
  EXPECT_EQ(result->run.stopped_by, StopReason::Cancelled);
  EXPECT_EQ(result->run.iterations_done, 2);
  ASSERT_TRUE(result->files.has_value());
  EXPECT_EQ(result->files->report["photons_emitted"], 40000);
  EXPECT_EQ(result->files->report["stopped_by"], "cancelled");

  Result<SimulatePlan> two = plan_simulation(bell(), small_run((dir / "two").string()));
  ASSERT_TRUE(two.ok()) << two.error().message;
  ASSERT_TRUE(simulate(two.value()).has_value());
  for (const char* name : {"bell.ies", "bell.ldt"})
    EXPECT_EQ(test::read_file(dir / "kept" / name), test::read_file(dir / "two" / name)) << name;
}

// on_failed receives the error that stopped the run as a value (the Python
// module raises it with its file): a model that cannot be read, a folder
// that cannot be made. One that was told only as text would leave it unset.
TEST(AppSimulate, TheErrorThatStopsTheRunIsGivenAsAValue) {
  test::TempDir dir;
  const std::string missing = (dir / "none.gltf").string();
  {
    Result<SimulatePlan> plan = plan_simulation(missing, small_run((dir / "a").string()));
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    Messages messages;
    SimulateHooks hooks;
    hooks.on_message = messages.sink();
    std::optional<Error> failure;
    hooks.on_failed = [&](const Error& e) { failure = e; };
    EXPECT_FALSE(simulate(plan.value(), hooks).has_value());
    ASSERT_TRUE(failure.has_value());
    EXPECT_EQ(failure->where.file, missing);
    ASSERT_FALSE(messages.told.empty());
    EXPECT_EQ(messages.told.back().first, Severity::Error);
  }
  {
    test::write_file(dir / "file", "not a folder");
    Result<SimulatePlan> plan = plan_simulation(bell(), small_run((dir / "file" / "out").string()));
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    SimulateHooks hooks;
    hooks.on_message = [](Severity, const std::string&) {};
    std::optional<Error> failure;
    hooks.on_failed = [&](const Error& e) { failure = e; };
    EXPECT_FALSE(simulate(plan.value(), hooks).has_value());
    ASSERT_TRUE(failure.has_value());
    EXPECT_NE(to_string(*failure).find("file"), std::string::npos) << to_string(*failure);
  }
}

// Plain options meet the command line's bounds and words, option named as
// the command spells it: a planner that trusted its caller (the parser
// checks these before it on the command line) would accept them.
TEST(AppSimulate, OptionsAreCheckedAsTheCommandChecksThem) {
  struct Case {
    void (*change)(SimulateOptions&);
    const char* says;
  };
  const Case cases[] = {
      {[](SimulateOptions& o) { o.photons = 0; }, "--photons must be between 1 and 4294967295, got 0"},
      {[](SimulateOptions& o) { o.iterations = 1'000'001; }, "--iterations must be between 1 and 1000000"},
      {[](SimulateOptions& o) { o.threads = -1; }, "--threads must be between 0 and 4096"},
      {[](SimulateOptions& o) { o.c_step = 7.0; }, "360"},
      {[](SimulateOptions& o) { o.min_lor = 1.5; }, "--min-lor must be between 0 and 1, got 1.5"},
      {[](SimulateOptions& o) { o.target_error_pct = -1.0; }, "--target-error must be between 0 and 100"},
      {[](SimulateOptions& o) { o.sampler = "halton"; }, "--sampler must be one of sobol|random"},
      {[](SimulateOptions& o) { o.bvh_quality = "best"; }, "--bvh-quality must be one of auto|low|medium|high"},
      {[](SimulateOptions& o) { o.ies_version = "1995"; }, "--ies-version must be one of 2002|2019"},
      {[](SimulateOptions& o) { o.symmetry_name = "hexagonal"; }, "--symmetry: unknown symmetry 'hexagonal'"},
      {[](SimulateOptions& o) { o.tm25_rays = 10; }, "--tm25-rays applies to --format tm25 only"},
      {[](SimulateOptions& o) { o.near_field = "1,0"; }, "--near-field: '0' is not a distance"},
      {[](SimulateOptions& o) { o.stem = "../x"; }, "--name: '../x' is not a plain file name"},
      {[](SimulateOptions& o) { o.cache_dir = "/tmp"; }, "--cache and --no-cache exclude each other"},
      {[](SimulateOptions& o) { o.preview.filter = "gaussian"; }, "--filter must be one of none|bilinear|bilateral"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.says);
    SimulateOptions o = small_run("out");
    c.change(o);
    const Result<SimulatePlan> plan = plan_simulation(bell(), o);
    ASSERT_FALSE(plan.ok());
    EXPECT_NE(plan.error().message.find(c.says), std::string::npos) << plan.error().message;
  }
  // The defaults are gonio simulate's: 5 x 2.5 degrees, 128 texels, Sobol'.
  const Result<SimulatePlan> plan = plan_simulation(bell(), SimulateOptions{});
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  EXPECT_EQ(plan->progressive.simulation.photons_per_iteration, 1'000'000u);
  EXPECT_EQ(plan->progressive.simulation.iterations, 10);
  EXPECT_EQ(plan->progressive.simulation.face_size, 128);
  EXPECT_EQ(plan->progressive.simulation.sampler, sim::SamplerKind::Sobol);
  EXPECT_EQ(plan->stem, "bell");
}

// A model that cannot be read is told to the sink (not printed), naming the
// file, and nothing runs: no hook is called.
TEST(AppSimulate, AMissingModelIsToldToTheSinkAndNothingRuns) {
  test::TempDir dir;
  const std::string model = (dir / "none.gltf").string();
  Result<SimulatePlan> plan = plan_simulation(model, small_run((dir / "out").string()));
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  Messages messages;
  SimulateHooks hooks;
  hooks.on_message = messages.sink();
  bool called = false;
  hooks.on_loaded = [&](const sim::SceneDesc&, const std::vector<Finding>&) -> const sim::Resampler* {
    called = true;
    return nullptr;
  };
  EXPECT_FALSE(simulate(plan.value(), hooks).has_value());
  EXPECT_FALSE(called);
  ASSERT_FALSE(messages.told.empty());
  EXPECT_EQ(messages.told.front().first, Severity::Error);
  EXPECT_NE(messages.told.front().second.find(model), std::string::npos) << messages.told.front().second;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

// adjust_scene changes the loaded scene before it is traced (gonio
// tolerance): doubling every emitter's flux doubles the escaped flux of the
// same photons exactly; its error stops the run, told and given as a value,
// with nothing written.
TEST(AppSimulate, AdjustSceneChangesWhatIsTracedAndItsErrorStopsTheRun) {
  test::TempDir dir;
  SimulateOptions o = small_run("");
  Result<SimulatePlan> plan = plan_simulation(bell(), o);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  std::optional<SimulateResult> plain = simulate(plan.value());
  ASSERT_TRUE(plain.has_value());
  SimulateHooks hooks;
  hooks.adjust_scene = [](sim::SceneDesc& scene) -> Status {
    for (sim::Emitter& e : scene.emitters) e.flux_lm *= 2.0;
    return Ok{};
  };
  std::optional<SimulateResult> doubled = simulate(plan.value(), hooks);
  ASSERT_TRUE(doubled.has_value());
  const sim::Ledger a = plain->run.simulation.ledger(), b = doubled->run.simulation.ledger();
  EXPECT_EQ(b.escaped.photons, a.escaped.photons);
  EXPECT_DOUBLE_EQ(b.escaped.flux_lm, 2.0 * a.escaped.flux_lm);

  Result<SimulatePlan> folder = plan_simulation(bell(), small_run((dir / "out").string()));
  ASSERT_TRUE(folder.ok());
  Messages messages;
  std::optional<Error> failed;
  hooks.on_message = messages.sink();
  hooks.on_failed = [&](const Error& e) { failed = e; };
  hooks.adjust_scene = [](sim::SceneDesc&) -> Status { return make_error("t.toml", "no such emitter"); };
  EXPECT_FALSE(simulate(folder.value(), hooks).has_value());
  ASSERT_TRUE(failed.has_value());
  EXPECT_EQ(to_string(*failed), "t.toml: no such emitter");
  ASSERT_FALSE(messages.told.empty());
  EXPECT_NE(messages.told.back().second.find("no such emitter"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

}  // namespace
}  // namespace gonio::app
