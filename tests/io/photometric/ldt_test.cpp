#include "io/photometric/ldt.h"

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "io/photometric/ies.h"
#include "io/support/text.h"
#include "photometry/direct_ratios.h"
#include "photometry/flux.h"
#include "photometry/luminance.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

using photometry::Distribution;
using photometry::Symmetry;

constexpr double kPi = std::numbers::pi;
constexpr double kRad = kPi / 180.0;

// ------------------------------------------------------------ test files

struct LampSpec {
  std::string count, type, flux, color, cri, watt;
};

// The fields of a small EULUMDAT file, as text, so tests can break any one.
struct Spec {
  std::string company = "ACME Licht GmbH";
  std::string ityp = "3", isym = "0", mc, dc, ng, dg;
  std::string report = "R-17/2024", name = "Downlight 60", number = "DL-60-830";
  std::string file = "dl60.ldt", date = "2024-05-01 / Lab A";
  std::vector<std::string> dims = {"600", "300", "80", "500", "250", "10", "20", "30", "40"};
  std::string dff = "95", lorl = "80", cfli = "1", tilt = "0";
  std::vector<LampSpec> sets = {{"2", "LED 830", "4000", "3000 K", "80", "35"}};
  std::vector<std::string> dr = {"0.5",  "0.55", "0.6",  "0.65", "0.7",
                                 "0.75", "0.8",  "0.85", "0.9",  "0.95"};
  std::vector<double> c, g;
  std::vector<double> values;  // stored planes × Ng [cd/klm], file order
};

std::string num(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.15g", x);
  return buf;
}

std::vector<std::string> lines_of(const Spec& s) {
  std::vector<std::string> l = {s.company,
                                s.ityp,
                                s.isym,
                                s.mc.empty() ? std::to_string(s.c.size()) : s.mc,
                                s.dc.empty() ? "0" : s.dc,
                                s.ng.empty() ? std::to_string(s.g.size()) : s.ng,
                                s.dg.empty() ? "0" : s.dg,
                                s.report,
                                s.name,
                                s.number,
                                s.file,
                                s.date};
  l.insert(l.end(), s.dims.begin(), s.dims.end());
  l.insert(l.end(), {s.dff, s.lorl, s.cfli, s.tilt, std::to_string(s.sets.size())});
  for (const LampSpec& k : s.sets)
    l.insert(l.end(), {k.count, k.type, k.flux, k.color, k.cri, k.watt});
  l.insert(l.end(), s.dr.begin(), s.dr.end());
  for (double x : s.c) l.push_back(num(x));
  for (double x : s.g) l.push_back(num(x));
  for (double x : s.values) l.push_back(num(x));
  return l;
}

std::string join(const std::vector<std::string>& lines, const std::string& eol = "\r\n") {
  std::string out;
  for (const std::string& l : lines) out += l + eol;
  return out;
}

std::vector<double> steps(double first, double step, double last) {
  std::vector<double> v;
  for (int i = 0; first + i * step <= last + 1e-9; ++i) v.push_back(first + i * step);
  return v;
}

// A file with Isym 0, 4 C-planes × 3 γ angles; value = 100 + 10·plane + γ/10.
Spec small_spec() {
  Spec s;
  s.c = {0, 90, 180, 270};
  s.g = {0, 45, 90};
  for (double c : s.c)
    for (double g : s.g) s.values.push_back(100 + c / 9 + g / 10);
  return s;
}

LdtFile parse_ok(const std::string& bytes, const LdtReadOptions& options = {}) {
  test::offer_fuzz_seed("ldt", bytes);
  auto r = parse_ldt(bytes, "test.ldt", options);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : to_string(r.error()));
  if (!r.ok()) return {};
  return std::move(r).value();
}

Error parse_error(const std::string& bytes) {
  test::offer_fuzz_seed("ldt", bytes);
  auto r = parse_ldt(bytes, "bad.ldt");
  EXPECT_FALSE(r.ok());
  if (r.ok()) return {};
  return r.error();
}

bool has_finding(const std::vector<Finding>& f, const std::string& code) {
  for (const Finding& x : f)
    if (x.code == code) return true;
  return false;
}

const Finding* finding(const std::vector<Finding>& f, const std::string& code) {
  for (const Finding& x : f)
    if (x.code == code) return &x;
  return nullptr;
}

std::string keyword(const Distribution& d, const std::string& key) {
  const auto* k = d.find_keyword(key);
  return k ? k->value : std::string("<none>");
}

// An asymmetric test distribution value at (C, γ): distinct in every plane
// and smooth, so a plane landing in the wrong place shows.
double asym(double c, double g) {
  return 100.0 * (1.0 + 0.5 * std::sin(c * kRad) + 0.2 * std::cos(c * kRad)) * (1.0 + g / 180.0);
}

// ------------------------------------------------------------ every field

TEST(LdtRead, ReadsEveryHeaderField) {
  Spec s = small_spec();
  s.dc = "90";
  s.dg = "45";
  s.dims = {"600", "300", "80", "500", "250", "10", "20", "30", "40"};
  s.tilt = "5";
  s.sets = {{"2", "LED 830", "4000", "3000 K", "80", "35"}};
  const LdtFile f = parse_ok(join(lines_of(s)));
  const Distribution& d = f.distribution;
  EXPECT_EQ(d.type, photometry::PhotometricType::C);
  EXPECT_EQ(d.symmetry, Symmetry::None);
  ASSERT_TRUE(d.ldt_type_indicator.has_value());
  EXPECT_EQ(*d.ldt_type_indicator, 3);
  EXPECT_EQ(keyword(d, "MANUFAC"), "ACME Licht GmbH");
  EXPECT_EQ(keyword(d, "TEST"), "R-17/2024");
  EXPECT_EQ(keyword(d, "LUMINAIRE"), "Downlight 60");
  EXPECT_EQ(keyword(d, "LUMCAT"), "DL-60-830");
  EXPECT_EQ(keyword(d, "ISSUEDATE"), "2024-05-01 / Lab A");
  EXPECT_EQ(keyword(d, kLdtFileNameKeyword), "dl60.ldt");
  // EULUMDAT's lengths lie along C90–C270, the model's along C0–C180.
  EXPECT_DOUBLE_EQ(d.luminaire.length_m, 0.3);
  EXPECT_DOUBLE_EQ(d.luminaire.width_m, 0.6);
  EXPECT_DOUBLE_EQ(d.luminaire.height_m, 0.08);
  EXPECT_EQ(d.opening.shape, photometry::OpeningShape::RectangularWithSides);
  EXPECT_DOUBLE_EQ(d.opening.length_m, 0.25);
  EXPECT_DOUBLE_EQ(d.opening.width_m, 0.5);
  EXPECT_DOUBLE_EQ(d.opening.height_m, 0.04);
  EXPECT_DOUBLE_EQ(d.opening.side_height_m[0], 0.01);
  EXPECT_DOUBLE_EQ(d.opening.side_height_m[1], 0.02);
  EXPECT_DOUBLE_EQ(d.opening.side_height_m[2], 0.03);
  EXPECT_DOUBLE_EQ(d.opening.side_height_m[3], 0.04);
  EXPECT_EQ(d.declared_dff_percent, 95.0);
  EXPECT_EQ(d.declared_lor_percent, 80.0);
  EXPECT_EQ(d.measurement_tilt_deg, 5.0);
  ASSERT_EQ(d.lamps.size(), 1u);
  EXPECT_EQ(d.lamps[0].count, 2);
  EXPECT_EQ(d.lamps[0].type, "LED 830");
  EXPECT_EQ(d.lamps[0].flux_lm, 4000.0);
  EXPECT_EQ(d.lamps[0].color, "3000 K");
  EXPECT_EQ(d.lamps[0].color_rendering, "80");
  EXPECT_EQ(d.lamps[0].power_w, 35.0);
  EXPECT_EQ(d.input_watts, 35.0);
  EXPECT_FALSE(d.absolute);
  ASSERT_EQ(d.direct_ratios.size(), 10u);
  EXPECT_EQ(d.direct_ratios[0], 0.5);
  EXPECT_EQ(d.direct_ratios[9], 0.95);
  EXPECT_EQ(d.horizontal_deg, s.c);
  EXPECT_EQ(d.vertical_deg, s.g);
  EXPECT_TRUE(f.findings.empty()) << f.findings[0].message;
}

TEST(LdtRead, CandelaAreCdPerKlmTimesTheFirstSetsFlux) {
  Spec s = small_spec();
  s.sets = {{"2", "LED", "4000", "", "", "35"}};
  const LdtFile f = parse_ok(join(lines_of(s)));
  for (std::size_t p = 0; p < 4; ++p)
    for (std::size_t v = 0; v < 3; ++v)
      EXPECT_DOUBLE_EQ(f.distribution.at(p, v), s.values[p * 3 + v] * 4.0);
  EXPECT_DOUBLE_EQ(f.distribution.rated_lamp_flux_lm(), 4000.0);
}

TEST(LdtRead, ConversionFactorMultipliesTheIntensities) {
  Spec s = small_spec();
  s.sets = {{"1", "LED", "2000", "", "", "20"}};
  s.cfli = "1,5";
  const LdtFile f = parse_ok(join(lines_of(s)));
  EXPECT_DOUBLE_EQ(f.distribution.at(1, 2), s.values[5] * 1.5 * 2.0);
  const Finding* note = finding(f.findings, "ldt-conversion-factor");
  ASSERT_NE(note, nullptr);
  EXPECT_EQ(note->where.line, 24);

  s.cfli = "0";
  const LdtFile zero = parse_ok(join(lines_of(s)));
  EXPECT_DOUBLE_EQ(zero.distribution.at(1, 2), s.values[5] * 2.0);
  EXPECT_TRUE(has_finding(zero.findings, "ldt-conversion-factor-zero"));
}

TEST(LdtRead, NegativeLampCountMeansAbsolutePhotometry) {
  Spec s = small_spec();
  s.sets = {{"-3", "LED module", "1250", "4000K", "90", "14"}};
  const LdtFile f = parse_ok(join(lines_of(s)));
  const Distribution& d = f.distribution;
  EXPECT_TRUE(d.absolute);
  ASSERT_EQ(d.lamps.size(), 1u);
  EXPECT_EQ(d.lamps[0].count, 3);
  EXPECT_TRUE(std::isnan(d.lamps[0].flux_lm));
  EXPECT_TRUE(std::isnan(d.rated_lamp_flux_lm()));
  // The flux field is the luminaire's flux; values are cd per 1000 lm of it.
  EXPECT_DOUBLE_EQ(d.at(2, 1), s.values[7] * 1.25);
}

TEST(LdtRead, FurtherLampSetsAreAlternativesAndTheFirstSetsFluxScales) {
  Spec s = small_spec();
  s.sets = {{"1", "Single lamp", "500", "3000", "100", "15"},
            {"2", "Double lamp", "1200", "3000", "100", "30"},
            {"1", "Alternative", "500", "5000", "90", "15"}};
  const LdtFile f = parse_ok(join(lines_of(s)));
  const Distribution& d = f.distribution;
  ASSERT_EQ(d.lamps.size(), 1u);
  ASSERT_EQ(d.alternative_lamps.size(), 2u);
  EXPECT_EQ(d.lamps[0].type, "Single lamp");
  EXPECT_EQ(d.alternative_lamps[0].type, "Double lamp");
  EXPECT_EQ(d.alternative_lamps[0].count, 2);
  EXPECT_EQ(d.alternative_lamps[0].flux_lm, 1200.0);
  EXPECT_EQ(d.alternative_lamps[1].color, "5000");
  EXPECT_DOUBLE_EQ(d.rated_lamp_flux_lm(), 500.0);
  EXPECT_DOUBLE_EQ(d.at(0, 0), s.values[0] * 0.5);
}

TEST(LdtRead, LuminousAreaShapes) {
  Spec s = small_spec();
  s.dims = {"120", "0", "30", "50", "0", "0", "0", "0", "0"};
  Distribution d = parse_ok(join(lines_of(s))).distribution;
  EXPECT_EQ(d.luminaire.width_m, 0.0);  // round luminaire
  EXPECT_EQ(d.opening.shape, photometry::OpeningShape::Circular);
  EXPECT_DOUBLE_EQ(d.opening.width_m, 0.05);
  s.dims = {"120", "0", "30", "50", "0", "11", "12", "13", "14"};
  d = parse_ok(join(lines_of(s))).distribution;
  EXPECT_EQ(d.opening.shape, photometry::OpeningShape::VerticalCylinder);
  EXPECT_DOUBLE_EQ(d.opening.height_m, 0.014);
  s.dims = {"120", "60", "30", "50", "40", "0", "0", "0", "0"};
  d = parse_ok(join(lines_of(s))).distribution;
  EXPECT_EQ(d.opening.shape, photometry::OpeningShape::Rectangular);
  s.dims = {"120", "60", "30", "0", "0", "0", "0", "0", "0"};
  d = parse_ok(join(lines_of(s))).distribution;
  EXPECT_EQ(d.opening.shape, photometry::OpeningShape::Point);
}

// Which horizontal axis each format's length lies along: EULUMDAT's
// luminous length along C90–C270 (a linear luminaire's lamp axis, CIE 190's
// model of the side faces), LM-63's along the 0–180° plane (LM-63-2002: the
// width "as measured along the 90-270 degree photometric plane", the length
// along 0-180). Read from photometric-viewer's files with side heights
// (../shared/corpus), through IES and back, and into the luminance the side
// faces give.
TEST(LdtRead, LengthAndWidthKeepTheirAxesThroughIes) {
  GONIO_REQUIRE_CORPUS();
  const auto path = test::corpus_dir() / "photometric-viewer" /
                    "rectangular_luminaire_rectangular_luminous_opening_with_heights.ldt";
  if (!std::filesystem::is_regular_file(path)) GONIO_MISSING(path.string());
  auto f = read_ldt(path.string());
  ASSERT_TRUE(f.ok()) << f.error().message;
  const Distribution& d = f->distribution;
  // Fields 13-21: luminaire 120 × 60 × 30, luminous area 50 × 40, side
  // heights 11, 12, 13, 14 mm (C0, C90, C180, C270).
  EXPECT_EQ(d.opening.shape, photometry::OpeningShape::RectangularWithSides);
  EXPECT_DOUBLE_EQ(d.opening.width_m, 0.050);   // the file's length: along C90–C270
  EXPECT_DOUBLE_EQ(d.opening.length_m, 0.040);  // the file's width: along C0–C180
  EXPECT_DOUBLE_EQ(d.luminaire.width_m, 0.120);
  EXPECT_DOUBLE_EQ(d.luminaire.length_m, 0.060);
  // The face toward C0 is as broad as the C90–C270 extent, 50 mm, and 11 mm
  // high; the one toward C90 is 40 mm broad and 12 mm high.
  const double s60 = std::sin(60 * std::numbers::pi / 180);
  EXPECT_NEAR(photometry::projected_area_m2(d.opening, 0, 60), 0.002 * 0.5 + 0.050 * 0.011 * s60, 1e-12);
  EXPECT_NEAR(photometry::projected_area_m2(d.opening, 90, 60), 0.002 * 0.5 + 0.040 * 0.012 * s60, 1e-12);
  EXPECT_NEAR(photometry::projected_area_m2(d.opening, 180, 60), 0.002 * 0.5 + 0.050 * 0.013 * s60, 1e-12);
  EXPECT_NEAR(photometry::projected_area_m2(d.opening, 270, 60), 0.002 * 0.5 + 0.040 * 0.014 * s60, 1e-12);
  // To LM-63: width (90-270) 0.05 m, length (0-180) 0.04 m; and back.
  std::vector<Finding> notes;
  const std::string ies = write_ies(d, {}, &notes);
  auto back_ies = parse_ies(ies, "converted.ies", "");
  ASSERT_TRUE(back_ies.ok()) << back_ies.error().message;
  EXPECT_NEAR(back_ies->distribution.opening.width_m, 0.050, 1e-9);
  EXPECT_NEAR(back_ies->distribution.opening.length_m, 0.040, 1e-9);
  Distribution via_ies = back_ies->distribution;
  auto ldt = write_ldt(via_ies, {}, &notes);
  ASSERT_TRUE(ldt.ok()) << ldt.error().message;
  const Distribution again = parse_ok(*ldt).distribution;
  EXPECT_NEAR(again.opening.width_m, 0.050, 1e-9);
  EXPECT_NEAR(again.opening.length_m, 0.040, 1e-9);
  // As the file writes it: field 16 (length) 50, field 17 (width) 40.
  std::vector<std::string> lines;
  std::stringstream in(*ldt);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_GT(lines.size(), 17u);
  EXPECT_EQ(std::stod(lines[15]), 50.0);
  EXPECT_EQ(std::stod(lines[16]), 40.0);
}

TEST(LdtRead, DecimalCommasLatin1CrlfAndBlanks) {
  Spec s = small_spec();
  s.company = "Leuchten M\xfcller \xb0";  // Latin-1
  s.dg = "45,0";
  s.lorl = " 72,5 \t";
  s.sets = {{"1 ", " T16 28W", "2600,0", "840", "1B", "31,5"}};
  std::vector<std::string> l = lines_of(s);
  l.back() = "  123,25  ";
  for (const std::string eol : {"\r\n", "\n", "\r"}) {
    const LdtFile f = parse_ok(join(l, eol));
    const Distribution& d = f.distribution;
    EXPECT_EQ(keyword(d, "MANUFAC"), "Leuchten M\xc3\xbcller \xc2\xb0");
    EXPECT_EQ(d.declared_lor_percent, 72.5);
    EXPECT_EQ(d.lamps[0].type, "T16 28W");
    EXPECT_EQ(d.lamps[0].flux_lm, 2600.0);
    EXPECT_EQ(d.lamps[0].power_w, 31.5);
    EXPECT_DOUBLE_EQ(d.candela.back(), 123.25 * 2.6);
  }
  // A UTF-8 byte order mark and UTF-8 text are accepted as well.
  s.company = "Leuchten M\xc3\xbcller";
  const LdtFile u = parse_ok("\xEF\xBB\xBF" + join(lines_of(s)));
  EXPECT_EQ(keyword(u.distribution, "MANUFAC"), "Leuchten M\xc3\xbcller");
}

TEST(LdtRead, EmptyTextFieldsGiveNoKeywords) {
  Spec s = small_spec();
  s.company = s.report = s.name = s.number = s.file = s.date = "";
  const Distribution d = parse_ok(join(lines_of(s))).distribution;
  EXPECT_TRUE(d.keywords.empty());
}

TEST(LdtRead, NotesWhatDoesNotFit) {
  Spec s = small_spec();
  s.dc = "90";
  s.c = {0, 90, 180, 300};
  s.company = std::string(90, 'x');
  std::vector<std::string> l = lines_of(s);
  l.push_back("");
  l.push_back("garbage after the data");
  const LdtFile f = parse_ok(join(l));
  const Finding* dc = finding(f.findings, "ldt-dc-mismatch");
  ASSERT_NE(dc, nullptr);
  EXPECT_EQ(dc->where.line, 5);
  EXPECT_EQ(dc->where.file, "test.ldt");
  const Finding* trailing = finding(f.findings, "ldt-trailing-lines");
  ASSERT_NE(trailing, nullptr);
  EXPECT_EQ(trailing->where.line, static_cast<int>(l.size()));
  const Finding* longer = finding(f.findings, "ldt-field-too-long");
  ASSERT_NE(longer, nullptr);
  EXPECT_EQ(longer->where.line, 1);
}

// Each reader warning fires on a file crafted for it, alone, on its line.
struct WarningCase {
  const char* code;
  int line;
  void (*edit)(Spec&);
};

TEST(LdtRead, EachWarningNamesItsLine) {
  const WarningCase cases[] = {
      {"ldt-dff-range", 22, [](Spec& s) { s.dff = "120"; }},
      {"ldt-dff-range", 22, [](Spec& s) { s.dff = "-5"; }},
      {"ldt-lorl-range", 23, [](Spec& s) { s.lorl = "100,5"; }},
      {"ldt-lorl-range", 23, [](Spec& s) { s.lorl = "-1"; }},
      {"ldt-dg-mismatch", 7, [](Spec& s) { s.dg = "40"; }},  // gamma 0, 45, 90
      {"ldt-dc-mismatch", 5, [](Spec& s) { s.dc = "45"; }},  // C 0, 90, 180, 270
      // Set 1 alone decides absolute photometry; set 2's count is on line 33.
      {"ldt-lamp-count-sign", 33,
       [](Spec& s) { s.sets.push_back({"-1", "LED", "2000", "", "", "20"}); }},
      {"ldt-lamp-count-sign", 33,
       [](Spec& s) {
         s.sets[0].count = "-2";
         s.sets.push_back({"1", "LED", "2000", "", "", "20"});
       }},
      {"ldt-first-plane-not-c0", 43, [](Spec& s) { s.c = {10, 100, 190, 280}; }},
      {"ldt-conversion-factor-zero", 24, [](Spec& s) { s.cfli = "0"; }},
      {"ldt-negative-intensity", 50, [](Spec& s) { s.values[0] = -1; }},
      {"ldt-ityp-isym-mismatch", 3, [](Spec& s) { s.ityp = "1"; }},
  };
  ASSERT_TRUE(parse_ok(join(lines_of(small_spec()))).findings.empty());
  for (const WarningCase& c : cases) {
    SCOPED_TRACE(c.code);
    Spec s = small_spec();
    c.edit(s);
    const LdtFile f = parse_ok(join(lines_of(s)));
    ASSERT_EQ(f.findings.size(), 1u);
    EXPECT_EQ(f.findings[0].code, c.code) << f.findings[0].message;
    EXPECT_EQ(f.findings[0].severity, Severity::Warning);
    EXPECT_EQ(f.findings[0].where.file, "test.ldt");
    EXPECT_EQ(f.findings[0].where.line, c.line) << f.findings[0].message;
  }
}

TEST(LdtRead, TwentyLampSetsAreReadMoreAreRefused) {
  Spec s = small_spec();
  s.sets.clear();
  for (int i = 1; i <= kMaxLdtLampSets; ++i)
    s.sets.push_back({"1", "Set " + std::to_string(i), std::to_string(1000 + i), "", "", "10"});
  const LdtFile f = parse_ok(join(lines_of(s)));
  EXPECT_TRUE(f.findings.empty()) << f.findings[0].message;
  const Distribution& d = f.distribution;
  ASSERT_EQ(d.lamps.size(), 1u);
  ASSERT_EQ(d.alternative_lamps.size(), 19u);
  EXPECT_EQ(d.alternative_lamps.back().type, "Set 20");
  EXPECT_EQ(d.alternative_lamps.back().flux_lm, 1020.0);
  EXPECT_DOUBLE_EQ(d.at(0, 0), s.values[0] * 1.001);  // set 1 scales

  // The standard's field 26 holds 1-20: a 21st set is an error on line 26,
  // before any set is read.
  s.sets.push_back({"1", "Set 21", "1021", "", "", "10"});
  const Error e = parse_error(join(lines_of(s)));
  EXPECT_EQ(e.where.line, 26);
  EXPECT_NE(e.message.find("number of lamp sets (1-20), found '21'"), std::string::npos)
      << e.message;
}

TEST(LdtRead, NegativeIntensitiesReadAsZeroWithAWarningNamingTheFirst) {
  // As the IES reader does: one stray value does not cost the whole file.
  Spec s = small_spec();
  s.values[1] = -3;    // C 0, gamma 45: line 51
  s.values[10] = -0.5;  // C 270, gamma 45
  const LdtFile f = parse_ok(join(lines_of(s)));
  const Distribution& d = f.distribution;
  EXPECT_EQ(d.at(0, 1), 0.0);
  EXPECT_EQ(d.at(3, 1), 0.0);
  EXPECT_DOUBLE_EQ(d.at(0, 0), s.values[0] * 4.0);  // the others as read
  EXPECT_DOUBLE_EQ(d.at(3, 2), s.values[11] * 4.0);
  ASSERT_EQ(f.findings.size(), 1u);
  const Finding& w = f.findings[0];
  EXPECT_EQ(w.code, "ldt-negative-intensity");
  EXPECT_EQ(w.severity, Severity::Warning);
  EXPECT_EQ(w.where.file, "test.ldt");
  EXPECT_EQ(w.where.line, 51);
  EXPECT_NE(w.message.find("2 negative"), std::string::npos) << w.message;
  EXPECT_NE(w.message.find("the first at C 0, gamma 45"), std::string::npos) << w.message;
  // What was read can be written: the file holds no negative value any more.
  auto text = write_ldt(d, {}, nullptr);
  ASSERT_TRUE(text.ok()) << to_string(text.error());
  EXPECT_TRUE(parse_ok(*text).findings.empty());

  // No negative value, no warning; -0 is not negative.
  s = small_spec();
  s.values[4] = -0.0;
  EXPECT_FALSE(has_finding(parse_ok(join(lines_of(s))).findings, "ldt-negative-intensity"));
}

// ------------------------------------------------------------ Ityp

TEST(LdtRead, TypeIndicatorZeroIsAcceptedAndKept) {
  Spec s = small_spec();
  s.ityp = "0";
  const LdtFile f = parse_ok(join(lines_of(s)));
  EXPECT_EQ(f.distribution.ldt_type_indicator, 0);
  EXPECT_FALSE(has_finding(f.findings, "ldt-ityp-isym-mismatch"));
  std::vector<Finding> w;
  auto text = write_ldt(f.distribution, {}, &w);
  ASSERT_TRUE(text.ok());
  EXPECT_EQ(split_lines(*text)[1].text, "0");
  EXPECT_EQ(parse_ok(*text).distribution.ldt_type_indicator, 0);
}

TEST(LdtRead, TypeIndicatorThatContradictsSymmetryIsAWarning) {
  Spec s = small_spec();
  s.ityp = "1";  // rotationally symmetric, but Isym 0
  const LdtFile f = parse_ok(join(lines_of(s)));
  const Finding* w = finding(f.findings, "ldt-ityp-isym-mismatch");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->where.line, 3);
  EXPECT_EQ(f.distribution.ldt_type_indicator, 1);  // kept as read
}

TEST(LdtRead, TypeIndicatorZeroWithSymmetryIsAWarningAndKept) {
  // Ityp 0 is a point source without symmetry: Isym 2 contradicts it.
  Spec s = small_spec();
  s.ityp = "0";
  s.isym = "2";
  s.values.resize(3 * 3);  // C0, C90, C180
  const LdtFile f = parse_ok(join(lines_of(s)));
  ASSERT_EQ(f.findings.size(), 1u) << f.findings[0].message;
  const Finding& w = f.findings[0];
  EXPECT_EQ(w.code, "ldt-ityp-isym-mismatch");
  EXPECT_EQ(w.severity, Severity::Warning);
  EXPECT_EQ(w.where.line, 3);
  EXPECT_NE(w.message.find("Ityp 0 does not fit Isym 2"), std::string::npos) << w.message;
  EXPECT_EQ(f.distribution.symmetry, Symmetry::C0_C180);  // Isym decides the planes
  EXPECT_EQ(f.distribution.ldt_type_indicator, 0);
  // Kept through LDT -> LDT, as read.
  auto text = write_ldt(f.distribution, {}, nullptr);
  ASSERT_TRUE(text.ok());
  EXPECT_EQ(split_lines(*text)[1].text, "0");
  EXPECT_EQ(split_lines(*text)[2].text, "2");
}

TEST(LdtWrite, TypeIndicatorZeroIsNeverDerived) {
  // A model without an Ityp (from IES) gets 1 (rotational) or 3, never 0,
  // which several readers reject, even without symmetry.
  Spec s = small_spec();
  Distribution d = parse_ok(join(lines_of(s))).distribution;
  ASSERT_EQ(d.symmetry, Symmetry::None);
  d.ldt_type_indicator.reset();
  auto text = write_ldt(d, {}, nullptr);
  ASSERT_TRUE(text.ok());
  EXPECT_EQ(split_lines(*text)[1].text, "3");
}

// ------------------------------------------------------------ symmetries

TEST(LdtSymmetry, Isym1StoresOnePlane) {
  Spec s;
  s.isym = "1";
  s.ityp = "1";
  s.dc = "90";
  s.c = {0, 90, 180, 270};
  s.g = {0, 30, 60, 90};
  s.values = {400, 300, 200, 100};
  const LdtFile f = parse_ok(join(lines_of(s)));
  EXPECT_EQ(f.distribution.symmetry, Symmetry::Rotational);
  EXPECT_EQ(f.distribution.horizontal_deg, std::vector<double>{0.0});
  EXPECT_DOUBLE_EQ(f.distribution.at(0, 1), 300 * 4.0);
  EXPECT_TRUE(f.findings.empty());
}

TEST(LdtSymmetry, Isym0WithASinglePlaneIsReadAsRotational) {
  Spec s;
  s.ityp = "0";
  s.c = {0};
  s.g = {0, 90};
  s.values = {10, 5};
  const LdtFile f = parse_ok(join(lines_of(s)));
  EXPECT_EQ(f.distribution.symmetry, Symmetry::Rotational);
  EXPECT_TRUE(has_finding(f.findings, "ldt-single-plane"));
}

// Builds a file with the given Isym from asym(), storing the planes the
// standard lists, and checks that every direction reads asym() back after
// symmetry expansion (asym() is made symmetric the way Isym says).
void check_isym(int isym, double (*fold)(double), Symmetry expected) {
  Spec s;
  s.isym = std::to_string(isym);
  s.dc = "15";
  s.c = steps(0, 15, 345);
  s.g = steps(0, 10, 180);
  s.sets = {{"1", "LED", "1000", "", "", "10"}};  // scale 1
  const std::size_t mc = s.c.size();
  std::vector<std::size_t> planes;
  if (isym == 2)
    for (std::size_t i = 0; i <= mc / 2; ++i) planes.push_back(i);
  if (isym == 3)
    for (std::size_t i = 3 * mc / 4; i <= 3 * mc / 4 + mc / 2; ++i) planes.push_back(i % mc);
  if (isym == 4)
    for (std::size_t i = 0; i <= mc / 4; ++i) planes.push_back(i);
  for (std::size_t p : planes)
    for (double g : s.g) s.values.push_back(asym(fold(s.c[p]), g));
  const LdtFile f = parse_ok(join(lines_of(s)));
  const Distribution& d = f.distribution;
  EXPECT_EQ(d.symmetry, expected);
  ASSERT_TRUE(photometry::validate(d).ok());
  const Distribution e = photometry::expand_symmetry(d);
  for (double c = 0; c < 360; c += 15)
    for (double g = 10; g < 180; g += 10)
      EXPECT_NEAR(photometry::interpolate(e, c, g), asym(fold(c), g), 1e-9)
          << "Isym " << isym << " at C " << c << ", gamma " << g;
}

TEST(LdtSymmetry, Isym2StoresC0ToC180) {
  check_isym(
      2, [](double c) { return c <= 180 ? c : 360 - c; }, Symmetry::C0_C180);
}

TEST(LdtSymmetry, Isym4StoresC0ToC90) {
  check_isym(
      4,
      [](double c) {
        c = c <= 180 ? c : 360 - c;
        return c <= 90 ? c : 180 - c;
      },
      Symmetry::Quadrant);
}

TEST(LdtSymmetry, Isym3StoresC270ThroughC0ToC90) {
  // asym() folded onto C270…C360…C90 by the mirror C -> 180 - C.
  check_isym(
      3,
      [](double c) {
        if (c > 90 && c < 270) c = 180 - c;
        return c < 0 ? c + 360 : c;
      },
      Symmetry::C90_C270);
}

TEST(LdtSymmetry, Isym3PlanesLandOnTheStandardsHalf) {
  // Mc = 4: C list 0, 90, 180, 270; the standard stores C270, C0, C90.
  Spec s;
  s.isym = "3";
  s.c = {0, 90, 180, 270};
  s.g = {0, 90};
  s.sets = {{"1", "LED", "1000", "", "", "10"}};
  s.values = {270, 271, 0, 1, 90, 91};  // values name their plane
  const Distribution d = parse_ok(join(lines_of(s))).distribution;
  ASSERT_EQ(d.symmetry, Symmetry::C90_C270);
  EXPECT_EQ(d.horizontal_deg, (std::vector<double>{90, 180, 270}));
  EXPECT_EQ(d.at(0, 0), 90);   // C90 holds the C90 data
  EXPECT_EQ(d.at(1, 0), 0);    // C180 mirrors C0
  EXPECT_EQ(d.at(2, 1), 271);  // C270 holds the C270 data
  const Distribution e = photometry::expand_symmetry(d);
  EXPECT_DOUBLE_EQ(photometry::interpolate(e, 0, 90), 1);
  EXPECT_DOUBLE_EQ(photometry::interpolate(e, 90, 90), 91);
  EXPECT_DOUBLE_EQ(photometry::interpolate(e, 180, 90), 1);
  EXPECT_DOUBLE_EQ(photometry::interpolate(e, 270, 90), 271);

  // QLumEdit's order: C90, C180, C270.
  LdtReadOptions q;
  q.isym3_order = LdtIsym3Order::C90_C180_C270;
  s.values = {90, 91, 180, 181, 270, 271};
  const Distribution dq = parse_ok(join(lines_of(s)), q).distribution;
  EXPECT_EQ(dq.at(0, 0), 90);
  EXPECT_EQ(dq.at(1, 0), 180);
  EXPECT_EQ(dq.at(2, 1), 271);
}

TEST(LdtSymmetry, Isym3NonEquidistantPlanes) {
  // The grid of a road luminaire: dense along the road (C0/C180), Dc = 0.
  Spec s;
  s.isym = "3";
  s.c = {0, 10, 20, 45, 90, 135, 160, 170, 180, 190, 200, 225, 270, 315, 340, 350};
  s.g = {0, 45, 90};
  s.sets = {{"1", "LED", "1000", "", "", "10"}};
  const std::vector<double> stored = {270, 315, 340, 350, 0, 10, 20, 45, 90};
  for (double c : stored)
    for (double g : s.g) s.values.push_back(asym(c, g));
  const Distribution d = parse_ok(join(lines_of(s))).distribution;
  EXPECT_EQ(d.horizontal_deg, (std::vector<double>{90, 135, 160, 170, 180, 190, 200, 225, 270}));
  const Distribution e = photometry::expand_symmetry(d);
  for (double c : stored)
    for (double g : {45.0, 90.0}) EXPECT_NEAR(photometry::interpolate(e, c, g), asym(c, g), 1e-9);
}

// ------------------------------------------------------------ writer

Distribution model_c0_c180() {
  Distribution d;
  d.symmetry = Symmetry::C0_C180;
  d.horizontal_deg = steps(0, 30, 180);
  d.vertical_deg = steps(0, 15, 180);
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg) d.candela.push_back(asym(c, g) * 3.7);
  photometry::LampSet l;
  l.count = 2;
  l.type = "LED 840";
  l.flux_lm = 3700;
  l.color = "4000 K";
  l.color_rendering = "Ra 85";
  l.power_w = 29.5;
  d.lamps = {l};
  d.keywords = {{"TEST", "T-1"},
                {"MANUFAC", "ACME"},
                {"LUMCAT", "X-1"},
                {"LUMINAIRE", "Wall washer"},
                {"ISSUEDATE", "2024-06-01"},
                {kLdtFileNameKeyword, "ww.ldt"}};
  d.luminaire = {0.6, 0.1, 0.05};
  d.opening.shape = photometry::OpeningShape::Rectangular;
  d.opening.length_m = 0.5;
  d.opening.width_m = 0.08;
  d.opening.height_m = 0;
  for (double& h : d.opening.side_height_m) h = 0;
  d.declared_dff_percent = 70;
  d.declared_lor_percent = 81.5;
  d.measurement_tilt_deg = 0;
  d.direct_ratios = {0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6, 0.65, 0.7, 0.75};
  d.ldt_type_indicator = 3;
  return d;
}

void expect_same_candela(const Distribution& a, const Distribution& b, double rel) {
  ASSERT_EQ(a.horizontal_deg.size(), b.horizontal_deg.size());
  for (std::size_t i = 0; i < a.horizontal_deg.size(); ++i)
    EXPECT_NEAR(a.horizontal_deg[i], b.horizontal_deg[i], 1e-9);
  ASSERT_EQ(a.vertical_deg, b.vertical_deg);
  ASSERT_EQ(a.candela.size(), b.candela.size());
  for (std::size_t i = 0; i < a.candela.size(); ++i)
    EXPECT_NEAR(a.candela[i], b.candela[i], rel * std::abs(a.candela[i])) << i;
}

// Found by tests/fuzz/ldt_fuzzer.cpp: control characters the reader
// accepts in a text field (here 70 in a long company name) were written
// back into the much shorter file, which the reader then refused as binary
// data.
TEST(LdtWrite, FuzzFoundControlCharactersInTextFieldsAreWrittenAsSpaces) {
  std::vector<std::string> l = lines_of(small_spec());
  l[0] = "ACME" + std::string(70, '\x14') + "Licht" + std::string(8000, 'x');
  const LdtFile f = parse_ok(join(l));
  std::vector<Finding> notes;
  auto written = write_ldt(f.distribution, {}, &notes);
  ASSERT_TRUE(written.ok()) << written.error().message;
  EXPECT_TRUE(has_finding(notes, "ldt-control-characters"));
  EXPECT_EQ(written->find('\x14'), std::string::npos);
  const LdtFile again = parse_ok(*written);
  EXPECT_EQ(again.distribution.candela, f.distribution.candela);
}

// Found by tests/fuzz/ldt_fuzzer.cpp: an intensity the reader accepts in
// exponent form (1.5e70 cd/klm) was written as 71 digits, more than the 64
// characters the reader takes for a number. It is written in exponent form.
TEST(LdtWrite, FuzzFoundHugeValuesAreWrittenSoThatTheyReadBack) {
  std::vector<std::string> l = lines_of(small_spec());
  l[49] = "1.5e70";
  const LdtFile f = parse_ok(join(l));
  auto written = write_ldt(f.distribution, {}, nullptr);
  ASSERT_TRUE(written.ok()) << written.error().message;
  const LdtFile again = parse_ok(*written);
  ASSERT_EQ(again.distribution.candela.size(), f.distribution.candela.size());
  for (std::size_t i = 0; i < f.distribution.candela.size(); ++i)
    EXPECT_NEAR(again.distribution.candela[i], f.distribution.candela[i], 1e-11 * std::abs(f.distribution.candela[i]));
}

// Found by tests/fuzz/ldt_fuzzer.cpp: a company line "\x05<tabs>IESNA…"
// was read (the control character is no blank), written with the control
// character as a space, and the file read back trimmed to "IESNA…", which
// the reader took for an IES file. The reader now looks at the line as it
// stands; the writer puts a company name that starts like an IES file after
// a space, so that it reads back unchanged.
TEST(LdtWrite, FuzzFoundACompanyThatStartsLikeAnIesFileReadsBack) {
  for (const std::string& company : {std::string("\x05\t\tIESNA\t"), std::string("IESNA Labs"),
                                    std::string("IES:LM-63 test house")}) {
    std::vector<std::string> l = lines_of(small_spec());
    l[0] = " " + company;  // read: the leading space keeps it EULUMDAT
    const LdtFile f = parse_ok(join(l));
    auto written = write_ldt(f.distribution, {}, nullptr);
    ASSERT_TRUE(written.ok()) << written.error().message;
    const LdtFile again = parse_ok(*written);
    if (company[0] != '\x05') {
      EXPECT_EQ(keyword(again.distribution, "MANUFAC"), company);
    }
    EXPECT_EQ(again.distribution.candela, f.distribution.candela);
  }
  // Found by the fuzzer in CI: in a Latin-1 file (one that is not UTF-8: the
  // "\xE9" at the end), a company " \xEF\xBB\xBFIES:LM-63 …" reads as
  // "ï»¿IES:LM-63 …"; written back as those bytes at the start of the file,
  // the reader took them for a UTF-8 byte order mark, dropped them and saw an
  // IES file. The writer decides on the bytes it writes: a space goes first.
  for (const std::string& company : {std::string("\xEF\xBB\xBFIES:LM-63 test house \xE9"),
                                    std::string("\xEF\xBB\xBF" "Acme \xE9")}) {
    std::vector<std::string> l = lines_of(small_spec());
    l[0] = " " + company;  // read: the leading space keeps the bytes company text
    const LdtFile f = parse_ok(join(l));
    const std::string read = keyword(f.distribution, "MANUFAC");
    auto written = write_ldt(f.distribution, {}, nullptr);
    ASSERT_TRUE(written.ok()) << written.error().message;
    EXPECT_EQ(written->substr(0, 1), " ");
    const LdtFile again = parse_ok(*written);
    EXPECT_EQ(keyword(again.distribution, "MANUFAC"), read);
  }
  // An IES file's own first line is still refused, saying what it is.
  std::vector<std::string> l = lines_of(small_spec());
  l[0] = "IESNA:LM-63-2002";
  auto r = parse_ldt(join(l), "x.ldt");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("IES LM-63 file"), std::string::npos) << r.error().message;
}

TEST(LdtWrite, RoundTripKeepsEveryField) {
  const Distribution d = model_c0_c180();
  std::vector<Finding> w;
  auto text = write_ldt(d, {}, &w);
  ASSERT_TRUE(text.ok()) << to_string(text.error());
  EXPECT_TRUE(w.empty()) << w[0].message;
  const LdtFile f = parse_ok(*text);
  const Distribution& r = f.distribution;
  EXPECT_TRUE(f.findings.empty()) << f.findings[0].message;
  EXPECT_EQ(r.symmetry, d.symmetry);
  expect_same_candela(d, r, 1e-11);
  EXPECT_EQ(r.keywords.size(), d.keywords.size());
  for (const auto& k : d.keywords) EXPECT_EQ(keyword(r, k.key), k.value) << k.key;
  EXPECT_EQ(r.lamps[0].count, 2);
  EXPECT_EQ(r.lamps[0].type, "LED 840");
  EXPECT_EQ(r.lamps[0].flux_lm, 3700);
  EXPECT_EQ(r.lamps[0].color, "4000 K");
  EXPECT_EQ(r.lamps[0].color_rendering, "Ra 85");
  EXPECT_EQ(r.lamps[0].power_w, 29.5);
  EXPECT_DOUBLE_EQ(r.luminaire.length_m, 0.6);
  EXPECT_DOUBLE_EQ(r.luminaire.width_m, 0.1);
  EXPECT_DOUBLE_EQ(r.luminaire.height_m, 0.05);
  EXPECT_EQ(r.opening.shape, photometry::OpeningShape::Rectangular);
  EXPECT_DOUBLE_EQ(r.opening.length_m, 0.5);
  EXPECT_DOUBLE_EQ(r.opening.width_m, 0.08);
  EXPECT_EQ(r.declared_dff_percent, 70);
  EXPECT_EQ(r.declared_lor_percent, 81.5);
  EXPECT_EQ(r.direct_ratios, d.direct_ratios);
  EXPECT_EQ(r.ldt_type_indicator, 3);
  EXPECT_FALSE(r.absolute);

  // Written again, the bytes do not change.
  auto again = write_ldt(r, {}, nullptr);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(*again, *text);
}

TEST(LdtWrite, FixedLayoutCrlfLatin1) {
  Distribution d = model_c0_c180();
  d.set_keyword("MANUFAC", "Leuchten M\xc3\xbcller");
  auto text = write_ldt(d, {}, nullptr);
  ASSERT_TRUE(text.ok());
  for (std::size_t i = 0; i < text->size(); ++i) {
    if ((*text)[i] == '\n') {
      EXPECT_TRUE(i > 0 && (*text)[i - 1] == '\r') << i;
    }
    if ((*text)[i] == '\r') {
      EXPECT_TRUE(i + 1 < text->size() && (*text)[i + 1] == '\n') << i;
    }
  }
  const auto lines = split_lines(*text);
  EXPECT_EQ(lines[0].text, "Leuchten M\xfcller");  // Latin-1 byte
  EXPECT_EQ(lines[1].text, "3");                   // Ityp
  EXPECT_EQ(lines[2].text, "2");                   // Isym
  EXPECT_EQ(lines[3].text, "12");                  // Mc: C 0…330
  EXPECT_EQ(lines[4].text, "30");                  // Dc
  EXPECT_EQ(lines[5].text, "13");                  // Ng
  EXPECT_EQ(lines[6].text, "15");                  // Dg
  EXPECT_EQ(lines[7].text, "T-1");
  EXPECT_EQ(lines[10].text, "ww.ldt");
  EXPECT_EQ(lines[11].text, "2024-06-01");
  // The model's luminaire is 0.6 m along C0 and 0.1 m along C90; EULUMDAT's
  // length (field 13) lies along C90–C270, its width (14) along C0–C180.
  EXPECT_EQ(lines[12].text, "100");
  EXPECT_EQ(lines[13].text, "600");
  EXPECT_EQ(lines[15].text, "80");   // luminous length: the opening's 0.08 m along C90
  EXPECT_EQ(lines[16].text, "500");  // luminous width: its 0.5 m along C0
  EXPECT_EQ(lines[23].text, "1");  // conversion factor
  EXPECT_EQ(lines[25].text, "1");  // one lamp set
  EXPECT_EQ(lines[26].text, "2");  // lamps
  EXPECT_EQ(lines[28].text, "3700");
  // 42 header lines, 12 C angles, 13 γ angles, 7 stored planes × 13 values.
  EXPECT_EQ(lines.size(), 42u + 12 + 13 + 7 * 13);
  EXPECT_EQ(lines[42 + 11].text, "330");
}

TEST(LdtWrite, PrintsNumbersToTheChosenPrecision) {
  Distribution d = model_c0_c180();
  d.candela[1] = 1234.56789012345678 * 3.7;
  auto text = write_ldt(d, {}, nullptr);
  ASSERT_TRUE(text.ok());
  const auto lines = split_lines(*text);
  EXPECT_EQ(lines[42 + 12 + 13 + 1].text, "1234.56789012");  // 12 significant digits
  LdtWriteOptions o;
  o.significant_digits = 4;
  text = write_ldt(d, o, nullptr);
  ASSERT_TRUE(text.ok());
  EXPECT_EQ(split_lines(*text)[42 + 12 + 13 + 1].text, "1235");
  o.significant_digits = 17;
  text = write_ldt(d, o, nullptr);
  ASSERT_TRUE(text.ok());
  const Distribution r = parse_ok(*text).distribution;
  expect_same_candela(d, r, 5e-16);
  o.significant_digits = 0;
  EXPECT_FALSE(write_ldt(d, o, nullptr).ok());
}

TEST(LdtWrite, EquidistantAnglesGiveDcAndDgElseZero) {
  Distribution d = model_c0_c180();
  d.horizontal_deg = {0, 20, 90, 170, 180};
  d.vertical_deg = {0, 5, 30, 90, 180};
  d.candela.assign(25, 100.0);
  auto text = write_ldt(d, {}, nullptr);
  ASSERT_TRUE(text.ok());
  const auto lines = split_lines(*text);
  EXPECT_EQ(lines[3].text, "8");  // 0 20 90 170 180 190 270 340
  EXPECT_EQ(lines[4].text, "0");
  EXPECT_EQ(lines[6].text, "0");
  const Distribution r = parse_ok(*text).distribution;
  expect_same_candela(d, r, 1e-11);
}

TEST(LdtWrite, Isym3RoundTripOfAnAsymmetricDistribution) {
  Distribution d = model_c0_c180();
  d.symmetry = Symmetry::C90_C270;
  d.horizontal_deg = steps(90, 15, 270);
  d.candela.clear();
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg) d.candela.push_back(asym(c, g) * 3.7);
  auto text = write_ldt(d, {}, nullptr);
  ASSERT_TRUE(text.ok());
  const auto lines = split_lines(*text);
  EXPECT_EQ(lines[2].text, "3");
  EXPECT_EQ(lines[3].text, "24");
  // The first stored plane is C270, the 8th (index 6) C0, the last C90.
  const std::size_t first = 42 + 24 + 13, nv = 13;
  EXPECT_NEAR(std::stod(std::string(lines[first + 5].text)), asym(270, 75), 1e-8);
  EXPECT_NEAR(std::stod(std::string(lines[first + 6 * nv + 5].text)), asym(180, 75), 1e-8);
  EXPECT_NEAR(std::stod(std::string(lines[first + 12 * nv + 5].text)), asym(90, 75), 1e-8);
  expect_same_candela(d, parse_ok(*text).distribution, 1e-11);

  // QLumEdit's order writes C90 first and reads back the same.
  LdtWriteOptions wq;
  wq.isym3_order = LdtIsym3Order::C90_C180_C270;
  LdtReadOptions rq;
  rq.isym3_order = LdtIsym3Order::C90_C180_C270;
  auto tq = write_ldt(d, wq, nullptr);
  ASSERT_TRUE(tq.ok());
  EXPECT_NEAR(std::stod(std::string(split_lines(*tq)[first + 5].text)), asym(90, 75), 1e-8);
  expect_same_candela(d, parse_ok(*tq, rq).distribution, 1e-11);
}

TEST(LdtWrite, GridsIsymCannotExpressAreWrittenWithoutSymmetry) {
  Distribution d = model_c0_c180();
  d.symmetry = Symmetry::C90_C270;
  d.horizontal_deg = steps(90, 20, 270);  // no C0 plane among the mirrors
  d.candela.clear();
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg) d.candela.push_back(asym(c, g));
  std::vector<Finding> w;
  auto text = write_ldt(d, {}, &w);
  ASSERT_TRUE(text.ok());
  EXPECT_TRUE(has_finding(w, "ldt-symmetry-expanded"));
  const Distribution r = parse_ok(*text).distribution;
  EXPECT_EQ(r.symmetry, Symmetry::None);
  const Distribution e = photometry::expand_symmetry(d);
  const Distribution er = photometry::expand_symmetry(r);
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg)
      EXPECT_NEAR(photometry::interpolate(er, c, g), photometry::interpolate(e, c, g),
                  1e-9 * asym(c, g));
}

TEST(LdtWrite, FullCircleFromIesDropsTheC360Plane) {
  Distribution d = model_c0_c180();
  d.symmetry = Symmetry::None;
  d.horizontal_deg = steps(0, 45, 360);
  d.candela.clear();
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg) d.candela.push_back(asym(c == 360 ? 0 : c, g));
  std::vector<Finding> w;
  auto text = write_ldt(d, {}, &w);
  ASSERT_TRUE(text.ok());
  EXPECT_FALSE(has_finding(w, "ldt-plane-360-dropped"));  // identical to C0
  const auto lines = split_lines(*text);
  EXPECT_EQ(lines[3].text, "8");
  const Distribution r = parse_ok(*text).distribution;
  EXPECT_EQ(r.horizontal_deg, steps(0, 45, 315));
  for (std::size_t i = 0; i < r.candela.size(); ++i)
    EXPECT_NEAR(r.candela[i], d.candela[i], 1e-11 * d.candela[i]);

  d.at(8, 3) += 1.0;  // C360 no longer a copy of C0
  w.clear();
  ASSERT_TRUE(write_ldt(d, {}, &w).ok());
  EXPECT_TRUE(has_finding(w, "ldt-plane-360-dropped"));
}

TEST(LdtWrite, AbsolutePhotometryWritesTheIntegratedLuminaireFlux) {
  // Isotropic 100 cd: Φ = 4π · 100 lm.
  Distribution d;
  d.symmetry = Symmetry::Rotational;
  d.horizontal_deg = {0};
  d.vertical_deg = steps(0, 5, 180);
  d.candela.assign(d.vertical_deg.size(), 100.0);
  d.absolute = true;
  photometry::LampSet l;
  l.count = 1;
  d.lamps = {l};
  std::vector<Finding> w;
  auto text = write_ldt(d, {}, &w);
  ASSERT_TRUE(text.ok());
  const auto lines = split_lines(*text);
  EXPECT_EQ(lines[2].text, "1");    // Isym
  EXPECT_EQ(lines[1].text, "1");    // Ityp derived: rotational
  EXPECT_EQ(lines[26].text, "-1");  // negative count: absolute
  // Stated to 6 significant digits (the candela are scaled by that value).
  EXPECT_EQ(lines[28].text, "1256.64");
  EXPECT_EQ(lines[22].text, "100");  // LORL of absolute photometry
  EXPECT_EQ(lines[21].text, "50");   // DFF of an isotropic source
  const Distribution r = parse_ok(*text).distribution;
  EXPECT_TRUE(r.absolute);
  expect_same_candela(d, r, 1e-11);
}

TEST(LdtWrite, ComputesLorlAndDffForModelsFromIes) {
  // Lambertian, I0 = 1000/π · 0.8 per 1000 lm of lamps: Φ = 800 lm, all down.
  Distribution d;
  d.symmetry = Symmetry::Quadrant;
  d.horizontal_deg = steps(0, 22.5, 90);
  d.vertical_deg = steps(0, 2.5, 180);
  for ([[maybe_unused]] double c : d.horizontal_deg)
    for (double g : d.vertical_deg)
      d.candela.push_back(g <= 90 ? 2000 / kPi * 0.8 * std::cos(g * kRad) : 0.0);
  photometry::LampSet l;
  l.count = 1;
  l.flux_lm = 2000;
  d.lamps = {l};
  d.keywords = {{"TEST", "1"}, {"TESTLAB", "Lab"}, {"OTHER", "x"}, {"LAMP", "LED"}, {"TEST", "2"}};
  std::vector<Finding> w;
  auto text = write_ldt(d, {}, &w);
  ASSERT_TRUE(text.ok());
  EXPECT_TRUE(has_finding(w, "ldt-computed-lorl"));
  EXPECT_TRUE(has_finding(w, "ldt-computed-dff"));
  int dropped = 0;
  for (const Finding& f : w)
    if (f.code == "ldt-keyword-dropped") {
      ++dropped;
      EXPECT_TRUE(f.message.find("[TESTLAB]") != std::string::npos ||
                  f.message.find("[OTHER]") != std::string::npos ||
                  f.message.find("repeated keyword [TEST]") != std::string::npos)
          << f.message;
    }
  EXPECT_EQ(dropped, 3);  // [LAMP] became the lamp type
  const auto lines = split_lines(*text);
  EXPECT_EQ(lines[1].text, "3");                                    // Ityp derived
  EXPECT_NEAR(std::stod(std::string(lines[22].text)), 80.0, 0.08);  // LORL within 0.1 %
  EXPECT_NEAR(std::stod(std::string(lines[21].text)), 100.0, 1e-9);
  EXPECT_EQ(lines[27].text, "LED");
  LdtWriteOptions o;
  o.type_indicator = 2;
  auto linear = write_ldt(d, o, nullptr);
  ASSERT_TRUE(linear.ok());
  EXPECT_EQ(split_lines(*linear)[1].text, "2");
}

TEST(LdtWrite, ReportsLm63FieldsItCannotHold) {
  Distribution d = model_c0_c180();
  std::vector<Finding> w;
  ASSERT_TRUE(write_ldt(d, {}, &w).ok());
  for (const char* code :
       {"ldt-tilt-dropped", "ldt-ballast-factor", "ldt-file-generation", "ldt-input-watts"})
    EXPECT_FALSE(has_finding(w, code)) << code;

  d.tilt.kind = photometry::Tilt::Kind::Include;
  d.tilt.lamp_geometry = 1;
  d.tilt.angles_deg = {0, 45, 90};
  d.tilt.factors = {1, 0.9, 0.8};
  d.ballast_factor = 0.95;
  d.ballast_lamp_factor = 0.9;
  d.file_generation = photometry::FileGenerationType::AccreditedLab;
  d.input_watts = 31.0;  // the lamp set says 29.5 W
  w.clear();
  auto text = write_ldt(d, {}, &w);
  ASSERT_TRUE(text.ok());
  for (const char* code :
       {"ldt-tilt-dropped", "ldt-ballast-factor", "ldt-file-generation", "ldt-input-watts"}) {
    const Finding* f = finding(w, code);
    ASSERT_NE(f, nullptr) << code;
    EXPECT_EQ(f->severity, Severity::Warning);
  }
  EXPECT_EQ(std::count_if(w.begin(), w.end(),
                          [](const Finding& f) { return f.code == "ldt-ballast-factor"; }),
            2);
  // EULUMDAT keeps the lamp set's wattage.
  EXPECT_EQ(parse_ok(*text).distribution.lamps[0].power_w, 29.5);
}

// Each writer finding fires on a model crafted for it, and the file says
// what the finding says.
struct WriteCase {
  const char* code;
  Severity severity;
  void (*edit)(Distribution&);
  void (*expect)(const std::vector<TextLine>& lines, const Distribution& back);
};

TEST(LdtWrite, EachFindingFiresOnItsModel) {
  const WriteCase cases[] = {
      {"ldt-first-plane-not-c0", Severity::Warning,
       [](Distribution& d) {
         d.symmetry = Symmetry::None;
         d.horizontal_deg = {10, 100, 190, 280};
         d.candela.resize(4 * d.vertical_count());
       },
       [](const std::vector<TextLine>& l, const Distribution& back) {
         EXPECT_EQ(l[2].text, "0");   // Isym
         EXPECT_EQ(l[42].text, "10");  // the first C angle, as the model has it
         EXPECT_EQ(back.horizontal_deg, (std::vector<double>{10, 100, 190, 280}));
       }},
      {"ldt-no-flux", Severity::Warning,
       [](Distribution& d) {
         d.absolute = true;
         d.lamps[0].flux_lm = photometry::kNaN;
         std::fill(d.candela.begin(), d.candela.end(), 0.0);
       },
       [](const std::vector<TextLine>& l, const Distribution& back) {
         EXPECT_EQ(l[26].text, "-2");    // absolute: negative lamp count
         EXPECT_EQ(l[28].text, "1000");  // relative to 1000 lm
         EXPECT_TRUE(back.absolute);
         EXPECT_EQ(photometry::total_flux_lm(back), 0.0);
       }},
      {"ldt-computed-flux", Severity::Info,
       [](Distribution& d) {
         d.absolute = true;
         d.lamps[0].flux_lm = photometry::kNaN;
       },
       [](const std::vector<TextLine>& l, const Distribution& back) {
         EXPECT_EQ(l[26].text, "-2");
         EXPECT_NEAR(std::stod(std::string(l[28].text)), photometry::total_flux_lm(back),
                     1e-5 * photometry::total_flux_lm(back));
       }},
      {"ldt-dimensions-unknown", Severity::Info,
       [](Distribution& d) { d.luminaire.height_m = photometry::kNaN; },
       [](const std::vector<TextLine>& l, const Distribution& back) {
         EXPECT_EQ(l[12].text, "100");  // EULUMDAT's length: the model's width (C90)
         EXPECT_EQ(l[13].text, "600");
         EXPECT_EQ(l[14].text, "0");  // unknown height
         EXPECT_EQ(back.luminaire.height_m, 0.0);
       }},
      {"ldt-too-many-lamp-sets", Severity::Warning,
       [](Distribution& d) {
         for (int i = 2; i <= kMaxLdtLampSets + 1; ++i) {
           photometry::LampSet alt = d.lamps[0];
           alt.type = "Set " + std::to_string(i);
           d.alternative_lamps.push_back(alt);
         }
       },
       [](const std::vector<TextLine>& l, const Distribution& back) {
         EXPECT_EQ(l[25].text, "20");
         ASSERT_EQ(back.alternative_lamps.size(), 19u);
         EXPECT_EQ(back.alternative_lamps.back().type, "Set 20");  // the 21st is left out
       }},
  };
  for (const WriteCase& c : cases) {
    SCOPED_TRACE(c.code);
    Distribution d = model_c0_c180();
    std::vector<Finding> w;
    ASSERT_TRUE(write_ldt(d, {}, &w).ok());
    ASSERT_FALSE(has_finding(w, c.code));
    c.edit(d);
    ASSERT_TRUE(photometry::validate(d).ok());
    w.clear();
    auto text = write_ldt(d, {}, &w);
    ASSERT_TRUE(text.ok()) << to_string(text.error());
    ASSERT_EQ(w.size(), 1u) << w[0].code << ": " << w[0].message;
    EXPECT_EQ(w[0].code, c.code) << w[0].message;
    EXPECT_EQ(w[0].severity, c.severity);
    c.expect(split_lines(*text), parse_ok(*text).distribution);
  }
}

TEST(LdtWrite, TwentyLampSetsAreWrittenWithoutAWarning) {
  Distribution d = model_c0_c180();
  for (int i = 2; i <= kMaxLdtLampSets; ++i) {
    photometry::LampSet alt = d.lamps[0];
    alt.type = "Set " + std::to_string(i);
    alt.flux_lm = 1000.0 + i;
    d.alternative_lamps.push_back(alt);
  }
  std::vector<Finding> w;
  auto text = write_ldt(d, {}, &w);
  ASSERT_TRUE(text.ok());
  EXPECT_TRUE(w.empty()) << w[0].message;
  EXPECT_EQ(split_lines(*text)[25].text, "20");
  const Distribution r = parse_ok(*text).distribution;
  ASSERT_EQ(r.alternative_lamps.size(), 19u);
  for (std::size_t i = 0; i < 19; ++i) {
    EXPECT_EQ(r.alternative_lamps[i].type, d.alternative_lamps[i].type);
    EXPECT_EQ(r.alternative_lamps[i].flux_lm, d.alternative_lamps[i].flux_lm);
  }
  expect_same_candela(d, r, 1e-11);
}

TEST(LdtWrite, ComputesMissingDirectRatiosFromTheDistribution) {
  Distribution d = model_c0_c180();
  d.direct_ratios.clear();  // as read from IES
  std::vector<Finding> w;
  auto text = write_ldt(d, {}, &w);
  ASSERT_TRUE(text.ok());
  const Finding* note = finding(w, "ldt-direct-ratios");
  ASSERT_NE(note, nullptr);
  EXPECT_EQ(note->severity, Severity::Info);
  const auto expected = photometry::direct_ratios(d);
  const Distribution r = parse_ok(*text).distribution;
  ASSERT_EQ(r.direct_ratios.size(), 10u);
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_NEAR(r.direct_ratios[i], expected[i], 1e-11) << i;
    if (i > 0) {
      EXPECT_GE(r.direct_ratios[i], r.direct_ratios[i - 1]);  // grows with k
    }
  }
  // Below the downward flux fraction, which they approach for large rooms.
  EXPECT_LE(r.direct_ratios[9], photometry::downward_flux_lm(d) / photometry::total_flux_lm(d));
  EXPECT_GT(r.direct_ratios[0], 0.0);

  d.direct_ratios = {0.5, 0.6};  // not ten: a warning, and computed ones instead
  w.clear();
  ASSERT_TRUE(write_ldt(d, {}, &w).ok());
  ASSERT_NE(finding(w, "ldt-direct-ratios"), nullptr);
  EXPECT_EQ(finding(w, "ldt-direct-ratios")->severity, Severity::Warning);
}

TEST(LdtWrite, TruncatesLongTextWithAWarning) {
  Distribution d = model_c0_c180();
  d.set_keyword("LUMINAIRE", std::string(100, 'L'));
  d.set_keyword(kLdtFileNameKeyword, "a_long_file_name.ldt");
  d.lamps[0].type = std::string(30, 'T');
  d.set_keyword("LUMCAT", "two\nlines");
  d.set_keyword("TEST", "\xe2\x82\xac 5");  // the euro sign is not Latin-1
  std::vector<Finding> w;
  auto text = write_ldt(d, {}, &w);
  ASSERT_TRUE(text.ok());
  const auto lines = split_lines(*text);
  EXPECT_EQ(lines[8].text, std::string(78, 'L'));
  EXPECT_EQ(lines[10].text, "a_long_file_");
  EXPECT_EQ(lines[27].text, std::string(24, 'T'));
  EXPECT_EQ(lines[9].text, "two lines");
  EXPECT_EQ(lines[7].text, "? 5");
  int truncated = 0;
  for (const Finding& f : w) truncated += f.code == "ldt-truncated";
  EXPECT_EQ(truncated, 3);
  EXPECT_TRUE(has_finding(w, "ldt-multiline"));
  EXPECT_TRUE(has_finding(w, "ldt-not-latin1"));
}

TEST(LdtWrite, AlternativeLampSetsRoundTripAndMergedSetsAreReported) {
  Distribution d = model_c0_c180();
  photometry::LampSet alt = d.lamps[0];
  alt.type = "Alternative";
  alt.flux_lm = 5000;
  d.alternative_lamps = {alt};
  auto text = write_ldt(d, {}, nullptr);
  ASSERT_TRUE(text.ok());
  const Distribution r = parse_ok(*text).distribution;
  ASSERT_EQ(r.alternative_lamps.size(), 1u);
  EXPECT_EQ(r.alternative_lamps[0].type, "Alternative");
  EXPECT_EQ(r.alternative_lamps[0].flux_lm, 5000);
  expect_same_candela(d, r, 1e-11);

  // Two sets lit together (not an EULUMDAT notion) become one set of the
  // summed flux, so the candela stay right.
  Distribution two = model_c0_c180();
  two.lamps[0].flux_lm = 1700;
  photometry::LampSet b = two.lamps[0];
  b.flux_lm = 2000;
  b.count = 1;
  two.lamps.push_back(b);
  std::vector<Finding> w;
  text = write_ldt(two, {}, &w);
  ASSERT_TRUE(text.ok());
  EXPECT_TRUE(has_finding(w, "ldt-lamp-sets-merged"));
  const Distribution r2 = parse_ok(*text).distribution;
  EXPECT_EQ(r2.lamps[0].count, 3);
  EXPECT_EQ(r2.lamps[0].flux_lm, 3700);
  expect_same_candela(two, r2, 1e-11);
}

TEST(LdtWrite, RefusesWhatEulumdatCannotHold) {
  Distribution d = model_c0_c180();
  d.type = photometry::PhotometricType::B;
  d.symmetry = Symmetry::None;
  d.horizontal_deg = {-90, 0, 90};
  d.vertical_deg = {-90, 0, 90};
  d.candela.assign(9, 1.0);
  auto r = write_ldt(d, {}, nullptr);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("Type C"), std::string::npos);

  Distribution no_lamps = model_c0_c180();
  no_lamps.lamps.clear();
  EXPECT_FALSE(write_ldt(no_lamps, {}, nullptr).ok());

  Distribution negative = model_c0_c180();
  negative.at(2, 12) = -1e-4;
  r = write_ldt(negative, {}, nullptr);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("C 60, gamma 180 is negative"), std::string::npos)
      << r.error().message;

  Distribution invalid = model_c0_c180();
  invalid.candela.pop_back();
  EXPECT_FALSE(write_ldt(invalid, {}, nullptr).ok());

  LdtWriteOptions o;
  o.type_indicator = 4;
  EXPECT_FALSE(write_ldt(model_c0_c180(), o, nullptr).ok());
}

// ------------------------------------------------------------ VALIDATION.md

TEST(LdtValidation, RelativeIntensitiesIntegrateToTheLightOutputRatio) {
  // cd/klm of a Lambertian luminaire of LORL 80 %: I = 800/π cos γ.
  Spec s;
  s.isym = "2";
  s.dc = "5";
  s.dg = "2.5";
  s.lorl = "80";
  s.c = steps(0, 5, 355);
  s.g = steps(0, 2.5, 180);
  for (std::size_t p = 0; p <= 36; ++p)
    for (double g : s.g) s.values.push_back(g <= 90 ? 800 / kPi * std::cos(g * kRad) : 0);
  s.sets = {{"3", "T5", "5400", "", "", "80"}};
  const Distribution d = parse_ok(join(lines_of(s))).distribution;
  const double phi_lamps = d.rated_lamp_flux_lm();
  const double cd_per_klm_integral =
      photometry::total_flux_lm(d) / (phi_lamps / 1000);
  EXPECT_NEAR(cd_per_klm_integral / 1000, d.declared_lor_percent / 100, 0.001);
}

// ------------------------------------------------------------ bad input

TEST(LdtBadInput, EveryTruncationNamesTheMissingLine) {
  const std::vector<std::string> lines = lines_of(small_spec());
  for (std::size_t n = 0; n < lines.size(); ++n) {
    std::vector<std::string> head(lines.begin(), lines.begin() + static_cast<std::ptrdiff_t>(n));
    const Error e = parse_error(join(head));
    EXPECT_EQ(e.where.file, "bad.ldt");
    EXPECT_EQ(e.where.line, static_cast<int>(n) + 1) << e.message;
    if (n > 0) {
      EXPECT_NE(e.message.find("expected "), std::string::npos) << e.message;
      EXPECT_NE(e.message.find("found the end of the file"), std::string::npos) << e.message;
    }
  }
  EXPECT_NE(parse_error("").message.find("empty"), std::string::npos);
  // A file cut in the middle of the intensities says which value is missing.
  std::vector<std::string> cut = lines;
  cut.resize(cut.size() - 2);
  const Error e = parse_error(join(cut));
  EXPECT_NE(e.message.find("intensity at C 270, gamma 45"), std::string::npos) << e.message;
}

struct BadCase {
  const char* what;
  int line;              // 1-based line that must be named
  const char* fragment;  // text the message must contain
  void (*edit)(Spec&, std::vector<std::string>&);
};

TEST(LdtBadInput, EachFieldNamesLineAndExpectation) {
  const BadCase cases[] = {
      {"absurd Mc", 4, "number of C-planes Mc (1-1440), found '1000000000'",
       [](Spec&, std::vector<std::string>& l) { l[3] = "1000000000"; }},
      {"absurd Ng", 6, "per C-plane Ng (1-1801), found '1e9'",
       [](Spec&, std::vector<std::string>& l) { l[5] = "1e9"; }},
      {"negative Mc", 4, "found '-5'", [](Spec&, std::vector<std::string>& l) { l[3] = "-5"; }},
      {"negative Ng", 6, "found '-1'", [](Spec&, std::vector<std::string>& l) { l[5] = "-1"; }},
      {"zero lamp sets", 26, "number of lamp sets (1-20), found '0'",
       [](Spec&, std::vector<std::string>& l) { l[25] = "0"; }},
      {"negative lamp sets", 26, "number of lamp sets (1-20), found '-1'",
       [](Spec&, std::vector<std::string>& l) { l[25] = "-1"; }},
      {"too many lamp sets", 26, "(1-20), found '21'",
       [](Spec&, std::vector<std::string>& l) { l[25] = "21"; }},
      {"Ityp 7", 2, "type indicator Ityp (0-3), found '7'",
       [](Spec&, std::vector<std::string>& l) { l[1] = "7"; }},
      {"Isym 1.5", 3, "symmetry indicator Isym (0-4), found '1.5'",
       [](Spec&, std::vector<std::string>& l) { l[2] = "1.5"; }},
      {"text for Dc", 5, "distance between C-planes Dc [deg] (0-360), found 'fifteen'",
       [](Spec&, std::vector<std::string>& l) { l[4] = "fifteen"; }},
      {"empty DFF", 22, "downward flux fraction DFF [%], found an empty line",
       [](Spec&, std::vector<std::string>& l) { l[21] = "  "; }},
      {"two numbers", 23, "found '80 81'",
       [](Spec&, std::vector<std::string>& l) { l[22] = "80 81"; }},
      {"negative dimension", 14, "width of the luminaire [mm] (0 for round) (>= 0), found '-300'",
       [](Spec&, std::vector<std::string>& l) { l[13] = "-300"; }},
      {"negative conversion factor", 24, "conversion factor",
       [](Spec&, std::vector<std::string>& l) { l[23] = "-1"; }},
      {"zero lamps", 27, "number of lamps of lamp set 1 (non-zero)",
       [](Spec&, std::vector<std::string>& l) { l[26] = "0"; }},
      {"zero lamp flux", 29, "total luminous flux of lamp set 1 [lm]",
       [](Spec&, std::vector<std::string>& l) { l[28] = "0"; }},
      {"NaN intensity", 50, "intensity at C 0, gamma 0 [cd/klm], found 'nan'",
       [](Spec&, std::vector<std::string>& l) { l[49] = "nan"; }},
      {"inf intensity", 51, "found 'inf'",
       [](Spec&, std::vector<std::string>& l) { l[50] = "inf"; }},
      {"-inf intensity", 52, "intensity at C 0, gamma 90 [cd/klm], found '-inf'",
       [](Spec&, std::vector<std::string>& l) { l[51] = "-inf"; }},
      {"unsorted C", 45, "C angles must increase: 90 follows 180",
       [](Spec&, std::vector<std::string>& l) { std::swap(l[43], l[44]); }},
      {"unsorted gamma", 49, "gamma angles must increase: 45 follows 90",
       [](Spec&, std::vector<std::string>& l) { std::swap(l[47], l[48]); }},
      {"gamma beyond 180", 49, "gamma angle 3 of 3 [deg] (0-180), found '190'",
       [](Spec&, std::vector<std::string>& l) { l[48] = "190"; }},
      {"C beyond 360", 46, "found '400'",
       [](Spec&, std::vector<std::string>& l) { l[45] = "400"; }},
      {"Isym 4 with Mc 30", 4,
       "Isym 4 (symmetry to the C0-C180 and C90-C270 planes) needs an Mc divisible by 4, found Mc "
       "= 30",
       [](Spec&, std::vector<std::string>& l) {
         l[2] = "4";
         l[3] = "30";
       }},
      {"Isym 2 with Mc 3", 4, "needs an even Mc, found Mc = 3",
       [](Spec&, std::vector<std::string>& l) {
         l[2] = "2";
         l[3] = "3";
       }},
      {"Isym 2 without C180 in place", 45, "needs C angle 3 to be 180, found 200",
       [](Spec&, std::vector<std::string>& l) {
         l[2] = "2";
         l[44] = "200";
       }},
      {"Isym 3 without C270 in place", 46, "needs C angle 4 to be 270, found 300",
       [](Spec&, std::vector<std::string>& l) {
         l[2] = "3";
         l[45] = "300";
       }},
      {"IES file", 1, "IES LM-63 file",
       [](Spec&, std::vector<std::string>& l) { l[0] = "IESNA:LM-63-2002"; }},
  };
  for (const BadCase& c : cases) {
    Spec s = small_spec();
    std::vector<std::string> l = lines_of(s);
    ASSERT_EQ(l[42], "0");  // C angles begin at line 43, γ at 47, intensities at 50
    ASSERT_EQ(l[49], num(s.values[0]));
    c.edit(s, l);
    test::offer_fuzz_seed("ldt", join(l));
    auto r = parse_ldt(join(l), "bad.ldt");
    ASSERT_FALSE(r.ok()) << c.what;
    EXPECT_EQ(r.error().where.line, c.line) << c.what << ": " << to_string(r.error());
    EXPECT_NE(r.error().message.find(c.fragment), std::string::npos)
        << c.what << ": " << to_string(r.error());
    EXPECT_EQ(to_string(r.error()).rfind("bad.ldt:" + std::to_string(c.line) + ": ", 0), 0u)
        << to_string(r.error());
  }
}

TEST(LdtBadInput, BinaryJunkDirectoriesAndMissingFiles) {
  const Error elf = parse_error(std::string("\x7f"
                                            "ELF\x02\x01\x01\0\0\0\0",
                                            12));
  EXPECT_NE(elf.message.find("binary"), std::string::npos);
  EXPECT_EQ(elf.where.line, 1);
  EXPECT_EQ(parse_error(std::string("Company\r\n1\r\n\0\0\0\0\0\0\0\0\0", 21)).where.line, 3);
  std::string junk;
  std::mt19937 rng(7);
  for (int i = 0; i < 4096; ++i) junk.push_back(static_cast<char>(rng() & 0xFF));
  EXPECT_FALSE(parse_ldt(junk, "junk.ldt").ok());

  test::TempDir dir;
  auto r = read_ldt(dir.path().string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("directory"), std::string::npos);
  r = read_ldt((dir / "missing.ldt").string());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where.file, (dir / "missing.ldt").string());

  test::write_file(dir / "ok.ldt", join(lines_of(small_spec())));
  r = read_ldt((dir / "ok.ldt").string());
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->distribution.horizontal_count(), 4u);
}

TEST(LdtBadInput, EndlessLinesAreRefusedBeforeTheyAreIndexed) {
  const std::string lines(kMaxLdtLines + 1, '\n');
  const Error e = parse_error(join(lines_of(small_spec())) + lines);
  EXPECT_NE(e.message.find("longer than any EULUMDAT file"), std::string::npos) << e.message;
}

TEST(LdtBadInput, MutatedFilesNeverCrash) {
  // Deterministic mutations of a valid file: each parse either succeeds with
  // a valid model or fails with an error that names a line.
  const std::vector<std::string> base = lines_of(small_spec());
  std::mt19937 rng(2024);
  const std::vector<std::string> tokens = {"",  "-1", "0",   "1e9",      "nan",
                                           "x", "3",  "2,5", "\x01\x02", "999999999999",
                                           "4", "-0", "360", "180.0"};
  int parsed = 0;
  for (int iter = 0; iter < 3000; ++iter) {
    std::vector<std::string> l = base;
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int k = 0; k < edits; ++k) {
      const std::size_t i = rng() % l.size();
      switch (rng() % 4) {
        case 0: l[i] = tokens[rng() % tokens.size()]; break;
        case 1: l.erase(l.begin() + static_cast<std::ptrdiff_t>(i)); break;
        case 2: l.insert(l.begin() + static_cast<std::ptrdiff_t>(i), l[rng() % l.size()]); break;
        default:
          if (!l[i].empty()) l[i][rng() % l[i].size()] = static_cast<char>(rng() & 0xFF);
      }
      if (l.empty()) l.push_back("");
    }
    auto r = parse_ldt(join(l), "fuzz.ldt");
    if (r.ok()) {
      ++parsed;
      EXPECT_TRUE(photometry::validate(r->distribution).ok());
      auto w = write_ldt(r->distribution, {}, nullptr);
      EXPECT_TRUE(w.ok()) << (w.ok() ? "" : w.error().message);
    } else {
      EXPECT_FALSE(r.error().message.empty());
      EXPECT_EQ(r.error().where.file, "fuzz.ldt");
    }
  }
  EXPECT_GT(parsed, 0);
}

}  // namespace
}  // namespace gonio::io
