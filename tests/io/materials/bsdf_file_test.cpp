// Measured BSDF files: Radiance/WINDOW XML (Klems in both data layouts,
// tensor trees) and goniometer CSV tables, against hand-made documents
// whose values are known; and hostile inputs, each refused with the file
// and line.
#include "io/materials/bsdf_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

Vec3 incident(double theta_deg, double phi_deg = 0.0) {
  const double t = theta_deg * kDeg, p = phi_deg * kDeg;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

const char* kKlemsBlocks =
    "<AngleBasis><AngleBasisName>LBNL/Klems Full</AngleBasisName>"
    "<AngleBasisBlock><Theta>0</Theta><nPhis>1</nPhis><ThetaBounds><LowerTheta>0</LowerTheta><UpperTheta>5</UpperTheta></ThetaBounds></AngleBasisBlock>"
    "<AngleBasisBlock><Theta>10</Theta><nPhis>8</nPhis><ThetaBounds><LowerTheta>5</LowerTheta><UpperTheta>15</UpperTheta></ThetaBounds></AngleBasisBlock>"
    "<AngleBasisBlock><Theta>20</Theta><nPhis>16</nPhis><ThetaBounds><LowerTheta>15</LowerTheta><UpperTheta>25</UpperTheta></ThetaBounds></AngleBasisBlock>"
    "<AngleBasisBlock><Theta>30</Theta><nPhis>20</nPhis><ThetaBounds><LowerTheta>25</LowerTheta><UpperTheta>35</UpperTheta></ThetaBounds></AngleBasisBlock>"
    "<AngleBasisBlock><Theta>40</Theta><nPhis>24</nPhis><ThetaBounds><LowerTheta>35</LowerTheta><UpperTheta>45</UpperTheta></ThetaBounds></AngleBasisBlock>"
    "<AngleBasisBlock><Theta>50</Theta><nPhis>24</nPhis><ThetaBounds><LowerTheta>45</LowerTheta><UpperTheta>55</UpperTheta></ThetaBounds></AngleBasisBlock>"
    "<AngleBasisBlock><Theta>60</Theta><nPhis>24</nPhis><ThetaBounds><LowerTheta>55</LowerTheta><UpperTheta>65</UpperTheta></ThetaBounds></AngleBasisBlock>"
    "<AngleBasisBlock><Theta>70</Theta><nPhis>16</nPhis><ThetaBounds><LowerTheta>65</LowerTheta><UpperTheta>75</UpperTheta></ThetaBounds></AngleBasisBlock>"
    "<AngleBasisBlock><Theta>82.5</Theta><nPhis>12</nPhis><ThetaBounds><LowerTheta>75</LowerTheta><UpperTheta>90</UpperTheta></ThetaBounds></AngleBasisBlock>"
    "</AngleBasis>";

// A WINDOW-style document around blocks of (direction, data text).
std::string window_xml(const std::string& structure, const std::string& definition_extra,
                       const std::vector<std::pair<std::string, std::string>>& blocks, bool klems = true) {
  std::ostringstream s;
  s << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<WindowElement xmlns=\"http://windows.lbl.gov\">\n<WindowElementType>System</WindowElementType>\n"
    << "<Optical>\n<Layer>\n<Material><Name>test sheet</Name></Material>\n"
    << "<DataDefinition><IncidentDataStructure>" << structure << "</IncidentDataStructure>" << definition_extra
    << "</DataDefinition>\n<WavelengthData>\n<Wavelength unit=\"Integral\">Visible</Wavelength>\n";
  for (const auto& [direction, data] : blocks) {
    s << "<WavelengthDataBlock>\n<WavelengthDataDirection>" << direction << "</WavelengthDataDirection>\n";
    if (klems)
      s << "<ColumnAngleBasis>LBNL/Klems Full</ColumnAngleBasis>\n<RowAngleBasis>LBNL/Klems Full</RowAngleBasis>\n";
    else
      s << "<AngleBasis>LBNL/Shirley-Chiu</AngleBasis>\n";
    s << "<ScatteringDataType>BTDF</ScatteringDataType>\n<ScatteringData>\n" << data << "\n</ScatteringData>\n"
      << "</WavelengthDataBlock>\n";
  }
  s << "</WavelengthData>\n</Layer>\n</Optical>\n</WindowElement>\n";
  return s.str();
}

// 145 × 145 values, value(o, i) written in the Columns layout (a line per
// outgoing patch) or the Rows layout (a line per incidence).
std::string klems_matrix(const std::function<double(int o, int i)>& value, bool rows) {
  std::ostringstream s;
  s.precision(9);
  for (int a = 0; a < 145; ++a) {
    for (int b = 0; b < 145; ++b) s << (rows ? value(b, a) : value(a, b)) << ",\t";
    s << "\n";
  }
  return s.str();
}

TEST(BsdfXml, KlemsClearSheetTransmitsItsDiagonal) {
  // A clear sheet as genBSDF writes it: a diagonal transmission matrix
  // T_ii / Λ_i. honeybee-resources' cl_Tn0.6.xml (genBSDF, "Transmission
  // Back") has 25.0987912 at patch 0, so T(0°) = 25.0987912 × Λ_0 =
  // 25.0987912 × 0.0238639 = 0.59896 for its stated Tn of 0.6 (its Radiance
  // material: ts 0.5997).
  const sim::PatchBasis basis = sim::PatchBasis::klems("LBNL/Klems Full");
  const auto diag = [&](int o, int i) {
    return o == i ? (i == 0 ? 25.0987912 : 0.6 / basis.projected_solid_angle(static_cast<std::size_t>(i))) : 0.0;
  };
  const std::string doc =
      window_xml("Columns", kKlemsBlocks, {{"Transmission Front", klems_matrix(diag, false)}});
  test::offer_fuzz_seed("bsdf", doc);
  std::vector<Finding> findings;
  Result<sim::TabulatedBsdf> t = read_bsdf_xml(doc, "clear.xml", findings);
  ASSERT_TRUE(t.ok()) << to_string(t.error());
  EXPECT_EQ(t->name, "clear.xml (test sheet)");
  double r = 0.0, tr = 0.0;
  t->albedo(true, incident(0.0), &r, &tr);
  EXPECT_NEAR(tr, 0.59896, 1e-5);
  EXPECT_EQ(r, 0.0);
  EXPECT_NEAR(t->albedo(true, incident(40.0, 123.0)), 0.6, 1e-6);
  // The light goes straight through: at 40° from the normal along any
  // azimuth, into the patch about the straight-through direction.
  const Vec3 wi = incident(40.0, 123.0);
  const Vec3 through{-wi.x, -wi.y, -wi.z};
  EXPECT_GT(t->evaluate(true, wi, through), 0.0);
  EXPECT_EQ(t->evaluate(true, wi, Vec3{wi.x, wi.y, -wi.z}), 0.0);
  // The back takes the front's transmission by reciprocity.
  EXPECT_NEAR(t->albedo(false, incident(40.0)), 0.6, 0.02);
}

TEST(BsdfXml, ColumnsAndRowsLayoutsAreReadTheirWay) {
  // Light along the normal (incidence patch 0) scatters into outgoing patch
  // 5 only; patch 7's light into patch 0. Written in either layout, the
  // same table comes back.
  const auto m = [](int o, int i) { return (i == 0 && o == 5) || (i == 7 && o == 0) ? 2.0 : 0.0; };
  for (bool rows : {false, true}) {
    const std::string doc = window_xml(rows ? "Rows" : "Columns", kKlemsBlocks, {{"Reflection Front", klems_matrix(m, rows)}});
    std::vector<Finding> findings;
    Result<sim::TabulatedBsdf> t = read_bsdf_xml(doc, "layout.xml", findings);
    ASSERT_TRUE(t.ok()) << to_string(t.error());
    const auto& row0 = t->front.rows[0].reflect;
    for (std::size_t p = 0; p < row0.size(); ++p) EXPECT_EQ(row0[p], p == 5 ? 2.0f : 0.0f) << rows << " " << p;
    // Patch 7 is not on azimuth 0 of its ring: the isotropic reading skips
    // it and says the data is anisotropic.
    bool aniso = false;
    for (const Finding& f : findings) aniso |= f.code == "bsdf-anisotropic";
    EXPECT_TRUE(aniso) << rows;
  }
}

TEST(BsdfXml, TensorTreesAreLookedUpAsRadianceDoes) {
  // TT3: a single value 1/π everywhere is a Lambertian reflector of albedo 1.
  std::vector<Finding> findings;
  Result<sim::TabulatedBsdf> flat =
      read_bsdf_xml(window_xml("TensorTree3", "", {{"Reflection Front", "{ 0.318309886 }"}}, false), "flat.xml", findings);
  ASSERT_TRUE(flat.ok()) << to_string(flat.error());
  EXPECT_NEAR(flat->albedo(true, incident(20.0)), 1.0, 1e-6);
  // One level of 8 children, child k = 0.02 (k + 1): the child index has
  // bit i for dimension i (incidence, square x, square y; Radiance's
  // bsdf_t.c), so near normal incidence (x0 < ½) the outgoing quadrant
  // (sx, sy) picks child 2·[sx ≥ ½] + 4·[sy ≥ ½].
  std::string tree = "{";
  for (int k = 0; k < 8; ++k) tree += " { " + std::to_string(0.02 * (k + 1)) + " }";
  tree += " }";
  const std::string doc = window_xml("TensorTree3", "", {{"Reflection Front", tree}}, false);
  test::offer_fuzz_seed("bsdf", doc);
  Result<sim::TabulatedBsdf> t = read_bsdf_xml(doc, "tree.xml", findings);
  ASSERT_TRUE(t.ok()) << to_string(t.error());
  ASSERT_EQ(t->basis.square_n, 2);
  ASSERT_EQ(t->front.rows.size(), 1u);
  EXPECT_NEAR(t->front.rows[0].theta_deg, 30.0, 1e-9);  // sin θ = 2 · ¼
  const Vec3 wi = incident(30.0, 180.0);  // the light travels along +x: no turn
  for (auto [sx, sy, child] : {std::tuple{0.25, 0.25, 0}, std::tuple{0.75, 0.25, 2}, std::tuple{0.25, 0.75, 4},
                                std::tuple{0.75, 0.75, 6}}) {
    double dx, dy;
    sim::square_to_disc(sx, sy, &dx, &dy);
    const Vec3 wo{dx, dy, std::sqrt(1.0 - dx * dx - dy * dy)};
    EXPECT_NEAR(t->evaluate(true, wi, wo) / wo.z, 0.02 * (child + 1), 1e-6) << sx << " " << sy;
  }
}

TEST(BsdfXml, HostileDocumentsAreRefusedWithTheLine) {
  const std::string diag = klems_matrix([](int o, int i) { return o == i ? 1.0 : 0.0; }, false);
  struct Case {
    std::string doc, expect;
  };
  std::string short_data = diag.substr(0, diag.size() / 2);
  std::string nan_data = diag;
  nan_data.replace(nan_data.find("0,"), 1, "nan");
  std::string negative = diag;
  negative.replace(negative.find("0,"), 1, "-3");
  // Nested first children: the parser meets the depth (or the leaf) before
  // it misses the siblings.
  std::string deep = "{ 0.1 }";
  for (int k = 0; k < 20; ++k) deep = "{ " + deep + " }";
  std::string fine = "{ 0.1 0.1 0.1 0.1 0.1 0.1 0.1 0.1 }";  // 2 per side, 7 levels down: 2^8
  for (int k = 0; k < 7; ++k) fine = "{ " + fine + " }";
  const Case cases[] = {
      {"not xml at all", "malformed XML"},
      {"<Other/>", "root element"},
      {"<WindowElement><Optical/></WindowElement>", "no Optical/Layer"},
      {window_xml("Diagonal", kKlemsBlocks, {{"Transmission Front", diag}}), "IncidentDataStructure 'Diagonal'"},
      {window_xml("Columns", kKlemsBlocks, {{"Transmission Front", short_data}}), "ScatteringData holds"},
      {window_xml("Columns", kKlemsBlocks, {{"Transmission Front", diag + " 1"}}), "more than the 21025"},
      {window_xml("Columns", kKlemsBlocks, {{"Transmission Front", nan_data}}), "is not a number"},
      {window_xml("Columns", kKlemsBlocks, {{"Transmission Front", negative}}), "negative"},
      {window_xml("Columns", kKlemsBlocks, {{"Transmission Sideways", diag}}), "Transmission Sideways"},
      {window_xml("Columns",
                  "<AngleBasis><AngleBasisName>LBNL/Klems Full</AngleBasisName><AngleBasisBlock><nPhis>9999999</nPhis>"
                  "<ThetaBounds><LowerTheta>0</LowerTheta><UpperTheta>90</UpperTheta></ThetaBounds></AngleBasisBlock></AngleBasis>",
                  {{"Transmission Front", "1"}}),
       "nPhis"},
      {window_xml("Columns",
                  "<AngleBasis><AngleBasisName>LBNL/Klems Full</AngleBasisName><AngleBasisBlock><nPhis>1</nPhis>"
                  "<ThetaBounds><LowerTheta>0</LowerTheta><UpperTheta>45</UpperTheta></ThetaBounds></AngleBasisBlock></AngleBasis>",
                  {{"Transmission Front", "1"}}),
       "not 90"},
      {window_xml("TensorTree3", "", {{"Reflection Front", deep}}, false), "deeper than"},
      {window_xml("TensorTree3", "", {{"Reflection Front", "{ 0.1 0.2 0.3 }"}}, false), "not a power"},
      {window_xml("TensorTree3", "", {{"Reflection Front", "{ 0.1 } }"}}, false), "after the tree"},
      {window_xml("TensorTree3", "", {{"Reflection Front", "{ { 0.1 } }"}}, false), "expected"},
      {window_xml("TensorTree3", "", {{"Reflection Front", fine}}, false), "finer than"},
      {window_xml("TensorTree3", "", {{"Reflection Front", "{ 0.1 }"}}, true), "Shirley-Chiu"},
  };
  for (const Case& c : cases) {
    test::offer_fuzz_seed("bsdf", c.doc);
    std::vector<Finding> findings;
    Result<sim::TabulatedBsdf> t = read_bsdf_xml(c.doc, "hostile.xml", findings);
    ASSERT_FALSE(t.ok()) << c.expect;
    EXPECT_EQ(t.error().where.file, "hostile.xml");
    EXPECT_NE(t.error().message.find(c.expect), std::string::npos) << t.error().message;
  }
  // The line of the value at fault.
  std::vector<Finding> findings;
  Result<sim::TabulatedBsdf> t =
      read_bsdf_xml(window_xml("Columns", kKlemsBlocks, {{"Transmission Front", nan_data}}), "hostile.xml", findings);
  EXPECT_GT(t.error().where.line, 10);
}

TEST(BsdfXml, AnAlbedoAboveOneIsAFindingAndScaled) {
  // Diffuse reflection 0.7 and transmission 0.5 (1.2 in all).
  const std::string doc = window_xml("Columns", kKlemsBlocks,
                                     {{"Reflection Front", klems_matrix([](int, int) { return 0.7 / kPi; }, false)},
                                      {"Transmission Front", klems_matrix([](int, int) { return 0.5 / kPi; }, false)}});
  std::vector<Finding> findings;
  Result<sim::TabulatedBsdf> t = read_bsdf_xml(doc, "bright.xml", findings);
  ASSERT_TRUE(t.ok());
  int above = 0, reciprocity = 0;
  for (const Finding& f : findings) {
    above += f.code == "bsdf-albedo-above-1";
    reciprocity += f.code == "bsdf-reciprocity";
    if (f.code == "bsdf-albedo-above-1") {
      EXPECT_NE(f.message.find("1.2"), std::string::npos) << f.message;
    }
  }
  EXPECT_EQ(above, 9);  // every incidence ring
  EXPECT_GE(reciprocity, 1);
  EXPECT_NEAR(t->albedo(true, incident(30.0)), 1.0, 1e-6);
}

std::string csv_grid(double reflect, double transmit, const char* separator = ",") {
  std::ostringstream s;
  s << "# a Lambertian sheet\ntheta_in_deg" << separator << "theta_out_deg" << separator << "phi_out_deg" << separator
    << "bsdf_per_sr\n";
  for (double ti : {0.0, 30.0, 60.0})
    for (double to = 0.0; to <= 180.0; to += 10.0) {
      if (to == 90.0) continue;
      for (double p = 0.0; p <= 180.0; p += 45.0)
        s << ti << separator << to << separator << p << separator << (to < 90 ? reflect : transmit) / kPi << "\n";
    }
  return s.str();
}

TEST(BsdfCsv, LambertianGridReflectsAndTransmitsItsAlbedo) {
  for (const char* sep : {",", ";", "\t", " "}) {
    std::vector<Finding> findings;
    const std::string doc = csv_grid(0.3, 0.5, sep);
    test::offer_fuzz_seed("bsdf", doc);
    Result<sim::TabulatedBsdf> t = read_bsdf_csv(doc, "grid.csv", findings);
    ASSERT_TRUE(t.ok()) << to_string(t.error());
    double r = 0.0, tr = 0.0;
    t->albedo(true, incident(45.0), &r, &tr);
    EXPECT_NEAR(r, 0.3, 1e-6) << sep;
    EXPECT_NEAR(tr, 0.5, 1e-6) << sep;
    // Mirror-symmetric data (φ within 0..180) covers the whole circle.
    EXPECT_EQ(t->basis.ring_phi_deg[3].size() - 1, 8u);
  }
}

TEST(BsdfCsv, ForwardPeakLandsInTheRightPatch) {
  // Transmission only straight through (θout = 180 − θin... here 180 − 0
  // and 150 for θin 30, φ = 0 on the far side): the peak must come out
  // along the straight-through direction.
  std::ostringstream s;
  s << "theta_in,theta_out,phi_out,btdf\n";
  for (double ti : {0.0, 30.0})
    for (double to : {100.0, 130.0, 150.0, 160.0, 180.0})
      for (double p : {0.0, 90.0, 180.0}) s << ti << "," << to << "," << p << "," << (std::abs(180.0 - to - ti) < 1e-9 && (p == 0.0 || ti == 0.0) ? 5.0 : 0.0) << "\n";
  std::vector<Finding> findings;
  Result<sim::TabulatedBsdf> t = read_bsdf_csv(s.str(), "peak.csv", findings);
  ASSERT_TRUE(t.ok()) << to_string(t.error());
  const Vec3 wi = incident(30.0, 200.0);
  EXPECT_GT(t->evaluate(true, wi, Vec3{-wi.x, -wi.y, -wi.z}), 0.0);
  EXPECT_EQ(t->evaluate(true, wi, Vec3{wi.x, wi.y, -wi.z}), 0.0);  // backwards: φ = 180
}

// Issue 45, case 13: a table measured over φ_out 0..180 is completed by
// the mirror about the plane of incidence, φ → 360 − φ (bsdf_file.h), not
// by a half turn, φ → φ − 180. Data that differ at φ 30 (0.2/sr) and 150
// (0.05/sr): the mirror puts 30's value at 330 and 150's at 210; a half
// turn would put them the other way round, which symmetric data cannot
// tell apart.
TEST(BsdfCsv, HalfPlaneTableIsCompletedByTheMirrorAboutThePlaneOfIncidence) {
  const auto value = [](double phi) { return phi == 30.0 ? 0.2 : phi == 150.0 ? 0.05 : 0.1; };
  std::ostringstream s;
  s << "theta_in,theta_out,phi_out,brdf\n";
  for (double ti : {0.0, 30.0})
    for (double to : {10.0, 30.0, 50.0, 70.0})
      for (double p : {0.0, 30.0, 150.0, 180.0}) s << ti << "," << to << "," << p << "," << value(p) << "\n";
  std::vector<Finding> findings;
  Result<sim::TabulatedBsdf> t = read_bsdf_csv(s.str(), "half.csv", findings);
  ASSERT_TRUE(t.ok()) << to_string(t.error());
  // φ_out = 0 is the plane of incidence on the far side: for light arriving
  // from azimuth 0, the outgoing azimuth φ_out lies at 180° + φ_out.
  const Vec3 wi = incident(30.0);
  const double theta = 50.0 * kDeg;
  const auto f = [&](double phi_out) {
    const Vec3 wo = incident(50.0, 180.0 + phi_out);
    return t->evaluate(true, wi, wo) / std::cos(theta);
  };
  EXPECT_NEAR(f(30.0), 0.2, 1e-6);
  EXPECT_NEAR(f(150.0), 0.05, 1e-6);
  EXPECT_NEAR(f(330.0), 0.2, 1e-6);   // the mirror of 30
  EXPECT_NEAR(f(210.0), 0.05, 1e-6);  // the mirror of 150
  EXPECT_NEAR(f(0.0), 0.1, 1e-6);
  EXPECT_NEAR(f(180.0), 0.1, 1e-6);
}

TEST(BsdfCsv, HostileTablesAreRefusedWithTheLine) {
  struct Case {
    std::string doc, expect;
    int line;
  };
  const Case cases[] = {
      {"", "no header", 0},
      {"theta_in,theta_out,phi_out\n0,0,0\n", "must name the columns", 1},
      {"theta_in,theta_out,phi_out,bsdf,colour\n", "unknown column", 1},
      {"theta_in,theta_out,phi_out,bsdf\n0,0,0\n", "expected 4 fields", 2},
      {"theta_in,theta_out,phi_out,bsdf\n0,0,0,nan\n", "is not a number", 2},
      {"theta_in,theta_out,phi_out,bsdf\n0,90,0,1\n", "not be 90", 2},
      {"theta_in,theta_out,phi_out,bsdf\n0,10,0,-1\n", ">= 0", 2},
      {"theta_in,theta_out,phi_out,bsdf\n95,10,0,1\n", "theta_in", 2},
      {"theta_in,theta_out,phi_out,bsdf\n0,10,0,1\n0,10,0,1\n", "appear twice", 3},
      {"theta_in,theta_out,phi_out,bsdf\n0,10,0,1\n0,20,90,1\n", "not a full grid", 0},
      {"theta_in,theta_out,phi_out,bsdf,side\n0,10,0,1,left\n", "front or back", 2},
      {"theta_in,theta_out,theta_out,bsdf\n", "appears twice", 1},
  };
  for (const Case& c : cases) {
    test::offer_fuzz_seed("bsdf", c.doc);
    std::vector<Finding> findings;
    Result<sim::TabulatedBsdf> t = read_bsdf_csv(c.doc, "hostile.csv", findings);
    ASSERT_FALSE(t.ok()) << c.expect;
    EXPECT_NE(t.error().message.find(c.expect), std::string::npos) << t.error().message;
    EXPECT_EQ(t.error().where.file, "hostile.csv");
    EXPECT_EQ(t.error().where.line, c.line) << c.expect;
  }
}

TEST(BsdfFile, OpensByContentAndNamesMissingFiles) {
  test::TempDir dir;
  test::write_file(dir / "a.txt", csv_grid(0.2, 0.0));
  test::write_file(dir / "b.dat",
                   "\xEF\xBB\xBF  " + window_xml("TensorTree3", "", {{"Reflection Front", "{ 0.1 }"}}, false));
  std::vector<Finding> findings;
  auto a = read_bsdf_file((dir / "a.txt").string(), findings);
  ASSERT_TRUE(a.ok()) << to_string(a.error());
  EXPECT_NEAR((*a)->albedo(true, incident(10.0)), 0.2, 1e-6);
  auto b = read_bsdf_file((dir / "b.dat").string(), findings);
  ASSERT_TRUE(b.ok()) << to_string(b.error());
  EXPECT_NEAR((*b)->albedo(true, incident(10.0)), 0.1 * kPi, 1e-6);
  auto c = read_bsdf_file((dir / "missing.xml").string(), findings);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(to_string(c.error()).find("missing.xml"), std::string::npos);
}

}  // namespace
}  // namespace gonio::io
