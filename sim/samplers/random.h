// Counter-based random numbers: photon i of a run draws its numbers from
// (seed, i) alone, so results do not depend on threads or scheduling.
//
// Draw k of photon i is mix(key_i + k·γ) with key_i = mix(mix(seed) + i)
// and mix the SplitMix64 finaliser (sim/samplers/sampler.h) (a bijection of 64-bit words with full
// avalanche; γ the golden-ratio increment). Distinct photons of one seed get
// distinct keys, and each draw costs a handful of multiplies.
//
// Under the Sobol' sampler (sim/samplers/sampler.h) the first kSobolDimensions draws
// of photon i are the coordinates of Sobol' point ⌊i/K⌋ Owen-scrambled with
// the keys of replicate i mod K (K replicates; 32 bits
// each: uniform() and uniform_open0() steps of 2⁻³², next_u64() the
// coordinate above 32 padding bits, uniform_pair() two coordinates), and the
// draws after them the pseudo-random stream above (padding). Callers ask
// low_discrepancy() to choose warps by inversion.
#pragma once

#include <cstdint>

#include "sim/samplers/sampler.h"

namespace gonio::sim {

class PhotonRandom {
 public:
  PhotonRandom(std::uint64_t seed, std::uint64_t photon)
      : key_(mix64(mix64(seed) + photon)), counter_(0) {}
  // Photon `photon` of the run `seed` under `sampler` (Sobol': with
  // `replicates` interleaved scrambles, 1 … kMaxSobolReplicates).
  PhotonRandom(std::uint64_t seed, std::uint64_t photon, SamplerKind sampler,
               int replicates = kSobolReplicates)
      : PhotonRandom(seed, photon) {
    if (sampler == SamplerKind::Sobol) {
      const auto k = static_cast<std::uint64_t>(replicates);
      sobol_dims_ = kSobolDimensions;
      index_ = static_cast<std::uint32_t>(photon / k);
      scramble_ = sobol_block_key(seed, static_cast<int>(photon % k), photon / k);
    }
  }
  // The same numbers as (seed, photon, Sobol') from a cursor at `photon`
  // (sim/samplers/sampler.h), which must outlive this and stay there.
  PhotonRandom(std::uint64_t seed, const SobolCursor& cursor) : PhotonRandom(seed, cursor.photon()) {
    sobol_dims_ = kSobolDimensions;
    cursor_ = &cursor;
  }

  std::uint64_t next_u64() {
    if (dim_ < sobol_dims_)
      return (static_cast<std::uint64_t>(next_sobol()) << 32) | (next_pseudo() >> 32);
    return next_pseudo();
  }
  // Uniform in [0, 1), 53 random bits (Sobol': 32).
  // (Converted through a signed integer: the value fits, and x86-64 converts
  // signed 64-bit integers in one instruction, unsigned ones with a branch.)
  double uniform() {
    if (dim_ < sobol_dims_) return static_cast<double>(static_cast<std::int64_t>(next_sobol())) * 0x1.0p-32;
    return static_cast<double>(static_cast<std::int64_t>(next_pseudo() >> 11)) * 0x1.0p-53;
  }
  // Uniform in (0, 1]: for logarithms.
  double uniform_open0() {
    if (dim_ < sobol_dims_)
      return static_cast<double>(static_cast<std::int64_t>(next_sobol()) + 1) * 0x1.0p-32;
    return static_cast<double>(static_cast<std::int64_t>(next_pseudo() >> 11) + 1) * 0x1.0p-53;
  }
  // Two uniforms in [0, 1) with 32 random bits each from one draw (enough
  // for directions: steps of 2⁻³² ≈ 2.3·10⁻¹⁰); Sobol': two coordinates.
  void uniform_pair(double* a, double* b) {
    if (dim_ < sobol_dims_) {
      *a = static_cast<double>(static_cast<std::int64_t>(next_sobol())) * 0x1.0p-32;
      *b = uniform();
      return;
    }
    const std::uint64_t x = next_pseudo();
    *a = static_cast<double>(static_cast<std::int64_t>(x >> 32)) * 0x1.0p-32;
    *b = static_cast<double>(static_cast<std::int64_t>(x & 0xffffffffULL)) * 0x1.0p-32;
  }
  // Draws from the pseudo-random stream so far (under Sobol': the padding's).
  std::uint64_t draws() const { return counter_; }
  // Sobol' coordinates drawn so far (0 under the random sampler).
  int dimensions() const { return dim_; }
  // Whether the draws are low-discrepancy coordinates (the Sobol' sampler,
  // before its padding): warps should then draw by inversion, a fixed count
  // of numbers each, rather than by rejection.
  bool low_discrepancy() const { return dim_ < sobol_dims_; }

 private:
  std::uint64_t next_pseudo() { return mix64(key_ + (++counter_) * 0x9e3779b97f4a7c15ULL); }
  std::uint32_t next_sobol() {
    const int d = dim_++;
    if (cursor_) return cursor_->value(d);
    return sobol_scrambled_u32(index_, d, sobol_dimension_key(scramble_, d));
  }

  std::uint64_t key_;
  std::uint64_t counter_;
  std::uint64_t scramble_ = 0;
  const SobolCursor* cursor_ = nullptr;
  std::uint32_t index_ = 0;
  int dim_ = 0;
  int sobol_dims_ = 0;  // 0: the random sampler
};

}  // namespace gonio::sim
