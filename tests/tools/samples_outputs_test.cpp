// Every sample luminaire through `gonio simulate` at the default grid: the
// files it writes, read back and integrated, carry the escaped flux within
// the 0.5 % the energy check demands — or the run says it cannot.
// Slow (about 10 s): ctest label `validation`.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

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

TEST(SampleOutputs, BellIsRotationalAndItsFilesCarryTheEscapedFlux) {
  test::TempDir dir;
  const SampleRun s = run_sample(dir, "bell");
  expect_files_carry_the_escaped_flux(s, "bell");
  EXPECT_EQ(s.report["outputs"]["symmetry"]["chosen"], "rotational");
  EXPECT_NE(s.err.find("symmetry auto: rotational"), std::string::npos) << s.err;
}

TEST(SampleOutputs, SpotlightAndLedArrayFilesCarryTheEscapedFlux) {
  test::TempDir dir;
  for (const char* name : {"spotlight", "led-array"}) expect_files_carry_the_escaped_flux(run_sample(dir, name), name);
}

// The downlight's ideal paraboloid collimates most of its light into less
// than 0.5° around the nadir: a 2.5° grid cannot carry that beam, and the IES
// and LDT files integrate to about 5 % less than escaped. The energy check
// must say so (and the exact cube map still carries the flux).
TEST(SampleOutputs, DownlightBeamNarrowerThanTheGridFailsTheFluxCheckLoudly) {
  test::TempDir dir;
  const SampleRun s = run_sample(dir, "downlight");
  EXPECT_EQ(s.exit_code, 1);
  EXPECT_NE(s.err.find("downlight.ies: flux"), std::string::npos) << s.err;
  EXPECT_NE(s.err.find("finer"), std::string::npos) << s.err;
  const double escaped = s.report["escaped_lm"].get<double>();
  for (const auto& f : s.report["outputs"]["files"]) {
    if (f["format"] == "exr" || f["format"] == "latlong") {
      EXPECT_NEAR(f["flux_lm"].get<double>(), escaped, 1e-5 * escaped);
    }
    if (f["format"] == "ies") {
      EXPECT_LT(f["flux_difference"].get<double>(), -0.005);
    }
  }
  EXPECT_FALSE(s.report["energy"]["passed"].get<bool>());
}

}  // namespace
}  // namespace gonio
