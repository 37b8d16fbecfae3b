#include "tools/bench/bench_reference.h"

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <type_traits>

#include "io/outputs/exr.h"
#include "io/support/file_io.h"
#include "io/outputs/report.h"
#include "sim/simulation.h"
#include "tools/run/scene_hash.h"

namespace gonio::cli {
namespace {


std::string path_in(const std::string& dir, const char* name) {
  return (std::filesystem::path(dir) / name).string();
}

ReferenceNoise measure_noise(const sim::FarField& half, const sim::FarField& full,
                             const std::shared_ptr<const sim::Resampler>& resampler) {
  // The second half as a run of its own: 2·full − first half (flux), full −
  // first half (photons).
  std::vector<double> flux(full.texel_count());
  std::vector<std::uint64_t> photons(full.texel_count());
  for (std::size_t t = 0; t < flux.size(); ++t) {
    flux[t] = std::max(0.0, 2.0 * full.flux_lm(t) - half.flux_lm(t));
    photons[t] = full.photons(t) - half.photons(t);
  }
  const sim::FarField second(full.face_size(), std::move(flux), std::move(photons));
  ReferenceNoise n;
  auto whole = sim::ConvergenceReference::create(full, resampler);
  auto other = sim::ConvergenceReference::create(second, resampler);
  if (!whole.ok() || !other.ok() || !(half.total_flux_lm() > 0.0)) return n;
  n.cube_map_estimated = whole->cube_map_noise();
  n.table_estimated_pct = whole->table_noise_pct();
  const std::vector<double> first = sim::texel_intensities(half);
  n.cube_map_measured = std::sqrt(other->cube_map_error(first).raw_mse) / 2.0;
  n.table_measured_pct = other->table_error(first).raw_rms_pct / 2.0;
  return n;
}

nlohmann::json noise_json(const ReferenceNoise& n) {
  return {{"cube_map_estimated", n.cube_map_estimated},
          {"cube_map_measured", n.cube_map_measured},
          {"table_estimated_pct", n.table_estimated_pct},
          {"table_measured_pct", n.table_measured_pct}};
}

// The cached reference, if it is there, readable and made from `key`.
std::optional<Reference> load_cached(const std::string& dir, const ReferenceKey& key) {
  const auto text = io::read_file(path_in(dir, "reference.json"), 1 << 20);
  if (!text.ok()) return std::nullopt;
  const nlohmann::json j = nlohmann::json::parse(text.value(), nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("key") || j["key"] != key.to_json())
    return std::nullopt;
  const auto image = io::read_exr(path_in(dir, "reference.exr"));
  if (!image.ok()) return std::nullopt;
  // Both files must come from the same run.
  const std::string* stamp = image->find_attribute("gonio:reference");
  if (!stamp || *stamp != key.to_json().dump()) return std::nullopt;
  auto field = io::far_field_from_image(image.value(), path_in(dir, "reference.exr"));
  if (!field.ok() || field->face_size() != key.face_size || field->total_photons() > key.photons)
    return std::nullopt;
  Reference r;
  r.key = key;
  r.far_field = std::move(field.value());
  r.reused = true;
  try {
    r.trace_s = j.at("trace_s").get<double>();
    r.threads = j.at("threads").get<int>();
    const nlohmann::json& n = j.at("noise");
    r.noise.cube_map_estimated = n.at("cube_map_estimated").get<double>();
    r.noise.cube_map_measured = n.at("cube_map_measured").get<double>();
    r.noise.table_estimated_pct = n.at("table_estimated_pct").get<double>();
    r.noise.table_measured_pct = n.at("table_measured_pct").get<double>();
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
  return r;
}

}  // namespace

nlohmann::json ReferenceKey::to_json() const {
  return {{"program_version", program_version}, {"tracer_revision", tracer_revision},
          {"model_hash", model_hash},
          {"scene_hash", scene_hash},           {"seed", seed},
          {"photons", photons},                 {"face_size", face_size},
          {"max_bounces", max_bounces},         {"robust_embree", robust_embree}};
}

Result<Reference> load_or_make_reference(const std::string& dir, const ReferenceKey& key,
                                         const sim::SceneDesc& scene, int threads,
                                         std::shared_ptr<const sim::Resampler> resampler,
                                         const std::function<void(std::uint64_t, std::uint64_t)>& progress,
                                         const sim::Ranks* ranks) {
  const bool lead = !ranks || ranks->rank() == 0;
  std::optional<Reference> cached = lead ? load_cached(dir, key) : std::nullopt;
  if (ranks && ranks->gather(std::uint64_t{cached.has_value()})[0] != 0 && !lead) {
    Reference r;  // rank 0 has it
    r.key = key;
    r.reused = true;
    return r;
  }
  if (cached) return std::move(*cached);
  if (key.photons < 2) return make_error("the reference needs at least 2 photons");

  sim::SimulationSettings s;
  s.photons_per_iteration = 1;  // each iteration below names its own size
  s.iterations = 1;
  s.seed = key.seed;
  s.threads = threads;
  s.max_bounces = key.max_bounces;
  s.face_size = key.face_size;
  s.robust_embree = key.robust_embree;
  s.bvh_quality = sim::EmbreeSceneOptions::Quality::High;  // one tree for every photon count
  s.ranks = ranks;
  auto created = sim::Simulation::create(scene, s);
  if (!created.ok()) return created.error();
  sim::Simulation& sim = created.value();
  constexpr std::uint64_t kStep = std::uint64_t{1} << 24;
  const std::uint64_t half = key.photons / 2;
  std::optional<sim::FarField> first_half;
  while (sim.stats().photons < key.photons) {
    const std::uint64_t done = sim.stats().photons;
    const std::uint64_t stop = done < half ? half : key.photons;
    sim.run_iteration(std::min(kStep, stop - done));
    if (sim.stats().photons == half) first_half = sim.far_field();
    if (progress && lead) progress(sim.stats().photons, key.photons);
  }
  Reference r;
  r.key = key;
  if (!lead) return r;
  r.far_field = sim.far_field();
  r.trace_s = sim.stats().trace_s;
  r.threads = sim.stats().threads;
  if (first_half) r.noise = measure_noise(*first_half, r.far_field, resampler);

  auto image = io::far_field_image(r.far_field);
  if (!image.ok()) return make_error(path_in(dir, "reference.exr") + ": " + image.error().message);
  image->attributes.emplace_back("gonio:reference", key.to_json().dump());
  if (Status st = io::write_exr(path_in(dir, "reference.exr"), image.value()); !st.ok()) return st.error();
  // Judge by what the cache holds (flux as float), so that a fresh and a
  // reused reference give the same figures.
  auto stored = io::far_field_from_image(image.value(), path_in(dir, "reference.exr"));
  if (!stored.ok()) return stored.error();
  r.far_field = std::move(stored.value());
  nlohmann::json j = {{"key", key.to_json()},
                      {"trace_s", r.trace_s},
                      {"threads", r.threads},
                      {"noise", noise_json(r.noise)}};
  if (Status st = io::write_json(path_in(dir, "reference.json"), j); !st.ok()) return st.error();
  return r;
}

}  // namespace gonio::cli
