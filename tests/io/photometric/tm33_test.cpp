#include "io/photometric/tm33.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include "io/photometric/ies.h"
#include "io/photometric/photometric_file.h"
#include "photometry/flux.h"
#include "tests/support/photometry_fixtures.h"
#include "tests/io/photometric/tm33_test_support.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

using photometry::Distribution;
using photometry::PhotometricType;
using photometry::Symmetry;

constexpr double kDeg = std::numbers::pi / 180.0;

using tm33_test::find;
using tm33_test::keyword;
using tm33_test::parse;

// A TM-33-23 document as a manufacturer might write it: two emitters of
// 500 lm each, I = 2 × 100 (1 + 0.5 cos C) cos γ below the horizon on
// C 0…180 (Symm_Bi_0) × γ 0…180 every 45°, multiplier 2, with a spectrum
// and radiant data Gonio does not keep.
std::string sample_document() {
  std::string s =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<IESTM33-22>\n"
      "  <Version>1.1</Version>\n"
      "  <Header>\n"
      "    <Manufacturer>ACME &amp; Sons</Manufacturer>\n"
      "    <CatalogNumber>DL-2</CatalogNumber>\n"
      "    <GTIN>4012345678901</GTIN>\n"
      "    <Description>Downlight</Description>\n"
      "    <Laboratory>Lab</Laboratory>\n"
      "    <ReportNumber>R-17</ReportNumber>\n"
      "    <ReportDate>2024-05-06</ReportDate>\n"
      "    <Comment>first</Comment>\n"
      "    <Comment>second</Comment>\n"
      "  </Header>\n"
      "  <Luminaire>\n"
      "    <Dimensions><Length>0.3</Length><Width>0.2</Width><Height>0.1</Height></Dimensions>\n"
      "    <NumEmitter>1</NumEmitter>\n"
      "  </Luminaire>\n"
      "  <Equipment><Gonioradiometer><Type>CIE_C</Type></Gonioradiometer></Equipment>\n"
      "  <Emitter>\n"
      "    <Quantity>2</Quantity>\n"
      "    <Description>LED module</Description>\n"
      "    <RatedLumens>500</RatedLumens>\n"
      "    <InputWattage>10</InputWattage>\n"
      "    <PowerFactor>0.95</PowerFactor>\n"
      "    <ColorTemperature><FixedCCT>3000</FixedCCT></ColorTemperature>\n"
      "    <ColorRendering><CIE_CRI><Ra>80</Ra><R9>20</R9></CIE_CRI></ColorRendering>\n"
      "    <DataGeneration><Simulation>false</Simulation><IntensityScaling>true</IntensityScaling>"
      "</DataGeneration>\n"
      "    <LuminousData>\n"
      "      <LuminousIntensity>\n"
      "        <AbsolutePhotometry>false</AbsolutePhotometry>\n"
      "        <Symm>Symm_Bi_0</Symm>\n"
      "        <Multiplier>2</Multiplier>\n"
      "        <NumberMeasured>25</NumberMeasured>\n"
      "        <NumberHorz>5</NumberHorz>\n"
      "        <NumberVert>5</NumberVert>\n";
  for (int c = 0; c <= 180; c += 45)
    for (int g = 0; g <= 180; g += 45) {
      const double v = g < 90 ? 100.0 * (1.0 + 0.5 * std::cos(c * kDeg)) * std::cos(g * kDeg) : 0.0;
      s += "        <IntData h=\"" + std::to_string(c) + "\" v=\"" + std::to_string(g) + "\">" +
           format_ies_number(v) + "</IntData>\n";
    }
  s +=
      "      </LuminousIntensity>\n"
      "    </LuminousData>\n"
      "    <RadiantData><MinWavelength>380</MinWavelength></RadiantData>\n"
      "    <SpectralData>\n"
      "      <EmitterSpectral>\n"
      "        <EmitterName>LED</EmitterName>\n"
      "        <NumberWavelength>3</NumberWavelength>\n"
      "        <Multiplier>0.5</Multiplier>\n"
      "        <PwrData w=\"500\">2</PwrData>\n"
      "        <PwrData w=\"450\">1</PwrData>\n"
      "        <PwrData w=\"550\">4</PwrData>\n"
      "      </EmitterSpectral>\n"
      "    </SpectralData>\n"
      "  </Emitter>\n"
      "</IESTM33-22>\n";
  return s;
}

TEST(Tm33, ReadsEveryPartOfADocument) {
  auto r = parse(sample_document(), "lamp.xml");
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  const Distribution& d = r->distribution;
  EXPECT_EQ(r->version, Tm33Version::TM33_23);
  EXPECT_EQ(d.type, PhotometricType::C);
  EXPECT_EQ(d.symmetry, Symmetry::C0_C180);
  EXPECT_EQ(d.horizontal_deg, (std::vector<double>{0, 45, 90, 135, 180}));
  EXPECT_EQ(d.vertical_deg, (std::vector<double>{0, 45, 90, 135, 180}));
  EXPECT_DOUBLE_EQ(d.at(0, 0), 2 * 150.0);  // multiplier applied
  EXPECT_DOUBLE_EQ(d.at(4, 0), 2 * 50.0);
  EXPECT_FALSE(d.absolute);
  ASSERT_EQ(d.lamps.size(), 1u);
  EXPECT_EQ(d.lamps[0].count, 2);
  EXPECT_DOUBLE_EQ(d.lamps[0].flux_lm, 1000.0);  // per emitter × quantity
  EXPECT_DOUBLE_EQ(d.input_watts, 20.0);
  EXPECT_EQ(d.lamps[0].type, "LED module");
  EXPECT_EQ(d.lamps[0].color, "3000 K");
  EXPECT_EQ(d.lamps[0].color_rendering, "80");
  EXPECT_DOUBLE_EQ(d.luminaire.length_m, 0.3);
  EXPECT_DOUBLE_EQ(d.luminaire.height_m, 0.1);
  EXPECT_EQ(d.file_generation, photometry::FileGenerationType::UnaccreditedLabScaled);
  EXPECT_EQ(keyword(d, "MANUFAC"), "ACME & Sons");
  EXPECT_EQ(keyword(d, "LUMCAT"), "DL-2");
  EXPECT_EQ(keyword(d, "LUMINAIRE"), "Downlight");
  EXPECT_EQ(keyword(d, "TEST"), "R-17");
  EXPECT_EQ(keyword(d, "ISSUEDATE"), "2024-05-06");
  EXPECT_EQ(keyword(d, "_TM33_HEADER_GTIN"), "4012345678901");
  EXPECT_EQ(keyword(d, "_TM33_EMITTER_POWERFACTOR"), "0.95");
  EXPECT_EQ(keyword(d, "_TM33_EMITTER_COLORRENDERING_CIE_CRI_R9"), "20");
  EXPECT_EQ(std::count_if(d.keywords.begin(), d.keywords.end(),
                          [](const photometry::Keyword& k) { return k.key == "OTHER"; }),
            2);
  ASSERT_EQ(d.spectra.size(), 1u);
  EXPECT_EQ(d.spectra[0].emitter, "LED");
  EXPECT_EQ(d.spectra[0].wavelength_nm, (std::vector<double>{450, 500, 550}));
  EXPECT_EQ(d.spectra[0].values, (std::vector<double>{0.5, 1, 2}));
  const Finding* radiant = find(r->findings, "tm33-not-kept");
  ASSERT_NE(radiant, nullptr);
  EXPECT_NE(radiant->message.find("RadiantData"), std::string::npos);
  EXPECT_EQ(radiant->where.file, "lamp.xml");
  EXPECT_EQ(radiant->where.line, 64);  // the line of <RadiantData>
  // Flux: the closed form of the grid's model is not needed here; the
  // distribution integrates like the same grid read from IES.
  EXPECT_GT(photometry::total_flux_lm(d), 0.0);
}

Distribution type_c(Symmetry symmetry, double c_first, double c_last, double c_step) {
  Distribution d = test::sample_c(symmetry, test::angles(c_first, c_last, c_step), test::angles(0, 180, 2.5),
                                  [](double c, double g) {
                                    if (g >= 90.0) return 0.0;
                                    return 1000.0 / 3.0 * (1.0 + 0.25 * std::cos(c * kDeg)) *
                                           std::pow(std::cos(g * kDeg), 1.5);
                                  });
  d.lamps = {photometry::LampSet{1, "LED", 2000.0, "4000 K", "Ra 90", 20.0}};
  d.keywords = {{"TEST", "T-9"}, {"TESTLAB", "Gonio"}, {"ISSUEDATE", "2025-02-03"}, {"MANUFAC", "Gonio"},
                {"LUMINAIRE", "Spot"}, {"FILEGENINFO", "written by a test"}, {"_USER", "kept"}};
  d.file_generation = photometry::FileGenerationType::ComputerSimulation;
  return d;
}

TEST(Tm33, WrittenFilesReadBackWithTheSameIntensitiesAndFlux) {
  std::vector<Distribution> cases = {
      type_c(Symmetry::None, 0, 350, 10), type_c(Symmetry::C0_C180, 0, 180, 15),
      type_c(Symmetry::C90_C270, 90, 270, 15), type_c(Symmetry::Quadrant, 0, 90, 5),
      type_c(Symmetry::Rotational, 0, 0, 1)};
  for (PhotometricType t : {PhotometricType::A, PhotometricType::B})
    for (Symmetry s : {Symmetry::None, Symmetry::Lateral}) {
      Distribution d;
      d.type = t;
      d.symmetry = s;
      d.horizontal_deg = s == Symmetry::Lateral ? test::angles(0, 90, 5) : test::angles(-90, 90, 5);
      d.vertical_deg = test::angles(-90, 90, 2.5);
      for (double h : d.horizontal_deg)
        for (double v : d.vertical_deg)
          d.candela.push_back(123.456789012345 * std::pow(std::cos(h * kDeg) * std::cos(v * kDeg), 8));
      d.absolute = true;
      d.lamps = {photometry::LampSet{}};
      cases.push_back(d);
    }
  for (const Distribution& d : cases) {
    SCOPED_TRACE(std::string(photometry::to_string(d.type)) + " " + photometry::to_string(d.symmetry));
    std::vector<Finding> w;
    const std::string xml = write_tm33(d, &w);
    auto r = parse(xml, "rt.xml");
    ASSERT_TRUE(r.ok()) << to_string(r.error());
    const Distribution& b = r->distribution;
    EXPECT_EQ(b.type, d.type);
    EXPECT_EQ(b.symmetry, d.symmetry);
    EXPECT_EQ(b.horizontal_deg, d.horizontal_deg);
    EXPECT_EQ(b.vertical_deg, d.vertical_deg);
    EXPECT_EQ(b.candela, d.candela);  // 15 significant digits read back exactly
    EXPECT_EQ(b.absolute, d.absolute);
    const double fa = photometry::total_flux_lm(d), fb = photometry::total_flux_lm(b);
    EXPECT_NEAR(fb, fa, 1e-12 * fa);
    if (!d.absolute) {
      EXPECT_EQ(b.lamps[0].flux_lm, d.lamps[0].flux_lm);
      EXPECT_EQ(b.input_watts, d.lamps[0].power_w);
      EXPECT_EQ(b.file_generation, d.file_generation);
      EXPECT_EQ(b.lamps[0].color, "4000 K");
      EXPECT_EQ(b.lamps[0].color_rendering, "90");
      for (const char* key : {"TEST", "TESTLAB", "ISSUEDATE", "MANUFAC", "LUMINAIRE", "FILEGENINFO", "_USER"})
        EXPECT_EQ(keyword(b, key), keyword(d, key)) << key;
      EXPECT_NE(find(w, "tm33-custom-keywords"), nullptr);
    }
    // Writing what was read gives the same document.
    EXPECT_EQ(write_tm33(b, nullptr), xml);
  }
}

TEST(Tm33, IesToTm33ToIesKeepsTheFileAndReportsWhatTm33Lacks) {
  Distribution d = type_c(Symmetry::C0_C180, 0, 180, 15);
  d.opening.shape = photometry::OpeningShape::Circular;
  d.opening.length_m = d.opening.width_m = 0.1;
  const std::string ies = write_ies(d, {}, nullptr);
  auto first = parse_ies(ies, "a.ies", ".");
  ASSERT_TRUE(first.ok());
  std::vector<Finding> w;
  auto back = parse(write_tm33(first->distribution, &w), "a.xml");
  ASSERT_TRUE(back.ok()) << to_string(back.error());
  EXPECT_EQ(back->distribution.candela, first->distribution.candela);
  const Finding* opening = find(w, "tm33-opening");
  ASSERT_NE(opening, nullptr);
  EXPECT_EQ(opening->severity, Severity::Warning);
  // And back to IES: the spectrum-free distribution loses nothing else.
  auto again = parse_ies(write_ies(back->distribution, {}, nullptr), "b.ies", ".");
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->distribution.candela, first->distribution.candela);
  EXPECT_EQ(keyword(again->distribution, "_USER"), "kept");
  EXPECT_EQ(again->distribution.lamps[0].flux_lm, first->distribution.lamps[0].flux_lm);
}

TEST(Tm33, SpectraAreKeptThroughTm33AndReportedWhereDropped) {
  auto r = parse(sample_document(), "lamp.xml");
  ASSERT_TRUE(r.ok());
  auto again = parse(write_tm33(r->distribution, nullptr), "again.xml");
  ASSERT_TRUE(again.ok()) << to_string(again.error());
  ASSERT_EQ(again->distribution.spectra.size(), 1u);
  EXPECT_EQ(again->distribution.spectra[0].values, r->distribution.spectra[0].values);
  EXPECT_EQ(keyword(again->distribution, "_TM33_HEADER_GTIN"), "4012345678901");
  EXPECT_EQ(keyword(again->distribution, "_TM33_EQUIPMENT_GONIORADIOMETER_TYPE"), "CIE_C");
  for (PhotometricFormat f : {PhotometricFormat::Ies, PhotometricFormat::Ldt}) {
    std::vector<Finding> w;
    ASSERT_TRUE(encode_photometric_file(r->distribution, f, {}, &w).ok());
    EXPECT_NE(find(w, "spectrum-dropped"), nullptr) << to_string(f);
  }
}

TEST(Tm33, AtlaS001RootIsReadAndRecognised) {
  std::string doc = sample_document();
  doc.replace(doc.find("<IESTM33-22>"), 12, "<IESTM33>");
  doc.replace(doc.find("</IESTM33-22>"), 13, "</IESTM33>");
  doc.replace(doc.find("<Version>1.1"), 12, "<Version>1.0");
  auto r = parse(doc, "old.xml");
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_EQ(r->version, Tm33Version::Atla_S001);
  EXPECT_TRUE(looks_like_tm33(doc));
  EXPECT_TRUE(looks_like_tm33(sample_document()));
  EXPECT_TRUE(looks_like_tm33("\xEF\xBB\xBF<!-- x --><!DOCTYPE a [<!ENTITY b \"c\">]>\n<t:IESTM33-22 xmlns:t=\"u\">"));
  EXPECT_FALSE(looks_like_tm33("<?xml version=\"1.0\"?><Root/>"));
  EXPECT_FALSE(looks_like_tm33("IESNA:LM-63-2002"));
}

struct Hostile {
  std::string name;
  std::string document;
  std::string says;
  int line;
};

std::string with(std::string doc, const std::string& from, const std::string& to) {
  const auto at = doc.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return doc.replace(at, from.size(), to);
}

TEST(Tm33, HostileDocumentsAreClearErrorsWithTheirLine) {
  const std::string good = sample_document();
  std::string deep = "<IESTM33-22>";
  for (int i = 0; i < 200; ++i) deep += "<a>";
  for (int i = 0; i < 200; ++i) deep += "</a>";
  deep += "</IESTM33-22>";
  const std::vector<Hostile> cases = {
      {"malformed", with(good, "</Header>", "</Heder>"), "malformed XML", 14},
      {"other root", "<?xml version=\"1.0\"?>\n<Root/>\n", "is not TM-33's", 2},
      {"no emitter", "<IESTM33-22><Version>1.1</Version><Header/></IESTM33-22>", "no <Emitter>", 1},
      {"count", with(good, "<NumberMeasured>25", "<NumberMeasured>24"), "<NumberMeasured> 24", 34},
      {"hole", with(good, "<IntData h=\"45\" v=\"90\">", "<IntData h=\"45\" v=\"91\">"), "<NumberVert> 5 but the data has 6", 36},
      {"twice", with(good, "<IntData h=\"45\" v=\"90\">", "<IntData h=\"45\" v=\"45\">"), "given twice", 44},
      {"not a number", with(good, ">500</RatedLumens>", ">five hundred</RatedLumens>"), "is not a number", 23},
      {"type", with(good, "CIE_C", "CUSTOM"), "photometric type 'CUSTOM'", 19},
      {"symm", with(good, "Symm_Bi_0", "Symm_Quad"), "<Symm> says quadrant", 32},
      {"deep", deep, "nested deeper than", 1},
  };
  for (const Hostile& c : cases) {
    SCOPED_TRACE(c.name);
    auto r = parse(c.document, "h.xml");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().where.file, "h.xml");
    EXPECT_EQ(r.error().where.line, c.line) << r.error().message;
    EXPECT_NE(r.error().message.find(c.says), std::string::npos) << r.error().message;
  }
}

// The "billion laughs": ten entities each ten times the one before. pugixml
// processes no DTD, so nothing is expanded: the reference stays the literal
// text "&lol9;", the reader says that is not a number, and it says so at once.
TEST(Tm33, EntityExpansionAndExternalEntitiesAreNeverExpanded) {
  std::string dtd = "<?xml version=\"1.0\"?>\n<!DOCTYPE IESTM33-22 [\n  <!ENTITY lol \"lol\">\n";
  for (int i = 1; i <= 9; ++i) {
    dtd += "  <!ENTITY lol" + std::to_string(i) + " \"";
    for (int j = 0; j < 10; ++j) dtd += "&lol" + (i == 1 ? std::string() : std::to_string(i - 1)) + ";";
    dtd += "\">\n";
  }
  dtd += "  <!ENTITY xxe SYSTEM \"file:///etc/passwd\">\n]>\n";
  std::string doc = sample_document();
  doc = doc.substr(doc.find("<IESTM33-22>"));
  const std::string bomb = dtd + with(doc, ">500</RatedLumens>", ">&lol9;</RatedLumens>");
  const auto start = std::chrono::steady_clock::now();
  auto r = parse(bomb, "bomb.xml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("'&lol9;' is not a number"), std::string::npos) << r.error().message;
  EXPECT_EQ(r.error().where.line, 36);
  // 10⁹ "lol"s would take gigabytes and seconds; not expanding takes neither.
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);

  const std::string external = dtd + with(doc, "<Description>Downlight", "<Description>&xxe;");
  auto x = parse(external, "xxe.xml");
  ASSERT_TRUE(x.ok()) << to_string(x.error());
  EXPECT_EQ(keyword(x->distribution, "LUMINAIRE"), "&xxe;");  // literally, /etc/passwd unread
}

TEST(Tm33, WriterReportsRequiredElementsItCannotFill) {
  Distribution d = type_c(Symmetry::Rotational, 0, 0, 1);
  d.keywords.clear();
  d.lamps[0].type.clear();
  d.lamps[0].power_w = photometry::kNaN;
  d.lamps[0].color = "warm white";
  std::vector<Finding> w;
  const std::string xml = write_tm33(d, &w);
  int required = 0;
  for (const Finding& f : w) required += f.code == "tm33-required-missing";
  EXPECT_EQ(required, 6);  // Description, Laboratory, ReportNumber, ReportDate, emitter Description, InputWattage
  EXPECT_NE(find(w, "tm33-lamp-color"), nullptr);
  EXPECT_NE(xml.find("<Laboratory>not stated</Laboratory>"), std::string::npos);
  EXPECT_EQ(xml.find("<InputWattage>"), std::string::npos);
}

}  // namespace
}  // namespace gonio::io
