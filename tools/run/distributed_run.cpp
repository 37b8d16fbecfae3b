#include "tools/run/distributed_run.h"

#include <cstdio>

#include "io/support/content_hash.h"
#include "tools/run/scene_hash.h"
#include "tools/run/console.h"

namespace gonio::cli {

std::optional<sim::Ranks> join_job(const std::string& command) {
  auto ranks = sim::Ranks::join_job();
  if (!ranks.ok()) {
    print_error(command + ": " + ranks.error().message);
    return std::nullopt;
  }
  return std::move(ranks.value());
}

std::string run_fingerprint(const sim::SceneDesc& scene, const sim::SimulationSettings& s) {
  char settings[256];
  std::snprintf(settings, sizeof settings,
                "photons %llu, iterations %d, seed %llu, max bounces %d, face size %d, robust %d, "
                "importance %d %d %.17g, bvh quality %d",
                static_cast<unsigned long long>(s.photons_per_iteration), s.iterations,
                static_cast<unsigned long long>(s.seed), s.max_bounces, s.face_size,
                s.robust_embree ? 1 : 0, s.importance.enabled ? 1 : 0, s.importance.emission_face_size,
                s.importance.min_acceptance, s.bvh_quality ? static_cast<int>(*s.bvh_quality) : -1);
  return io::content_hash_hex(scene_hash(scene) + "; " + settings);
}

bool ranks_agree(const sim::Ranks& ranks, const std::optional<std::string>& fingerprint,
                 const std::string& command) {
  if (!ranks.distributed()) return fingerprint.has_value();
  const std::vector<std::uint64_t> ready = ranks.gather(std::uint64_t{fingerprint.has_value()});
  const std::vector<std::uint64_t> hashes = ranks.gather(
      static_cast<std::uint64_t>(fingerprint ? std::stoull(*fingerprint, nullptr, 16) : 0));
  bool agree = true;
  for (int r = 0; r < ranks.size(); ++r) {
    std::string fault;
    if (!ready[r])
      fault = "could not get ready (its error above)";
    else if (ready[0] && hashes[r] != hashes[0])
      fault = "holds another model or other settings than rank 0 (run fingerprint " +
              io::to_hex(hashes[r]) + " against " + io::to_hex(hashes[0]) +
              "): every rank must load the same model with the same options";
    if (fault.empty()) continue;
    agree = false;
    if (ranks.rank() == 0) print_error(command + ": " + ranks.name_of(r) + " " + fault);
  }
  if (!agree && ranks.rank() == 0) print_error(command + ": nothing was traced");
  return agree;
}

nlohmann::json ranks_json(const sim::Ranks& ranks, const sim::SimulationStats& st) {
  const std::vector<std::uint64_t> photons = ranks.gather(st.rank_photons);
  const std::vector<double> trace = ranks.gather(st.rank_trace_s);
  const std::vector<double> wait = ranks.gather(st.wait_s);
  const std::vector<double> reduce = ranks.gather(st.reduce_s);
  const std::vector<double> fastest = ranks.gather(st.reduce_fastest_s);
  const std::vector<std::uint64_t> threads = ranks.gather(static_cast<std::uint64_t>(st.threads));
  nlohmann::json per_rank = nlohmann::json::array();
  for (std::size_t r = 0; r < photons.size(); ++r)
    per_rank.push_back({{"rank", r},
                        {"threads", threads[r]},
                        {"photons", photons[r]},
                        {"trace_s", trace[r]},
                        {"photons_per_s", trace[r] > 0.0 ? static_cast<double>(photons[r]) / trace[r] : 0.0},
                        {"wait_s", wait[r]},
                        {"reduce_s", reduce[r]},
                        {"reduce_fastest_s", fastest[r]}});
  return {{"ranks", ranks.size()}, {"per_rank", per_rank}};
}

}  // namespace gonio::cli
