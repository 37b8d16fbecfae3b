// The TM-33 layouts in circulation beside the standard's, each written here
// by the test (our own text, following the layout other tools write; the
// tools' files themselves are not committed: docs/formats.md "TM-33 files of other
// tools" lists which of them read). Each must read as the same distribution
// as the standard's layout of the same data.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>

#include "io/photometric/ies.h"
#include "io/photometric/tm33.h"
#include "photometry/flux.h"
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

// I = 100 (1 + 0.5 cos C) cos γ below the horizon [cd/klm], C 0…180
// (bilateral about C0) × γ 0…180 every 45°, as `element` elements with
// attributes h_name and v_name, times `scale` and halved (every layout below
// says multiplier 2). The luminaire: 2 emitters of 1000 lm.
std::string grid(const std::string& element, const std::string& h_name, const std::string& v_name,
                 double scale) {
  std::string s;
  for (int c = 0; c <= 180; c += 45)
    for (int g = 0; g <= 180; g += 45) {
      const double v = g < 90 ? scale * 50.0 * (1.0 + 0.5 * std::cos(c * kDeg)) * std::cos(g * kDeg) : 0.0;
      s += "      <" + element + " " + h_name + "=\"" + std::to_string(c) + "\" " + v_name + "=\"" +
           std::to_string(g) + "\">" + format_ies_number(v) + "</" + element + ">\n";
    }
  return s;
}

// The standard's layout (TM-33-23 as published: LuminousData/
// LuminousIntensity/IntData h v, SpectralData/EmitterSpectral/PwrData w);
// relative photometry in candelas for the rated 2 × 1000 lm.
std::string standard() {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<IESTM33-22>\n"
         "  <Version>1.1</Version>\n"
         "  <Header>\n"
         "    <Manufacturer>ACME</Manufacturer>\n"
         "    <CatalogNumber>DL-2</CatalogNumber>\n"
         "    <Description>Downlight</Description>\n"
         "    <Laboratory>Lab</Laboratory>\n"
         "    <ReportNumber>R-17</ReportNumber>\n"
         "    <ReportDate>2024-05-06</ReportDate>\n"
         "    <Comment>first</Comment>\n"
         "  </Header>\n"
         "  <Luminaire>\n"
         "    <Dimensions><Length>0.3</Length><Width>0.2</Width><Height>0.1</Height></Dimensions>\n"
         "    <NumEmitter>1</NumEmitter>\n"
         "  </Luminaire>\n"
         "  <Equipment><Gonioradiometer><Type>CIE_C</Type></Gonioradiometer></Equipment>\n"
         "  <Emitter>\n"
         "    <Quantity>2</Quantity>\n"
         "    <Description>LED module</Description>\n"
         "    <RatedLumens>1000</RatedLumens>\n"
         "    <InputWattage>10</InputWattage>\n"
         "    <ColorTemperature><FixedCCT>3000</FixedCCT></ColorTemperature>\n"
         "    <ColorRendering><CIE_CRI><Ra>80</Ra><R9>20</R9></CIE_CRI></ColorRendering>\n"
         "    <LuminousData>\n"
         "      <LuminousIntensity>\n"
         "      <AbsolutePhotometry>false</AbsolutePhotometry>\n"
         "      <Symm>Symm_Bi_0</Symm>\n"
         "      <Multiplier>2</Multiplier>\n" +
         grid("IntData", "h", "v", 2.0) +
         "      </LuminousIntensity>\n"
         "      <LuminousFlux>650</LuminousFlux>\n"
         "    </LuminousData>\n"
         "    <SpectralData><EmitterSpectral><Normalized>true</Normalized>\n"
         "      <PwrData w=\"450\">0.25</PwrData><PwrData w=\"500\">0.5</PwrData><PwrData w=\"550\">1</PwrData>\n"
         "    </EmitterSpectral></SpectralData>\n"
         "  </Emitter>\n"
         "</IESTM33-22>\n";
}

// TM-33-23 root with the intensities as <IntensityData horz vert> directly in
// <LuminousData> in cd/klm (eulumdat-rs's unit there), spectra as lists,
// dimensions in millimetres and the renamed elements eulumdat-rs writes (its
// crates/atla/tests/samples/tm33-23/).
std::string tm33_23_intensity_data() {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<IESTM33-22>\n"
         "    <Version>1.1</Version>\n"
         "    <Header>\n"
         "        <Manufacturer>ACME</Manufacturer>\n"
         "        <CatalogNumber>DL-2</CatalogNumber>\n"
         "        <Description>Downlight</Description>\n"
         "        <Laboratory>Lab</Laboratory>\n"
         "        <ReportNumber>R-17</ReportNumber>\n"
         "        <ReportDate>2024-05-06</ReportDate>\n"
         "        <UUID>urn:uuid:0</UUID>\n"
         "        <Comments>first</Comments>\n"
         "    </Header>\n"
         "    <Luminaire>\n"
         "        <Dimensions><Length>300</Length><Width>200</Width><Height>100</Height></Dimensions>\n"
         "        <Mounting>Recessed</Mounting>\n"
         "        <NumEmitters>1</NumEmitters>\n"
         "    </Luminaire>\n"
         "    <Equipment><Gonioradiometer><Type>CIE _ C</Type><Distance>10</Distance></Gonioradiometer></Equipment>\n"
         "    <Emitter>\n"
         "        <ID>led-1</ID>\n"
         "        <Description>LED module</Description>\n"
         "        <Quantity>2</Quantity>\n"
         "        <RatedLumens>1000</RatedLumens>\n"
         "        <InputWattage>10</InputWattage>\n"
         "        <FixedCCT>3000</FixedCCT>\n"
         "        <ColorRendering><Ra>80</Ra><R9>20</R9></ColorRendering>\n"
         "        <MeasuredLumens>650</MeasuredLumens>\n"
         "        <DataGeneration><Source>Measured</Source><Scaled>false</Scaled><Interpolated>false</Interpolated>"
         "</DataGeneration>\n"
         "        <LuminousData>\n"
         "            <PhotometryType>CIE _ C</PhotometryType>\n"
         "            <Metric>Luminous</Metric>\n"
         "            <SymmType>Symm _ Bi _ 0</SymmType>\n"
         "            <Multiplier>2</Multiplier>\n" +
         grid("IntensityData", "horz", "vert", 1.0) +
         "        </LuminousData>\n"
         "        <SpectralDistribution>\n"
         "            <Wavelengths>450 500 550</Wavelengths>\n"
         "            <Values>0.25 0.5 1</Values>\n"
         "            <Units>Relative</Units>\n"
         "        </SpectralDistribution>\n"
         "    </Emitter>\n"
         "</IESTM33-22>\n";
}

// ATLA S001 / UNI 11733 as eulumdat-rs writes it: root
// <LuminaireOpticalData version="1.0"> in a namespace, <Goniometer> with
// <GoniometerType>Type C</GoniometerType>, <IntensityDistribution>,
// <InputWatts>, <CCT>, <TestDate>; intensities in cd/klm.
std::string luminaire_optical_data() {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<LuminaireOpticalData version=\"1.0\" xmlns=\"http://www.ies.org/tm-33\">\n"
         "  <Header>\n"
         "    <Manufacturer>ACME</Manufacturer>\n"
         "    <CatalogNumber>DL-2</CatalogNumber>\n"
         "    <Description>Downlight</Description>\n"
         "    <Laboratory>Lab</Laboratory>\n"
         "    <ReportNumber>R-17</ReportNumber>\n"
         "    <TestDate>2024-01-15</TestDate>\n"
         "    <LuminaireType>Recessed</LuminaireType>\n"
         "    <Comments>first</Comments>\n"
         "  </Header>\n"
         "  <Luminaire>\n"
         "    <Dimensions><Length>300</Length><Width>200</Width><Height>100</Height></Dimensions>\n"
         "    <NumEmitters>1</NumEmitters>\n"
         "  </Luminaire>\n"
         "  <Equipment><Goniometer><GoniometerType>Type C</GoniometerType></Goniometer></Equipment>\n"
         "  <Emitter>\n"
         "    <ID>lamp-1</ID>\n"
         "    <Description>LED module</Description>\n"
         "    <Quantity>2</Quantity>\n"
         "    <RatedLumens>1000</RatedLumens>\n"
         "    <InputWatts>10</InputWatts>\n"
         "    <CCT>3000</CCT>\n"
         "    <ColorRendering><Ra>80</Ra></ColorRendering>\n"
         "    <SpectralDistribution>\n"
         "      <Wavelengths>450, 500, 550</Wavelengths>\n"
         "      <Values>0.25, 0.5, 1</Values>\n"
         "      <Units>Relative</Units>\n"
         "    </SpectralDistribution>\n"
         "    <IntensityDistribution>\n"
         "      <PhotometryType>C</PhotometryType>\n"
         "      <Metric>Luminous</Metric>\n"
         "      <Multiplier>2</Multiplier>\n" +
         grid("IntensityData", "horz", "vert", 1.0) +
         "    </IntensityDistribution>\n"
         "  </Emitter>\n"
         "</LuminaireOpticalData>\n";
}

// <IESTM33> (TM-33-18) as the DesignLights Consortium's template writes it:
// Version 1.1, booleans "False", the standard's IntData layout.
std::string iestm33_dlc_style() {
  std::string s = standard();
  s.replace(s.find("<IESTM33-22>"), 12, "<IESTM33>");
  s.replace(s.find("</IESTM33-22>"), 13, "</IESTM33>");
  s.replace(s.find("    <LuminousData>"), 18,
            "    <DataGeneration><IntensityScaling>False</IntensityScaling>"
            "<AngleInterpolation>False</AngleInterpolation></DataGeneration>\n    <LuminousData>");
  return s;
}

std::string replaced(std::string doc, const std::string& from, const std::string& to) {
  const auto at = doc.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return doc.replace(at, from.size(), to);
}

void expect_same_distribution(const Tm33File& got, const Tm33File& want) {
  const Distribution& a = got.distribution;
  const Distribution& b = want.distribution;
  EXPECT_EQ(a.type, b.type);
  EXPECT_EQ(a.symmetry, b.symmetry);
  EXPECT_EQ(a.horizontal_deg, b.horizontal_deg);
  EXPECT_EQ(a.vertical_deg, b.vertical_deg);
  // The same values, printed by format_ies_number at two scales.
  ASSERT_EQ(a.candela.size(), b.candela.size());
  for (std::size_t i = 0; i < a.candela.size(); ++i) EXPECT_NEAR(a.candela[i], b.candela[i], 1e-6 * b.candela[i]);
  EXPECT_NEAR(photometry::total_flux_lm(a), photometry::total_flux_lm(b), 1e-6 * photometry::total_flux_lm(b));
  EXPECT_EQ(a.absolute, b.absolute);
  ASSERT_EQ(a.lamps.size(), 1u);
  EXPECT_EQ(a.lamps[0].count, 2);
  EXPECT_DOUBLE_EQ(a.lamps[0].flux_lm, 2000.0);
  EXPECT_DOUBLE_EQ(a.input_watts, 20.0);
  EXPECT_EQ(a.lamps[0].type, "LED module");
  EXPECT_EQ(a.lamps[0].color, "3000 K");
  EXPECT_EQ(a.lamps[0].color_rendering, "80");
  EXPECT_DOUBLE_EQ(a.luminaire.length_m, 0.3);
  EXPECT_DOUBLE_EQ(a.luminaire.width_m, 0.2);
  EXPECT_DOUBLE_EQ(a.luminaire.height_m, 0.1);
  EXPECT_EQ(keyword(a, "MANUFAC"), "ACME");
  EXPECT_EQ(keyword(a, "OTHER"), "first");
  ASSERT_EQ(a.spectra.size(), 1u);
  EXPECT_TRUE(a.spectra[0].normalized);
  EXPECT_EQ(a.spectra[0].wavelength_nm, (std::vector<double>{450, 500, 550}));
  EXPECT_EQ(a.spectra[0].values, (std::vector<double>{0.25, 0.5, 1}));
}

TEST(Tm33Dialects, StandardLayoutReadsWithoutDialectNote) {
  auto r = parse(standard(), "standard.xml");
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_EQ(find(r->findings, "tm33-dialect"), nullptr);
  EXPECT_EQ(find(r->findings, "tm33-dimensions-mm"), nullptr);
  EXPECT_DOUBLE_EQ(r->distribution.at(0, 0), 300.0);
  EXPECT_EQ(r->distribution.symmetry, Symmetry::C0_C180);
}

TEST(Tm33Dialects, Tm3323WithIntensityDataInLuminousDataReadsAsTheStandardLayout) {
  auto want = parse(standard(), "standard.xml");
  auto got = parse(tm33_23_intensity_data(), "eulumdat-rs.xml");
  ASSERT_TRUE(want.ok()) << to_string(want.error());
  ASSERT_TRUE(got.ok()) << to_string(got.error());
  EXPECT_EQ(got->version, Tm33Version::TM33_23);
  expect_same_distribution(*got, *want);
  EXPECT_EQ(keyword(got->distribution, "_TM33_HEADER_UNIQUEIDENTIFIER"), "urn:uuid:0");
  EXPECT_EQ(keyword(got->distribution, "_TM33_EMITTER_COLORRENDERING_CIE_CRI_R9"), "20");
  EXPECT_EQ(keyword(got->distribution, "_TM33_EMITTER_LUMINOUSDATA_LUMINOUSFLUX"), "650");
  EXPECT_EQ(keyword(got->distribution, "_TM33_EQUIPMENT_GONIORADIOMETER_TYPE"), "CIE_C");
  EXPECT_EQ(got->distribution.file_generation, photometry::FileGenerationType::UnaccreditedLab);
  const Finding* note = find(got->findings, "tm33-dialect");
  ASSERT_NE(note, nullptr);
  EXPECT_EQ(note->severity, Severity::Info);
  EXPECT_NE(note->message.find("<IntensityData horz vert>"), std::string::npos) << note->message;
  EXPECT_NE(note->message.find("<SpectralDistribution>"), std::string::npos) << note->message;
  const Finding* klm = find(got->findings, "tm33-dialect-cd-per-klm");
  ASSERT_NE(klm, nullptr);
  EXPECT_NE(klm->message.find("2000 lm"), std::string::npos) << klm->message;
  const Finding* mm = find(got->findings, "tm33-dimensions-mm");
  ASSERT_NE(mm, nullptr);
  EXPECT_EQ(mm->where.line, 15);  // the <Dimensions> line
}

TEST(Tm33Dialects, IntensityDataOfAbsolutePhotometryAreCandelas) {
  std::string doc = tm33_23_intensity_data();
  doc.replace(doc.find("<Metric>"), 8, "<AbsolutePhotometry>true</AbsolutePhotometry><Metric>");
  auto r = parse(doc, "absolute.xml");
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_TRUE(r->distribution.absolute);
  EXPECT_DOUBLE_EQ(r->distribution.at(0, 0), 150.0);  // as written, multiplier 2
  EXPECT_EQ(find(r->findings, "tm33-dialect-cd-per-klm"), nullptr);
}

// Without <Equipment> (as eulumdat-rs's Astral Sky GLDF files have it) the
// dialect's <PhotometryType> gives the type.
TEST(Tm33Dialects, PhotometryTypeStandsInForEquipment) {
  std::string doc = tm33_23_intensity_data();
  const auto from = doc.find("    <Equipment>");
  doc.erase(from, doc.find('\n', from) + 1 - from);
  doc = replaced(doc, "<PhotometryType>CIE _ C", "<PhotometryType>CIE _ B");
  auto r = parse(doc, "no-equipment.xml");
  ASSERT_FALSE(r.ok());  // Type B angles on a Type C grid: the type was read
  doc = replaced(doc, "<PhotometryType>CIE _ B", "<PhotometryType>CIE _ C");
  r = parse(doc, "no-equipment.xml");
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_EQ(r->distribution.type, PhotometricType::C);
  EXPECT_EQ(keyword(r->distribution, "_TM33_EQUIPMENT_GONIORADIOMETER_TYPE"), "CIE_C");
  EXPECT_EQ(find(r->findings, "tm33-type-assumed"), nullptr);
  const Finding* note = find(r->findings, "tm33-dialect");
  ASSERT_NE(note, nullptr);
  EXPECT_NE(note->message.find("<PhotometryType>"), std::string::npos) << note->message;
}

TEST(Tm33Dialects, LuminaireOpticalDataRootReadsAsTheStandardLayout) {
  auto want = parse(standard(), "standard.xml");
  auto got = parse(luminaire_optical_data(), "s001.xml");
  ASSERT_TRUE(want.ok()) << to_string(want.error());
  ASSERT_TRUE(got.ok()) << to_string(got.error());
  EXPECT_EQ(got->version, Tm33Version::LuminaireOpticalData);
  EXPECT_STREQ(to_string(got->version), "ATLA S001/UNI 11733 (LuminaireOpticalData)");
  expect_same_distribution(*got, *want);
  EXPECT_EQ(keyword(got->distribution, "TESTDATE"), "2024-01-15");
  EXPECT_EQ(find(got->findings, "tm33-version"), nullptr);  // version="1.0" as an attribute
  EXPECT_TRUE(looks_like_tm33(luminaire_optical_data()));
  EXPECT_TRUE(looks_like_tm33("<?xml version=\"1.1\"?>\n<ATLA_S001_A>"));
}

TEST(Tm33Dialects, Tm3318RootAsDlcWritesItReads) {
  auto want = parse(standard(), "standard.xml");
  auto got = parse(iestm33_dlc_style(), "dlc.xml");
  ASSERT_TRUE(want.ok()) << to_string(want.error());
  ASSERT_TRUE(got.ok()) << to_string(got.error());
  EXPECT_EQ(got->version, Tm33Version::Atla_S001);
  expect_same_distribution(*got, *want);
  EXPECT_EQ(find(got->findings, "tm33-version"), nullptr);  // 1.1 under <IESTM33>, as DLC writes
  EXPECT_EQ(got->distribution.file_generation, photometry::FileGenerationType::UnaccreditedLab);
}

TEST(Tm33Dialects, WriterWritesTheStandardLayoutWhateverWasRead) {
  for (const std::string& doc : {tm33_23_intensity_data(), luminaire_optical_data()}) {
    auto r = parse(doc, "in.xml");
    ASSERT_TRUE(r.ok()) << to_string(r.error());
    const std::string out = write_tm33(r->distribution, nullptr);
    EXPECT_NE(out.find("<IESTM33-22>"), std::string::npos);
    EXPECT_NE(out.find("<LuminousIntensity>"), std::string::npos);
    EXPECT_NE(out.find("<IntData h=\"0\" v=\"0\">300</IntData>"), std::string::npos);
    EXPECT_EQ(out.find("IntensityData"), std::string::npos);
    EXPECT_NE(out.find("<PwrData w=\"450\">0.25</PwrData>"), std::string::npos);
    auto back = parse(out, "out.xml");
    ASSERT_TRUE(back.ok()) << to_string(back.error());
    EXPECT_EQ(find(back->findings, "tm33-dialect"), nullptr);
    EXPECT_EQ(back->distribution.candela, r->distribution.candela);
    ASSERT_EQ(back->distribution.spectra.size(), 1u);
    EXPECT_EQ(back->distribution.spectra[0].values, r->distribution.spectra[0].values);
    EXPECT_TRUE(back->distribution.spectra[0].normalized);
    EXPECT_EQ(write_tm33(back->distribution, nullptr), out);
  }
}

TEST(Tm33Dialects, DialectErrorsNameTheirLine) {
  struct Case {
    std::string document, says;
    int line;
  };
  const std::string a = tm33_23_intensity_data();
  const std::string b = luminaire_optical_data();
  // The line of the element each error names: where `at` is in the document.
  const auto line_of = [](const std::string& doc, const std::string& at) {
    const auto i = doc.find(at);
    EXPECT_NE(i, std::string::npos) << at;
    return 1 + static_cast<int>(std::count(doc.begin(), doc.begin() + static_cast<std::ptrdiff_t>(i), '\n'));
  };
  const std::vector<Case> cases = {
      {replaced(a, "<Metric>Luminous", "<Metric>Radiant"), "not luminous intensities", line_of(a, "<Metric>")},
      {replaced(a, "<Values>0.25 0.5 1", "<Values>0.25 0.5"), "3 wavelengths but 2 values", line_of(a, "<Values>")},
      {replaced(b, "<Values>0.25, 0.5, 1", "<Values>0.25, x, 1"), "'x' is not a number", line_of(b, "<Values>")},
      {replaced(b, "<GoniometerType>Type C", "<GoniometerType>Type D"), "photometric type 'Type D'",
       line_of(b, "<GoniometerType>")},
      {replaced(b, "<LuminaireOpticalData version=\"1.0\" ", "<LuminaireOpticalData "), "<Version> is missing",
       line_of(b, "<LuminaireOpticalData")},
      {replaced(a, "<SymmType>Symm _ Bi _ 0", "<SymmType>Symm _ Quad"), "<Symm> says", line_of(a, "<SymmType>")},
  };
  for (const Case& c : cases) {
    auto r = parse(c.document, "bad.xml");
    ASSERT_FALSE(r.ok()) << c.says;
    EXPECT_NE(r.error().message.find(c.says), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().where.line, c.line) << c.says << ": " << r.error().message;
    EXPECT_EQ(r.error().where.file, "bad.xml");
  }
  // Photon intensity only (DLC's horticultural template): said so.
  std::string photon = replaced(standard(), "<LuminousData>", "<PhotonData>");
  photon = replaced(photon, "</LuminousData>", "</PhotonData>");
  auto r = parse(photon, "photon.xml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("photon or radiant intensity"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace gonio::io
