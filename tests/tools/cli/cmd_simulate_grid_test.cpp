// gonio simulate on fine and non-uniform grids (issue 44): --gamma-angles,
// --c-angles, --grid-like, γ steps down to 0.1°, and gonio compare saying
// when it interpolates between grids. The narrow-beam model is a mirror
// paraboloid with a point source at its focus, written here as glTF.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/photometric/photometric_file.h"
#include "photometry/beam.h"
#include "photometry/flux.h"
#include "photometry/format.h"
#include "samples/gltf_writer.h"
#include "sim/shapes.h"
#include "tests/support/test_support.h"
#include "tools/run/grid_options.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

// A polished mirror paraboloid (f = 20 mm, aperture radius 80 mm, opening
// downwards) with a 1000 lm point light at its focus. Flat facets (no
// shading normals), 24 rings by 96 segments: each facet tilts the reflected
// rays by up to about half its angular size, which spreads the reflected
// light into a beam a few degrees wide around the nadir; the light the
// mirror misses (the cone of 53° around the nadir) leaves directly.
fs::path write_paraboloid(const fs::path& dir) {
  sim::Mesh mirror = sim::paraboloid(0.02, 0.08, 0.0, 24, 96);
  mirror.normals.clear();
  samples::GltfWriter w;
  const int material = w.material({{"name", "mirror"}, {"pbrMetallicRoughness", samples::pbr(1.0, 1.0, 0.0)}});
  w.node({{"name", "reflector"}, {"mesh", w.mesh(mirror, material, "reflector")}});
  const int light = w.khr_light({{"type", "point"}, {"intensity", 1000.0 / (4.0 * 3.141592653589793)}});
  w.node({{"name", "lamp"}, {"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}});
  std::string bin;
  const std::string text = w.finish("paraboloid.bin", bin);
  test::write_file(dir / "paraboloid.bin", bin);
  test::write_file(dir / "paraboloid.gltf", text);
  return dir / "paraboloid.gltf";
}

// 0 … 5° every 0.1°, then every 1° to 180°: what a luminaire maker writes for
// a narrow spot.
std::vector<double> fine_then_coarse() {
  std::vector<double> g;
  for (int k = 0; k <= 50; ++k) g.push_back(k / 10.0);
  for (int k = 6; k <= 180; ++k) g.push_back(k);
  return g;
}

void expect_angles(const std::vector<double>& got, const std::vector<double>& want, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t k = 0; k < want.size(); ++k) EXPECT_NEAR(got[k], want[k], 1e-9) << what << " angle " << k;
}

nlohmann::json file_entry(const nlohmann::json& report, const std::string& format) {
  for (const auto& f : report["outputs"]["files"])
    if (f["format"] == format) return f;
  return {};
}

TEST(SimulateGrids, AngleListsParse) {
  const auto list = app::parse_angle_list("0:0.1:5,6:1:90, 92.5:2.5:180", "--gamma-angles");
  ASSERT_TRUE(list.ok()) << list.error().message;
  EXPECT_EQ(list.value().size(), 51u + 85u + 36u);
  EXPECT_EQ(list.value()[3], 0.3);  // from the range's ends, not summed
  EXPECT_EQ(list.value()[50], 5.0);
  EXPECT_EQ(list.value().back(), 180.0);
  // A range may start where the previous item ended.
  const auto joined = app::parse_angle_list("0:0.5:5,5:5:180", "--gamma-angles");
  ASSERT_TRUE(joined.ok());
  EXPECT_EQ(joined.value().size(), 11u + 35u);
  for (const auto& [text, says] : std::vector<std::pair<std::string, std::string>>{
           {"0,5,3,180", "ascending"}, {"0:1:5,4:1:180", "ascending"}, {"0:0.3:1", "whole number"},
           {"0:0:5", "positive"}, {"5:1:0", "ends below"}, {"0,x,180", "not a number"}, {"0,,180", "empty"},
           {"", "empty"}, {"0:1", "FROM:STEP:TO"}, {"0:1:2:3", "FROM:STEP:TO"}, {"0:1e-9:1", "more than"}}) {
    const auto r = app::parse_angle_list(text, "--gamma-angles");
    ASSERT_FALSE(r.ok()) << text;
    EXPECT_EQ(r.error().message.rfind("--gamma-angles: ", 0), 0u) << r.error().message;
    EXPECT_NE(r.error().message.find(says), std::string::npos) << text << ": " << r.error().message;
  }
  // C lists: the symmetry's range alone is mirrored to the full circle.
  EXPECT_EQ(app::full_circle_c_angles({0, 30, 90}, photometry::Symmetry::Quadrant),
            (std::vector<double>{0, 30, 90, 150, 180, 210, 270, 330}));
  EXPECT_EQ(app::full_circle_c_angles({0, 45, 180, 360}, photometry::Symmetry::None),
            (std::vector<double>{0, 45, 180}));
}

// The case: a beam a few degrees wide is written within 0.5 % of the
// escaped flux on a grid fine near the axis (IES, LDT and TM-33 alike, each
// read back on the listed angles), where the default 2.5° step fails the
// flux check. --face-size 256 keeps the test light: the files' flux depends
// on the γ grid, not on the cube map (the bins keep every texel's flux).
TEST(SimulateGrids, NarrowBeamKeepsItsFluxOnAFineGammaList) {
  test::TempDir dir;
  const fs::path model = write_paraboloid(dir.path());
  const fs::path fine = dir / "fine";
  auto r = gonio({"simulate", model.string(), "--out", fine.string(), "--photons", "200000", "--iterations", "2",
                  "--face-size", "256", "--format", "ies,ldt,tm33", "--gamma-angles", "0:0.1:5,6:1:180"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto report = nlohmann::json::parse(test::read_file(fine / "report.json"));
  const double escaped = report["escaped_lm"].get<double>();
  EXPECT_GT(escaped, 900.0);
  for (const char* format : {"ies", "ldt", "tm33"}) {
    const nlohmann::json f = file_entry(report, format);
    ASSERT_FALSE(f.is_null()) << format;
    EXPECT_LT(std::abs(f["flux_difference"].get<double>()), 0.005) << format << ": " << f.dump();
    std::printf("fine grid: %s carries %.6g of %.6g lm (%+.3f %%)\n", format, f["flux_lm"].get<double>(), escaped,
                100.0 * f["flux_difference"].get<double>());
  }
  expect_angles(report["outputs"]["grid"]["gamma_angles_deg"].get<std::vector<double>>(), fine_then_coarse(),
                "report.json");
  for (const char* name : {"paraboloid.ies", "paraboloid.ldt", "paraboloid.xml"}) {
    auto file = io::read_photometric_file((fine / name).string());
    ASSERT_TRUE(file.ok()) << file.error().message;
    expect_angles(file.value().distribution.vertical_deg, fine_then_coarse(), name);
    EXPECT_NEAR(photometry::total_flux_lm(file.value().distribution), escaped, 0.005 * escaped) << name;
    if (std::string(name) == "paraboloid.ies") {
      const double beam = photometry::beam_angle(file.value().distribution, 0.0).angle_deg;
      std::printf("beam angle (50 %%) in C0-C180: %.3f deg\n", beam);
      EXPECT_GT(beam, 1.0);
      EXPECT_LT(beam, 5.0);
    }
  }
  // EULUMDAT: Dg = 0 in the header, as the standard has it for unequal spacing.
  EXPECT_NE(test::read_file(fine / "paraboloid.ldt").find("\r\n0\r\n"), std::string::npos);

  // The default 2.5° step: the same light, and the flux check fails.
  const fs::path coarse = dir / "coarse";
  r = gonio({"simulate", model.string(), "--out", coarse.string(), "--photons", "200000", "--iterations", "2",
             "--face-size", "256", "--format", "ies"});
  EXPECT_NE(r.exit_code, 0) << r.out;
  const auto coarse_report = nlohmann::json::parse(test::read_file(coarse / "report.json"));
  const double coarse_difference = file_entry(coarse_report, "ies")["flux_difference"].get<double>();
  std::printf("2.5 deg step: the IES carries %+.3f %% of the escaped flux\n", 100.0 * coarse_difference);
  EXPECT_GT(std::abs(coarse_difference), 0.005);
}

// A measured file's angles: a non-uniform IES (C every 30°, γ finer near the
// nadir) and the 0…90° downlight sample, whose γ is extended to 180° (said on
// stderr). gonio compare then finds the angles shared, where a run on the
// default grid is interpolated (a line, and grids_differ in --json).
TEST(SimulateGrids, GridLikeTakesAMeasuredFilesAngles) {
  test::TempDir dir;
  const std::vector<double> gamma = {0,  1,  2,  3,  4,  5,   7.5, 10,  15,  20, 30,
                                     45, 60, 75, 90, 105, 120, 135, 150, 165, 180};
  std::vector<double> c;
  for (int k = 0; k <= 12; ++k) c.push_back(30.0 * k);
  std::string ies = "IES:LM-63-2002\r\n[TEST] grid\r\nTILT=NONE\r\n1 -1 1 " + std::to_string(gamma.size()) + " " +
                    std::to_string(c.size()) + " 1 2 0.1 0.1 0\r\n1 1 10\r\n";
  for (double g : gamma) ies += format_number(g) + " ";
  ies += "\r\n";
  for (double h : c) ies += format_number(h) + " ";
  ies += "\r\n";
  for (std::size_t i = 0; i < c.size(); ++i) {
    for (double g : gamma) ies += format_number(g < 90 ? 100.0 * std::cos(g * 3.141592653589793 / 180) : 0.0) + " ";
    ies += "\r\n";
  }
  test::write_file(dir / "measured.ies", ies);
  const fs::path model = write_paraboloid(dir.path());
  const fs::path out = dir / "like";
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations", "1",
                  "--face-size", "64", "--format", "ies,ldt", "--symmetry", "none", "--flux-tolerance", "1",
                  "--grid-like", (dir / "measured.ies").string()});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const char* name : {"paraboloid.ies", "paraboloid.ldt"}) {
    auto file = io::read_photometric_file((out / name).string());
    ASSERT_TRUE(file.ok()) << file.error().message;
    expect_angles(file.value().distribution.vertical_deg, gamma, name);
    expect_angles(photometry::expand_symmetry(file.value().distribution).horizontal_deg, c, name);
  }
  // The same angles from the file as EULUMDAT and as TM-33 (gonio convert keeps a Type C grid).
  for (const char* ext : {"ldt", "xml"}) {
    const fs::path measured = dir / (std::string("measured.") + ext);
    r = gonio({"convert", (dir / "measured.ies").string(), measured.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const fs::path from = dir / (std::string("like-") + ext);
    r = gonio({"simulate", model.string(), "--out", from.string(), "--photons", "20000", "--iterations", "1",
               "--face-size", "64", "--format", "ies", "--symmetry", "none", "--flux-tolerance", "1",
               "--grid-like", measured.string()});
    ASSERT_EQ(r.exit_code, 0) << ext << ": " << r.err;
    auto file = io::read_photometric_file((from / "paraboloid.ies").string());
    ASSERT_TRUE(file.ok()) << file.error().message;
    expect_angles(file.value().distribution.vertical_deg, gamma, ext);
    expect_angles(photometry::expand_symmetry(file.value().distribution).horizontal_deg, c, ext);
  }
  r = gonio({"compare", (dir / "measured.ies").string(), (out / "paraboloid.ies").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("angles: A and B share theirs"), std::string::npos) << r.out;
  r = gonio({"compare", (dir / "measured.ies").string(), (out / "paraboloid.ies").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(nlohmann::json::parse(r.out)["grids_differ"].get<bool>());

  // The default grid: compare says it interpolates.
  const fs::path plain = dir / "plain";
  r = gonio({"simulate", model.string(), "--out", plain.string(), "--photons", "20000", "--iterations", "1",
             "--face-size", "64", "--format", "ies", "--flux-tolerance", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = gonio({"compare", (dir / "measured.ies").string(), (plain / "paraboloid.ies").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("angles: A and B differ"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("interpolated"), std::string::npos) << r.out;
  r = gonio({"compare", (dir / "measured.ies").string(), (plain / "paraboloid.ies").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(nlohmann::json::parse(r.out)["grids_differ"].get<bool>());

  // A downlight measured on γ 0…90 (rotational): γ continues to 180 every
  // 2.5°, C-planes every --c-step's default 5°, and stderr says so.
  const fs::path downlight = test::source_dir() / "samples" / "curves" / "downlight.ies";
  const fs::path down = dir / "down";
  r = gonio({"simulate", model.string(), "--out", down.string(), "--photons", "20000", "--iterations", "1",
             "--face-size", "64", "--format", "ies", "--flux-tolerance", "1", "--grid-like", downlight.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("gamma 90-180 every 2.5 deg"), std::string::npos) << r.err;
  auto written = io::read_photometric_file((down / "paraboloid.ies").string());
  ASSERT_TRUE(written.ok());
  auto measured = io::read_photometric_file(downlight.string());
  ASSERT_TRUE(measured.ok());
  const auto& v = written.value().distribution.vertical_deg;
  const auto& m = measured.value().distribution.vertical_deg;
  ASSERT_GE(v.size(), m.size());
  expect_angles(std::vector<double>(v.begin(), v.begin() + static_cast<long>(m.size())), m, "downlight");
  EXPECT_EQ(v.back(), 180.0);
}

// Bad grids: errors name the option (and the file), exit 2, nothing written.
TEST(SimulateGrids, BadGridsAreErrorsNamingTheOption) {
  test::TempDir dir;
  const fs::path model = write_paraboloid(dir.path());
  struct Case {
    std::vector<std::string> args;
    std::vector<std::string> says;
  };
  const std::string missing = (dir / "missing.ies").string();
  test::write_file(dir / "garbage.ies", "not a photometric file\n");
  const std::string garbage = (dir / "garbage.ies").string();
  for (const Case& c : std::vector<Case>{
           {{"--gamma-angles", "0,5,3,180"}, {"--gamma-angles", "ascending"}},
           {{"--gamma-angles", "0:1:190"}, {"--gamma-angles", "180"}},
           {{"--gamma-angles", "0:1:90"}, {"--gamma-angles", "last angle must be 180"}},
           {{"--gamma-angles", "0,0.05,180"}, {"--gamma-angles"}},
           {{"--c-angles", "0,90,400"}, {"--c-angles", "outside"}},
           {{"--c-angles", "0:0.2:359.8"}, {"--c-angles", "EULUMDAT", "1800 C-planes"}},
           {{"--c-angles", "0,45", "--symmetry", "C90-C270"}, {"--c-angles"}},
           {{"--c-angles", "0:15:90"}, {"--c-angles", "--symmetry quadrant"}},
           {{"--gamma-step", "0.05"}, {"--gamma-step"}},
           {{"--gamma-step", "0.5", "--gamma-angles", "0:1:180"}, {"--gamma-step", "--gamma-angles", "exclude"}},
           {{"--grid-like", missing}, {"--grid-like", missing}},
           {{"--grid-like", garbage}, {"--grid-like", garbage}},
           {{"--grid-like", missing, "--gamma-angles", "0:1:180"}, {"--grid-like", "exclude"}}}) {
    const fs::path out = dir / "out";
    std::vector<std::string> args = {"simulate", model.string(), "--out", out.string(), "--photons", "1000"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto r = gonio(args);
    EXPECT_EQ(r.exit_code, 2) << c.args[1] << ": " << r.err;
    for (const std::string& s : c.says) EXPECT_NE(r.err.find(s), std::string::npos) << s << " in " << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.args[1];
  }
  // Within EULUMDAT's limits when ldt is left out: the IES takes 1800 planes.
  const auto lists = app::parse_angle_list("0:0.2:359.8", "--c-angles");
  ASSERT_TRUE(lists.ok());
  EXPECT_EQ(lists.value().size(), 1800u);
}

}  // namespace
}  // namespace gonio
