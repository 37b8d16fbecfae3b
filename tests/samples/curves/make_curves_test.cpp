// samples/curves/make_curves.cpp: the committed sample curves are what the
// generator writes, and they are what their README says.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "io/photometric/photometric_file.h"
#include "photometry/summary.h"
#include "tests/tools/cli/cli_fixtures.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;

const char* const kCurves[] = {"downlight.ies", "downlight.ldt", "wall_washer.ies",
                               "wall_washer.ldt"};

fs::path committed(const std::string& name) {
  return test::source_dir() / "samples" / "curves" / name;
}

photometry::Distribution read(const fs::path& p) {
  auto r = io::read_photometric_file(p.string());
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : to_string(r.error()));
  return r.ok() ? r->distribution : photometry::Distribution{};
}

TEST(SampleCurves, GeneratorWritesTheCommittedBytes) {
  test::TempDir dir;
  const auto r = test::run_process({GONIO_MAKE_CURVES, dir.path().string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : kCurves) {
    SCOPED_TRACE(name);
    EXPECT_EQ(test::read_file(dir / name), test::read_file(committed(name)))
        << "regenerate with: ./build/samples/curves/gonio_make_curves samples/curves";
  }
  EXPECT_EQ(test::gonio({"--version"}).exit_code, 0);
  EXPECT_EQ(test::run_process({GONIO_MAKE_CURVES}).exit_code, 2);  // usage
}

TEST(SampleCurves, AreCleanAndBothFormatsHoldTheSameLuminaire) {
  std::vector<std::string> args = {"check"};
  for (const char* name : kCurves) args.push_back(committed(name).string());
  const auto check = test::gonio(args);
  EXPECT_EQ(check.exit_code, 0) << check.out;

  for (const char* stem : {"downlight", "wall_washer"}) {
    SCOPED_TRACE(stem);
    const auto ies = read(committed(std::string(stem) + ".ies"));
    const auto ldt = read(committed(std::string(stem) + ".ldt"));
    ASSERT_EQ(ies.candela.size(), ldt.candela.size());
    for (std::size_t i = 0; i < ies.candela.size(); ++i)
      ASSERT_NEAR(ldt.candela[i], ies.candela[i], 1e-11 * ies.candela[i]) << i;
    EXPECT_EQ(ies.lamps[0].flux_lm, ldt.lamps[0].flux_lm);
  }
  // The downlight's flux is 2π (1700/5 + 110/2) lm but for the cut-off ramp
  // at 85-90° and the rounding to 0.1 cd.
  const double expected = 2.0 * std::numbers::pi * (1700.0 / 5.0 + 110.0 / 2.0);
  const auto s = photometry::summarize(read(committed("downlight.ies")));
  EXPECT_NEAR(s.flux_lm, expected, 1e-3 * expected);
  EXPECT_EQ(s.max_intensity_cd, 1810.0);
  // The wall-washer throws towards C0: its peak is there, below the horizon.
  const auto w = photometry::summarize(read(committed("wall_washer.ldt")));
  EXPECT_EQ(w.max_c_deg, 0.0);
  EXPECT_EQ(w.max_gamma_deg, 60.0);
  EXPECT_NEAR(w.dff, 1.0, 1e-12);
  EXPECT_LT(photometry::interpolate(photometry::expand_symmetry(read(committed("wall_washer.ldt"))),
                                    180.0, 60.0),
            0.3 * w.max_intensity_cd);
}

}  // namespace
}  // namespace gonio
