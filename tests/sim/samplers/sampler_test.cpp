#include "sim/samplers/sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <vector>

#include "sim/samplers/random.h"
#include "sim/samplers/sampling.h"

namespace gonio::sim {
namespace {

double unit(std::uint32_t x) { return static_cast<double>(x) * 0x1.0p-32; }

TEST(Sobol, FirstPointsInGrayCodeOrderAreJoeAndKuosPoints) {
  // The first ten points in three dimensions as Joe and Kuo's generator
  // (sobol.cc, which walks the sequence in Gray-code order) prints them
  // with new-joe-kuo-6.21201.
  const double published[10][3] = {{0, 0, 0},           {0.5, 0.5, 0.5},       {0.75, 0.25, 0.25},
                                   {0.25, 0.75, 0.75},  {0.375, 0.375, 0.625}, {0.875, 0.875, 0.125},
                                   {0.625, 0.125, 0.875}, {0.125, 0.625, 0.375}, {0.1875, 0.3125, 0.9375},
                                   {0.6875, 0.8125, 0.4375}};
  for (std::uint32_t n = 0; n < 10; ++n) {
    const std::uint32_t gray = n ^ (n >> 1);
    for (int d = 0; d < 3; ++d) EXPECT_EQ(unit(sobol_u32(gray, d)), published[n][d]) << "point " << n << ", dim " << d;
  }
}

TEST(Sobol, DirectionNumbersAreOddAndBelowTheirPowerOfTwo) {
  // m_k odd and < 2^k: what makes every dimension's first 2^m points one
  // per interval of length 2^−m (typing errors in the table show here).
  for (const sobol_detail::Primitive& p : sobol_detail::kJoeKuo) {
    for (int k = 1; k <= p.s; ++k) {
      EXPECT_EQ(p.m[k - 1] % 2, 1u);
      EXPECT_LT(p.m[k - 1], 1u << k);
    }
    EXPECT_LT(p.a, 1u << (p.s - 1));  // the inner coefficients of a degree-s polynomial
  }
}

// Whether the first 2^m values of `dim` (scrambled with `key`, or not) lie
// one in each interval [j·2^−m, (j+1)·2^−m).
bool stratified(int m, int dim, std::uint32_t key, bool scrambled) {
  std::set<std::uint32_t> cells;
  for (std::uint32_t i = 0; i < (1u << m); ++i) {
    const std::uint32_t x = scrambled ? sobol_scrambled_u32(i, dim, key) : sobol_u32(i, dim);
    cells.insert(x >> (32 - m));
  }
  return cells.size() == (1u << m);
}

TEST(Sobol, EveryDimensionIsStratifiedScrambledOrNot) {
  for (int d = 0; d < kSobolDimensions; ++d) {
    for (int m : {1, 4, 10}) {
      EXPECT_TRUE(stratified(m, d, 0, false)) << "dim " << d << ", 2^" << m;
      EXPECT_TRUE(stratified(m, d, 0x9e3779b9u * static_cast<std::uint32_t>(d + 1), true))
          << "dim " << d << ", 2^" << m;
    }
  }
}

TEST(Sobol, FirstTwoDimensionsAreA0m2NetAfterScrambling) {
  // Every elementary interval of area 2^−m (2^a × 2^(m−a) cells) holds
  // exactly one of the first 2^m points: Owen scrambling keeps the net.
  const int m = 10;
  for (std::uint32_t key : {0u, 12345u, 0xdeadbeefu}) {
    for (int a = 0; a <= m; ++a) {
      std::set<std::uint64_t> cells;
      for (std::uint32_t i = 0; i < (1u << m); ++i) {
        const std::uint32_t x = sobol_scrambled_u32(i, 0, key), y = sobol_scrambled_u32(i, 1, key + 1);
        const std::uint64_t cx = a == 0 ? 0 : x >> (32 - a), cy = a == m ? 0 : y >> (32 - (m - a));
        cells.insert(cx << 32 | cy);
      }
      EXPECT_EQ(cells.size(), 1u << m) << "key " << key << ", 2^" << a << " × 2^" << (m - a);
    }
  }
}

TEST(Sobol, ScramblesOfDifferentKeysDifferAndAreUniform) {
  // The scramble is a bijection of 32-bit values for every key and moves
  // most of them; over many keys a fixed point is uniform (mean ½, var 1/12).
  EXPECT_NE(sobol_scrambled_u32(5, 3, 1), sobol_scrambled_u32(5, 3, 2));
  const int keys = 20000;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < keys; ++k) {
    const double u = unit(sobol_scrambled_u32(7, 2, static_cast<std::uint32_t>(mix64(static_cast<std::uint64_t>(k)))));
    sum += u;
    sum2 += u * u;
  }
  const double mean = sum / keys, var = sum2 / keys - mean * mean;
  EXPECT_NEAR(mean, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / keys));
  EXPECT_NEAR(var, 1.0 / 12.0, 0.005);
}

TEST(PhotonRandom, SobolDrawsDependOnSeedAndPhotonAloneThenPad) {
  PhotonRandom a(9, 1234, SamplerKind::Sobol), b(9, 1234, SamplerKind::Sobol);
  for (int k = 0; k < 2 * kSobolDimensions; ++k) EXPECT_EQ(a.uniform(), b.uniform());
  PhotonRandom c(9, 1234, SamplerKind::Sobol);
  EXPECT_TRUE(c.low_discrepancy());
  for (int k = 0; k < kSobolDimensions; ++k) c.uniform();
  EXPECT_FALSE(c.low_discrepancy());
  EXPECT_EQ(c.dimensions(), kSobolDimensions);
  EXPECT_EQ(c.draws(), 0u);  // the padding starts after the last dimension
  c.uniform();
  EXPECT_EQ(c.draws(), 1u);
  // Another seed scrambles differently; the random sampler is unchanged.
  PhotonRandom d(10, 1234, SamplerKind::Sobol), e(9, 1234, SamplerKind::Random), f(9, 1234);
  EXPECT_NE(PhotonRandom(9, 1234, SamplerKind::Sobol).uniform(), d.uniform());
  EXPECT_FALSE(e.low_discrepancy());
  for (int k = 0; k < 10; ++k) EXPECT_EQ(e.next_u64(), f.next_u64());
}

TEST(PhotonRandom, SobolPhotonsOfOneReplicateStratifyEachDimension) {
  // Photons r, r + K, …, r + (2^12 − 1)·K of one seed (replicate r: points
  // 0 … 2^12 − 1 of its scramble): each of the first dimensions takes one
  // value in each interval of 2^−12, whatever was drawn before it.
  const int m = 12;
  const auto k = static_cast<std::uint64_t>(kSobolReplicates);
  for (std::uint64_t r : {std::uint64_t{0}, k - 1}) {
    for (int d = 0; d < 6; ++d) {
      std::set<int> cells;
      for (std::uint64_t j = 0; j < (1u << m); ++j) {
        PhotonRandom p(3, r + k * j, SamplerKind::Sobol);
        for (int q = 0; q < d; ++q) p.uniform();
        cells.insert(static_cast<int>(p.uniform() * (1 << m)));
      }
      EXPECT_EQ(cells.size(), 1u << m) << "replicate " << r << ", dim " << d;
    }
  }
  // Photons of one point in different replicates are scrambled apart (they
  // are independent); points beyond 2³² start a block with keys of their own.
  PhotonRandom first(3, 0, SamplerKind::Sobol), second(3, 1, SamplerKind::Sobol);
  EXPECT_NE(first.uniform(), second.uniform());
  PhotonRandom low(3, 5, SamplerKind::Sobol), high(3, (k << 32) + 5, SamplerKind::Sobol);
  EXPECT_NE(low.uniform(), high.uniform());
  // One replicate (K = 1): photon i is point i.
  for (int d = 0; d < 3; ++d) {
    std::set<int> cells;
    for (std::uint64_t i = 0; i < (1u << m); ++i) {
      PhotonRandom p(3, i, SamplerKind::Sobol, 1);
      for (int q = 0; q < d; ++q) p.uniform();
      cells.insert(static_cast<int>(p.uniform() * (1 << m)));
    }
    EXPECT_EQ(cells.size(), 1u << m) << "K = 1, dim " << d;
  }
}

TEST(PhotonRandom, ReplicatesAreIndependentScramblesOfOnePointSet) {
  // Replicates share the Sobol' points but not the scramble: over many
  // seeds, two replicates' draws of one point are uncorrelated, as
  // independent uniforms are, and each stays uniform.
  const int seeds = 20000;
  double sab = 0.0, sa = 0.0, sb = 0.0;
  for (int s = 0; s < seeds; ++s) {
    const double a = PhotonRandom(static_cast<std::uint64_t>(s), 8 * 40, SamplerKind::Sobol, 8).uniform();
    const double b = PhotonRandom(static_cast<std::uint64_t>(s), 8 * 40 + 3, SamplerKind::Sobol, 8).uniform();
    sa += a;
    sb += b;
    sab += a * b;
  }
  const double cov = sab / seeds - (sa / seeds) * (sb / seeds);
  EXPECT_NEAR(cov / (1.0 / 12.0), 0.0, 5.0 / std::sqrt(seeds));
  EXPECT_NEAR(sa / seeds, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / seeds));
}

TEST(PhotonRandom, ACursorGivesThePhotonsOwnNumbers) {
  // The tracer's cursor (photons in order, one XOR per dimension each) gives
  // what (seed, i) gives alone: in order, after jumps, across the 2³² block
  // of points (photon K · 2³²).
  SobolCursor cursor(21, kSobolReplicates);
  const std::uint64_t block = static_cast<std::uint64_t>(kSobolReplicates) << 32;
  std::vector<std::uint64_t> photons;
  for (std::uint64_t i = 0; i < 300; ++i) photons.push_back(i);
  for (std::uint64_t i : {std::uint64_t{4096}, std::uint64_t{77}, std::uint64_t{78}, block - 2, block - 1, block,
                          block + 1, std::uint64_t{5}})
    photons.push_back(i);
  for (std::uint64_t i : photons) {
    PhotonRandom direct(21, i, SamplerKind::Sobol), cached(21, cursor.at(i));
    for (int k = 0; k < kSobolDimensions + 3; ++k) ASSERT_EQ(direct.uniform(), cached.uniform()) << i << ", " << k;
  }
  // Another replicate count, photons in order across points.
  SobolCursor three(21, 3);
  for (std::uint64_t i = 0; i < 100; ++i) {
    PhotonRandom direct(21, i, SamplerKind::Sobol, 3), cached(21, three.at(i));
    for (int k = 0; k < kSobolDimensions; ++k) ASSERT_EQ(direct.uniform(), cached.uniform()) << i << ", " << k;
  }
}

TEST(SobolWarps, SinCosOfATurnAndTheConcentricDiscMatchTheLibrary) {
  for (int k = 0; k < 100000; ++k) {
    const double u = (k + 0.37) / 100000.0;
    double s, c;
    sincos_turn(u, &s, &c);
    ASSERT_NEAR(s, std::sin(2.0 * std::numbers::pi * u), 2e-15) << u;
    ASSERT_NEAR(c, std::cos(2.0 * std::numbers::pi * u), 2e-15) << u;
  }
  // The concentric map: square rings to disc rings (r = max(|a|, |b|)),
  // the square's diagonal to the disc's diagonals.
  double x, y;
  concentric_disc(0.75, 0.5, &x, &y);  // a = 0.5, b = 0
  EXPECT_NEAR(x, 0.5, 1e-15);
  EXPECT_NEAR(y, 0.0, 1e-15);
  concentric_disc(1.0, 1.0, &x, &y);  // a = b = 1: φ = π/4
  EXPECT_NEAR(x, std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(y, std::sqrt(0.5), 1e-15);
  concentric_disc(0.25, 0.0, &x, &y);  // a = −0.5, b = −1: r = −1, φ = π/2 − π/8
  EXPECT_NEAR(std::hypot(x, y), 1.0, 1e-15);
  EXPECT_NEAR(std::atan2(y, x), -std::numbers::pi / 2.0 - std::numbers::pi / 8.0, 1e-14);
  concentric_disc(0.5, 0.5, &x, &y);
  EXPECT_EQ(x, 0.0);
  EXPECT_EQ(y, 0.0);
}

TEST(PhotonRandom, SobolUniformsHaveTheRightMomentsOverSeeds) {
  // A fixed photon over many seeds: every dimension uniform in [0, 1).
  const int seeds = 20000;
  std::vector<double> sum(8, 0.0), sum2(8, 0.0);
  for (int s = 0; s < seeds; ++s) {
    PhotonRandom r(static_cast<std::uint64_t>(s), 77, SamplerKind::Sobol);
    for (int d = 0; d < 8; ++d) {
      const double u = r.uniform();
      ASSERT_GE(u, 0.0);
      ASSERT_LT(u, 1.0);
      sum[d] += u;
      sum2[d] += u * u;
    }
  }
  for (int d = 0; d < 8; ++d) {
    EXPECT_NEAR(sum[d] / seeds, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / seeds)) << "dim " << d;
    EXPECT_NEAR(sum2[d] / seeds, 1.0 / 3.0, 0.01) << "dim " << d;
  }
}

}  // namespace
}  // namespace gonio::sim
