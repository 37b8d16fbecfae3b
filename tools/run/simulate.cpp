#include "tools/run/simulate.h"

#include <algorithm>
#include <filesystem>
#include <memory>
#include <utility>

#include "design/design_file.h"
#include "io/support/file_io.h"
#include "io/support/text.h"
#include "photometry/format.h"
#include "sim/emitters/ray_set_emitter.h"
#include "sim/samplers/sampler.h"
#include "sim/simulation.h"  // sim::parse_luminance_views (sim/detectors)
#include "sim/detectors/symmetry.h"
#include "tools/run/distributed_run.h"
#include "tools/run/glossy_energy_cache.h"
#include "tools/run/resampler_cache.h"
#include "tools/run/simulation_outputs.h"

namespace gonio::app {
namespace {

// The comma-separated words of a list, spaces around each trimmed.
std::vector<std::string> split_list(const std::string& list) {
  std::vector<std::string> words;
  for (std::size_t start = 0; start <= list.size();) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    std::string word = list.substr(start, comma - start);
    start = comma + 1;
    while (!word.empty() && word.front() == ' ') word.erase(word.begin());
    while (!word.empty() && word.back() == ' ') word.pop_back();
    words.push_back(word);
  }
  return words;
}

// --near-field D1,D2,…: distinct distances in (0, 1e4] m, at most 16, ascending.
Result<std::vector<double>> near_field_distances(const std::string& list) {
  std::vector<double> distances;
  for (std::size_t start = 0; start <= list.size();) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    const std::string token = list.substr(start, comma - start);
    start = comma + 1;
    const std::optional<double> d = io::parse_number(token);
    if (!d || !(*d > 0.0 && *d <= 1e4))
      return make_error("--near-field: '" + token + "' is not a distance in metres in (0, 1e4]");
    if (std::find(distances.begin(), distances.end(), *d) == distances.end()) distances.push_back(*d);
  }
  if (distances.size() > 16) return make_error("--near-field: at most 16 distances");
  std::sort(distances.begin(), distances.end());
  return distances;
}

Status check_ranges(const SimulateOptions& o) {
  const std::pair<const char*, std::pair<long long, Bounds<long long>>> integers[] = {
      {"photons", {o.photons, kPhotonsBounds}},
      {"iterations", {o.iterations, kIterationsBounds}},
      {"seed", {o.seed, kSeedBounds}},
      {"threads", {o.threads, kThreadsBounds}},
      {"max-bounces", {o.max_bounces, kMaxBouncesBounds}},
      {"face-size", {o.face_size == 0 ? 1 : o.face_size, kFaceSizeBounds}},
      {"tm25-rays", {o.tm25_rays.value_or(1), kTm25RaysBounds}},
      {"cache-limit", {o.cache_limit_mb, kCacheLimitMbBounds}},
      {"connections", {o.connections, kConnectionsBounds}}};
  for (const auto& [name, check] : integers)
    if (Status s = check_range(name, check.first, check.second); !s.ok()) return s;
  const std::pair<const char*, std::pair<double, Bounds<double>>> reals[] = {
      {"c-step", {o.c_step, kGridStepBounds}},
      {"gamma-step", {o.gamma_step, kGammaStepBounds}},
      {"min-lor", {o.min_lor, kFractionBounds}},
      {"flux-tolerance", {o.flux_tolerance, kFractionBounds}},
      {"target-error", {o.target_error_pct, kTargetErrorBounds}}};
  for (const auto& [name, check] : reals)
    if (Status s = check_range(name, check.first, check.second); !s.ok()) return s;
  return Ok{};
}

}  // namespace

Result<SimulatePlan> plan_simulation(const std::string& model, const SimulateOptions& o) {
  if (Status s = check_ranges(o); !s.ok()) return s.error();
  const Result<sim::PreviewFilterParams> preview_params_result = preview_params(o.preview);
  if (!preview_params_result.ok()) return preview_params_result.error();
  std::optional<photometry::Symmetry> symmetry;
  if (o.symmetry_name != "auto") {
    symmetry = sim::parse_symmetry(o.symmetry_name);
    if (!symmetry)
      return make_error("--symmetry: unknown symmetry '" + o.symmetry_name +
                        "'; expected auto, none, C0-C180, C90-C270, quadrant or rotational");
  }
  GridOptions grid_options;
  grid_options.c_step = o.c_step;
  grid_options.gamma_step = o.gamma_step;
  grid_options.c_angles = o.c_angles;
  grid_options.gamma_angles = o.gamma_angles;
  grid_options.grid_like = o.grid_like;
  grid_options.symmetry = symmetry;
  std::string grid_note;
  Result<sim::CGammaGrid> resolved = resolve_grid(grid_options, &grid_note);
  if (!resolved.ok()) return resolved.error();
  const sim::CGammaGrid grid = std::move(resolved.value());
  const std::string c_source = o.c_angles ? "--c-angles" : o.grid_like ? "--grid-like" : "--c-step";
  const std::string gamma_source = o.gamma_angles ? "--gamma-angles" : o.grid_like ? "--grid-like" : "--gamma-step";
  if (symmetry)
    if (Status s = sim::check_grid_supports(grid, *symmetry); !s.ok())
      return make_error(c_source + ": " + s.error().message);
  // tm25 is written by write_run_files (the ray file), the others by write_outputs.
  bool tm25 = false;
  std::string other_formats;
  for (const std::string& name : split_list(o.format_list)) {
    if (name == "tm25") {
      tm25 = true;
    } else {
      other_formats += (other_formats.empty() ? "" : ",") + name;
    }
  }
  std::vector<double> near_field_m;
  if (o.near_field) {
    Result<std::vector<double>> distances = near_field_distances(*o.near_field);
    if (!distances.ok()) return distances.error();
    near_field_m = std::move(distances.value());
  }
  std::vector<sim::LuminanceView> views;
  if (o.luminance_images)
    if (const std::string why = sim::parse_luminance_views(*o.luminance_images, &views); !why.empty())
      return make_error("--luminance-image: " + why);
  if (!tm25 && o.tm25_rays) return make_error("--tm25-rays applies to --format tm25 only");
  Result<std::vector<OutputFormat>> formats =
      tm25 && other_formats.empty() ? Result<std::vector<OutputFormat>>(std::vector<OutputFormat>{})
                                    : parse_formats(other_formats);
  if (!formats.ok()) return formats.error();
  for (OutputFormat f : formats.value())
    if (f == OutputFormat::Ldt || f == OutputFormat::Gldf)
      if (Status s = check_grid_for_ldt(grid, c_source, gamma_source); !s.ok()) return s.error();
  std::string stem = o.stem.empty() ? design::model_stem(model) : o.stem;
  if (stem.empty() || stem.find_first_of("/\\") != std::string::npos || stem == "." || stem == "..")
    return make_error("--name: '" + stem + "' is not a plain file name");
  if (o.ies_version != "2002" && o.ies_version != "2019")
    return make_error("--ies-version must be one of 2002|2019, got '" + o.ies_version + "'");
  const std::optional<sim::NextEventMode> next_event = sim::parse_next_event_mode(o.next_event);
  if (!next_event) return make_error("--next-event must be one of auto|on|off, got '" + o.next_event + "'");
  const std::optional<sim::SamplerKind> sampler = sim::parse_sampler(o.sampler);
  if (!sampler) return make_error("--sampler must be one of sobol|random, got '" + o.sampler + "'");
  using Quality = sim::EmbreeSceneOptions::Quality;
  std::optional<Quality> bvh_quality;
  for (Quality q : {Quality::Low, Quality::Medium, Quality::High})
    if (o.bvh_quality == sim::to_string(q)) bvh_quality = q;
  if (!bvh_quality && o.bvh_quality != "auto")
    return make_error("--bvh-quality must be one of auto|low|medium|high, got '" + o.bvh_quality + "'");
  if (o.no_cache && o.cache_dir) return make_error("--cache and --no-cache exclude each other");

  SimulatePlan plan;
  plan.model = model;
  plan.out_dir = o.out_dir;
  plan.stem = stem;
  plan.grid = grid;
  plan.grid_note = grid_note;
  plan.symmetry = symmetry;
  plan.formats = formats.value();
  plan.tm25 = tm25;
  plan.ies_version = o.ies_version == "2002" ? io::IesVersion::LM63_2002 : io::IesVersion::LM63_2019;
  plan.preview = o.preview.enabled;
  plan.preview_params = preview_params_result.value();
  plan.min_lor = o.min_lor;
  plan.flux_tolerance = o.flux_tolerance;
  plan.model_input = o.model_input;
  // A CAD model's default tessellation follows the γ step (the finest of a list).
  plan.model_input.gamma_step_deg = grid.finest_gamma_step_deg();
  if (Status s = check_model_input(plan.model_input, {model}); !s.ok()) return s.error();
  plan.model_input.cache_dir = o.no_cache ? std::string() : o.cache_dir.value_or(io::default_cache_dir());
  plan.cache_limit_bytes = static_cast<std::uint64_t>(o.cache_limit_mb) << 20;
  plan.progressive.target_error_pct = o.target_error_pct;
  sim::SimulationSettings& settings = plan.progressive.simulation;
  settings.photons_per_iteration = static_cast<std::uint64_t>(o.photons);
  settings.iterations = static_cast<int>(o.iterations);
  settings.seed = static_cast<std::uint64_t>(o.seed);
  settings.sampler = *sampler;
  settings.threads = static_cast<int>(o.threads);
  // Without TM-25 rays the trace keeps the escapes of its first
  // kOpeningPhotons photons, so that the luminous opening is found from them
  // instead of tracing them again (simulated_opening, issue 40).
  settings.capture_escaped_photons = tm25 ? static_cast<std::uint64_t>(o.tm25_rays.value_or(1'000'000)) : kOpeningPhotons;
  settings.near_field_distances_m = near_field_m;
  settings.next_event = *next_event;
  settings.next_event_connections = static_cast<int>(o.connections);
  settings.luminance.views = views;
  settings.max_bounces = static_cast<int>(o.max_bounces);
  settings.face_size = o.face_size == 0 ? sim::face_size_for(grid) : static_cast<int>(o.face_size);
  settings.bvh_quality = bvh_quality;  // none: auto
  return plan;
}

std::optional<SimulateResult> simulate(const SimulatePlan& plan, const SimulateHooks& hooks,
                                       std::chrono::steady_clock::time_point start) {
  const sim::SimulationSettings& settings = plan.progressive.simulation;
  const sim::Ranks one_process;
  const sim::Ranks& ranks = settings.ranks ? *settings.ranks : one_process;
  const bool lead = ranks.rank() == 0;
  ModelInputTimes input_times;
  std::vector<Finding> findings;

  // Load, then check the geometry: errors stop the run, warnings are told.
  std::optional<Error> failure;
  const auto failed = [&] {
    if (failure && hooks.on_failed) hooks.on_failed(*failure);
  };
  std::optional<sim::SceneDesc> scene = load_checked_model(plan.model, "simulated", plan.model_input,
                                                           &input_times, hooks.on_message, &findings, &failure);
  if (scene && hooks.adjust_scene)
    if (Status s = hooks.adjust_scene(*scene); !s.ok()) {
      tell(hooks.on_message, s.error());
      failure = s.error();
      scene.reset();
    }
  // Ray-set emitters asked for more photons than their rays can give.
  if (scene)
    for (Finding& f : sim::ray_set_photon_findings(
             *scene, settings.photons_per_iteration * static_cast<std::uint64_t>(settings.iterations))) {
      f.where.file = plan.model;
      if (lead) tell(hooks.on_message, f.severity, format_finding(f));
      findings.push_back(f);
    }
  // The output directory is made before tracing so that previews can land in it.
  bool ready = scene.has_value();
  if (ready && lead && !plan.out_dir.empty()) {
    if (Status s = io::make_directories(plan.out_dir); !s.ok()) {
      tell(hooks.on_message, s.error());
      failure = s.error();
      ready = false;
    }
  }
  if (!ready) failed();
  // Every rank ready, with the same model and settings, or none traces.
  std::optional<std::string> fingerprint;
  if (ready) fingerprint = ranks.distributed() ? run_fingerprint(*scene, settings) : std::string();
  if (!ranks_agree(ranks, fingerprint, "simulate", hooks.on_message)) return std::nullopt;

  std::optional<PreviewOutput> preview;
  if (plan.preview && lead && !plan.out_dir.empty())
    preview.emplace(plan.out_dir, settings.face_size, plan.preview_params);
  Status preview_status = Ok{};
  // The estimate needs the output grid's resampler (0.07 s to build at the
  // defaults, else from the cache): the front end's, or made here only where
  // the target error needs it.
  const sim::Resampler* resampler = lead && hooks.on_loaded ? hooks.on_loaded(*scene, findings) : nullptr;
  std::optional<sim::Resampler> own_resampler;
  if (!resampler && plan.progressive.target_error_pct > 0.0)
    resampler = &own_resampler.emplace(
        cached_resampler(settings.face_size, scene->frame, plan.grid, plan.model_input.cache_dir));

  auto on_iteration = [&](const IterationReport& r, const sim::Simulation& simulation) {
    if (preview && preview_status.ok()) preview_status = preview->write(simulation.far_field());
    return !lead || !hooks.on_iteration || hooks.on_iteration(r, simulation);
  };
  // The glossy lobes' energy tables from the cache folder where it has them.
  (void)load_glossy_energy_tables(*scene, plan.model_input.cache_dir);
  Result<ProgressiveOutcome> run =
      run_progressive(std::move(scene.value()), plan.progressive, resampler, on_iteration, hooks.cancel);
  if (!run.ok()) {
    Error e = run.error();
    if (e.where.file.empty()) e.where.file = plan.model;
    tell(hooks.on_message, e);
    if (hooks.on_failed) hooks.on_failed(e);
    return std::nullopt;
  }
  // Each rank's share and speed; then rank 0 alone writes.
  const nlohmann::json ranks_report =
      settings.ranks ? ranks_json(ranks, run->simulation.stats()) : nlohmann::json(nullptr);
  if (lead && hooks.on_traced) hooks.on_traced(run.value());
  std::optional<RunFiles> files;
  const bool keep = run->stopped_by != StopReason::Cancelled || (hooks.keep_when_stopped && hooks.keep_when_stopped());
  if (lead && !plan.out_dir.empty() && keep) {
    // From here on a failure loses nothing (write_run_files): a preview that
    // could not be written is listed in report.json with the files that were.
    std::vector<Error> failures;
    if (!preview_status.ok()) failures.push_back(preview_status.error());
    files = write_run_files(plan, run.value(), input_times, preview ? &*preview : nullptr, start, ranks_report,
                            std::move(failures), resampler);
  }
  return SimulateResult{std::move(run.value()), input_times, std::move(findings), lead, std::move(files)};
}

}  // namespace gonio::app
