// Every sample luminaire through `gonio simulate` at the default grid: the
// files it writes, read back and integrated, carry the escaped flux within
// the 0.5 % the energy check demands — or the run says it cannot.
// Slow (about 10 s): ctest label `validation`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace gonio {
namespace {

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

struct SampleRun {
  int exit_code;
  std::string err;
  nlohmann::json report;
};

SampleRun run_sample(const test::TempDir& dir, const std::string& name) {
  const std::string model = std::string(GONIO_SAMPLES_DIR) + "/" + name + "/" + name + ".gltf";
  const auto out = dir / name;
  auto r = gonio({"simulate", model, "--out", out.string(), "--photons", "1000000", "--iterations", "1"});
  SampleRun s{r.exit_code, r.err, {}};
  if (std::filesystem::exists(out / "report.json"))
    s.report = nlohmann::json::parse(test::read_file(out / "report.json"));
  return s;
}

void expect_files_carry_the_escaped_flux(const SampleRun& s, const std::string& name) {
  ASSERT_EQ(s.exit_code, 0) << name << ": " << s.err;
  const double escaped = s.report["escaped_lm"].get<double>();
  ASSERT_EQ(s.report["outputs"]["files"].size(), 5u);
  for (const auto& f : s.report["outputs"]["files"]) {
    EXPECT_TRUE(f["clean"].get<bool>()) << f.dump();
    if (f["format"] == "plot") continue;
    EXPECT_LT(std::abs(f["flux_lm"].get<double>() / escaped - 1.0), 0.005) << name << ": " << f.dump();
  }
  EXPECT_TRUE(s.report["energy"]["passed"].get<bool>());
  EXPECT_TRUE(s.report["energy"]["photons_close"].get<bool>());
  // The losses are complete: per mesh and per material they add up to the
  // absorbed and cut-off photons, exactly.
  for (const char* part : {"meshes", "materials"}) {
    std::uint64_t absorbed = 0, cutoff = 0;
    for (const auto& m : s.report[part]) {
      absorbed += m["photons_absorbed"].get<std::uint64_t>();
      cutoff += m["photons_cutoff"].get<std::uint64_t>();
      EXPECT_FALSE(m["name"].get<std::string>().empty());
    }
    EXPECT_EQ(absorbed, s.report["photons_absorbed"].get<std::uint64_t>()) << name << " " << part;
    EXPECT_EQ(cutoff, s.report["photons_cutoff"].get<std::uint64_t>()) << name << " " << part;
  }
}

// The luminous opening the LDT carries (tools/run/simulation_outputs.h,
// simulated_opening) against the sample's drawn aperture, and the UGR table
// `gonio info` gives through it.
void expect_opening(const test::TempDir& dir, const std::string& name, const std::string& shape, double length_m,
                    double width_m, double tolerance_m) {
  auto r = gonio({"info", (dir / name / (name + ".ldt")).string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["luminous_opening"]["shape"], shape) << name;
  EXPECT_NEAR(j["luminous_opening"]["length_m"].get<double>(), length_m, tolerance_m) << name;
  EXPECT_NEAR(j["luminous_opening"]["width_m"].get<double>(), width_m, tolerance_m) << name;
  EXPECT_FALSE(j["ugr_table"].is_null()) << name << ": " << j.value("ugr_table_why", "");
}

TEST(SampleOutputs, BellIsRotationalAndItsFilesCarryTheEscapedFlux) {
  test::TempDir dir;
  const SampleRun s = run_sample(dir, "bell");
  expect_files_carry_the_escaped_flux(s, "bell");
  expect_opening(dir, "bell", "circular", 0.400, 0.400, 0.002);  // the shade's rim, Ø 400 mm
  EXPECT_EQ(s.report["outputs"]["symmetry"]["chosen"], "rotational");
  EXPECT_NE(s.err.find("symmetry auto: rotational"), std::string::npos) << s.err;
}

// The bell's glossy lobes (white plastic, black cable) take their energy
// tables from the cache folder once a run has stored them
// (tools/run/glossy_energy_cache.h): the same IES bytes with a cold cache, a
// warm one, none, and one whose tables were damaged (rebuilt and rewritten,
// not trusted).
TEST(SampleOutputs, BellIsTheSameBytesWithAColdOrWarmGlossyEnergyCache) {
  namespace fs = std::filesystem;
  test::TempDir dir;
  const std::string model = std::string(GONIO_SAMPLES_DIR) + "/bell/bell.gltf";
  const fs::path cache = dir / "cache";
  const auto run = [&](const std::string& out, const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"simulate", model, "--out", (dir / out).string(), "--photons", "20000",
                                     "--iterations", "1", "--face-size", "16"};
    args.insert(args.end(), extra.begin(), extra.end());
    auto r = gonio(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return test::read_file(dir / out / "bell.ies");
  };
  const auto tables = [&] {
    std::vector<fs::path> found;
    for (const auto& e : fs::directory_iterator(cache))
      if (e.path().filename().string().rfind("glossy-energy-", 0) == 0) found.push_back(e.path());
    std::sort(found.begin(), found.end());
    return found;
  };
  const std::string cold = run("cold", {"--cache", cache.string()});
  const std::vector<fs::path> stored = tables();
  ASSERT_EQ(stored.size(), 2u);  // two roughnesses
  std::vector<std::string> good;
  for (const fs::path& p : stored) good.push_back(test::read_file(p));
  EXPECT_EQ(run("warm", {"--cache", cache.string()}), cold);
  EXPECT_EQ(run("none", {"--no-cache"}), cold);
  // A node's bit flipped in each table: rebuilt, the same bytes again.
  for (const fs::path& p : stored) {
    std::string bad = test::read_file(p);
    bad[16 + 8 + 16 + 8 * 20] ^= 0x01;
    test::write_file(p, bad);
  }
  EXPECT_EQ(run("damaged", {"--cache", cache.string()}), cold);
  ASSERT_EQ(tables(), stored);
  for (std::size_t i = 0; i < stored.size(); ++i) EXPECT_EQ(test::read_file(stored[i]), good[i]) << stored[i];
}

TEST(SampleOutputs, DownlightSpotlightAndLedArrayFilesCarryTheEscapedFlux) {
  test::TempDir dir;
  for (const char* name : {"downlight", "spotlight", "led-array"})
    expect_files_carry_the_escaped_flux(run_sample(dir, name), name);
  expect_opening(dir, "downlight", "circular", 0.160, 0.160, 0.002);     // reflector rim Ø 160 mm
  expect_opening(dir, "led-array", "rectangular", 0.300, 0.300, 0.001);  // diffuser 300 × 300 mm
  // Lens Ø 40 mm in a tube Ø 43 mm: light leaves the lens and the tube's edge.
  expect_opening(dir, "spotlight", "circular", 0.0415, 0.0415, 0.0016);
}

// A beam far narrower than the output grid (a spot light of 0.2° half-angle,
// written by the test) cannot be carried by a 2.5° table: the IES and LDT
// files integrate to less than escaped. The energy check must say so, and the
// exact cube map still carries the flux.
TEST(SampleOutputs, BeamNarrowerThanTheGridFailsTheFluxCheckLoudly) {
  test::TempDir dir;
  const auto model = dir / "laser.gltf";
  // KHR spot lights shine along the node's -Z; -90° about X aims it down.
  const double h = std::sqrt(0.5);
  nlohmann::json g = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", {"KHR_lights_punctual"}},
      {"extensions",
       {{"KHR_lights_punctual",
         {{"lights", {{{"type", "spot"}, {"intensity", 1.0e6}, {"spot", {{"innerConeAngle", 0.001}, {"outerConeAngle", 0.0035}}}}}}}}}},
      {"nodes", {{{"name", "laser"}, {"rotation", {-h, 0.0, 0.0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0}};
  test::write_file(model, g.dump());
  const auto out = dir / "laser";
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "200000", "--iterations", "1"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("laser.ies: flux"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("finer"), std::string::npos) << r.err;
  const auto report = nlohmann::json::parse(test::read_file(out / "report.json"));
  const double escaped = report["escaped_lm"].get<double>();
  for (const auto& f : report["outputs"]["files"]) {
    if (f["format"] == "exr" || f["format"] == "latlong") {
      EXPECT_NEAR(f["flux_lm"].get<double>(), escaped, 1e-5 * escaped);
    }
    if (f["format"] == "ies") {
      EXPECT_GT(std::abs(f["flux_difference"].get<double>()), 0.005);
    }
  }
  EXPECT_FALSE(report["energy"]["passed"].get<bool>());
}

}  // namespace
}  // namespace gonio
