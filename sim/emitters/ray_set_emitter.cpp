#include "sim/emitters/ray_set_emitter.h"

#include <cmath>
#include <vector>

#include "photometry/format.h"

namespace gonio::sim {

Result<RaySetSampler> make_ray_set_sampler(std::shared_ptr<const RaySet> rays) {
  if (!rays || rays->size() == 0) return make_error("the ray set holds no rays");
  const RaySet& r = *rays;
  if (r.position_m.size() != r.size() || r.direction.size() != r.size())
    return make_error("the ray set's positions, directions and fluxes differ in number");
  std::vector<double> weights(r.size());
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double f = r.flux_lm[i];
    if (!std::isfinite(f) || f < 0.0)
      return make_error("ray " + std::to_string(i + 1) + " has flux " + format_number(f) + " lm");
    const Vec3 p = to_double(r.position_m[i]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return make_error("ray " + std::to_string(i + 1) + " starts at a point that is not finite");
    if (!(std::abs(length(to_double(r.direction[i])) - 1.0) < 1e-3))
      return make_error("ray " + std::to_string(i + 1) + "'s direction is not a unit vector");
    weights[i] = f;
    sum += f;
    sum2 += f * f;
  }
  if (!(sum > 0.0)) return make_error("the ray set carries no flux");
  RaySetSampler s;
  s.rays_ = std::move(rays);
  s.table_ = AliasTable(weights);
  s.effective_ = sum * sum / sum2;
  return s;
}

Result<RaySetSampler> RaySetSampler::create(const RaySet& rays) {
  return make_ray_set_sampler(std::make_shared<const RaySet>(rays));
}

RaySetSampler::Sample RaySetSampler::sample(double u) const {
  const std::uint32_t i = table_.sample(u);
  return {to_double(rays_->position_m[i]), to_double(rays_->direction[i]), i};
}

std::vector<Finding> ray_set_photon_findings(const SceneDesc& scene, std::uint64_t photons) {
  std::vector<Finding> out;
  const double total = scene.total_flux_lm();
  if (!(total > 0.0)) return out;
  for (const Emitter& e : scene.emitters) {
    if (e.kind != Emitter::Kind::RaySet || !e.rays) continue;
    auto s = make_ray_set_sampler(e.rays);
    if (!s.ok()) continue;
    const double drawn = static_cast<double>(photons) * e.flux_lm / total;
    const double limit = s->effective_ray_count();
    if (drawn > limit * (1.0 + 1e-6))  // float rounding of equal fluxes
      out.push_back({Severity::Warning, "ray-set-oversampled",
                     "ray-set emitter '" + e.name + "' gives about " + std::to_string(std::llround(drawn)) +
                         " photons from " + std::to_string(s->ray_count()) + " rays (effective " +
                         std::to_string(std::llround(limit)) + "): beyond that the set's own sampling noise dominates, "
                         "and the error stays about " + format_number(std::sqrt(1.0 + limit / drawn), 3) +
                         " times the set's own (docs/formats.md, Ray-file emitters)",
                     {}});
  }
  return out;
}

}  // namespace gonio::sim
