#include "sim/samplers/random.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace gonio::sim {
namespace {

TEST(PhotonRandom, DependsOnSeedAndPhotonAlone) {
  PhotonRandom a(42, 7), b(42, 7);
  for (int k = 0; k < 100; ++k) EXPECT_EQ(a.next_u64(), b.next_u64());
  // Draw k of photon i does not depend on what other photons drew before.
  PhotonRandom c(42, 8);
  for (int k = 0; k < 1000; ++k) c.next_u64();
  PhotonRandom d(42, 7), e(42, 8);
  std::set<std::uint64_t> seen;
  for (int k = 0; k < 100; ++k) {
    seen.insert(d.next_u64());
    seen.insert(e.next_u64());
  }
  EXPECT_EQ(seen.size(), 200u);  // no collisions between neighbouring photons
  EXPECT_NE(PhotonRandom(1, 0).next_u64(), PhotonRandom(2, 0).next_u64());
}

TEST(PhotonRandom, UniformsAreInRangeWithTheRightMoments) {
  const int n = 200000;
  double sum = 0.0, sum2 = 0.0;
  double lo = 1.0, hi = 0.0;
  for (int i = 0; i < n; ++i) {
    PhotonRandom r(3, static_cast<std::uint64_t>(i));
    const double u = r.uniform();
    const double v = r.uniform_open0();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    ASSERT_GT(v, 0.0);
    ASSERT_LE(v, 1.0);
    sum += u;
    sum2 += u * u;
    lo = std::min(lo, u);
    hi = std::max(hi, u);
  }
  // Mean 1/2 ± 5σ (σ = 1/√(12n)), second moment 1/3.
  EXPECT_NEAR(sum / n, 0.5, 5.0 / std::sqrt(12.0 * n));
  EXPECT_NEAR(sum2 / n, 1.0 / 3.0, 5.0 * 0.2981 / std::sqrt(n));
  EXPECT_LT(lo, 1e-4);
  EXPECT_GT(hi, 1.0 - 1e-4);
}

}  // namespace
}  // namespace gonio::sim
