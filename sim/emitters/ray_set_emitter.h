// Ray-set emitters: photons drawn from a near-field ray set (an IES TM-25
// file on a glTF node, io/model/gltf.h) in proportion to ray flux.
//
// A photon takes the start point and direction of the ray it draws; every
// photon carries the same power, so a ray is drawn with probability
// flux_i / Σ flux (alias table, O(1), one uniform number: sample(u) takes
// any u in [0, 1), so a sampler other than PhotonRandom can drive it).
//
// How many photons a set can give. A ray set of N rays is itself one sample
// of the source: its far field (and near field) carries a relative noise of
// about 1/√N_eff per bin, where N_eff = (Σφ)² / Σφ² is Kish's effective
// count (N for rays of equal flux). Drawing M photons from it adds a second,
// independent noise of 1/√M, so the run's error is the set's times
// √(1 + N_eff/M). Beyond M = N_eff the set's own noise dominates and more
// photons no longer lower the error (at M = 4 N_eff it is 1.12× the floor,
// at M = N_eff 1.41×): the rule is M ≤ N_eff photons per ray set, and
// simulate warns ("ray-set-oversampled") when a run draws more.
#pragma once

#include <cstddef>

#include "photometry/diagnostics.h"
#include "sim/samplers/alias_table.h"
#include "sim/scene.h"

namespace gonio::sim {

class RaySetSampler {
 public:
  // Errors: no rays, no flux, a non-finite or negative flux, a non-finite
  // position, a direction that is not unit (to 1e-3).
  static Result<RaySetSampler> create(const RaySet& rays);

  struct Sample {
    Vec3 position;   // [m]
    Vec3 direction;  // unit
    std::uint32_t ray;
  };
  // The ray for a uniform u in [0, 1).
  Sample sample(double u) const;
  std::size_t ray_count() const { return rays_ ? rays_->size() : 0; }
  double total_flux_lm() const { return table_.total_weight(); }
  // Kish's effective number of rays, (Σφ)² / Σφ²: the most photons the set
  // should give (above).
  double effective_ray_count() const { return effective_; }

 private:
  std::shared_ptr<const RaySet> rays_;
  AliasTable table_;
  double effective_ = 0.0;
  friend Result<RaySetSampler> make_ray_set_sampler(std::shared_ptr<const RaySet> rays);
};

// The sampler of a shared ray set (kept, not copied).
Result<RaySetSampler> make_ray_set_sampler(std::shared_ptr<const RaySet> rays);

// The photons a run of `photons` gives to each ray-set emitter (in
// proportion to its flux) above its effective ray count: one warning
// "ray-set-oversampled" per emitter that exceeds the rule above.
std::vector<Finding> ray_set_photon_findings(const SceneDesc& scene, std::uint64_t photons);

}  // namespace gonio::sim
