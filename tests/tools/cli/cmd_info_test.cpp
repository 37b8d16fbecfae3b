// gonio info, run as a user would.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "io/photometric/ldt.h"
#include "io/photometric/photometric_file.h"
#include "photometry/summary.h"
#include "tests/tools/cli/cli_fixtures.h"

namespace gonio {
namespace {

using nlohmann::json;
using test::contains;
using test::gonio;

constexpr double kDeg = std::numbers::pi / 180.0;

json parse_json(const std::string& text) {
  json j = json::parse(text, nullptr, false);
  EXPECT_FALSE(j.is_discarded()) << text;
  return j;
}

TEST(CliInfo, TableShowsTheClosedFormValues) {
  test::TempDir dir;
  for (const char* name : {"downlight.ies", "downlight.ldt"}) {
    SCOPED_TRACE(name);
    const auto path = dir / name;
    test::write_distribution(path, test::lambertian_downlight());
    auto r = gonio({"info", path.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << r.err;  // a clean file: no reader warnings
    const std::string& out = r.out;
    EXPECT_TRUE(contains(out, "File                  " + path.string() + "\n")) << out;
    EXPECT_TRUE(contains(out, std::string(name).ends_with(".ies") ? "IES LM-63-2019" : "EULUMDAT"));
    EXPECT_TRUE(contains(out, "Luminaire             Lambertian downlight\n")) << out;
    EXPECT_TRUE(contains(out, "C0-C180")) << out;
    EXPECT_TRUE(contains(out, "73 (0 to 180 deg, step 2.5 deg)")) << out;
    EXPECT_TRUE(contains(out, "37 (0 to 180 deg, step 5 deg)")) << out;
    // IES keeps the input watts only, EULUMDAT the lamp set's wattage.
    EXPECT_TRUE(contains(out, "1 x LED module, 1000 lm")) << out;
    EXPECT_TRUE(contains(out, "Input power           10 W\n")) << out;
    // Closed forms of the Lambertian downlight (cli_fixtures.h).
    EXPECT_TRUE(contains(out, "Total flux            800.0 lm\n")) << out;
    EXPECT_TRUE(contains(out, "LOR                   80.00 %\n")) << out;
    EXPECT_TRUE(contains(out, "DFF                   100.00 %\n")) << out;
    EXPECT_TRUE(contains(out, "254.6 cd at C 0.0 deg, gamma 0.0 deg")) << out;
    EXPECT_TRUE(contains(out, "Beam angle C0-C180    120.0 deg\n")) << out;
    EXPECT_TRUE(contains(out, "Field angle C90-C270  168.5 deg\n")) << out;
    EXPECT_TRUE(contains(out, "CIE flux code         44 75 94 100 80\n")) << out;
    EXPECT_TRUE(contains(out, "Efficacy              80.0 lm/W\n")) << out;
    // Zonal flux of a Lambertian source: Φ sin²γ within γ.
    EXPECT_TRUE(contains(out, "0-60 deg         600.0 lm   75.0 %\n")) << out;
    EXPECT_TRUE(contains(out, "90-180 deg         0.0 lm    0.0 %\n")) << out;
  }
}

TEST(CliInfo, JsonCarriesTheLibrarysValuesAndTheClosedForms) {
  test::TempDir dir;
  const auto path = dir / "downlight.ldt";
  test::write_distribution(path, test::lambertian_downlight());
  auto r = gonio({"info", path.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = parse_json(r.out);
  ASSERT_TRUE(j.is_object());

  auto file = io::read_photometric_file(path.string());
  ASSERT_TRUE(file.ok());
  const photometry::Summary s = photometry::summarize(file->distribution);
  // The library's values, digit for digit (JSON numbers round-trip doubles).
  EXPECT_EQ(j["flux_lm"].get<double>(), s.flux_lm);
  EXPECT_EQ(j["max_cd"].get<double>(), s.max_intensity_cd);
  EXPECT_EQ(j["lor"].get<double>(), s.lor);
  EXPECT_EQ(j["dff"].get<double>(), s.dff);
  EXPECT_EQ(j["downward_flux_lm"].get<double>(), s.downward_flux_lm);
  EXPECT_EQ(j["beam_angle_c0_c180_deg"].get<double>(), s.beam_c0_c180.angle_deg);
  EXPECT_EQ(j["field_angle_c90_c270_deg"].get<double>(), s.field_c90_c270.angle_deg);
  EXPECT_EQ(j["cie_flux_code"]["n1"].get<double>(), s.cie_flux_code.n1);
  EXPECT_EQ(j["efficacy_lm_per_w"].get<double>(), s.efficacy_lm_per_w);
  ASSERT_EQ(j["zones_10deg"].size(), 18u);
  for (std::size_t i = 0; i < 18; ++i)
    EXPECT_EQ(j["zones_10deg"][i]["flux_lm"].get<double>(), s.zones_10deg[i].flux_lm);

  // And the closed forms they stand for.
  const double flux = test::kDownlightFluxLm;
  EXPECT_NEAR(j["flux_lm"].get<double>(), flux, 1e-5 * flux);
  EXPECT_NEAR(j["lor"].get<double>(), 0.8, 1e-5);
  EXPECT_NEAR(j["dff"].get<double>(), 1.0, 1e-12);
  EXPECT_NEAR(j["max_cd"].get<double>(), flux / std::numbers::pi, 1e-6);
  EXPECT_EQ(j["max_gamma_deg"].get<double>(), 0.0);
  EXPECT_NEAR(j["beam_angle_c0_c180_deg"].get<double>(), 120.0, 1e-9);
  EXPECT_NEAR(j["field_angle_c0_c180_deg"].get<double>(), 2.0 * std::acos(0.1) / kDeg, 0.05);
  EXPECT_NEAR(j["cie_flux_code"]["n2"].get<double>(), 75.0, 0.01);
  EXPECT_EQ(j["cie_flux_code"]["text"], "44 75 94 100 80");
  EXPECT_NEAR(j["rated_lamp_flux_lm"].get<double>(), 1000.0, 1e-9);
  EXPECT_NEAR(j["efficacy_lm_per_w"].get<double>(), 80.0, 1e-3);
  EXPECT_NEAR(j["zones"][2]["flux_lm"].get<double>(), 0.75 * flux, 1e-4 * flux);  // 0-60°

  // The file's own data, with units in the keys.
  EXPECT_EQ(j["format"], "EULUMDAT");
  EXPECT_TRUE(j["version"].is_null());
  EXPECT_EQ(j["photometric_type"], "C");
  EXPECT_EQ(j["symmetry"], "C0-C180");
  EXPECT_EQ(j["vertical_angles"]["count"], 73);
  EXPECT_EQ(j["vertical_angles"]["step_deg"], 2.5);
  EXPECT_EQ(j["horizontal_angles"]["last_deg"], 180.0);
  EXPECT_EQ(j["absolute_photometry"], false);
  EXPECT_EQ(j["lamps"][0]["count"], 1);
  EXPECT_EQ(j["lamps"][0]["flux_lm"], 1000.0);
  EXPECT_EQ(j["luminous_opening"]["shape"], "circular");
  EXPECT_NEAR(j["luminous_opening"]["width_m"].get<double>(), 0.1, 1e-12);
  EXPECT_NEAR(j["declared_lor_percent"].get<double>(), 80.0, 1e-3);  // the LDT writer's
  EXPECT_TRUE(j["findings"].is_array());
  bool lumcat = false;
  for (const auto& k : j["keywords"])
    lumcat = lumcat || (k["key"] == "LUMCAT" && k["value"] == "DL-800");
  EXPECT_TRUE(lumcat);
}

TEST(CliInfo, JsonMarksUndefinedValuesNull) {
  // Absolute photometry has no LOR; an isotropic source no beam.
  photometry::Distribution d;
  d.symmetry = photometry::Symmetry::Rotational;
  d.horizontal_deg = {0.0};
  for (int i = 0; i <= 36; ++i) d.vertical_deg.push_back(5.0 * i);
  d.candela.assign(d.vertical_deg.size(), 100.0);
  d.absolute = true;
  d.lamps = {photometry::LampSet{}};
  test::TempDir dir;
  const auto path = dir / "iso.ies";
  test::write_distribution(path, d);
  auto r = gonio({"info", path.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = parse_json(r.out);
  EXPECT_TRUE(j["lor"].is_null());
  EXPECT_TRUE(j["rated_lamp_flux_lm"].is_null());
  EXPECT_TRUE(j["cie_flux_code"]["n5"].is_null());
  EXPECT_TRUE(j["beam_angle_c0_c180_deg"].is_null());
  EXPECT_TRUE(j["efficacy_lm_per_w"].is_null());  // input watts 0: unknown
  EXPECT_EQ(j["absolute_photometry"], true);
  EXPECT_NEAR(j["flux_lm"].get<double>(), 400.0 * std::numbers::pi,
              1e-9 * 400.0 * std::numbers::pi);
  EXPECT_NEAR(j["dff"].get<double>(), 0.5, 1e-12);

  auto table = gonio({"info", path.string()});
  ASSERT_EQ(table.exit_code, 0);
  EXPECT_TRUE(contains(table.out, "LOR                   - (absolute photometry)\n")) << table.out;
  EXPECT_TRUE(contains(table.out, "Beam angle C0-C180    none\n")) << table.out;
}

TEST(CliInfo, ReaderWarningsGoToStderrWithFileAndLine) {
  test::TempDir dir;
  const auto path = dir / "old.ies";
  // LM-63-2002 without [TESTLAB] and with a keyword the standard lacks.
  test::write_file(path,
                   "IESNA:LM-63-2002\r\n[TEST] 1\r\n[ISSUEDATE] 2002\r\n[MANUFAC] M\r\n"
                   "[WEIRD] x\r\nTILT=NONE\r\n1 1000 1 3 1 1 2 0 0 0\r\n1 1 10\r\n0 45 90\r\n0\r\n"
                   "100 80 0\r\n");
  auto r = gonio({"info", path.string()});
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_TRUE(contains(r.err, "gonio: " + path.string() + ":5: warning: ")) << r.err;
  EXPECT_TRUE(contains(r.err, "[unknown-keyword]")) << r.err;
  EXPECT_TRUE(contains(r.err, "[missing-keyword]")) << r.err;
  EXPECT_TRUE(contains(r.out, "Total flux")) << r.out;
  // --json keeps stdout one JSON object; the findings are in it as well.
  auto j = gonio({"info", path.string(), "--json"});
  EXPECT_EQ(j.exit_code, 0);
  const json parsed = parse_json(j.out);
  bool unknown = false;
  for (const auto& f : parsed["findings"])
    unknown = unknown || (f["code"] == "unknown-keyword" && f["line"] == 5);
  EXPECT_TRUE(unknown);
}

TEST(CliInfo, BadFilesExitWith1AndNameFileAndLine) {
  test::TempDir dir;
  const auto good = dir / "good.ies";
  test::write_distribution(good, test::lambertian_downlight());
  const std::string text = test::read_file(good);
  test::write_file(dir / "truncated.ies", text.substr(0, text.size() / 2));
  test::write_file(dir / "junk.ldt", std::string("\x7f"
                                                 "ELF\x02\x01\x01\0\0\0\0\x03\0>\0",
                                                 16));
  test::write_file(dir / "junk.ies", std::string("PK\x03\x04\x14\0\0\0\x08\0", 10));
  test::write_file(dir / "empty.ldt", "");
  std::filesystem::create_directory(dir / "folder.ies");
  test::write_file(dir / "notes.txt", "not photometry");

  struct Case {
    std::string file;
    std::string says;  // after "gonio: FILE"
  };
  const std::vector<Case> cases = {
      {"truncated.ies", ":"},  // a line number follows
      {"junk.ldt", ":1: binary data"},
      {"junk.ies", ":1: binary data"},
      {"empty.ldt", ":1: empty file"},
      {"folder.ies", ": is a directory"},
      {"notes.txt", ": file extension '.txt' and content name no photometric format"},
      {"missing.ies", ": cannot open"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string path = (dir / c.file).string();
    for (bool as_json : {false, true}) {
      auto r = as_json ? gonio({"info", path, "--json"}) : gonio({"info", path});
      EXPECT_EQ(r.exit_code, 1);
      EXPECT_EQ(r.err.rfind("gonio: " + path + c.says, 0), 0u) << r.err;
      EXPECT_TRUE(r.out.empty()) << r.out;
    }
  }
  // The truncated file's error names the line where the data ran out.
  auto r = gonio({"info", (dir / "truncated.ies").string()});
  const std::string prefix = "gonio: " + (dir / "truncated.ies").string() + ":";
  ASSERT_EQ(r.err.rfind(prefix, 0), 0u);
  EXPECT_GT(std::atoi(r.err.c_str() + prefix.size()), 10) << r.err;
}

TEST(CliInfo, Isym3PlaneOrderIsAnOption) {
  // A distribution with C90-C270 symmetry whose peak lies on the C90 side
  // (C 60 and, mirrored, C 120), written in the standard's plane order.
  photometry::Distribution d;
  d.symmetry = photometry::Symmetry::C90_C270;
  for (int i = 0; i <= 12; ++i) d.horizontal_deg.push_back(90.0 + 15.0 * i);
  for (int i = 0; i <= 18; ++i) d.vertical_deg.push_back(5.0 * i);
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg)
      d.candela.push_back(100.0 + 900.0 * std::pow(std::cos((c - 120.0) * kDeg / 2.0), 8) *
                                      std::sin(g * kDeg * 2.0));
  d.lamps = {photometry::LampSet{1, "HPS", 10000.0, "", "", 100.0}};
  test::TempDir dir;
  const auto path = dir / "road.ldt";
  test::write_distribution(path, d);

  auto standard = gonio({"info", path.string(), "--json"});
  auto qlumedit = gonio({"info", path.string(), "--json", "--ldt-isym3", "qlumedit"});
  ASSERT_EQ(standard.exit_code, 0) << standard.err;
  ASSERT_EQ(qlumedit.exit_code, 0) << qlumedit.err;
  const json s = parse_json(standard.out), q = parse_json(qlumedit.out);
  EXPECT_EQ(s["max_c_deg"].get<double>(), 120.0);
  // QLumEdit's order turns the luminaire by half a turn: the peak at 300
  // (C 120 + 180), which the model holds as its mirror image 240.
  const double qc = q["max_c_deg"].get<double>();
  EXPECT_TRUE(qc == 240.0 || qc == 300.0) << qc;
  EXPECT_EQ(q["max_cd"].get<double>(), s["max_cd"].get<double>());
  EXPECT_NEAR(q["flux_lm"].get<double>(), s["flux_lm"].get<double>(),
              1e-12 * s["flux_lm"].get<double>());  // summed in another order
}

}  // namespace
}  // namespace gonio
