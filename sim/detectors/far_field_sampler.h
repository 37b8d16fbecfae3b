// Far fields drawn from a known intensity distribution: the ground truth the
// preview filter's tests and study measure against.
//
// expected_texel_flux integrates an intensity function over every texel (the
// converged map, exactly what an infinitely long run would hold), and
// FarFieldSampler draws photons from it: each photon lands in texel t with
// probability expected[t] / Σ expected (sim/samplers/alias_table.h, O(1) per
// photon), which is how a photon tracer's histogram fills.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <random>
#include <span>
#include <vector>

#include "photometry/vec3.h"
#include "sim/samplers/alias_table.h"
#include "sim/detectors/far_field.h"

namespace gonio::sim {

// ∫ I dΩ over each texel [lm] of an intensity function I(direction) [cd]
// (called with unit directions), by q × q midpoint sub-texels each weighted by
// its exact solid angle: exact for piecewise-constant I, error O(1/q²) for
// smooth I.
std::vector<double> expected_texel_flux(const CubeMapGrid& grid,
                                        const std::function<double(const Vec3&)>& intensity_cd,
                                        int q);

class FarFieldSampler {
 public:
  // Texel weights ≥ 0 with a positive sum (e.g. expected_texel_flux).
  explicit FarFieldSampler(std::span<const double> weights);

  std::size_t texel_count() const { return table_.size(); }
  // The probability that a photon lands in texel t: its density.
  double probability(std::size_t t) const { return table_.pmf(t); }
  // The texel of one photon, from a uniform number in [0, 1).
  std::size_t sample(double u) const { return table_.sample(u); }

  // Adds `photons` photons of `flux_per_photon_lm` each to the field, drawn
  // with `rng` (deterministic for a given seed).
  void add_photons(FarField& field, std::uint64_t photons, double flux_per_photon_lm,
                   std::mt19937_64& rng) const;

 private:
  AliasTable table_;
};

}  // namespace gonio::sim
