// One way to open a photometric file: every subcommand that reads one (info,
// check, convert, plot, compare) opens the same file the same way, by
// extension and then by content, with the same --ldt-isym3 option.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <nlohmann/json.hpp>

#include "io/photometric/ldt.h"
#include "tests/tools/cli/cli_fixtures.h"

namespace gonio {
namespace {

using nlohmann::json;

// Symmetric about the C90–C270 plane (EULUMDAT Isym 3), brighter towards C90
// than towards C270: I = 100 (2 + sin C) cos γ below the horizon.
photometry::Distribution c90_c270_lobe() {
  photometry::Distribution d;
  d.symmetry = photometry::Symmetry::C90_C270;
  for (int i = 0; i <= 12; ++i) d.horizontal_deg.push_back(90.0 + 15.0 * i);
  for (int i = 0; i <= 36; ++i) d.vertical_deg.push_back(5.0 * i);
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg)
      d.candela.push_back(g < 90.0 ? 100.0 * (2.0 + std::sin(c * std::numbers::pi / 180.0)) *
                                         std::cos(g * std::numbers::pi / 180.0)
                                   : 0.0);
  d.lamps = {photometry::LampSet{1, "LED", 1000.0, "", "", 10.0}};
  return d;
}

// The JSON a command prints; its exit code must be `expected_exit` (-1: any).
json run_json(std::vector<std::string> args, int expected_exit = 0) {
  const test::ProcessResult r = test::gonio(args);
  if (expected_exit >= 0) {
    EXPECT_EQ(r.exit_code, expected_exit) << r.err;
  }
  return json::parse(r.out);
}

TEST(PhotometricInput, TheSameFileOpensTheSameWayInEveryCommand) {
  test::TempDir dir;
  test::write_distribution(dir / "lamp.ies", test::lambertian_downlight());
  // IES content under a name that names no format, and no name at all.
  test::write_file(dir / "lamp.txt", test::read_file(dir / "lamp.ies"));
  test::write_file(dir / "lamp", test::read_file(dir / "lamp.ies"));
  const json reference = run_json({"info", (dir / "lamp.ies").string(), "--json"});
  EXPECT_NEAR(reference["flux_lm"].get<double>(), test::kDownlightFluxLm, 1e-6 * test::kDownlightFluxLm);

  for (const char* name : {"lamp.txt", "lamp"}) {
    SCOPED_TRACE(name);
    const std::string path = (dir / name).string();
    const json info = run_json({"info", path, "--json"});
    EXPECT_EQ(info["format"], reference["format"]);
    EXPECT_EQ(info["version"], reference["version"]);
    EXPECT_EQ(info["flux_lm"], reference["flux_lm"]);

    const json check = run_json({"check", path, "--json"});
    EXPECT_EQ(check["files"][0]["format"], "IES LM-63-2019");
    EXPECT_TRUE(check["files"][0]["readable"].get<bool>());

    const std::string out = (dir / (std::string(name) + "-out.ldt")).string();
    const test::ProcessResult converted = test::gonio({"convert", path, out, "--quiet"});
    EXPECT_EQ(converted.exit_code, 0) << converted.err;
    EXPECT_NEAR(run_json({"info", out, "--json"})["flux_lm"].get<double>(), reference["flux_lm"].get<double>(),
                1e-9 * test::kDownlightFluxLm);

    const std::string svg = (dir / (std::string(name) + ".svg")).string();
    const test::ProcessResult plot = test::gonio({"plot", path, "--out", svg});
    EXPECT_EQ(plot.exit_code, 0) << plot.err;
    EXPECT_TRUE(std::filesystem::exists(svg));

    const json cmp = run_json({"compare", (dir / "lamp.ies").string(), path, "--json"});
    EXPECT_EQ(cmp["b"]["format"], "IES LM-63-2019");
    EXPECT_EQ(cmp["max_relative"].get<double>(), 0.0);
  }

  // A file that is no photometry is refused alike, naming the file.
  test::write_file(dir / "notes.txt", "a shopping list\n");
  const std::string notes = (dir / "notes.txt").string();
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"info", notes},
           {"convert", notes, (dir / "x.ies").string()},
           {"plot", notes, "--out", (dir / "x.svg").string()},
           {"compare", (dir / "lamp.ies").string(), notes}}) {
    SCOPED_TRACE(args[0]);
    const test::ProcessResult r = test::gonio(args);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(test::contains(r.err, "gonio: " + notes + ": file extension '.txt' and content name no "
                                                          "photometric format"))
        << r.err;
  }
  const test::ProcessResult check = test::gonio({"check", notes});
  EXPECT_EQ(check.exit_code, 4);
  EXPECT_TRUE(test::contains(check.out, "no photometric format Gonio knows; expected")) << check.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.ies"));
  EXPECT_FALSE(std::filesystem::exists(dir / "x.svg"));
}

TEST(PhotometricInput, LdtIsym3OrderIsTheSameOptionEverywhere) {
  test::TempDir dir;
  auto ldt = io::write_ldt(c90_c270_lobe(), {}, nullptr);
  ASSERT_TRUE(ldt.ok());
  // EULUMDAT content recognised without the extension.
  test::write_file(dir / "road.dat", *ldt);
  const std::string road = (dir / "road.dat").string();

  const json standard = run_json({"info", road, "--json"});
  const json qlumedit = run_json({"info", road, "--json", "--ldt-isym3", "qlumedit"});
  EXPECT_EQ(standard["format"], "EULUMDAT");
  EXPECT_NEAR(standard["max_c_deg"].get<double>(), 90.0, 1e-9);
  EXPECT_NEAR(qlumedit["max_c_deg"].get<double>(), 270.0, 1e-9);  // half a turn

  // The QLumEdit reading converted to IES equals the file read the same way
  // by compare, and differs from the standard reading.
  const std::string as_ies = (dir / "road-q.ies").string();
  ASSERT_EQ(test::gonio({"convert", road, as_ies, "--ldt-isym3", "qlumedit", "--quiet"}).exit_code, 0);
  const json same = run_json({"compare", as_ies, road, "--json", "--ldt-isym3", "qlumedit"});
  EXPECT_LT(same["max_relative"].get<double>(), 1e-9);
  const json differs = run_json({"compare", as_ies, road, "--json"});
  EXPECT_GT(differs["max_relative"].get<double>(), 0.5);

  for (const char* order : {"standard", "qlumedit"}) {
    SCOPED_TRACE(order);
    const std::string svg = (dir / (std::string(order) + ".svg")).string();
    const test::ProcessResult plot = test::gonio({"plot", road, "--out", svg, "--ldt-isym3", order});
    EXPECT_EQ(plot.exit_code, 0) << plot.err;
    const json check = run_json({"check", road, "--json", "--ldt-isym3", order}, -1);
    EXPECT_EQ(check["files"][0]["format"], "EULUMDAT");
  }
  // The two plots differ: the brighter side moved from C90 to C270.
  EXPECT_NE(test::read_file(dir / "standard.svg"), test::read_file(dir / "qlumedit.svg"));
  for (const char* command : {"info", "check", "convert", "plot", "compare"}) {
    SCOPED_TRACE(command);
    const test::ProcessResult help = test::gonio({command, "--help"});
    EXPECT_TRUE(test::contains(help.out + help.err, "--ldt-isym3")) << help.out;
  }
}

}  // namespace
}  // namespace gonio
