// gonio bench, run as a user would, on the downlight sample (the fastest)
// with small photon counts.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;

const std::string kModel = std::string(GONIO_SAMPLES_DIR) + "/downlight/downlight.gltf";

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

std::vector<std::string> small(const fs::path& out, std::vector<std::string> more = {}) {
  std::vector<std::string> a = {"bench",     kModel,  "--out",       out.string(), "--photons", "65536",
                                "--first",   "4096",  "--reference", "524288",     "--no-png",  "--threads",
                                "2"};
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

// column `name` of series.csv, for the rows of one series
std::vector<std::string> column(const std::string& csv, const std::string& series, const std::string& name) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  const auto at = std::find(header.begin(), header.end(), name) - header.begin();
  std::vector<std::string> out;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) cells.push_back(cell);
    if (line.back() == ',') cells.emplace_back();
    EXPECT_EQ(cells.size(), header.size()) << line;
    if (!cells.empty() && cells[0] == series) out.push_back(cells[static_cast<std::size_t>(at)]);
  }
  return out;
}

TEST(CmdBench, WritesSeriesChartsAndReusesItsReference) {
  test::TempDir dir;
  const test::ProcessResult first = gonio(small(dir.path(), {"--importance"}));
  ASSERT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.out.find("traced in"), std::string::npos) << first.out;
  for (const char* f : {"series.csv", "bench.json", "reference.exr", "reference.json", "candela-time.svg",
                        "cubemap-time.svg", "photons.svg", "psnr-snr.svg"})
    EXPECT_TRUE(fs::is_regular_file(dir / f)) << f;
  EXPECT_FALSE(fs::exists(dir / "photons.png"));  // --no-png

  const std::string csv = test::read_file(dir / "series.csv");
  // 4096 · 2^(k/2) up to 65536: 9 iterations; every series has all of them.
  const std::vector<std::string> photons = column(csv, "raw", "photons");
  ASSERT_EQ(photons.size(), 9u);
  EXPECT_EQ(photons.front(), "4096");
  EXPECT_EQ(photons.back(), "65536");
  for (const char* s : {"bilinear-50", "bilateral-300", "adaptive", "guided", "guided-adaptive", "sobol",
                        "sobol-adaptive"})
    EXPECT_EQ(column(csv, s, "photons").size(), 9u) << s;
  // Guided emission traces fewer photons than it draws.
  EXPECT_LT(std::stoull(column(csv, "guided", "photons_traced").back()), 65536u);
  // The run's own error estimate beside the measured error: raw series
  // only (pseudo-random count-based, Sobol' from its replicates), within
  // a factor 1.5 of the measured error at the last iteration
  // (docs/validation.md: 0.9–1.0 on the samples at 2²⁰ photons).
  for (const char* s : {"raw", "sobol"}) {
    const std::string estimated = column(csv, s, "estimated_rms_pct").back();
    ASSERT_FALSE(estimated.empty()) << s;
    const double ratio = std::stod(estimated) / std::stod(column(csv, s, "table_rms_pct").back());
    EXPECT_GT(ratio, 1.0 / 1.5) << s;
    EXPECT_LT(ratio, 1.5) << s;
  }
  EXPECT_TRUE(column(csv, "adaptive", "estimated_rms_pct").back().empty());

  const nlohmann::json j = nlohmann::json::parse(test::read_file(dir / "bench.json"));
  EXPECT_EQ(j["reference"]["reused"], false);
  EXPECT_EQ(j["reference"]["key"]["photons"], 524288);
  EXPECT_EQ(j["reference"]["key"]["seed"], 2);  // its own seed
  EXPECT_EQ(j["series"].size(), 16u);  // with the Sobol' raw and adaptive series (--sampler both)
  EXPECT_EQ(j["settings"]["sampler"], "random");
  EXPECT_EQ(j["settings"]["next_event"], "auto");  // as gonio simulate's default
  EXPECT_EQ(j["settings"]["next_event_connections"], 16);
  EXPECT_EQ(j["series"][14]["name"], "sobol");
  EXPECT_EQ(j["series"][14]["sampler"], "sobol");
  const double estimated = j["reference"]["noise"]["table_estimated_pct"];
  const double measured = j["reference"]["noise"]["table_measured_pct"];
  EXPECT_GT(estimated, 0.0);
  EXPECT_NEAR(measured / estimated, 1.0, 0.25);
  // The raw error falls like 1/√N.
  EXPECT_NEAR(j["series"][0]["cube_slope"].get<double>(), -0.5, 0.15);

  // Same settings: the reference is read back, and the errors are the same
  // (same seed, same trace, same reference).
  const test::ProcessResult again = gonio(small(dir.path(), {"--importance"}));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.out.find("reused"), std::string::npos) << again.out;
  const std::string csv2 = test::read_file(dir / "series.csv");
  EXPECT_EQ(column(csv2, "raw", "cube_rmse"), column(csv, "raw", "cube_rmse"));
  EXPECT_EQ(column(csv2, "adaptive", "table_rms_pct"), column(csv, "adaptive", "table_rms_pct"));
  EXPECT_EQ(column(csv2, "guided", "table_rms_pct"), column(csv, "guided", "table_rms_pct"));

  // Another reference seed: traced anew.
  const test::ProcessResult other = gonio(small(dir.path(), {"--reference-seed", "9"}));
  ASSERT_EQ(other.exit_code, 0) << other.err;
  EXPECT_EQ(other.out.find("reused"), std::string::npos) << other.out;
  EXPECT_EQ(nlohmann::json::parse(test::read_file(dir / "bench.json"))["series"].size(), 14u);  // + Sobol' 2

  // --sampler random: the pseudo-random series alone; sobol: the same
  // series, each traced with Sobol' points.
  ASSERT_EQ(gonio(small(dir.path(), {"--sampler", "random"})).exit_code, 0);
  EXPECT_EQ(nlohmann::json::parse(test::read_file(dir / "bench.json"))["series"].size(), 12u);
  ASSERT_EQ(gonio(small(dir.path(), {"--sampler", "sobol"})).exit_code, 0);
  const nlohmann::json sobol = nlohmann::json::parse(test::read_file(dir / "bench.json"));
  ASSERT_EQ(sobol["series"].size(), 12u);
  EXPECT_EQ(sobol["series"][0]["name"], "raw");
  EXPECT_EQ(sobol["series"][0]["sampler"], "sobol");
  EXPECT_EQ(sobol["settings"]["sampler"], "sobol");
  // Its raw series is the Sobol' series of the run with both.
  EXPECT_EQ(column(test::read_file(dir / "series.csv"), "raw", "cube_rmse"), column(csv, "sobol", "cube_rmse"));
}

TEST(CmdBench, WritesEveryChartAsAValidPng) {
  // The one run with PNG charts (gnuplot's pngcairo), on the smallest
  // settings: each chart is a PNG (its 8-byte signature, then the IHDR chunk
  // of a plot-sized image) beside its SVG.
  test::TempDir dir;
  const std::vector<std::string> args = {"bench",     kModel,   "--out",       dir.path().string(), "--photons",
                                         "16384",     "--first", "4096",       "--reference",       "131072",
                                         "--threads", "2"};
  const test::ProcessResult r = gonio(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* stem : {"candela-time", "cubemap-time", "photons", "psnr-snr"}) {
    const fs::path png = dir / (std::string(stem) + ".png");
    ASSERT_TRUE(fs::is_regular_file(png)) << png;
    EXPECT_TRUE(fs::is_regular_file(dir / (std::string(stem) + ".svg"))) << stem;
    const std::string bytes = test::read_file(png);
    EXPECT_GT(bytes.size(), 10'000u) << png;  // a chart, not an empty image
    ASSERT_GE(bytes.size(), 24u);
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << png;
    EXPECT_EQ(bytes.substr(12, 4), "IHDR") << png;
    const auto be32 = [&](std::size_t at) {
      return (static_cast<unsigned>(static_cast<unsigned char>(bytes[at])) << 24) |
             (static_cast<unsigned>(static_cast<unsigned char>(bytes[at + 1])) << 16) |
             (static_cast<unsigned>(static_cast<unsigned char>(bytes[at + 2])) << 8) |
             static_cast<unsigned>(static_cast<unsigned char>(bytes[at + 3]));
    };
    EXPECT_GE(be32(16), 400u) << png << ": width";
    EXPECT_GE(be32(20), 300u) << png << ": height";
    EXPECT_EQ(bytes.substr(bytes.size() - 8, 4), "IEND") << png;  // complete
  }
}

TEST(CmdBench, PageOverSeveralModels) {
  test::TempDir dir;
  const std::string bell = std::string(GONIO_SAMPLES_DIR) + "/bell/bell.gltf";
  std::vector<std::string> args = {"bench",    kModel,       bell,        "--out",  (dir / "results").string(),
                                   "--photons", "16384",      "--first",   "4096",   "--reference",
                                   "131072",   "--no-png",   "--page",    (dir / "results.md").string()};
  const test::ProcessResult r = gonio(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string page = test::read_file(dir / "results.md");
  for (const char* name : {"downlight", "bell"}) {
    EXPECT_NE(page.find(std::string("## ") + name), std::string::npos) << name;
    const std::string link = std::string("results/") + name + "/photons.svg";
    EXPECT_NE(page.find("](" + link + ")"), std::string::npos) << page;
    EXPECT_TRUE(fs::is_regular_file(dir / link)) << link;
  }
  EXPECT_NE(page.find("Time to 1 % RMS candela error"), std::string::npos);
  // The samplers side by side (--sampler both): their own columns, and the
  // best fixed-threshold filter is a pseudo-random series.
  EXPECT_NE(page.find("| Sobol', raw | Sobol', adaptive |"), std::string::npos) << page;
  EXPECT_EQ(page.find("(Sobol'"), std::string::npos) << page;
}

TEST(CmdBench, UsageAndModelErrors) {
  test::TempDir dir;
  EXPECT_EQ(gonio({"bench", kModel}).exit_code, 2);  // no --out
  const test::ProcessResult same = gonio(small(dir.path(), {"--reference-seed", "1"}));
  EXPECT_EQ(same.exit_code, 2);
  EXPECT_NE(same.err.find("seed of its own"), std::string::npos) << same.err;
  EXPECT_EQ(gonio(small(dir.path(), {"--first", "100000"})).exit_code, 2);
  EXPECT_EQ(gonio(small(dir.path(), {"--c-step", "7"})).exit_code, 2);
  EXPECT_EQ(gonio(small(dir.path(), {"--min-acceptance", "0.5"})).exit_code, 2);  // needs --importance
  const test::ProcessResult missing =
      gonio({"bench", (dir / "none.gltf").string(), "--out", (dir / "o").string()});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("none.gltf"), std::string::npos) << missing.err;
  EXPECT_EQ(gonio({"bench", "--help"}).exit_code, 0);
  // --next-event takes auto, on or off only, and the help names it.
  const test::ProcessResult maybe = gonio(small(dir.path(), {"--next-event", "maybe"}));
  EXPECT_EQ(maybe.exit_code, 2);
  EXPECT_NE(maybe.err.find("next-event"), std::string::npos) << maybe.err;
  EXPECT_NE(gonio({"bench", "--help"}).out.find("--next-event"), std::string::npos);
}

}  // namespace
}  // namespace gonio
