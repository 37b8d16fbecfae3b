// The outputs of `gonio bench`: CSV and the results page.
#include "tools/bench/bench_report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace gonio::cli {
namespace {

SeriesResult fake(const std::string& name, std::vector<double> rms) {
  SeriesResult r;
  r.spec.name = r.spec.label = name;
  for (std::size_t i = 0; i < rms.size(); ++i) {
    SeriesPoint p;
    p.iteration = static_cast<int>(i) + 1;
    p.photons = p.photons_traced = 1000u << i;
    p.time_s = 0.1 * static_cast<double>(1u << i);
    p.trace_s = p.time_s;
    p.table.rms_pct = rms[i];
    p.cube.rmse = rms[i] / 10.0;
    r.points.push_back(p);
  }
  return r;
}

TEST(BenchReport, CsvLeavesNotANumberEmpty) {
  const std::string csv = series_csv({fake("raw", {2.0, std::nan("")})});
  std::istringstream in(csv);
  std::string header, first, second;
  std::getline(in, header);
  std::getline(in, first);
  std::getline(in, second);
  EXPECT_EQ(header.rfind("series,iteration,photons,photons_traced,", 0), 0u);
  EXPECT_NE(header.find(",estimated_rms_pct"), std::string::npos);
  const auto columns = [](const std::string& line) { return std::count(line.begin(), line.end(), ',') + 1; };
  EXPECT_EQ(columns(header), 16);  // the last: estimated_rms_pct
  EXPECT_EQ(columns(first), 16);  // the last: estimated_rms_pct
  EXPECT_EQ(columns(second), 16);  // the last: estimated_rms_pct
  EXPECT_NE(first.find(",2,"), std::string::npos);
  EXPECT_EQ(second.find("nan"), std::string::npos);
  EXPECT_NE(second.find(",,"), std::string::npos);
}

TEST(BenchReport, PageLinksChartsRelativeToItself) {
  BenchOutcome o;
  o.model = "samples/bell.gltf";
  o.name = "bell";
  o.directory = "out/results/bell";
  o.grid = "5° × 2.5°";
  o.smallest_raw_error_pct = 0.5;
  o.reference.key.photons = 1u << 20;
  o.series = {fake("raw", {4.0, 2.0, 1.0, 0.5}), fake("adaptive", {1.5, 0.8, 0.6, 0.45})};
  o.series[0].time_to_target_s = 0.4;
  o.series[0].photons_to_target = 4000;
  o.series[1].time_to_target_s = 0.15;
  o.series[1].photons_to_target = 1500;
  for (SeriesResult& r : o.series) r.time_to_cube_target_s = r.photons_to_cube_target = std::nan("");
  const std::string page = results_page({o}, "out/results.md", "Machine: test.", "gonio bench x");
  EXPECT_NE(page.find("](results/bell/candela-time.svg)"), std::string::npos) << page;
  // Each headline cell: the time and the photons traced to the target.
  EXPECT_NE(page.find("| bell | 0.4 s, 4 k |  | 0.15 s, 1.5 k |"), std::string::npos) << page;
  // Not reached in the run: the run's length, no photon count.
  EXPECT_NE(page.find("| bell | > 0.8 s |  | > 0.8 s |"), std::string::npos) << page;
  EXPECT_NE(page.find("Machine: test."), std::string::npos);
  EXPECT_NE(page.find("`gonio bench x`"), std::string::npos);
}

}  // namespace
}  // namespace gonio::cli
