// gonio report and the planning figures of gonio info, run as a user would.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <regex>
#include <unistd.h>

#include "tests/support/test_support.h"
#include "tests/tools/cli/cli_fixtures.h"

namespace gonio {
namespace {

using nlohmann::json;
using test::contains;
using test::gonio;

// The Lambertian downlight with a 0.6 m round opening.
photometry::Distribution panel() {
  photometry::Distribution d = test::lambertian_downlight();
  d.opening.shape = photometry::OpeningShape::Circular;
  d.opening.length_m = d.opening.width_m = 0.6;
  return d;
}

// The program's full path from $PATH; empty if absent.
std::string find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t colon = std::min(dirs.find(':', start), dirs.size());
    const std::filesystem::path candidate = std::filesystem::path(dirs.substr(start, colon - start)) / program;
    if (!dirs.substr(start, colon - start).empty() && ::access(candidate.c_str(), X_OK) == 0) return candidate;
    start = colon + 1;
  }
  return {};
}

bool on_path(const char* program) { return !find_on_path(program).empty(); }

// The tool is required under CI=true; elsewhere its absence skips, saying so.
#define REQUIRE_TOOL(program)                                                                        \
  do {                                                                                               \
    if (!on_path(program)) GONIO_MISSING(std::string(program) + " (scripts/setup.sh installs it)"); \
  } while (false)

TEST(CliInfoPlanning, JsonHasTheIssuesKeysAndShapes) {
  test::TempDir dir;
  const auto path = dir / "panel.ldt";
  test::write_distribution(path, panel());
  auto r = gonio({"info", path.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out, nullptr, false);
  ASSERT_FALSE(j.is_discarded());
  const json& u = j["ugr_table"];
  ASSERT_TRUE(u.is_object()) << j.dump();
  EXPECT_EQ(u["spacing_h"].get<double>(), 0.25);
  ASSERT_EQ(u["reflectances"].size(), 5u);
  EXPECT_EQ(u["reflectances"][0], json({0.7, 0.5, 0.2}));
  EXPECT_EQ(u["reflectances"][4], json({0.3, 0.3, 0.2}));
  ASSERT_EQ(u["rooms"].size(), 19u);
  const double order[19][2] = {{2, 2}, {2, 3}, {2, 4}, {2, 6}, {2, 8}, {2, 12}, {4, 2},
                               {4, 3}, {4, 4}, {4, 6}, {4, 8}, {4, 12}, {8, 4},  {8, 6},
                               {8, 8}, {8, 12}, {12, 4}, {12, 6}, {12, 8}};
  for (int i = 0; i < 19; ++i) {
    const json& room = u["rooms"][i];
    EXPECT_EQ(room["x_h"].get<double>(), order[i][0]);
    EXPECT_EQ(room["y_h"].get<double>(), order[i][1]);
    ASSERT_EQ(room["crosswise"].size(), 5u);
    ASSERT_EQ(room["endwise"].size(), 5u);
    for (int k = 0; k < 5; ++k) {
      // Rotationally symmetric in effect (a Lambertian with a round opening).
      EXPECT_NEAR(room["crosswise"][k].get<double>(), room["endwise"][k].get<double>(), 1e-6);
      EXPECT_GT(room["crosswise"][k].get<double>(), 5.0);
      EXPECT_LT(room["crosswise"][k].get<double>(), 30.0);
    }
  }
  const json& cu = j["cu_table"];
  ASSERT_TRUE(cu.is_object());
  EXPECT_EQ(cu["floor_reflectance"].get<double>(), 0.2);
  ASSERT_EQ(cu["pairs"].size(), 18u);
  EXPECT_EQ(cu["pairs"][0], json({0.8, 0.7}));
  EXPECT_EQ(cu["pairs"][17], json({0.0, 0.0}));
  ASSERT_EQ(cu["rcr"].size(), 11u);
  ASSERT_EQ(cu["values"].size(), 11u);
  ASSERT_EQ(cu["values"][0].size(), 18u);
  // RCR 0, black ceiling: the downward flux over the lamp flux, the LOR 0.8.
  EXPECT_NEAR(cu["values"][0][17].get<double>(), 0.8, 1e-4);
  const json& sc = j["spacing_criterion"];
  EXPECT_NEAR(sc["c0_c180"].get<double>(), 1.287, 0.005);
  EXPECT_NEAR(sc["c90_c270"].get<double>(), 1.287, 0.005);
  EXPECT_NEAR(sc["diagonal"].get<double>(), 1.414, 0.005);
  const json& bug = j["bug"];
  for (const char* k : {"b", "u", "g"}) EXPECT_TRUE(bug[k].is_number_integer()) << k;
  EXPECT_EQ(bug["u"].get<int>(), 0);
  // Rotationally symmetric: every octant alike, so the Types V and VS table.
  EXPECT_EQ(bug["glare_table"], "Types V and VS (quadrilateral symmetric)");
  for (const char* k : {"bl", "bm", "bh", "bvh", "fl", "fm", "fh", "fvh", "ul", "uh"})
    EXPECT_TRUE(bug["zones_lm"][k].is_number()) << k;
  // 800 lm Lambertian: the zones add up to the flux.
  double sum = 0;
  for (const auto& [k, v] : bug["zones_lm"].items()) sum += v.get<double>();
  EXPECT_NEAR(sum, 800.0, 0.01);
  const json& l = j["luminance_table"];
  ASSERT_TRUE(l.is_object());
  EXPECT_EQ(l["gamma_deg"].size(), 9u);
  // Uniform luminance I0 / A of a Lambertian disc: (800/π) / (π 0.09).
  EXPECT_NEAR(l["cd_m2"][0][0].get<double>(), 800 / (3.14159265358979 * 3.14159265358979 * 0.09), 1.0);
  // Each figure says its method, convention and outside reference.
  EXPECT_EQ(u["background"], "cie190");
  const json& m = j["methods"];
  for (const char* key : {"ugr_table", "cu_table", "spacing_criterion", "bug", "luminance_table"})
    for (const char* field : {"figure", "method", "convention", "checked_against"})
      EXPECT_FALSE(m[key][field].get<std::string>().empty()) << key << "." << field;
  EXPECT_TRUE(contains(m["ugr_table"]["method"].get<std::string>(), "CIE 190")) << m.dump();
  EXPECT_TRUE(contains(m["ugr_table"]["checked_against"].get<std::string>(), "example")) << m.dump();
  EXPECT_TRUE(contains(m["bug"]["method"].get<std::string>(), "TM-15-11 Addendum A")) << m.dump();
  EXPECT_TRUE(contains(m["cu_table"]["method"].get<std::string>(), "zonal cavity")) << m.dump();
  // The other background: another method, named as such.
  r = gonio({"info", path.string(), "--json", "--ugr-background", "flux-transfer"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json f = json::parse(r.out);
  EXPECT_EQ(f["ugr_table"]["background"], "flux-transfer");
  EXPECT_TRUE(contains(f["methods"]["ugr_table"]["method"].get<std::string>(), "flux-transfer")) << f.dump();
  EXPECT_NE(f["ugr_table"]["rooms"][10]["crosswise"][0], u["rooms"][10]["crosswise"][0]);
  r = gonio({"info", path.string(), "--ugr-background", "dialux"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  r = gonio({"info", path.string()});
  EXPECT_TRUE(contains(r.out, "Methods               UGR: CIE 190:2010")) << r.out;
}

TEST(CliInfoPlanning, PointOpeningSaysWhyUgrIsMissing) {
  test::TempDir dir;
  const auto path = dir / "point.ies";
  photometry::Distribution d = test::lambertian_downlight();
  d.opening = {};  // a point: no luminous area
  test::write_distribution(path, d);
  auto r = gonio({"info", path.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out, nullptr, false);
  EXPECT_TRUE(j["ugr_table"].is_null());
  ASSERT_TRUE(j.contains("ugr_table_why"));
  EXPECT_TRUE(contains(j["ugr_table_why"].get<std::string>(), "luminous area"));
  EXPECT_TRUE(j["luminance_table"].is_null());
  auto t = gonio({"info", path.string()});
  EXPECT_TRUE(contains(t.out, "UGR                   - (no luminous area")) << t.out;
  EXPECT_TRUE(contains(t.out, "Spacing criterion     C0-C180 1.29, C90-C270 1.29, diagonal 1.41\n")) << t.out;
  EXPECT_TRUE(contains(t.out, "BUG rating            B0-U0-G1\n")) << t.out;
}

TEST(CliReport, HtmlIsSelfContainedAndHoldsEveryFigure) {
  REQUIRE_TOOL("gnuplot");
  test::TempDir dir;
  const auto a = dir / "panel.ldt";
  const auto b = dir / "point.ies";
  test::write_distribution(a, panel());
  photometry::Distribution point = test::lambertian_downlight();
  point.opening = {};
  test::write_distribution(b, point);
  const auto out = dir / "sheet.html";
  const std::string before = test::read_file(a);
  auto r = gonio({"report", a.string(), b.string(), "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(test::read_file(a), before);  // inputs untouched
  const std::string html = test::read_file(out);
  for (const char* part : {"<!DOCTYPE html>", "</html>", "Intensity distribution", "<svg", "UGR table",
                           "Coefficients of utilisation", "Spacing criterion", "BUG rating B", "Luminance table",
                           "Candela table", "Zonal lumen summary", "isolux", "Efficacy", "glare table of Types"})
    EXPECT_TRUE(contains(html, part)) << part;
  // Two sections, one per file.
  EXPECT_EQ(std::count(html.begin(), html.end(), '\f'), 0);
  std::size_t sections = 0;
  for (std::size_t at = html.find("<section"); at != std::string::npos; at = html.find("<section", at + 1)) ++sections;
  EXPECT_EQ(sections, 2u);
  // Nothing is fetched from elsewhere: no src/href to a URL, no CSS url(), no script.
  const std::regex external(R"((src|href)\s*=\s*["']?\s*(https?:|//)|url\(|@import|<script|<link|<img)",
                            std::regex::icase);
  EXPECT_FALSE(std::regex_search(html, external));
}

TEST(CliReport, PdfIsARealPdfWithTheFigures) {
  REQUIRE_TOOL("gnuplot");
  REQUIRE_TOOL("chromium");
  REQUIRE_TOOL("pdftotext");
  test::TempDir dir;
  const auto a = dir / "panel.ldt";
  test::write_distribution(a, panel());
  const auto out = dir / "sheet.pdf";
  auto r = gonio({"report", a.string(), "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string pdf = test::read_file(out);
  ASSERT_EQ(pdf.rfind("%PDF-", 0), 0u);
  auto info = test::run_process({find_on_path("pdfinfo"), out.string()});
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_TRUE(contains(info.out, "Pages:")) << info.out;
  auto text = test::run_process({find_on_path("pdftotext"), "-layout", out.string(), "-"});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_TRUE(contains(text.out, "UGR table")) << text.out;
  // A figure read back from the PDF: the CU at RCR 0, black ceiling, 80 %.
  EXPECT_TRUE(contains(text.out, "RCR 0")) << text.out;
  EXPECT_TRUE(contains(text.out, "Coefficients of utilisation")) << text.out;
}

// Issue 44: two runs print the same bytes. Chromium stamps the time of
// printing (/CreationDate, /ModDate) and numbers the tagged structure by
// its session's DOM node ids, which shift from run to run (node00000015 in
// one run, node00000014 in the next); io::make_pdf_deterministic blanks the
// dates (or sets $SOURCE_DATE_EPOCH's) and renumbers the ids in order. Without
// it the two files differ in 20 bytes or more; poppler still reads the
// result, without dates, or with the epoch's.
TEST(CliReport, PdfIsTheSameBytesRunToRun) {
  REQUIRE_TOOL("gnuplot");
  REQUIRE_TOOL("chromium");
  REQUIRE_TOOL("pdfinfo");
  test::TempDir dir;
  const auto a = dir / "panel.ldt";
  test::write_distribution(a, panel());
  std::string bytes[2];
  for (int k = 0; k < 2; ++k) {
    const auto out = dir / ("sheet" + std::to_string(k) + ".pdf");
    auto r = gonio({"report", a.string(), "--out", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    bytes[k] = test::read_file(out);
    if (k == 0) sleep(1);  // another second of printing: the dates would differ
  }
  ASSERT_EQ(bytes[0].rfind("%PDF-", 0), 0u);
  EXPECT_TRUE(bytes[0] == bytes[1]) << "the two runs differ";
  EXPECT_EQ(bytes[0].find("/CreationDate"), std::string::npos);
  auto info = test::run_process({find_on_path("pdfinfo"), (dir / "sheet0.pdf").string()});
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_TRUE(contains(info.out, "Pages:")) << info.out;
  EXPECT_TRUE(std::regex_search(info.out, std::regex(R"(Tagged:\s+yes)"))) << info.out;  // the structure kept

  test::ScopedEnv epoch("SOURCE_DATE_EPOCH", "86400");
  const auto dated = dir / "dated.pdf";
  auto r = gonio({"report", a.string(), "--out", dated.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(test::read_file(dated), "/CreationDate (D:19700102000000+00'00')"));
  auto dated_info = test::run_process({find_on_path("pdfinfo"), dated.string()});
  ASSERT_EQ(dated_info.exit_code, 0) << dated_info.err;
  EXPECT_TRUE(contains(dated_info.out, "1970")) << dated_info.out;
}

TEST(CliReport, BadInputsFailClearly) {
  test::TempDir dir;
  const auto a = dir / "panel.ldt";
  test::write_distribution(a, panel());
  auto no_out = gonio({"report", a.string()});
  EXPECT_EQ(no_out.exit_code, 2);
  EXPECT_TRUE(contains(no_out.err, "--out")) << no_out.err;
  auto bad_ext = gonio({"report", a.string(), "--out", (dir / "x.docx").string()});
  EXPECT_EQ(bad_ext.exit_code, 1);
  EXPECT_TRUE(contains(bad_ext.err, "x.docx")) << bad_ext.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "x.docx"));
  test::write_file(dir / "broken.ies", "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1\n");
  auto broken = gonio({"report", (dir / "broken.ies").string(), "--out", (dir / "y.html").string()});
  EXPECT_EQ(broken.exit_code, 1);
  EXPECT_TRUE(contains(broken.err, "broken.ies")) << broken.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "y.html"));
}

}  // namespace
}  // namespace gonio
