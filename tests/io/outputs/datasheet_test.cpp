#include "io/outputs/datasheet.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <regex>
#include <vector>

#include "tests/support/photometry_fixtures.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_direction;

DatasheetEntry entry() {
  DatasheetEntry e;
  e.source = "panel.ldt";
  e.format = "EULUMDAT";
  e.distribution = sample_direction(photometry::PhotometricType::C, photometry::Symmetry::Rotational, {0},
                                    angles(0, 180, 5), cos_lobe(1000, 1));
  e.distribution.opening.shape = photometry::OpeningShape::Circular;
  e.distribution.opening.length_m = e.distribution.opening.width_m = 0.3;
  e.distribution.set_keyword("LUMINAIRE", "Panel <A&B>");
  return e;
}

bool have_gnuplot() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

TEST(Datasheet, HoldsEveryFigureAndEscapesText) {
  if (!have_gnuplot()) GONIO_MISSING(std::string("gnuplot (scripts/setup.sh installs gnuplot-nox)"));
  auto html = datasheet_html({entry()});
  ASSERT_TRUE(html.ok()) << html.error().message;
  const std::string& h = html.value();
  EXPECT_NE(h.find("<h1>Panel &lt;A&amp;B&gt;</h1>"), std::string::npos);  // escaped
  EXPECT_EQ(h.find("<A&B>"), std::string::npos);
  for (const char* part : {"<svg", "UGR table", "Coefficients of utilisation", "Spacing criterion", "BUG rating",
                           "Luminance table", "Candela table", "Zonal lumen summary"})
    EXPECT_NE(h.find(part), std::string::npos) << part;
  // Each planning figure says its method, convention and outside reference.
  for (const char* part : {"Method: CIE 190:2010 catalogue table", "Method: IES zonal cavity method",
                           "Method: IES spacing criterion", "Method: IES TM-15-11 Addendum A",
                           "Method: average luminance"})
    EXPECT_NE(h.find(part), std::string::npos) << part;
  std::size_t checked = 0;
  for (std::size_t at = h.find("Checked against: "); at != std::string::npos; at = h.find("Checked against: ", at + 1))
    ++checked;
  EXPECT_EQ(checked, 5u);
  // No ledger for a measured file; one when a simulation's books are given.
  EXPECT_EQ(h.find("Energy ledger"), std::string::npos);
  DatasheetEntry sim = entry();
  sim.simulation_report = nlohmann::json{{"emitted_lm", 1000.0}, {"escaped_lm", 800.0}, {"absorbed_lm", 150.0},
                                         {"cutoff_lm", 50.0}, {"photons_emitted", 12345}};
  auto with = datasheet_html({sim});
  ASSERT_TRUE(with.ok());
  EXPECT_NE(with.value().find("Energy ledger"), std::string::npos);
  EXPECT_NE(with.value().find("800.00 lm</td><td>80.00 %"), std::string::npos);
}

// A spectral simulation's sheet: the luminaire's colour (x, y, u′v′, CCT,
// Duv), Δu′v′ max with the colour-over-angle chart, and the books in watts;
// a grey simulation's sheet has none of them.
TEST(Datasheet, SpectralSimulationShowsColourAndRadiantBooks) {
  if (!have_gnuplot()) GONIO_MISSING(std::string("gnuplot (scripts/setup.sh installs gnuplot-nox)"));
  DatasheetEntry sim = entry();
  sim.simulation_report = nlohmann::json{{"emitted_lm", 1000.0}, {"escaped_lm", 800.0}, {"absorbed_lm", 200.0},
                                         {"cutoff_lm", 0.0}, {"photons_emitted", 1000}};
  auto grey = datasheet_html({sim});
  ASSERT_TRUE(grey.ok());
  EXPECT_EQ(grey.value().find("<h2>Colour</h2>"), std::string::npos);
  EXPECT_EQ(grey.value().find("(radiant)"), std::string::npos);
  nlohmann::json& r = *sim.simulation_report;
  r["colour"] = {{"cie_x", 0.45986}, {"cie_y", 0.41060}, {"u_prime", 0.25597}, {"v_prime", 0.52423},
                 {"cct_k", 2856.0}, {"duv", 0.00001}, {"method", "CIE 1931 2 deg, 5 nm; CCT and Duv by Ohno 2014"}};
  nlohmann::json planes = nlohmann::json::array();
  for (double c : {0.0, 90.0, 180.0, 270.0})
    planes.push_back({{"c_deg", c},
                      {"gamma_deg", {0.0, 45.0, 90.0, 135.0, 180.0}},
                      {"u_prime", {0.2560, 0.2570, 0.2580, nullptr, nullptr}},
                      {"v_prime", {0.5242, 0.5250, 0.5260, nullptr, nullptr}},
                      {"cct_k", {2856.0, 2830.0, 2800.0, nullptr, nullptr}},
                      {"duv", {0.0, 0.0005, 0.001, nullptr, nullptr}}});
  r["colour_over_angle"] = {{"threshold_fraction", 0.1}, {"mean_u_prime", 0.2565}, {"mean_v_prime", 0.5246},
                            {"delta_uv_max", 0.00232}, {"bins_counted", 24},  {"planes", planes}};
  r["radiant"] = {{"emitted_w", 8.2233}, {"escaped_w", 6.5786}, {"absorbed_w", 1.6447}, {"cutoff_w", 0.0}};
  auto html = datasheet_html({sim});
  ASSERT_TRUE(html.ok()) << html.error().message;
  const std::string& h = html.value();
  for (const char* part : {"<h2>Colour</h2>", "0.4599, 0.4106", "0.2560, 0.5242", "2856 K", "0.0000", "Δu′v′ max",
                           "0.0023", "colour-chart", "8.2233 W", "6.5786 W</td><td>80.00 %", "cut off (radiant)"})
    EXPECT_NE(h.find(part), std::string::npos) << part;
  // The chart is inline SVG like the others: the page stays self-contained.
  const std::size_t chart = h.find("<div class=\"svg colour-chart\"><svg");
  EXPECT_NE(chart, std::string::npos);
  const std::regex external(R"((src|href)\s*=\s*["']?\s*(https?:|//)|url\(|@import|<script|<link|<img)",
                            std::regex::icase);
  EXPECT_FALSE(std::regex_search(h, external));
}

// A simulation with luminance images: thumbnails as inline SVG, CIE 232's
// figures per view, and the UGR table's 4H × 8H room moved by the largest
// ΔUGR; the near field's verdicts and why the distance has no answer.
TEST(Datasheet, LuminanceImagesShowCie232FiguresAndTheCorrectedUgr) {
  if (!have_gnuplot()) GONIO_MISSING(std::string("gnuplot (scripts/setup.sh installs gnuplot-nox)"));
  DatasheetEntry sim = entry();
  sim.simulation_report = nlohmann::json{{"emitted_lm", 1000.0}, {"escaped_lm", 800.0}, {"absorbed_lm", 200.0},
                                         {"cutoff_lm", 0.0}, {"photons_emitted", 1000}};
  nlohmann::json& r = *sim.simulation_report;
  nlohmann::json thumb = {{"size", 2}, {"cd_m2", {0.0, 12000.0, 3000.0, 1.0}}};
  r["luminance_images"] = nlohmann::json::array();
  r["luminance_images"].push_back({{"c_deg", 0.0}, {"gamma_deg", 65.0}, {"file", "panel.luminance-C0-G65.exr"},
                                   {"intensity_cd", 123.4}, {"max_cd_m2", 12000.0}, {"cone_deg", 2.5},
                                   {"thumbnail", thumb},
                                   {"cie232", {{"defined", true}, {"intensity_cd", 123.4}, {"projected_area_m2", 0.03},
                                               {"mean_luminance_cd_m2", 4113.3}, {"glare_area_m2", 0.0012},
                                               {"glare_luminance_cd_m2", 52000.0}, {"k2", 6.37}, {"delta_ugr", 6.43}}}});
  r["luminance_images"].push_back({{"c_deg", 90.0}, {"gamma_deg", 50.0}, {"file", "panel.luminance-C90-G50.exr"},
                                   {"cie232", {{"defined", false}, {"why_undefined", "no pixel reaches 500 cd/m2"}}}});
  r["cie232"] = {{"delta_ugr", 6.43}};
  r["near_field"] = nlohmann::json::array({{{"distance_m", 2.0}, {"verdict", "undecided"}, {"upper_bound_pct", 1.7},
                                             {"cell_deviation_pct", 1.5}}});
  r["far_field_distance"] = {{"farthest", "undecided"}, {"photons_to_tell", 3.0e8}};
  auto html = datasheet_html({sim});
  ASSERT_TRUE(html.ok()) << html.error().message;
  const std::string& h = html.value();
  for (const char* part : {"CIE 232:2019", "panel.luminance-C0-G65.exr", "12000 cd/m²", "6.37", "6.4",
                           "no pixel reaches 500 cd/m2", "300.0 cm²", "12.0 cm²", "undecided", "about 300 million"})
    EXPECT_NE(h.find(part), std::string::npos) << part;
  // The 4H × 8H room of the table, crosswise and endwise, each + 6.4.
  const std::regex moved(R"(crosswise (\d+\.\d) → (\d+\.\d), endwise (\d+\.\d) → (\d+\.\d))");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(h, m, moved));
  EXPECT_NEAR(std::stod(m[2]) - std::stod(m[1]), 6.4, 0.11);
  EXPECT_NEAR(std::stod(m[4]) - std::stod(m[3]), 6.4, 0.11);
  // Thumbnails: inline SVG, the brightest pixel white-ish, the dark one not drawn.
  EXPECT_NE(h.find("<svg xmlns='http://www.w3.org/2000/svg' width='8'"), std::string::npos);
  const std::regex external(R"((src|href)\s*=\s*["']?\s*(https?:|//)|url\(|@import|<script|<link|<img)",
                            std::regex::icase);
  EXPECT_FALSE(std::regex_search(h, external));
}

// A measured file with a spectrum (TM-33 SpectralData): the sheet shows the
// colour it gives; colord's CIE illuminant A table (2856 K by definition)
// read in place as the file's spectrum gives CCT 2856 K and Duv 0.
TEST(Datasheet, FileSpectrumShowsItsColour) {
  if (!have_gnuplot()) GONIO_MISSING(std::string("gnuplot (scripts/setup.sh installs gnuplot-nox)"));
  DatasheetEntry e = entry();
  photometry::Spectrum a;
  a.emitter = "lamp";
  a.normalized = true;
  {
    // colord's CGATS .sp: SPECTRAL_START_NM, SPECTRAL_END_NM, then the values
    // between BEGIN_DATA and END_DATA.
    std::ifstream in("/usr/share/colord/illuminant/CIE-A.sp");
    if (!in) GONIO_MISSING(std::string("colord-data's /usr/share/colord/illuminant/CIE-A.sp"));
    std::string word;
    double first = 0.0, last = 0.0;
    std::vector<double> values;
    bool data = false;
    while (in >> word) {
      if (word == "SPECTRAL_START_NM") in >> first;
      else if (word == "SPECTRAL_END_NM") in >> last;
      else if (word == "BEGIN_DATA") data = true;
      else if (word == "END_DATA") data = false;
      else if (data) values.push_back(std::stod(word));
    }
    ASSERT_GT(values.size(), 10u);
    for (std::size_t i = 0; i < values.size(); ++i) {
      a.wavelength_nm.push_back(first + (last - first) * static_cast<double>(i) / static_cast<double>(values.size() - 1));
      a.values.push_back(values[i]);
    }
  }
  e.distribution.spectra = {a};
  auto html = datasheet_html({e});
  ASSERT_TRUE(html.ok()) << html.error().message;
  for (const char* part : {"<h2>Colour</h2>", "2856 K", "From the file's spectrum (lamp)"})
    EXPECT_NE(html.value().find(part), std::string::npos) << part;
}

// The isolux lines of a Lambertian emitter (I = I0 cos γ) on the floor h
// below: E = I0 cos⁴γ / h², so the line at a fraction f of the maximum is the
// circle r = h tan(acos(f^¼)). Every vertex of the drawn lines lies on it to
// within half a texel (61 texels over ±2h; px = 5 per texel in the SVG).
TEST(Datasheet, IsoluxLinesAreTheClosedFormsCircles) {
  if (!have_gnuplot()) GONIO_MISSING(std::string("gnuplot (scripts/setup.sh installs gnuplot-nox)"));
  DatasheetOptions options;
  options.mounting_height_m = 2.0;
  auto html = datasheet_html({entry()}, options);
  ASSERT_TRUE(html.ok()) << html.error().message;
  const double h = options.mounting_height_m, half = 2 * h, cell = 2 * half / 61, px = 5;
  const std::regex path_re("class=\"isolux\" data-lx=\"([^\"]+)\" d=\"([^\"]+)\"");
  const std::regex point_re("[ML]([-0-9.]+) ([-0-9.]+)");
  const std::string& text = html.value();
  std::vector<double> levels;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), path_re); it != std::sregex_iterator(); ++it) {
    levels.push_back(std::stod((*it)[1]));
    const std::string d = (*it)[2];
    int points = 0;
    double r_expected = 0.0;
    for (auto p = std::sregex_iterator(d.begin(), d.end(), point_re); p != std::sregex_iterator(); ++p, ++points) {
      const double x = -half + std::stod((*p)[1]) / px * cell, y = half - std::stod((*p)[2]) / px * cell;
      if (points == 0) r_expected = std::hypot(x, y);  // same for every point of the line
      EXPECT_NEAR(std::hypot(x, y), r_expected, 0.5 * cell) << levels.back() << " lx";
    }
    EXPECT_GT(points, 8);
    levels.back() = r_expected;
  }
  // 50, 20 and 10 % of the maximum lie within ±2h; 5 % reaches the corners.
  ASSERT_GE(levels.size(), 3u);
  const double fractions[3] = {0.5, 0.2, 0.1};
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(levels[k], h * std::tan(std::acos(std::pow(fractions[k], 0.25))), 0.5 * cell) << fractions[k];
}

TEST(Datasheet, InvalidDistributionNamesItsSource) {
  DatasheetEntry e = entry();
  e.distribution.candela.pop_back();
  auto html = datasheet_html({e});
  ASSERT_FALSE(html.ok());
  EXPECT_EQ(html.error().where.file, "panel.ldt");
  EXPECT_FALSE(datasheet_html({}).ok());
}

TEST(Datasheet, UnknownExtensionWritesNothing) {
  test::TempDir dir;
  const auto path = (dir / "sheet.docx").string();
  const Status s = write_datasheet(path, {entry()});
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().where.file, path);
  EXPECT_FALSE(std::filesystem::exists(path));
}

// make_pdf_deterministic on the parts of a Chromium PDF that change from
// run to run: the dates are blanked (or set from $SOURCE_DATE_EPOCH), the
// structure ids renumbered by rank with their widths, so two prints whose
// node ids are shifted become the same bytes; the length never changes
// (the cross-reference table's offsets hold). A renumbering out of order
// would unsort the ID tree; one by first appearance would too.
TEST(Datasheet, PdfIdsAndDatesBecomeDeterministic) {
  const auto print = [](int shift, const std::string& date) {
    const auto id = [shift](int n) {
      char b[16];
      std::snprintf(b, sizeof b, "node%08d", n + shift);
      return std::string(b);
    };
    return "%PDF-1.4\n1 0 obj\n<</Producer (Skia/PDF m156)\n/CreationDate (D:" + date +
           "+00'00')\n/ModDate (D:" + date + "+00'00')>>\nendobj\n2 0 obj\n<</K 30 0 R /ID (" + id(27) +
           ")>> <</Headers [(" + id(15) + ")]>>\n<</Limits [(" + id(15) + ") (" + id(5001) + ")]\n/Names [(" +
           id(15) + ") 27 0 R (" + id(27) + ") 32 0 R (" + id(5001) + ") 40 0 R]>> (node) (node12a) (nodes)\n";
  };
  std::string a = print(0, "20261207132317"), b = print(-1, "20261207132324");
  const std::size_t size = a.size();
  ASSERT_NE(a, b);
  make_pdf_deterministic(a);
  make_pdf_deterministic(b);
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.size(), size);
  EXPECT_EQ(a.find("CreationDate"), std::string::npos);
  EXPECT_EQ(a.find("ModDate"), std::string::npos);
  EXPECT_NE(a.find("/Producer (Skia/PDF m156)"), std::string::npos);
  EXPECT_NE(a.find("/Limits [(node00000000) (node00000002)]"), std::string::npos) << a;
  EXPECT_NE(a.find("/Names [(node00000000) 27 0 R (node00000001) 32 0 R (node00000002) 40 0 R]"), std::string::npos);
  EXPECT_NE(a.find("/ID (node00000001)"), std::string::npos);
  EXPECT_NE(a.find("(node) (node12a) (nodes)"), std::string::npos);  // not ids: left alone

  // The run that failed in CI's load: Chromium's ids came in another order
  // (the element at object 27 numbered above the one at 32). Renumbered by
  // the objects the ID tree names, the bytes are the same; by the ids' rank
  // they were not.
  std::string swapped =
      "%PDF-1.4\n1 0 obj\n<</Producer (Skia/PDF m156)\n/CreationDate (D:20261207132399+00'00')\n/ModDate "
      "(D:20261207132399+00'00')>>\nendobj\n2 0 obj\n<</K 30 0 R /ID (node00000014)>> <</Headers "
      "[(node00000027)]>>\n<</Limits [(node00000014) (node00005001)]\n/Names [(node00000014) 32 0 R "
      "(node00000027) 27 0 R (node00005001) 40 0 R]>> (node) (node12a) (nodes)\n";
  make_pdf_deterministic(swapped);
  EXPECT_EQ(swapped, a);

  test::ScopedEnv epoch("SOURCE_DATE_EPOCH", "86400");
  std::string c = print(0, "20261207132317");
  make_pdf_deterministic(c);
  EXPECT_EQ(c.size(), size);
  EXPECT_NE(c.find("/CreationDate (D:19700102000000+00'00')"), std::string::npos) << c;
  EXPECT_NE(c.find("/ModDate (D:19700102000000+00'00')"), std::string::npos);
}

}  // namespace
}  // namespace gonio::io
