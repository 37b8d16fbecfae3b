#include "sim/samplers/alias_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sim/samplers/random.h"

namespace gonio::sim {
namespace {

TEST(AliasTable, DrawsInProportionToWeights) {
  const std::vector<double> w = {0.0, 1.0, 3.0, 0.0, 0.5, 2.5, 0.0};
  const AliasTable t(w);
  EXPECT_DOUBLE_EQ(t.total_weight(), 7.0);
  EXPECT_DOUBLE_EQ(t.pmf(2), 3.0 / 7.0);
  const int n = 700000;
  std::vector<int> count(w.size(), 0);
  for (int i = 0; i < n; ++i) ++count[t.sample(PhotonRandom(5, static_cast<std::uint64_t>(i)).uniform())];
  double chi2 = 0.0;
  int bins = 0;
  for (std::size_t i = 0; i < w.size(); ++i) {
    if (w[i] == 0.0) {
      EXPECT_EQ(count[i], 0) << "index " << i << " has no weight";
      continue;
    }
    const double e = n * t.pmf(i);
    chi2 += (count[i] - e) * (count[i] - e) / e;
    ++bins;
  }
  // 3 degrees of freedom: P(χ² > 16.3) = 0.001.
  EXPECT_LT(chi2, 16.3);
  EXPECT_EQ(bins, 4);
}

TEST(AliasTable, EdgesOfTheUnitInterval) {
  const std::vector<double> w = {1.0, 0.0, 1.0};
  const AliasTable t(w);
  EXPECT_NE(t.sample(0.0), 1u);
  EXPECT_NE(t.sample(std::nextafter(1.0, 0.0)), 1u);
  EXPECT_NE(t.sample(0.5), 1u);
  const std::vector<double> one = {2.0};
  EXPECT_EQ(AliasTable(one).sample(0.999), 0u);
}

}  // namespace
}  // namespace gonio::sim
