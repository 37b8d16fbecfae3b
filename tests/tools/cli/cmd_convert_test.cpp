// gonio convert, run as a user would.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "io/photometric/ies.h"
#include "io/photometric/ldt.h"
#include "io/photometric/photometric_file.h"
#include "io/photometric/gldf.h"
#include "io/support/zip.h"
#include "photometry/flux.h"
#include "tests/tools/cli/cli_fixtures.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;
using photometry::Distribution;
using test::contains;
using test::gonio;

Distribution read(const fs::path& p, io::LdtIsym3Order order = io::LdtIsym3Order::C270_C0_C90) {
  io::PhotometricReadOptions options;
  options.ldt.isym3_order = order;
  auto r = io::read_photometric_file(p.string(), options);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : to_string(r.error()));
  return r.ok() ? r->distribution : Distribution{};
}

void expect_same_candela(const Distribution& a, const Distribution& b, double tolerance) {
  ASSERT_EQ(a.horizontal_deg, b.horizontal_deg);
  ASSERT_EQ(a.vertical_deg, b.vertical_deg);
  for (std::size_t i = 0; i < a.candela.size(); ++i)
    ASSERT_NEAR(b.candela[i], a.candela[i], tolerance * std::abs(a.candela[i])) << i;
}

TEST(CliConvert, IesToLdtAndBackKeepsIntensitiesAndFlux) {
  test::TempDir dir;
  const auto ies = dir / "in.ies", ldt = dir / "out.LDT", back = dir / "back.Ies";
  test::write_distribution(ies, test::lambertian_downlight());
  const std::string input_bytes = test::read_file(ies);

  auto r = gonio({"convert", ies.string(), ldt.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "Wrote " + ldt.string() + " (EULUMDAT)")) << r.out;
  // IES keywords without an EULUMDAT field are reported, with the output named.
  EXPECT_TRUE(contains(r.err, "gonio: " + ldt.string() + ": warning: keyword [TESTLAB]")) << r.err;
  EXPECT_TRUE(contains(r.err, "[ldt-keyword-dropped]")) << r.err;
  EXPECT_TRUE(contains(r.err, ": info: ")) << r.err;  // computed LORL, DFF, direct ratios
  EXPECT_EQ(test::read_file(ies), input_bytes);       // the input is untouched

  auto r2 = gonio({"convert", ldt.string(), back.string()});
  ASSERT_EQ(r2.exit_code, 0) << r2.err;
  EXPECT_TRUE(contains(r2.out, "(IES LM-63-2019)")) << r2.out;
  EXPECT_TRUE(contains(r2.err, "[ldt-only-field]")) << r2.err;  // declared LOR, direct ratios

  const Distribution a = read(ies), b = read(ldt), c = read(back);
  expect_same_candela(a, b, 1e-11);
  expect_same_candela(a, c, 1e-11);
  const double flux = photometry::total_flux_lm(a);
  EXPECT_NEAR(photometry::total_flux_lm(c), flux, 1e-9 * flux);
  EXPECT_EQ(c.lamps[0].flux_lm, 1000.0);
  EXPECT_EQ(c.find_keyword("LUMCAT")->value, "DL-800");
  EXPECT_EQ(c.find_keyword("MANUFAC")->value, "Gonio");
  EXPECT_EQ(c.opening.shape, photometry::OpeningShape::Circular);
  // LM-63-2019 output says where it came from when the input does not.
  const std::string info = c.find_keyword("FILEGENINFO")->value;
  EXPECT_EQ(info.rfind("Converted by Gonio ", 0), 0u) << info;
  EXPECT_TRUE(info.ends_with(" from out.LDT (EULUMDAT)")) << info;
  // Only the outputs were added to the directory: no temporaries left.
  EXPECT_EQ(test::directory_entries(dir.path()),
            (std::vector<std::string>{"back.Ies", "in.ies", "out.LDT"}));
}

TEST(CliConvert, VersionChangeAndQuietRuns) {
  test::TempDir dir;
  const auto in = dir / "in.ies", out = dir / "v2002.ies";
  test::write_distribution(in, test::lambertian_downlight());
  auto r = gonio({"convert", in.string(), out.string(), "--ies-version", "2002", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  // IES → IES loses nothing but LM-63-2019's own keyword; no info lines with --quiet.
  EXPECT_EQ(r.err, "gonio: " + out.string() +
                       ": warning: [FILEGENINFO] is an LM-63-2019 keyword; written as [OTHER] "
                       "[keyword-renamed]\n");
  EXPECT_EQ(test::read_file(out).rfind("IESNA:LM-63-2002\r\n", 0), 0u);
  expect_same_candela(read(in), read(out), 0.0);  // 15 digits: IES → IES is exact
  // Converting again over an existing output replaces it.
  auto again = gonio({"convert", in.string(), out.string()});
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(test::read_file(out).rfind("IES:LM-63-2019\r\n", 0), 0u);
}

TEST(CliConvert, RefusesToOverwriteTheInputEvenThroughLinks) {
  test::TempDir dir;
  const auto in = dir / "lamp.ies";
  test::write_distribution(in, test::lambertian_downlight());
  const std::string bytes = test::read_file(in);
  fs::create_symlink(in, dir / "symlink.ies");
  fs::create_hard_link(in, dir / "hardlink.ies");
  fs::create_directory(dir / "sub");
  for (const fs::path& out :
       {in, dir / "symlink.ies", dir / "hardlink.ies", dir / "sub" / ".." / "lamp.ies"}) {
    SCOPED_TRACE(out.string());
    auto r = gonio({"convert", in.string(), out.string()});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.err, "gonio: " + out.string() + ": is the input file")) << r.err;
    EXPECT_TRUE(contains(r.err, "refusing to overwrite the input")) << r.err;
    EXPECT_EQ(test::read_file(in), bytes);
  }
  // Also when the input is named through the link.
  auto r = gonio({"convert", (dir / "symlink.ies").string(), in.string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::read_file(in), bytes);
  EXPECT_TRUE(fs::is_symlink(dir / "symlink.ies"));
  EXPECT_EQ(test::directory_entries(dir.path()),
            (std::vector<std::string>{"hardlink.ies", "lamp.ies", "sub", "symlink.ies"}));
}

TEST(CliConvert, AFailedConversionLeavesNoOutput) {
  test::TempDir dir;
  const auto good = dir / "good.ies";
  test::write_distribution(good, test::lambertian_downlight());
  const std::string text = test::read_file(good);
  test::write_file(dir / "truncated.ies", text.substr(0, text.size() - 200));
  test::write_file(dir / "junk.ldt", std::string("\0\1\2\3\4\5\6\7\x08\x0e\x0f", 11));
  std::vector<std::string> before = test::directory_entries(dir.path());

  struct Case {
    std::vector<std::string> args;
    std::string says;
  };
  const std::string out = (dir / "out.ldt").string();
  const std::vector<Case> cases = {
      {{(dir / "truncated.ies").string(), out}, "gonio: " + (dir / "truncated.ies").string() + ":"},
      {{(dir / "junk.ldt").string(), (dir / "out.ies").string()},
       "gonio: " + (dir / "junk.ldt").string() + ":1: binary data"},
      {{(dir / "missing.ies").string(), out},
       "gonio: " + (dir / "missing.ies").string() + ": cannot open"},
      {{dir.path().string() + "/", out}, "is a directory"},
      {{good.string(), (dir / "no-such-dir" / "out.ldt").string()}, "cannot write"},
      // A grid that does not divide the circle: the resampling fails.
      {{good.string(), out, "--c-step", "7"}, "gonio: " + out + ": cannot resample to Type C"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {"convert"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    SCOPED_TRACE(c.args[0] + " -> " + c.args[1]);
    auto r = gonio(args);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.err, c.says)) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_EQ(test::directory_entries(dir.path()), before);
  }

  // An existing output survives a failed conversion unchanged.
  test::write_file(out, "previous output");
  before = test::directory_entries(dir.path());
  auto r = gonio({"convert", (dir / "truncated.ies").string(), out});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(test::read_file(out), "previous output");
  auto grid = gonio({"convert", good.string(), out, "--gamma-step", "7"});
  EXPECT_EQ(grid.exit_code, 1);
  EXPECT_EQ(test::read_file(out), "previous output");
  EXPECT_EQ(test::directory_entries(dir.path()), before);
}

// Type B floodlight, I = I0 (cos H cos V)^20 on a 2.5° grid: Φ = 2π I0 / 21.
Distribution floodlight() {
  Distribution d;
  d.type = photometry::PhotometricType::B;
  d.symmetry = photometry::Symmetry::None;
  for (int i = -36; i <= 36; ++i) {
    d.horizontal_deg.push_back(2.5 * i);
    d.vertical_deg.push_back(2.5 * i);
  }
  const double r = std::numbers::pi / 180.0;
  for (double h : d.horizontal_deg)
    for (double v : d.vertical_deg)
      d.candela.push_back(10000.0 * std::pow(std::cos(h * r) * std::cos(v * r), 20));
  d.lamps = {photometry::LampSet{1, "MH 150 W", 14000.0, "", "", 165.0}};
  return d;
}

TEST(CliConvert, TypeBIntoLdtIsResampledOnTheGridItStates) {
  test::TempDir dir;
  const auto in = dir / "flood.ies", out = dir / "flood.ldt", fine = dir / "fine.ldt";
  test::write_distribution(in, floodlight());
  const double exact = 2.0 * std::numbers::pi * 10000.0 / 21.0;

  auto r = gonio({"convert", in.string(), out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "gonio: " + out.string() + ": warning: Type B photometry resampled"))
      << r.err;
  EXPECT_TRUE(contains(r.err, "C 0 to 360 every 5 deg")) << r.err;
  EXPECT_TRUE(contains(r.err, "gamma 0 to 90 every 1 deg")) << r.err;
  EXPECT_TRUE(contains(r.err, "[type-c-resampled]")) << r.err;
  const Distribution c = read(out);
  EXPECT_EQ(c.type, photometry::PhotometricType::C);
  EXPECT_EQ(c.horizontal_count(), 72u);
  EXPECT_EQ(c.vertical_count(), 91u);
  EXPECT_NEAR(photometry::total_flux_lm(c), exact, 5e-4 * exact);

  auto f = gonio({"convert", in.string(), fine.string(), "--c-step", "2.5", "--gamma-step", "0.5"});
  ASSERT_EQ(f.exit_code, 0) << f.err;
  EXPECT_TRUE(contains(f.err, "C 0 to 360 every 2.5 deg")) << f.err;
  EXPECT_TRUE(contains(f.err, "gamma 0 to 90 every 0.5 deg")) << f.err;
  const Distribution cf = read(fine);
  EXPECT_EQ(cf.horizontal_count(), 144u);
  EXPECT_EQ(cf.vertical_count(), 181u);
  EXPECT_NEAR(photometry::total_flux_lm(cf), exact, 5e-4 * exact);

  // Into IES, Type B stays Type B unless a grid is asked for.
  auto keep = gonio({"convert", in.string(), (dir / "b.ies").string()});
  ASSERT_EQ(keep.exit_code, 0) << keep.err;
  EXPECT_FALSE(contains(keep.err, "type-c-resampled")) << keep.err;
  EXPECT_EQ(read(dir / "b.ies").type, photometry::PhotometricType::B);
  auto to_c = gonio({"convert", in.string(), (dir / "c.ies").string(), "--gamma-step", "0.5"});
  ASSERT_EQ(to_c.exit_code, 0) << to_c.err;
  EXPECT_EQ(read(dir / "c.ies").type, photometry::PhotometricType::C);
}

TEST(CliConvert, Isym3OrderOfInputAndOutput) {
  // An Isym 3 file in QLumEdit's order, read that way and written the
  // standard way: the same luminaire, the standard's plane order.
  Distribution d;
  d.symmetry = photometry::Symmetry::C90_C270;
  for (int i = 0; i <= 12; ++i) d.horizontal_deg.push_back(90.0 + 15.0 * i);
  for (int i = 0; i <= 18; ++i) d.vertical_deg.push_back(5.0 * i);
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg) d.candela.push_back(100.0 + c + 3.0 * g);
  d.lamps = {photometry::LampSet{1, "HPS", 10000.0, "", "", 100.0}};
  test::TempDir dir;
  const auto q = dir / "q.ldt", s = dir / "s.ldt", q2 = dir / "q2.ldt";
  io::LdtWriteOptions qo;
  qo.isym3_order = io::LdtIsym3Order::C90_C180_C270;
  auto bytes = io::write_ldt(d, qo, nullptr);
  ASSERT_TRUE(bytes.ok());
  test::write_file(q, *bytes);

  auto r = gonio({"convert", q.string(), s.string(), "--ldt-isym3", "qlumedit"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_same_candela(d, read(s), 1e-11);             // standard order
  EXPECT_NE(test::read_file(s), test::read_file(q));  // planes reordered
  auto back = gonio({"convert", s.string(), q2.string(), "--ldt-isym3-out", "qlumedit"});
  ASSERT_EQ(back.exit_code, 0) << back.err;
  expect_same_candela(d, read(q2, io::LdtIsym3Order::C90_C180_C270), 1e-11);
}

TEST(CliConvert, Tm33IsWrittenReadAndAcceptedByEveryCommand) {
  test::TempDir dir;
  const auto ies = dir / "in.ies", xml = dir / "lamp.xml", back = dir / "back.ies";
  test::write_distribution(ies, test::lambertian_downlight());
  auto r = gonio({"convert", ies.string(), xml.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "Wrote " + xml.string() + " (TM-33)")) << r.out;
  // What TM-33 lacks is said, with a stable code, naming the output.
  EXPECT_TRUE(contains(r.err, "gonio: " + xml.string() + ": warning: luminous opening")) << r.err;
  EXPECT_TRUE(contains(r.err, "[tm33-opening]")) << r.err;
  EXPECT_TRUE(contains(test::read_file(xml), "<IESTM33-22>"));

  r = gonio({"info", xml.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"version\": \"TM-33-23\"")) << r.out;
  EXPECT_EQ(gonio({"check", xml.string()}).exit_code, 0);
  EXPECT_EQ(gonio({"plot", xml.string(), "--out", (dir / "p.svg").string()}).exit_code, 0);
  r = gonio({"compare", ies.string(), xml.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"max_relative\": 0.0")) << r.out;
  ASSERT_EQ(gonio({"convert", xml.string(), back.string(), "--quiet"}).exit_code, 0);
  const Distribution a = read(ies), b = read(xml), c = read(back);
  expect_same_candela(a, b, 0.0);
  expect_same_candela(a, c, 0.0);
  // Recognised by content under any name.
  test::write_file(dir / "lamp.dat", test::read_file(xml));
  expect_same_candela(a, read(dir / "lamp.dat"), 0.0);
}

TEST(CliConvert, GldfPackagesTheFileAndEveryCommandOpensIt) {
  test::TempDir dir;
  const auto ldt = dir / "in.ldt", gldf = dir / "lamp.gldf", back = dir / "back.ldt";
  test::write_distribution(ldt, test::lambertian_downlight());
  auto r = gonio({"convert", ldt.string(), gldf.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "Wrote " + gldf.string() + " (GLDF)")) << r.out;
  EXPECT_TRUE(contains(r.err, "[gldf-packaged]")) << r.err;

  r = gonio({"info", gldf.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, gldf.string() + ":ldc/lamp.ldt")) << r.out;
  EXPECT_TRUE(contains(r.out, "GLDF (EULUMDAT)")) << r.out;
  r = gonio({"check", gldf.string()});
  EXPECT_TRUE(contains(r.out, gldf.string() + ":ldc/lamp.ldt: ")) << r.out;
  EXPECT_EQ(r.exit_code, gonio({"check", ldt.string()}).exit_code) << r.out;
  ASSERT_EQ(gonio({"convert", gldf.string(), back.string(), "--quiet"}).exit_code, 0);
  EXPECT_EQ(test::read_file(back), test::read_file(ldt));  // LDT -> GLDF -> LDT: the same bytes
  EXPECT_EQ(gonio({"plot", gldf.string(), "--out", (dir / "p.svg").string()}).exit_code, 0);
  EXPECT_EQ(gonio({"compare", ldt.string(), gldf.string()}).exit_code, 0);
}

// product.xml of a GLDF file.
std::string product_xml(const fs::path& gldf) {
  Result<std::vector<io::ZipEntry>> entries = io::read_zip(test::read_file(gldf), gldf.string());
  if (!entries.ok()) return "";
  for (const io::ZipEntry& e : *entries)
    if (e.name == "product.xml") return e.bytes;
  return "";
}

// With $SOURCE_DATE_EPOCH the GLDF's dates (product.xml's creation time
// and the ZIP entries' times) are that moment: the same input gives the same
// bytes (scripts/fuzz.sh's seeds rely on it). Without it, the clock.
TEST(CliConvert, SourceDateEpochMakesGldfBytesRepeatable) {
  test::TempDir dir;
  const auto ldt = dir / "in.ldt";
  test::write_distribution(ldt, test::lambertian_downlight());
  std::string first;
  for (int k = 0; k < 2; ++k) {
    fs::create_directories(dir / std::to_string(k));
    const auto gldf = dir / std::to_string(k) / "lamp.gldf";  // the name goes into the archive
    {
      test::ScopedEnv epoch("SOURCE_DATE_EPOCH", "1764620000");  // 2025-12-01T20:13:20Z
      ASSERT_EQ(gonio({"convert", ldt.string(), gldf.string(), "--quiet"}).exit_code, 0);
    }
    const std::string bytes = test::read_file(gldf);
    if (k == 0) first = bytes;
    EXPECT_EQ(bytes, first);
    Result<io::GldfFile> g = io::parse_gldf(bytes, gldf.string());
    ASSERT_TRUE(g.ok()) << to_string(g.error());
    EXPECT_TRUE(contains(product_xml(gldf), "2025-12-01T20:13:20Z")) << product_xml(gldf);
  }
  // Not a number of seconds: the clock, so the date is not 1970's or 2025's.
  test::ScopedEnv bad("SOURCE_DATE_EPOCH", "yesterday");
  const auto gldf = dir / "clock.gldf";
  ASSERT_EQ(gonio({"convert", ldt.string(), gldf.string(), "--quiet"}).exit_code, 0);
  const std::string xml = product_xml(gldf);
  EXPECT_TRUE(contains(xml, "GldfCreationTimeCode")) << xml;
  EXPECT_FALSE(contains(xml, "2025-12-01T20:13:20"));
  EXPECT_FALSE(contains(xml, "1970-01-01"));
}

TEST(CliConvert, EachPhotometryOfAGldfCanBeExtracted) {
  test::TempDir dir;
  const Distribution d = test::lambertian_downlight();
  io::GldfProduct p;
  p.name = "two";
  p.photometries.push_back({"two.ldt", "ldc/eulumdat", *io::write_ldt(d, {}, nullptr), d});
  p.photometries.push_back({"two.ies", "ldc/ies", io::write_ies(d, {}, nullptr), d});
  p.created_unix = 1764620000;
  const auto gldf = dir / "two.gldf";
  test::write_file(gldf, *io::write_gldf(p));

  auto r = gonio({"convert", gldf.string(), (dir / "first.ies").string(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = gonio({"convert", gldf.string(), (dir / "first.ldt").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "read 'photometry1' (ldc/two.ldt), not 'photometry2' [gldf-first-photometry]")) << r.err;
  EXPECT_EQ(test::read_file(dir / "first.ldt"), p.photometries[0].bytes);
  for (const char* which : {"photometry2", "ldc/two.ies"}) {
    r = gonio({"convert", gldf.string(), (dir / "second.ies").string(), "--photometry", which, "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    expect_same_candela(read(dir / "first.ies"), read(dir / "second.ies"), 1e-11);  // LDT: 12 digits
  }
  r = gonio({"info", gldf.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "\"gldf_photometry_id\": \"photometry2\"")) << r.out;
  r = gonio({"check", gldf.string(), "--photometry", "photometry2"});
  EXPECT_TRUE(contains(r.out, "two.gldf:ldc/two.ies: ")) << r.out;
  EXPECT_FALSE(contains(r.out, "two.gldf:ldc/two.ldt")) << r.out;
  r = gonio({"convert", gldf.string(), (dir / "x.ies").string(), "--photometry", "photometry9"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.err, "no photometry 'photometry9' in the archive; it holds photometry1 (ldc/two.ldt), "
                              "photometry2 (ldc/two.ies)"))
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.ies"));
}

TEST(CliConvert, HostileGldfIsAClearErrorAndNothingIsWritten) {
  test::TempDir dir;
  const std::string ldt = *io::write_ldt(test::lambertian_downlight(), {}, nullptr);
  const std::string product =
      "<Root><GeneralDefinitions><Files><File id=\"f\" contentType=\"ldc/eulumdat\" "
      "type=\"localFileName\">xx/evil.ldt</File></Files><Photometries><Photometry id=\"p\">"
      "<PhotometryFileReference fileId=\"f\"/></Photometry></Photometries></GeneralDefinitions></Root>";
  std::string zip = *io::write_zip({{"product.xml", product}, {"ldc/xx/evil.ldt", ldt}}, 0);
  for (auto at = zip.find("ldc/xx/evil.ldt"); at != std::string::npos; at = zip.find("ldc/xx/evil.ldt", at))
    zip.replace(at, 15, "../../evil.ldt1");  // same length: the archive stays well formed
  test::write_file(dir / "evil.gldf", zip);
  const auto before = test::directory_entries(dir.path());
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"convert", (dir / "evil.gldf").string(), (dir / "out.ldt").string()},
           {"info", (dir / "evil.gldf").string()}}) {
    auto r = gonio(args);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_TRUE(contains(r.err, "gonio: " + (dir / "evil.gldf").string() + ": entry '../../evil.ldt1' leaves "
                                "the archive"))
        << r.err;
  }
  EXPECT_EQ(test::directory_entries(dir.path()), before);
  EXPECT_FALSE(fs::exists(dir.path().parent_path() / "evil.ldt1"));
}

}  // namespace
}  // namespace gonio
