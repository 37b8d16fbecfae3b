// Counter-based random numbers: photon i of a run draws its numbers from
// (seed, i) alone, so results do not depend on threads or scheduling.
//
// Draw k of photon i is mix(key_i + k·γ) with key_i = mix(mix(seed) + i)
// and mix the SplitMix64 finaliser (a bijection of 64-bit words with full
// avalanche; γ the golden-ratio increment). Distinct photons of one seed get
// distinct keys, and each draw costs a handful of multiplies.
#pragma once

#include <cstdint>

namespace gonio::sim {

constexpr std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

class PhotonRandom {
 public:
  PhotonRandom(std::uint64_t seed, std::uint64_t photon)
      : key_(mix64(mix64(seed) + photon)), counter_(0) {}

  std::uint64_t next_u64() { return mix64(key_ + (++counter_) * 0x9e3779b97f4a7c15ULL); }
  // Uniform in [0, 1), 53 random bits.
  // (Converted through a signed integer: the value fits, and x86-64 converts
  // signed 64-bit integers in one instruction, unsigned ones with a branch.)
  double uniform() { return static_cast<double>(static_cast<std::int64_t>(next_u64() >> 11)) * 0x1.0p-53; }
  // Uniform in (0, 1]: for logarithms.
  double uniform_open0() {
    return static_cast<double>(static_cast<std::int64_t>(next_u64() >> 11) + 1) * 0x1.0p-53;
  }
  // Two uniforms in [0, 1) with 32 random bits each from one draw (enough
  // for directions: steps of 2⁻³² ≈ 2.3·10⁻¹⁰).
  void uniform_pair(double* a, double* b) {
    const std::uint64_t x = next_u64();
    *a = static_cast<double>(static_cast<std::int64_t>(x >> 32)) * 0x1.0p-32;
    *b = static_cast<double>(static_cast<std::int64_t>(x & 0xffffffffULL)) * 0x1.0p-32;
  }
  // Number of draws so far.
  std::uint64_t draws() const { return counter_; }

 private:
  std::uint64_t key_;
  std::uint64_t counter_;
};

}  // namespace gonio::sim
