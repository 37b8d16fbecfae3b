#include "tools/bench/bench.h"

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <utility>

#include "design/design_file.h"
#include "gonio/tracer_revision.h"
#include "gonio/version.h"
#include "io/support/content_hash.h"
#include "io/support/file_io.h"
#include "io/outputs/report.h"
#include "photometry/format.h"
#include "sim/detectors/cube_map.h"
#include "sim/samplers/sampler.h"
#include "tools/bench/bench_reference.h"
#include "tools/run/distributed_run.h"
#include "tools/run/scene_hash.h"
#include "tools/run/simulate.h"

namespace gonio::app {
namespace {

namespace fs = std::filesystem;

std::string first_line_of(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      const std::size_t colon = line.find(':');
      if (colon != std::string::npos) {
        std::size_t b = colon + 1;
        while (b < line.size() && line[b] == ' ') ++b;
        return line.substr(b);
      }
    }
  return "";
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  double a = 0, b = 0, c = 0;
  if (!(in >> a >> b >> c)) return "unknown";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f, %.2f, %.2f", a, b, c);
  return buf;
}

Status check_ranges(const BenchOptions& o) {
  const std::pair<const char*, std::pair<long long, Bounds<long long>>> integers[] = {
      {"photons", {o.photons, kBenchPhotonsBounds}},
      {"first", {o.first, kBenchFirstBounds}},
      {"steps", {o.steps, kBenchStepsBounds}},
      {"reference", {o.reference_photons == 0 ? 2 : o.reference_photons, kBenchReferenceBounds}},
      {"seed", {o.seed, kBenchSeedBounds}},
      {"reference-seed", {o.reference_seed.value_or(0), kBenchReferenceSeedBounds}},
      {"threads", {o.threads, kThreadsBounds}},
      {"max-bounces", {o.max_bounces, kMaxBouncesBounds}},
      {"face-size", {o.face_size == 0 ? 1 : o.face_size, kBenchFaceSizeBounds}},
      {"emission-face-size", {o.emission_face_size.value_or(1), kBenchFaceSizeBounds}}};
  for (const auto& [name, check] : integers)
    if (Status s = check_range(name, check.first, check.second); !s.ok()) return s;
  const std::pair<const char*, std::pair<double, Bounds<double>>> reals[] = {
      {"c-step", {o.c_step, kGridStepBounds}},
      {"gamma-step", {o.gamma_step, kGridStepBounds}},
      {"target", {o.target, kBenchTargetBounds}},
      {"cube-target", {o.cube_target, kBenchCubeTargetBounds}},
      {"min-acceptance", {o.min_acceptance.value_or(1.0), kMinAcceptanceBounds}}};
  for (const auto& [name, check] : reals)
    if (Status s = check_range(name, check.first, check.second); !s.ok()) return s;
  return Ok{};
}

// Where and when the page was made: the machine, its load, the date.
std::string machine_text(const BenchPlan& plan, const std::string& load_before) {
  const std::string cpu = first_line_of("/proc/cpuinfo", "model name");
  const int threads = plan.settings.threads > 0 ? plan.settings.threads
                                                : static_cast<int>(std::thread::hardware_concurrency());
  char machine[512];
  std::snprintf(machine, sizeof machine,
                "Machine: %s, %u hardware threads, %d threads used; load average %s at the start and "
                "%s at the end (1, 5, 15 min); finished %s; gonio %s.",
                cpu.empty() ? "unknown CPU" : cpu.c_str(), std::thread::hardware_concurrency(), threads,
                load_before.c_str(), load_average().c_str(),
                format_utc(std::time(nullptr), "%Y-%m-%d %H:%M UTC").c_str(), kVersion);
  return machine;
}

// One model's bench: its reference (shared by the ranks), then on rank 0 its
// series and files. Nothing where it failed (told; the job is to be ended).
class ModelBench {
 public:
  ModelBench(const BenchPlan& plan, const BenchHooks& hooks, const sim::Ranks& ranks)
      : plan_(plan), hooks_(hooks), ranks_(ranks) {}

  // Returns false where the bench cannot go on; `outcome` is set on rank 0.
  bool run(const std::string& model, std::optional<BenchOutcome>* outcome, bool* agreed);

 private:
  std::optional<Reference> reference(BenchOutcome& o, const sim::SceneDesc& scene, const ReferenceKey& key,
                                     const std::shared_ptr<const sim::Resampler>& resampler);
  bool write(BenchOutcome& o);

  const BenchPlan& plan_;
  const BenchHooks& hooks_;
  const sim::Ranks& ranks_;
};

bool ModelBench::run(const std::string& model, std::optional<BenchOutcome>* outcome, bool* agreed) {
  const bool lead = ranks_.rank() == 0;
  std::optional<sim::SceneDesc> scene =
      load_checked_model(model, "benchmarked", plan_.model_input, nullptr, hooks_.on_message);
  Result<std::string> bytes =
      scene ? io::read_file(model, std::size_t{1} << 31) : Result<std::string>(Error{{}, "not read"});
  if (scene && !bytes.ok()) tell(hooks_.on_message, bytes.error());
  BenchOutcome o;
  o.model = model;
  o.name = design::model_stem(model);
  o.directory = plan_.models.size() == 1 ? plan_.out_dir : (fs::path(plan_.out_dir) / o.name).string();
  o.settings = plan_.settings;
  char grid_text[64];
  std::snprintf(grid_text, sizeof grid_text, "%g° × %g°", plan_.grid.c_step_deg, plan_.grid.gamma_step_deg);
  o.grid = grid_text;
  bool ready = bytes.ok();
  if (ready && lead) {
    if (Status s = io::make_directories(o.directory); !s.ok()) {
      tell(hooks_.on_message, s.error());
      ready = false;
    }
  }
  ReferenceKey key;
  if (ready) {
    key.program_version = kVersion;
    key.tracer_revision = kTracerRevision;
    key.model_hash = io::content_hash_hex(bytes.value());
    key.scene_hash = scene_hash(scene.value());
    key.seed = plan_.reference_seed;
    key.photons = plan_.reference_photons;
    key.face_size = plan_.settings.face_size;
    key.max_bounces = plan_.settings.max_bounces;
    key.robust_embree = true;
  }
  // Every rank ready, with the same model and reference settings, or none traces.
  std::optional<std::string> fingerprint;
  if (ready) fingerprint = ranks_.distributed() ? io::content_hash_hex(key.to_json().dump()) : std::string();
  *agreed = ranks_agree(ranks_, fingerprint, "bench", hooks_.on_message);
  if (!*agreed) return false;
  const auto resampler = std::make_shared<const sim::Resampler>(plan_.settings.face_size, scene->frame, plan_.grid);
  std::optional<Reference> ref = reference(o, scene.value(), key, resampler);
  if (!ref) return false;
  if (!lead) return true;  // the series measure one process: rank 0's
  auto judge = sim::ConvergenceReference::create(ref->far_field, resampler);
  if (!judge.ok()) {
    tell(hooks_.on_message, Severity::Error, model + ": " + judge.error().message);
    return false;
  }
  auto series = run_series(scene.value(), plan_.settings,
                           default_series(plan_.settings.importance, plan_.settings.sampler,
                                          plan_.settings.compare_samplers),
                           judge.value(), [&](const BenchProgress& pr) {
                             if (hooks_.on_series) hooks_.on_series(o.name, pr);
                           });
  if (!series.ok()) {
    Error e = series.error();
    if (e.where.file.empty()) e.where.file = model;
    tell(hooks_.on_message, e);
    return false;
  }
  o.series = std::move(series.value());
  o.reference = std::move(ref.value());
  o.reference.far_field = sim::FarField(1);  // not needed any more
  o.smallest_raw_error_pct = std::numeric_limits<double>::quiet_NaN();
  for (const SeriesResult& s : o.series)
    if (s.spec.name == "raw" && !s.points.empty()) o.smallest_raw_error_pct = s.points.back().table.rms_pct;
  if (!write(o)) return false;
  if (hooks_.on_model) hooks_.on_model(o);
  *outcome = std::move(o);
  return true;
}

std::optional<Reference> ModelBench::reference(BenchOutcome& o, const sim::SceneDesc& scene, const ReferenceKey& key,
                                               const std::shared_ptr<const sim::Resampler>& resampler) {
  auto reference = load_or_make_reference(
      o.directory, key, scene, plan_.settings.threads, resampler,
      [&](std::uint64_t done, std::uint64_t total) {
        if (hooks_.on_reference) hooks_.on_reference(o.name, done, total);
      },
      &ranks_);
  if (reference.ok()) return std::move(reference.value());
  Error e = reference.error();
  if (e.where.file.empty()) e.where.file = o.model;
  tell(hooks_.on_message, e);
  return std::nullopt;
}

// DIR/series.csv, DIR/bench.json and the charts.
bool ModelBench::write(BenchOutcome& o) {
  const std::string dir = o.directory;
  nlohmann::json j = bench_json(o);
  j["program"] = {{"name", kProgramName}, {"version", kVersion}};
  // In this order, stopping at the first that fails.
  Status s = io::write_file_atomic((fs::path(dir) / "series.csv").string(), series_csv(o.series));
  if (s.ok()) s = io::write_json((fs::path(dir) / "bench.json").string(), j);
  if (s.ok()) s = write_charts(o, plan_.png);
  if (!s.ok()) tell(hooks_.on_message, s.error());
  return s.ok();
}

}  // namespace

Result<BenchPlan> plan_bench(const BenchOptions& o) {
  if (Status s = check_ranges(o); !s.ok()) return s.error();
  if (o.models.empty()) return make_error("missing MODEL");
  if (o.out_dir.empty()) return make_error("--out DIR is required");
  if (o.first > o.photons) return make_error("--first must not exceed --photons");
  const long long reference_seed = o.reference_seed.value_or(o.seed + 1);
  if (reference_seed == o.seed) return make_error("the reference needs a seed of its own (--reference-seed)");
  long long reference_photons = o.reference_photons;
  if (reference_photons == 0) {
    if (o.photons > (1LL << 39) / 16) return make_error("--photons too large for the default reference; give --reference");
    reference_photons = 16 * o.photons;
  }
  const sim::CGammaGrid grid{o.c_step, o.gamma_step};
  if (Status s = sim::validate(grid); !s.ok()) return s.error();
  ModelInputOptions model_input = o.model_input;
  model_input.gamma_step_deg = o.gamma_step;  // a CAD model's default tessellation follows it
  if (Status s = check_model_input(model_input, o.models); !s.ok()) return s.error();
  if (!o.importance && (o.emission_face_size || o.min_acceptance))
    return make_error("--emission-face-size and --min-acceptance need --importance");
  const std::optional<sim::NextEventMode> next_event = sim::parse_next_event_mode(o.next_event);
  if (!next_event) return make_error("--next-event must be one of auto|on|off, got '" + o.next_event + "'");
  if (o.sampler != "random" && o.sampler != "sobol" && o.sampler != "both")
    return make_error("--sampler must be one of random|sobol|both, got '" + o.sampler + "'");
  std::set<std::string> stems;
  for (const std::string& m : o.models)
    if (!stems.insert(design::model_stem(m)).second)
      return make_error("two models named '" + design::model_stem(m) + "': give them separate runs");

  BenchPlan plan;
  plan.models = o.models;
  plan.out_dir = o.out_dir;
  plan.page = o.page;
  plan.command = o.command;
  plan.grid = grid;
  plan.reference_photons = static_cast<std::uint64_t>(reference_photons);
  plan.reference_seed = static_cast<std::uint64_t>(reference_seed);
  plan.png = !o.no_png;
  plan.model_input = model_input;
  BenchSettings& settings = plan.settings;
  settings.photons = static_cast<std::uint64_t>(o.photons);
  settings.first_photons = static_cast<std::uint64_t>(o.first);
  settings.steps_per_doubling = static_cast<int>(o.steps);
  settings.seed = static_cast<std::uint64_t>(o.seed);
  settings.threads = static_cast<int>(o.threads);
  settings.max_bounces = static_cast<int>(o.max_bounces);
  settings.face_size = o.face_size == 0 ? sim::face_size_for(grid) : static_cast<int>(o.face_size);
  settings.importance = o.importance;
  settings.sampler = o.sampler == "sobol" ? sim::SamplerKind::Sobol : sim::SamplerKind::Random;
  settings.compare_samplers = o.sampler == "both";
  settings.importance_settings.emission_face_size = static_cast<int>(o.emission_face_size.value_or(32));
  settings.importance_settings.min_acceptance = o.min_acceptance.value_or(1.0 / 16.0);
  settings.next_event = *next_event;
  settings.target_pct = o.target;
  settings.cube_target = o.cube_target;
  return plan;
}

std::optional<std::vector<BenchOutcome>> bench(const BenchPlan& plan, const BenchHooks& hooks,
                                               const sim::Ranks* ranks) {
  const sim::Ranks one_process;
  const sim::Ranks& job = ranks ? *ranks : one_process;
  const bool lead = job.rank() == 0;
  const std::string load_before = load_average();
  std::vector<BenchOutcome> outcomes;
  ModelBench model_bench(plan, hooks, job);
  for (const std::string& model : plan.models) {
    std::optional<BenchOutcome> outcome;
    bool agreed = false;
    if (!model_bench.run(model, &outcome, &agreed)) {
      // A failure on one rank (rank 0's writes) while the others go on to the
      // next model's reference: end them all (they would wait for it for ever).
      if (agreed && job.distributed()) job.abort(kExitFailure);
      return std::nullopt;
    }
    if (outcome) outcomes.push_back(std::move(*outcome));
  }
  if (plan.page.empty() || !lead) return outcomes;
  if (Status s = io::make_directories(fs::absolute(plan.page).parent_path().string()); !s.ok()) {
    tell(hooks.on_message, s.error());
    return std::nullopt;
  }
  const std::string page = results_page(outcomes, plan.page, machine_text(plan, load_before), plan.command);
  if (Status s = io::write_file_atomic(plan.page, page); !s.ok()) {
    tell(hooks.on_message, s.error());
    return std::nullopt;
  }
  return outcomes;
}

}  // namespace gonio::app
