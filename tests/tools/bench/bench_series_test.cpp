// The series of `gonio bench` without a model file: the schedule and the
// series the brief asks for.
#include "tools/bench/bench_series.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace gonio::cli {
namespace {


TEST(BenchSchedule, GrowsBySqrtTwoAndEndsAtTheTotal) {
  const std::vector<std::uint64_t> s = photon_schedule(1000, 16000, 2);
  // 1000·2^(k/2): 1000, 1414, 2000, 2828, 4000, 5657, 8000, 11314, then 16000.
  const std::vector<std::uint64_t> expected = {1000, 1414, 2000, 2828, 4000, 5657, 8000, 11314, 16000};
  EXPECT_EQ(s, expected);
  EXPECT_EQ(photon_schedule(5, 5, 2), std::vector<std::uint64_t>{5});
  EXPECT_EQ(photon_schedule(10, 7, 1), std::vector<std::uint64_t>{7});
  // Small counts never repeat a value.
  const std::vector<std::uint64_t> tiny = photon_schedule(1, 10, 4);
  for (std::size_t i = 1; i < tiny.size(); ++i) EXPECT_GT(tiny[i], tiny[i - 1]);
  EXPECT_EQ(tiny.back(), 10u);
}

TEST(BenchSeries, TheBriefsSeries) {
  const std::vector<SeriesSpec> plain = default_series(false);
  std::set<std::string> names;
  for (const SeriesSpec& s : plain) names.insert(s.name);
  EXPECT_EQ(plain.size(), 12u);
  for (const char* n : {"raw", "bilinear-50", "bilinear-100", "bilinear-150", "bilinear-200", "bilinear-300",
                        "bilateral-50", "bilateral-100", "bilateral-150", "bilateral-200", "bilateral-300",
                        "adaptive"})
    EXPECT_TRUE(names.count(n)) << n;
  for (const SeriesSpec& s : plain) {
    EXPECT_FALSE(s.guided);
    if (s.name.rfind("bil", 0) == 0) {
      EXPECT_FALSE(s.filter.adaptive) << s.name;  // the thesis's mode
      EXPECT_EQ(s.filter.threshold_photons, std::stod(s.name.substr(s.name.find('-') + 1)));
    }
  }
  EXPECT_TRUE(default_series(false)[11].filter.adaptive);
  const std::vector<SeriesSpec> guided = default_series(true);
  ASSERT_EQ(guided.size(), 14u);
  EXPECT_TRUE(guided[12].guided && !guided[12].filtered);
  EXPECT_TRUE(guided[13].guided && guided[13].filtered && guided[13].filter.adaptive);
  for (const SeriesSpec& s : guided) EXPECT_EQ(s.sampler, sim::SamplerKind::Random);
  // Both samplers: Sobol' raw and adaptive after the pseudo-random series.
  const std::vector<SeriesSpec> both = default_series(false, sim::SamplerKind::Random, true);
  ASSERT_EQ(both.size(), 14u);
  EXPECT_EQ(both[12].name, "sobol");
  EXPECT_TRUE(both[12].sampler == sim::SamplerKind::Sobol && !both[12].filtered);
  EXPECT_EQ(both[13].name, "sobol-adaptive");
  EXPECT_TRUE(both[13].sampler == sim::SamplerKind::Sobol && both[13].filter.adaptive);
  // Sobol' alone: the same series, each traced with it.
  const std::vector<SeriesSpec> sobol = default_series(false, sim::SamplerKind::Sobol);
  ASSERT_EQ(sobol.size(), 12u);
  for (const SeriesSpec& s : sobol) EXPECT_EQ(s.sampler, sim::SamplerKind::Sobol) << s.name;
}

}  // namespace
}  // namespace gonio::cli
