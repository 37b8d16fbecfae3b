// Samplers: what maps (seed, photon index, dimension) to the uniform numbers
// a photon draws. Emission and scattering draw through sim::PhotonRandom
// (sim/samplers/random.h), which answers from the sampler of the run:
//
//   random  counter-based pseudo-random numbers (sim/samplers/random.h): draw k of
//           photon i is a hash of (seed, i, k). Errors fall as N^−1/2.
//   sobol   randomised quasi-Monte Carlo: photon i is point ⌊i/K⌋ of a
//           Sobol' sequence in kSobolDimensions dimensions, each dimension
//           Owen-scrambled (nested uniform scrambling) with a key from
//           (seed, replicate r = i mod K, dimension): K independent
//           scrambles interleaved (replicates, below); draws beyond the
//           Sobol' dimensions come from the random sampler's stream of
//           (seed, i) (padding). Each point
//           is uniform in [0, 1)^d whatever the scramble's key, so every
//           estimate stays unbiased; the points of one key are a
//           low-discrepancy set, so smooth integrands converge faster than
//           N^−1/2 (Owen 1997: never worse than a constant times the Monte
//           Carlo variance).
//
// Dimensions are handed out in the order a photon draws: emission first
// (the emitter when there are several, then the emitter's position and
// direction: an area emitter's triangle, point on it, side if two-sided and
// direction; a profile's grid cell and the direction inside it; an isotropic
// point's direction), then its bounces (the absorption test of an
// attenuating volume crossed, the lobe, the lobe's own draws) until
// kSobolDimensions are used, after which it draws padding. Under `sobol` the
// warps draw by inversion (a fixed count of numbers, monotone where they
// can be) rather than rejection, so the low-discrepancy structure reaches
// the directions (sim/samplers/sampling.h, sim/emitters/emission.h).
//
// Sobol' points: direction numbers of Joe & Kuo (2008, "Constructing Sobol
// sequences with better two-dimensional projections", SIAM J. Sci. Comput.
// 30, 2635–2654; their table new-joe-kuo-6.21201, dimensions 2–32, typed
// below as (degree s, coefficients a, initial numbers m)); the first
// dimension is the van der Corput sequence. Point j is the matrix product of
// the generator matrices with the bits of j (not the Gray-code order), so
// photon i needs no other photon. Points beyond 2³² use further blocks of
// 2³² points, each block with keys of its own (independent scrambles).
//
// Scrambling: Owen scrambling by a hash of the bit-reversed value in which
// every output bit depends only on the input bits below it (Laine & Karras
// 2011; Burley 2020, "Practical hash-based Owen scrambling", JCGT 9(4)),
// with the hash constants of Vegdahl (2021, "Building a better LK hash").
// Coordinates carry 32 bits (steps of 2⁻³², as the random sampler's
// direction pairs).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace gonio::sim {

enum class SamplerKind : std::uint8_t { Random, Sobol };

constexpr std::string_view to_string(SamplerKind kind) {
  return kind == SamplerKind::Sobol ? "sobol" : "random";
}
constexpr std::optional<SamplerKind> parse_sampler(std::string_view name) {
  if (name == "random") return SamplerKind::Random;
  if (name == "sobol") return SamplerKind::Sobol;
  return std::nullopt;
}

inline constexpr int kSobolDimensions = 32;

namespace sobol_detail {

struct Primitive {
  int s;             // degree of the primitive polynomial
  std::uint32_t a;   // its inner coefficients
  std::uint32_t m[8];  // initial direction numbers m_1 … m_s
};

// Joe & Kuo, new-joe-kuo-6.21201, dimensions 2–32.
inline constexpr Primitive kJoeKuo[kSobolDimensions - 1] = {
    {1, 0, {1}},
    {2, 1, {1, 3}},
    {3, 1, {1, 3, 1}},
    {3, 2, {1, 1, 1}},
    {4, 1, {1, 1, 3, 3}},
    {4, 4, {1, 3, 5, 13}},
    {5, 2, {1, 1, 5, 5, 17}},
    {5, 4, {1, 1, 5, 5, 5}},
    {5, 7, {1, 1, 7, 11, 19}},
    {5, 11, {1, 1, 5, 1, 1}},
    {5, 13, {1, 1, 1, 3, 11}},
    {5, 14, {1, 3, 5, 5, 31}},
    {6, 1, {1, 3, 3, 9, 7, 49}},
    {6, 13, {1, 1, 1, 15, 21, 21}},
    {6, 16, {1, 3, 1, 13, 27, 49}},
    {6, 19, {1, 1, 1, 15, 7, 5}},
    {6, 22, {1, 3, 1, 15, 13, 25}},
    {6, 25, {1, 1, 5, 5, 19, 61}},
    {7, 1, {1, 3, 7, 11, 23, 15, 103}},
    {7, 4, {1, 3, 7, 13, 13, 15, 69}},
    {7, 7, {1, 1, 3, 13, 7, 35, 63}},
    {7, 8, {1, 3, 5, 9, 1, 25, 53}},
    {7, 14, {1, 3, 1, 13, 9, 35, 107}},
    {7, 19, {1, 3, 1, 5, 27, 61, 31}},
    {7, 21, {1, 1, 5, 11, 19, 41, 61}},
    {7, 28, {1, 3, 5, 3, 3, 13, 69}},
    {7, 31, {1, 1, 7, 13, 1, 19, 1}},
    {7, 32, {1, 3, 7, 5, 13, 19, 59}},
    {7, 37, {1, 1, 3, 9, 25, 29, 41}},
    {7, 41, {1, 3, 5, 13, 23, 1, 55}},
    {7, 42, {1, 3, 7, 3, 13, 59, 17}},
};

constexpr std::uint32_t reverse_bits(std::uint32_t x) {
  x = __builtin_bswap32(x);
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  return ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
}

// Generator matrices by column: column b is the value bit b of the index
// contributes (direction number v_{b+1}), stored bit-reversed so that the
// scramble (which works on reversed bits) needs one reversal only.
using Matrices = std::array<std::array<std::uint32_t, 32>, kSobolDimensions>;
constexpr Matrices make_matrices() {
  Matrices out{};
  for (int b = 0; b < 32; ++b) out[0][b] = reverse_bits(std::uint32_t{1} << (31 - b));
  for (int d = 1; d < kSobolDimensions; ++d) {
    const Primitive& p = kJoeKuo[d - 1];
    std::uint32_t v[33] = {};
    for (int k = 1; k <= 32; ++k) {
      if (k <= p.s) {
        v[k] = p.m[k - 1] << (32 - k);
      } else {
        v[k] = v[k - p.s] ^ (v[k - p.s] >> p.s);
        for (int j = 1; j < p.s; ++j)
          if ((p.a >> (p.s - 1 - j)) & 1u) v[k] ^= v[k - j];
      }
    }
    for (int b = 0; b < 32; ++b) out[d][b] = reverse_bits(v[b + 1]);
  }
  return out;
}
inline constexpr Matrices kMatrices = make_matrices();

// Prefix XORs of the columns, by trailing zeros first: kPrefix[k][d] =
// column 0 ^ … ^ column k of dimension d, what point i − 1 changes by to
// point i when i has k trailing zero bits (one row for all dimensions, so
// the update is a vector XOR).
constexpr Matrices make_prefix() {
  Matrices out{};
  for (int d = 0; d < kSobolDimensions; ++d) {
    std::uint32_t x = 0;
    for (int b = 0; b < 32; ++b) out[b][d] = x ^= kMatrices[d][b];
  }
  return out;
}
static_assert(kSobolDimensions == 32, "kPrefix is square");
inline constexpr Matrices kPrefix = make_prefix();

}  // namespace sobol_detail

// The SplitMix64 finaliser: a bijection of 64-bit words with full avalanche
// (the random sampler's hash, sim/samplers/random.h, and the scramble keys').
constexpr std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Replicates: photon i belongs to replicate r = i mod K and is point ⌊i/K⌋
// of the Sobol' sequence scrambled with replicate r's keys, so the run is K
// independent scrambles, each a prefix of its own sequence, interleaved.
// Their K estimates of the far field are independent and each unbiased: the
// spread between them gives the error of their mean, which counting photons
// cannot (tools/run/progressive_run.h). kSobolReplicates is the measured choice
// (docs/validation.md: replicates cost error, fewer give a noisier
// estimate).
inline constexpr int kSobolReplicates = 4;
inline constexpr int kMaxSobolReplicates = 32;

// Scramble keys: one per replicate and block of 2³² points of a seed (apart
// from the padding stream's keys), then one per dimension of it.
constexpr std::uint64_t sobol_block_key(std::uint64_t seed, int replicate, std::uint64_t point) {
  return mix64(mix64(mix64(seed ^ 0x5ab01d5eed5ab01dULL) + (point >> 32)) + static_cast<std::uint64_t>(replicate));
}
constexpr std::uint32_t sobol_dimension_key(std::uint64_t block_key, int dim) {
  return static_cast<std::uint32_t>(mix64(block_key + static_cast<std::uint64_t>(dim)));
}

// Value of dimension `dim` of Sobol' point `index`, unscrambled, as a 32-bit
// fraction (x · 2⁻³² in [0, 1)).
constexpr std::uint32_t sobol_u32(std::uint32_t index, int dim) {
  std::uint32_t x = 0;
  for (std::uint32_t i = index; i != 0; i &= i - 1) x ^= sobol_detail::kMatrices[dim][__builtin_ctz(i)];
  return sobol_detail::reverse_bits(x);
}

// Owen scrambling of a value in reversed bit order (each output bit depends
// on the input bits below it alone): Vegdahl's LK hash.
constexpr std::uint32_t owen_scramble_reversed(std::uint32_t x, std::uint32_t key) {
  x ^= x * 0x3d20adeau;
  x += key;
  x *= (key >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

// Dimension `dim` of point `index`, Owen-scrambled with `key`.
constexpr std::uint32_t sobol_scrambled_u32(std::uint32_t index, int dim, std::uint32_t key) {
  std::uint32_t x = 0;
  for (std::uint32_t i = index; i != 0; i &= i - 1) x ^= sobol_detail::kMatrices[dim][__builtin_ctz(i)];
  return sobol_detail::reverse_bits(owen_scramble_reversed(x, key));
}

// The unscrambled points (bit-reversed) and the keys of consecutive photons
// of one run, for a thread that traces photons in order: the K photons of
// one point share its values (only their replicate's keys differ), and
// moving to the next point costs one XOR per dimension (point j differs
// from point j − 1 by a prefix of columns), where computing a point afresh
// costs one per set bit of j. A cache only: the values are those of
// (seed, i) whichever photon the cursor came from.
class SobolCursor {
 public:
  SobolCursor(std::uint64_t seed, int replicates) : seed_(seed), replicates_(replicates) {}

  // Positioned at `photon`; returns itself.
  const SobolCursor& at(std::uint64_t photon) {
    const auto k = static_cast<std::uint64_t>(replicates_);
    const std::uint64_t point = photon / k;
    if (valid_ && point == point_ + 1 && static_cast<std::uint32_t>(point) != 0) {
      const int z = __builtin_ctz(static_cast<std::uint32_t>(point));
      const auto& row = sobol_detail::kPrefix[static_cast<std::size_t>(z)];
      for (int d = 0; d < kSobolDimensions; ++d) values_[d] ^= row[static_cast<std::size_t>(d)];
    } else if (!valid_ || point != point_) {
      if (!valid_ || (point >> 32) != (point_ >> 32)) {
        for (int r = 0; r < replicates_; ++r) {
          const std::uint64_t block = sobol_block_key(seed_, r, point);
          for (int d = 0; d < kSobolDimensions; ++d) keys_[r][d] = sobol_dimension_key(block, d);
        }
      }
      const auto index = static_cast<std::uint32_t>(point);
      for (int d = 0; d < kSobolDimensions; ++d) {
        std::uint32_t x = 0;
        for (std::uint32_t i = index; i != 0; i &= i - 1) x ^= sobol_detail::kMatrices[d][__builtin_ctz(i)];
        values_[d] = x;
      }
    }
    photon_ = photon;
    point_ = point;
    replicate_ = static_cast<int>(photon % k);
    valid_ = true;
    return *this;
  }
  std::uint64_t photon() const { return photon_; }
  // Dimension d's value, scrambled, as a 32-bit fraction.
  std::uint32_t value(int d) const {
    return sobol_detail::reverse_bits(owen_scramble_reversed(values_[d], keys_[replicate_][d]));
  }

 private:
  std::uint64_t seed_;
  int replicates_;
  std::uint64_t photon_ = 0;
  std::uint64_t point_ = 0;
  int replicate_ = 0;
  bool valid_ = false;
  std::uint32_t values_[kSobolDimensions] = {};  // unscrambled, bit-reversed
  std::uint32_t keys_[kMaxSobolReplicates][kSobolDimensions] = {};
};

}  // namespace gonio::sim
