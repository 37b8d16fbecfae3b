// gonio plot and gonio compare, run as a user would, on IES and LDT files
// written here from distributions with known properties.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "io/support/file_io.h"
#include "io/photometric/ies.h"
#include "io/photometric/ldt.h"
#include "photometry/flux.h"
#include "tests/support/photometry_fixtures.h"
#include "tests/support/test_support.h"

namespace gonio {
namespace {

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

// I = 1000 cos γ below the horizontal (Φ = π·1000 lm), times `scale`,
// optionally tilted towards C0 by adding a C-dependent term.
photometry::Distribution lobe(double scale, bool asymmetric) {
  photometry::Distribution d = test::sample_c(
      photometry::Symmetry::None, test::angles(0, 360, 15), test::angles(0, 180, 5), [&](double c, double g) {
        const double gr = g * M_PI / 180.0, cr = c * M_PI / 180.0;
        if (g > 90.0) return 0.0;
        const double tilt = asymmetric ? 1.0 + 0.5 * std::sin(gr) * std::cos(cr) : 1.0;
        return scale * 1000.0 * std::cos(gr) * tilt;
      });
  d.lamps = {photometry::LampSet{1, "LED", 4000.0, "", "", photometry::kNaN}};
  return d;
}

void write_ies_file(const std::filesystem::path& path, const photometry::Distribution& d) {
  ASSERT_TRUE(io::write_file_atomic(path.string(), io::write_ies(d, {}, nullptr)).ok());
}

TEST(Plot, DrawsIesAndLdtAsSvgOrPng) {
  test::TempDir dir;
  write_ies_file(dir / "lobe.ies", lobe(1.0, true));
  auto ldt = io::write_ldt(lobe(1.0, true), {}, nullptr);
  ASSERT_TRUE(ldt.ok());
  test::write_file(dir / "lobe.ldt", *ldt);

  auto r = gonio({"plot", (dir / "lobe.ies").string()});  // default: lobe.svg beside it
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string svg = test::read_file(dir / "lobe.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("C0–C180"), std::string::npos);
  EXPECT_NE(svg.find("[cd]"), std::string::npos);

  r = gonio({"plot", (dir / "lobe.ldt").string(), "--out", (dir / "rel.png").string(), "--unit", "cdklm"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(test::read_file(dir / "rel.png").substr(1, 3), "PNG");
  r = gonio({"plot", (dir / "lobe.ldt").string(), "--out", (dir / "rel.svg").string(), "--unit", "cdklm"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(test::read_file(dir / "rel.svg").find("cd/klm"), std::string::npos);
}

TEST(Plot, BadFilesAndOptions) {
  test::TempDir dir;
  test::write_file(dir / "broken.ies", "IES:LM-63-2019\r\n[TEST] x\r\nTILT=NONE\r\n1 1000 1 3 1\r\n");
  auto r = gonio({"plot", (dir / "broken.ies").string(), "--out", (dir / "x.svg").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("broken.ies:"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.svg"));

  r = gonio({"plot", (dir / "missing.ldt").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("missing.ldt"), std::string::npos);
  test::write_file(dir / "notes.txt", "hello");
  r = gonio({"plot", (dir / "notes.txt").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("no photometric format Gonio knows"), std::string::npos) << r.err;

  write_ies_file(dir / "lobe.ies", lobe(1.0, false));
  EXPECT_EQ(gonio({"plot", (dir / "lobe.ies").string(), "--out", (dir / "x.jpg").string()}).exit_code, 2);
  EXPECT_EQ(gonio({"plot", (dir / "lobe.ies").string(), "--unit", "lux"}).exit_code, 2);
  EXPECT_EQ(gonio({"plot"}).exit_code, 2);
}

TEST(Compare, IdenticalFilesAgreeAndAScaledCopyDiffersByItsScale) {
  test::TempDir dir;
  write_ies_file(dir / "a.ies", lobe(1.0, true));
  write_ies_file(dir / "b.ies", lobe(1.1, true));
  auto ldt = io::write_ldt(lobe(1.0, true), {}, nullptr);
  ASSERT_TRUE(ldt.ok());
  test::write_file(dir / "a.ldt", *ldt);

  // The same distribution through IES and LDT.
  auto r = gonio({"compare", (dir / "a.ies").string(), (dir / "a.ldt").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(r.out);
  EXPECT_LT(j["rms_relative"].get<double>(), 1e-9);
  EXPECT_LT(j["max_relative"].get<double>(), 1e-9);
  EXPECT_NEAR(j["flux_ratio"].get<double>(), 1.0, 1e-9);
  EXPECT_EQ(j["a"]["format"], "IES LM-63-2019");
  EXPECT_EQ(j["b"]["format"], "EULUMDAT");

  // B = 1.1 A: the largest difference is exactly 10 % of the peak, the
  // flux ratio 1.1, the beam the same; normalised, nothing is left.
  r = gonio({"compare", (dir / "a.ies").string(), (dir / "b.ies").string(), "--json", "--plot",
             (dir / "overlay.svg").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["max_relative"].get<double>(), 0.1, 1e-9);
  EXPECT_NEAR(j["flux_ratio"].get<double>(), 1.1, 1e-9);
  EXPECT_NEAR(j["flux_difference_lm"].get<double>(), 0.1 * j["a"]["flux_lm"].get<double>(), 1e-6);
  EXPECT_NEAR(j["beam_difference_deg"]["c0_c180"].get<double>(), 0.0, 1e-9);
  EXPECT_GT(j["beam_angle_deg"]["a"]["c0_c180"].get<double>(), 60.0);
  const std::string svg = test::read_file(dir / "overlay.svg");
  EXPECT_NE(svg.find("A a.ies C0–C180"), std::string::npos);
  EXPECT_NE(svg.find("B b.ies C90–C270"), std::string::npos);

  r = gonio({"compare", (dir / "a.ies").string(), (dir / "b.ies").string(), "--json", "--normalize"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["scale_b"].get<double>(), 1.0 / 1.1, 1e-9);
  EXPECT_LT(j["max_relative"].get<double>(), 1e-9);

  // The text form says the same for people.
  r = gonio({"compare", (dir / "a.ies").string(), (dir / "b.ies").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("largest difference: 10.000 %"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("B/A = 1.10000"), std::string::npos) << r.out;
}

TEST(Compare, ShapesThatDifferAreSeenOnACommonGrid) {
  test::TempDir dir;
  write_ies_file(dir / "sym.ies", lobe(1.0, false));
  write_ies_file(dir / "tilt.ies", lobe(1.0, true));
  auto r = gonio({"compare", (dir / "sym.ies").string(), (dir / "tilt.ies").string(), "--json", "--c-step", "15",
                  "--gamma-step", "5"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  // The tilt adds 0.5 sin γ cos C × 1000 cos γ: at most 250 cd at γ 45°, C 0,
  // relative to A's peak of 1000 cd.
  EXPECT_NEAR(j["max_relative"].get<double>(), 0.25, 1e-9);
  EXPECT_NEAR(j["max_at"]["c_deg"].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(j["max_at"]["gamma_deg"].get<double>(), 45.0, 1e-9);
  EXPECT_EQ(j["grid"]["c_step_deg"], 15.0);
}

TEST(Compare, BadFilesAndOptions) {
  test::TempDir dir;
  write_ies_file(dir / "a.ies", lobe(1.0, false));
  auto r = gonio({"compare", (dir / "a.ies").string(), (dir / "missing.ies").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("missing.ies"), std::string::npos);
  test::write_file(dir / "bad.ldt", "company\r\nnot a number\r\n");
  r = gonio({"compare", (dir / "bad.ldt").string(), (dir / "a.ies").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("bad.ldt:"), std::string::npos) << r.err;
  EXPECT_EQ(gonio({"compare", (dir / "a.ies").string()}).exit_code, 2);
  r = gonio({"compare", (dir / "a.ies").string(), (dir / "a.ies").string(), "--c-step", "7"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--c-step"), std::string::npos);
  EXPECT_EQ(gonio({"compare", (dir / "a.ies").string(), (dir / "a.ies").string(), "--plot", "x.gif"}).exit_code, 2);
}

}  // namespace
}  // namespace gonio
