#include "io/photometric/ies.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include "io/support/text.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

using photometry::Distribution;
using photometry::FileGenerationType;
using photometry::kNaN;
using photometry::LengthUnit;
using photometry::OpeningShape;
using photometry::PhotometricType;
using photometry::Symmetry;
using photometry::Tilt;

constexpr const char* kName = "test.ies";

// The keyword part of a valid LM-63-2002 file.
const std::string kHead2002 =
    "IESNA:LM-63-2002\r\n"
    "[TEST] T-1\r\n"
    "[TESTLAB] ACME Photometrics\r\n"
    "[ISSUEDATE] 2024-05-01\r\n"
    "[MANUFAC] ACME\r\n"
    "[LAMP] LED module\r\n"
    "TILT=NONE\r\n";

// Photometric data: Type C quadrant, 3 vertical × 2 horizontal angles.
const std::string kData =
    "1 1000 1 3 2 1 2 0 0 0\r\n"
    "1 1 10\r\n"
    "0 45 90\r\n"
    "0 90\r\n"
    "100 80 10\r\n"
    "100 70 5\r\n";

Result<IesFile> parse(const std::string& text, const std::string& dir = "") {
  test::offer_fuzz_seed("ies", text);
  return parse_ies(text, kName, dir);
}

IesFile parse_ok(const std::string& text, const std::string& dir = "") {
  auto r = parse(text, dir);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : to_string(r.error()));
  return r.ok() ? std::move(r).value() : IesFile{};
}

// The error for `text`, which must not parse.
Error parse_error(const std::string& text, const std::string& dir = "") {
  auto r = parse(text, dir);
  EXPECT_FALSE(r.ok()) << "parsed, but should not have:\n" << text;
  return r.ok() ? Error{} : r.error();
}

bool has_finding(const IesFile& f, const std::string& code, int line = -1) {
  return std::any_of(f.findings.begin(), f.findings.end(), [&](const Finding& x) {
    return x.code == code && (line < 0 || x.where.line == line) && x.where.file == kName;
  });
}

bool has_warning(const std::vector<Finding>& w, const std::string& code) {
  return std::any_of(w.begin(), w.end(), [&](const Finding& x) { return x.code == code; });
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  for (const TextLine& l : split_lines(text)) out.emplace_back(l.text);
  return out;
}

// ---------------------------------------------------------------------------
// Reading: versions and header

TEST(IesRead, BasicFile) {
  const IesFile f = parse_ok(kHead2002 + kData);
  EXPECT_EQ(f.version, IesVersion::LM63_2002);
  EXPECT_TRUE(f.findings.empty());
  const Distribution& d = f.distribution;
  EXPECT_EQ(d.type, PhotometricType::C);
  EXPECT_EQ(d.symmetry, Symmetry::Quadrant);
  EXPECT_EQ(d.vertical_deg, (std::vector<double>{0, 45, 90}));
  EXPECT_EQ(d.horizontal_deg, (std::vector<double>{0, 90}));
  EXPECT_EQ(d.candela, (std::vector<double>{100, 80, 10, 100, 70, 5}));
  EXPECT_EQ(d.at(1, 2), 5.0);
  ASSERT_EQ(d.lamps.size(), 1u);
  EXPECT_EQ(d.lamps[0].count, 1);
  EXPECT_EQ(d.lamps[0].flux_lm, 1000.0);
  EXPECT_EQ(d.lamps[0].type, "LED module");
  EXPECT_FALSE(d.absolute);
  EXPECT_EQ(d.input_watts, 10.0);
  EXPECT_EQ(d.ballast_factor, 1.0);
  EXPECT_EQ(d.tilt.kind, Tilt::Kind::None);
  EXPECT_EQ(d.opening.shape, OpeningShape::Point);
  EXPECT_TRUE(photometry::validate(d).ok());
}

TEST(IesRead, DetectsEveryVersion) {
  struct Case {
    std::string line;
    IesVersion version;
    const char* warning;  // expected finding code or nullptr
  };
  const std::vector<Case> cases = {
      {"IESNA91", IesVersion::LM63_1991, nullptr},
      {"IESNA:LM-63-1995", IesVersion::LM63_1995, nullptr},
      {"IESNA:LM-63-2002", IesVersion::LM63_2002, nullptr},
      {"IES:LM-63-2019", IesVersion::LM63_2019, nullptr},
      {"iesna:lm-63-2002", IesVersion::LM63_2002, nullptr},
      {"IESNA95", IesVersion::LM63_1995, "nonstandard-version"},
      {"IESNA:LM-63-1991", IesVersion::LM63_1991, "nonstandard-version"},
      {"IES:LM-63-2031", IesVersion::LM63_2019, "nonstandard-version"},
      {"IESNA:LM-63", IesVersion::LM63_2002, "unknown-version"},
  };
  const std::string keywords =
      "[TEST] 1\r\n[TESTLAB] L\r\n[ISSUEDATE] D\r\n[MANUFAC] M\r\nTILT=NONE\r\n";
  for (const Case& c : cases) {
    SCOPED_TRACE(c.line);
    const IesFile f = parse_ok(c.line + "\r\n" + keywords + kData);
    EXPECT_EQ(f.version, c.version);
    if (c.warning) {
      EXPECT_TRUE(has_finding(f, c.warning, 1));
    } else {
      EXPECT_TRUE(f.findings.empty()) << f.findings.front().message;
    }
  }
}

TEST(IesRead, Lm63_1986LabelLines) {
  // No version line; free-form label lines up to TILT, kept as [OTHER].
  const std::string text =
      "ERCO Leuchten GmbH  BY: ERCO/LUM650/8701\r\n"
      "-\r\n"
      "Downlight 100W\r\n"
      "TILT=NONE\r\n" +
      kData;
  const IesFile f = parse_ok(text);
  EXPECT_EQ(f.version, IesVersion::LM63_1986);
  EXPECT_TRUE(f.findings.empty());
  const auto& k = f.distribution.keywords;
  ASSERT_EQ(k.size(), 3u);
  EXPECT_EQ(k[0].key, "OTHER");
  EXPECT_EQ(k[0].value, "ERCO Leuchten GmbH  BY: ERCO/LUM650/8701");
  EXPECT_EQ(k[1].value, "-");
  EXPECT_EQ(k[2].value, "Downlight 100W");
}

TEST(IesRead, LabelLineInLaterVersionsWarns) {
  const std::string text =
      "IESNA:LM-63-1995\r\n[TEST] 1\r\nfree text\r\n[MANUFAC] M\r\nTILT=NONE\r\n" + kData;
  const IesFile f = parse_ok(text);
  EXPECT_TRUE(has_finding(f, "label-line", 3));
  ASSERT_EQ(f.distribution.keywords.size(), 3u);
  EXPECT_EQ(f.distribution.keywords[1].key, "OTHER");
  EXPECT_EQ(f.distribution.keywords[1].value, "free text");
}

TEST(IesRead, ByteOrderMarkBlankLinesIndentationAndLowerCase) {
  const std::string text =
      "\xEF\xBB\xBF\r\n\r\n   IESNA:LM-63-2002\r\n"
      "  [test] T-1\r\n"
      "[TestLab]   ACME   \r\n"
      "\r\n"
      "[issuedate] x\r\n[manufac] m\r\n"
      "  tilt = none\r\n" +
      kData;
  const IesFile f = parse_ok(text);
  EXPECT_EQ(f.version, IesVersion::LM63_2002);
  EXPECT_TRUE(f.findings.empty());
  const auto& k = f.distribution.keywords;
  ASSERT_EQ(k.size(), 4u);
  EXPECT_EQ(k[0].key, "TEST");
  EXPECT_EQ(k[0].value, "T-1");
  EXPECT_EQ(k[1].key, "TESTLAB");
  EXPECT_EQ(k[1].value, "ACME");
  EXPECT_EQ(f.distribution.candela.size(), 6u);
}

TEST(IesRead, KeywordsInFileOrderWithMoreJoined) {
  const std::string text =
      "IES:LM-63-2019\r\n"
      "[TEST] 1\r\n[TESTLAB] L\r\n[ISSUEDATE] D\r\n[MANUFAC] M\r\n"
      "[LUMINAIRE] Line one\r\n"
      "[MORE] line two\r\n"
      "[more] line three\r\n"
      "[_USER] my own\r\n"
      "[LUMINAIRE] second luminaire keyword\r\n"
      "[FILEGENINFO] made by hand\r\n"
      "TILT=NONE\r\n" +
      kData;
  const IesFile f = parse_ok(text);
  EXPECT_TRUE(f.findings.empty());
  const auto& k = f.distribution.keywords;
  ASSERT_EQ(k.size(), 8u);
  EXPECT_EQ(k[4].key, "LUMINAIRE");
  EXPECT_EQ(k[4].value, "Line one\nline two\nline three");
  EXPECT_EQ(k[5].key, "_USER");
  EXPECT_EQ(k[6].value, "second luminaire keyword");
  EXPECT_EQ(k[7].key, "FILEGENINFO");
  EXPECT_EQ(f.distribution.find_keyword("LUMINAIRE")->value, "Line one\nline two\nline three");
}

TEST(IesRead, UnknownKeywordAndOrphanMoreWarn) {
  const std::string text =
      "IESNA:LM-63-1995\r\n[MORE] orphan\r\n[TEST] 1\r\n[MANUFAC] M\r\n[FIXTURE] "
      "x\r\nTILT=NONE\r\n" +
      kData;
  const IesFile f = parse_ok(text);
  EXPECT_TRUE(has_finding(f, "more-without-keyword", 2));
  EXPECT_TRUE(has_finding(f, "unknown-keyword", 5));
  EXPECT_EQ(f.distribution.keywords[0].key, "OTHER");
  EXPECT_EQ(f.distribution.keywords[3].key, "FIXTURE");
}

TEST(IesRead, MissingRequiredKeywordsWarn) {
  const IesFile f = parse_ok("IES:LM-63-2019\r\n[TEST] 1\r\n[MANUFAC] M\r\nTILT=NONE\r\n" + kData);
  int missing = 0;
  for (const Finding& x : f.findings) {
    if (x.code != "missing-keyword") continue;
    ++missing;
    EXPECT_EQ(x.where.line, 4);  // the TILT line: where the keywords end
    EXPECT_TRUE(contains(x.message, "TESTLAB") || contains(x.message, "ISSUEDATE")) << x.message;
  }
  EXPECT_EQ(missing, 2);
  // LM-63-1995 requires only [TEST] and [MANUFAC].
  const IesFile g = parse_ok("IESNA:LM-63-1995\r\n[TEST] 1\r\nTILT=NONE\r\n" + kData);
  EXPECT_EQ(std::count_if(g.findings.begin(), g.findings.end(),
                          [](const Finding& x) { return x.code == "missing-keyword"; }),
            1);
}

TEST(IesRead, Latin1LabelsBecomeUtf8) {
  const std::string text =
      "IESNA:LM-63-2002\r\n[TEST] 1\r\n[TESTLAB] L\r\n[ISSUEDATE] D\r\n"
      "[MANUFAC] Leuchten M\xfcller\r\n[LUMINAIRE] 55\xb0 beam\r\nTILT=NONE\r\n" +
      kData;
  const IesFile f = parse_ok(text);
  EXPECT_EQ(f.distribution.find_keyword("MANUFAC")->value, "Leuchten M\xc3\xbcller");
  EXPECT_EQ(f.distribution.find_keyword("LUMINAIRE")->value, "55\xc2\xb0 beam");
}

// ---------------------------------------------------------------------------
// Reading: numbers

TEST(IesRead, SeparatorsAndLineEnds) {
  // Tabs and commas, lone CR line ends, values wrapped one per line and
  // several lists on one line: all the same file.
  const std::string text =
      "IESNA:LM-63-2002\r[TEST] 1\r[TESTLAB] L\r[ISSUEDATE] D\r[MANUFAC] M\rTILT=NONE\r"
      "1\t1000,1\r3\r2 1 2\t0,0,0 1 1\r10\r0\r45\r90 0 90 100,80,10\r100\r70\r5\r";
  const IesFile f = parse_ok(text);
  EXPECT_EQ(f.distribution.candela, (std::vector<double>{100, 80, 10, 100, 70, 5}));
  EXPECT_TRUE(f.findings.empty());

  // LF only, and CRLF mixed with LF.
  std::string lf = kHead2002 + kData;
  lf.erase(std::remove(lf.begin(), lf.end(), '\r'), lf.end());
  EXPECT_EQ(parse_ok(lf).distribution.candela, f.distribution.candela);
}

TEST(IesRead, FindingsComeInFileOrder) {
  std::string long_line(300, ' ');
  long_line += "0 90";
  const std::string text =
      "IESNA:LM-63-2002\r\n[TEST] 1\r\n[FOO] x\r\nTILT=NONE\r\n"
      "1 1000 1 3 2 1 2 0 0 0\r\n1 1 10\r\n0 45 90\r\n" +
      long_line + "\r\n100 80 10\r\n100 70 5\r\nEND\r\n";
  const IesFile f = parse_ok(text);
  std::vector<std::string> codes;
  for (const Finding& x : f.findings) codes.push_back(x.code);
  EXPECT_EQ(codes,
            (std::vector<std::string>{"unknown-keyword", "missing-keyword", "missing-keyword",
                                      "missing-keyword", "long-line", "trailing-data"}));
  for (std::size_t i = 1; i < f.findings.size(); ++i)
    EXPECT_LE(f.findings[i - 1].where.line, f.findings[i].where.line);
}

TEST(IesRead, LongLinesWarnOnceAndAreRead) {
  std::string values;
  for (int i = 0; i < 60; ++i) values += "100.25 ";  // 420 characters
  const std::string text = kHead2002 + "1 1000 1 3 20 1 2 0 0 0\r\n1 1 10\r\n0 45 90\r\n" +
                           "0 5 10 15 20 25 30 35 40 45 50 55 60 65 70 75 80 85 88 90\r\n" +
                           values + "\r\n";
  const IesFile f = parse_ok(text);
  ASSERT_EQ(f.findings.size(), 1u);
  EXPECT_EQ(f.findings[0].code, "long-line");
  EXPECT_EQ(f.findings[0].where.line, 12);
  EXPECT_EQ(f.distribution.candela.size(), 60u);
}

TEST(IesRead, MultiplierAppliedBallastAndFactorsKept) {
  const std::string text = kHead2002 +
                           "2 1500 2.5 3 2 1 2 0 0 0\r\n"
                           "0.95 1 42.5\r\n"
                           "0 45 90\r\n0 90\r\n100 80 10\r\n100 70 5\r\n";
  const Distribution d = parse_ok(text).distribution;
  EXPECT_EQ(d.candela, (std::vector<double>{250, 200, 25, 250, 175, 12.5}));
  EXPECT_EQ(d.lamps[0].count, 2);
  EXPECT_EQ(d.lamps[0].flux_lm, 3000.0);
  EXPECT_EQ(d.ballast_factor, 0.95);
  EXPECT_EQ(d.input_watts, 42.5);
  EXPECT_EQ(d.ballast_lamp_factor, 1.0);

  // LM-63-1995: the second value is the ballast-lamp photometric factor.
  const std::string text95 =
      "IESNA:LM-63-1995\r\n[TEST] 1\r\n[MANUFAC] M\r\nTILT=NONE\r\n"
      "1 1000 1 3 2 1 2 0 0 0\r\n1 0.9 10\r\n0 45 90\r\n0 90\r\n1 2 3 4 5 6\r\n";
  const IesFile f95 = parse_ok(text95);
  EXPECT_EQ(f95.distribution.ballast_lamp_factor, 0.9);
  EXPECT_EQ(f95.distribution.candela[5], 6.0);  // kept, not applied
  EXPECT_TRUE(f95.findings.empty());

  // LM-63-2002 calls it "future use": anything but 1 is worth a warning.
  const std::string text02 =
      kHead2002 + "1 1000 1 3 2 1 2 0 0 0\r\n1 0.9 10\r\n0 45 90\r\n0 90\r\n1 2 3 4 5 6\r\n";
  const IesFile f02 = parse_ok(text02);
  EXPECT_TRUE(has_finding(f02, "future-use", 9));
  EXPECT_EQ(f02.distribution.ballast_lamp_factor, 0.9);
}

TEST(IesRead, FileGenerationType2019) {
  const std::string head =
      "IES:LM-63-2019\r\n[TEST] 1\r\n[TESTLAB] L\r\n[ISSUEDATE] D\r\n[MANUFAC] M\r\nTILT=NONE\r\n"
      "1 1000 1 3 2 1 2 0 0 0\r\n";
  const std::string rest = " 10\r\n0 45 90\r\n0 90\r\n1 2 3 4 5 6\r\n";
  const std::vector<std::pair<std::string, FileGenerationType>> cases = {
      {"1.00001", FileGenerationType::Undefined},
      {"1.00010", FileGenerationType::ComputerSimulation},
      {"1.0001", FileGenerationType::ComputerSimulation},
      {"1", FileGenerationType::UnaccreditedLab},
      {"1.00100", FileGenerationType::UnaccreditedLabScaled},
      {"1.01000", FileGenerationType::UnaccreditedLabInterpolated},
      {"1.01100", FileGenerationType::UnaccreditedLabInterpolatedScaled},
      {"1.10000", FileGenerationType::AccreditedLab},
      {"1.10100", FileGenerationType::AccreditedLabScaled},
      {"1.11000", FileGenerationType::AccreditedLabInterpolated},
      {"1.11100", FileGenerationType::AccreditedLabInterpolatedScaled},
  };
  for (const auto& [code, type] : cases) {
    SCOPED_TRACE(code);
    const IesFile f = parse_ok(head + "1 " + code + rest);
    EXPECT_EQ(f.distribution.file_generation, type);
    EXPECT_TRUE(f.findings.empty());
    EXPECT_EQ(file_generation_from_code(file_generation_code(type)), type);
  }
  const IesFile bad = parse_ok(head + "1 1.2345" + rest);
  EXPECT_TRUE(has_finding(bad, "file-generation-type", 8));
  EXPECT_EQ(bad.distribution.file_generation, FileGenerationType::Undefined);
  EXPECT_FALSE(file_generation_from_code(0.95));
  EXPECT_FALSE(file_generation_from_code(1.000015));
}

TEST(IesRead, AbsolutePhotometry) {
  const std::string text =
      kHead2002 + "1 -1 1 3 2 1 2 0 0 0\r\n1 1 10\r\n0 45 90\r\n0 90\r\n1 2 3 4 5 6\r\n";
  const IesFile f = parse_ok(text);
  EXPECT_TRUE(f.distribution.absolute);
  EXPECT_TRUE(std::isnan(f.distribution.lamps[0].flux_lm));
  EXPECT_TRUE(std::isnan(f.distribution.rated_lamp_flux_lm()));
  EXPECT_TRUE(f.findings.empty());

  const std::string odd =
      kHead2002 + "1 -2 1 3 2 1 2 0 0 0\r\n1 1 10\r\n0 45 90\r\n0 90\r\n1 2 3 4 5 6\r\n";
  const IesFile g = parse_ok(odd);
  EXPECT_TRUE(g.distribution.absolute);
  EXPECT_TRUE(has_finding(g, "absolute-flux", 8));
}

TEST(IesRead, NegativeIntensitiesReadAsZeroWithWarning) {
  const std::string text = kHead2002 +
                           "1 1000 1 3 2 1 2 0 0 0\r\n1 1 10\r\n0 45 90\r\n0 90\r\n"
                           "1 -0.5 3\r\n4 5 -6\r\n";
  const IesFile f = parse_ok(text);
  EXPECT_EQ(f.distribution.candela, (std::vector<double>{1, 0, 3, 4, 5, 0}));
  ASSERT_TRUE(has_finding(f, "negative-intensity", 12));
  EXPECT_TRUE(contains(f.findings[0].message, "2 negative"));
}

TEST(IesRead, TrailingDataWarns) {
  const IesFile f = parse_ok(kHead2002 + kData + "\r\nEND\r\n\x1a");
  EXPECT_TRUE(has_finding(f, "trailing-data", 15));
  EXPECT_EQ(f.distribution.candela.size(), 6u);
  // A DOS end-of-file byte alone is not data.
  EXPECT_TRUE(parse_ok(kHead2002 + kData + "\x1a").findings.empty());
}

// ---------------------------------------------------------------------------
// Reading: angle ranges and symmetry

std::string type_c(const std::string& h_angles, int nh,
                   const std::string& version = "IESNA:LM-63-2002") {
  std::string text = version +
                     "\r\n[TEST] 1\r\n[TESTLAB] L\r\n[ISSUEDATE] D\r\n[MANUFAC] M\r\nTILT=NONE\r\n"
                     "1 1000 1 2 " +
                     std::to_string(nh) + " 1 2 0 0 0\r\n1 1 10\r\n0 90\r\n" + h_angles + "\r\n";
  for (int i = 0; i < nh; ++i)
    text += std::to_string(10 * i + 1) + " " + std::to_string(10 * i + 2) + "\r\n";
  return text;
}

TEST(IesRead, TypeCHorizontalRanges) {
  EXPECT_EQ(parse_ok(type_c("0", 1)).distribution.symmetry, Symmetry::Rotational);
  EXPECT_EQ(parse_ok(type_c("0 45 90", 3)).distribution.symmetry, Symmetry::Quadrant);
  EXPECT_EQ(parse_ok(type_c("0 90 180", 3)).distribution.symmetry, Symmetry::C0_C180);
  EXPECT_EQ(parse_ok(type_c("0 90 180 270 360", 5)).distribution.symmetry, Symmetry::None);
  EXPECT_EQ(parse_ok(type_c("0 120 240 345", 4)).distribution.symmetry, Symmetry::None);

  // 90–270: an LM-63-1995 range; accepted with a warning in later versions.
  const IesFile f95 = parse_ok(type_c("90 180 270", 3, "IESNA:LM-63-1995"));
  EXPECT_EQ(f95.distribution.symmetry, Symmetry::C90_C270);
  EXPECT_TRUE(f95.findings.empty());
  const IesFile f02 = parse_ok(type_c("90 180 270", 3));
  EXPECT_EQ(f02.distribution.symmetry, Symmetry::C90_C270);
  EXPECT_TRUE(has_finding(f02, "horizontal-range", 10));
  EXPECT_DOUBLE_EQ(photometry::interpolate(photometry::expand_symmetry(f02.distribution), 45, 90),
                   photometry::interpolate(photometry::expand_symmetry(f02.distribution), 135, 90));

  const IesFile single = parse_ok(type_c("30", 1));
  EXPECT_EQ(single.distribution.symmetry, Symmetry::Rotational);
  EXPECT_TRUE(has_finding(single, "horizontal-range", 10));

  Error e = parse_error(type_c("0 20 45", 3));
  EXPECT_EQ(e.where.line, 10);
  EXPECT_TRUE(contains(e.message, "0 to 45")) << e.message;
  e = parse_error(type_c("10 90 180", 3));
  EXPECT_EQ(e.where.line, 10);
  EXPECT_TRUE(contains(e.message, "must start at 0")) << e.message;
  e = parse_error(type_c("0 180 370", 3));
  EXPECT_TRUE(contains(e.message, "370")) << e.message;
}

TEST(IesRead, TypeCVerticalRange) {
  std::string text = kHead2002 + "1 1000 1 3 1 1 2 0 0 0\r\n1 1 10\r\n0 90 190\r\n0\r\n1 2 3\r\n";
  Error e = parse_error(text);
  EXPECT_EQ(e.where.file, kName);
  EXPECT_EQ(e.where.line, 10);
  EXPECT_TRUE(contains(e.message, "outside 0 to 180")) << e.message;

  e = parse_error(kHead2002 + "1 1000 1 3 1 1 2 0 0 0\r\n1 1 10\r\n-5 0 90\r\n0\r\n1 2 3\r\n");
  EXPECT_TRUE(contains(e.message, "-5")) << e.message;

  // Inside 0–180 but not one of the standard ranges: read, with a warning.
  const IesFile f =
      parse_ok(kHead2002 + "1 1000 1 3 1 1 2 0 0 0\r\n1 1 10\r\n0 40 85\r\n0\r\n1 2 3\r\n");
  EXPECT_TRUE(has_finding(f, "vertical-range", 10));
}

std::string type_ab(int type, const std::string& v, int nv, const std::string& h, int nh) {
  std::string text = kHead2002 + "1 1000 1 " + std::to_string(nv) + " " + std::to_string(nh) + " " +
                     std::to_string(type) + " 2 0 0 0\r\n1 1 10\r\n" + v + "\r\n" + h + "\r\n";
  for (int i = 0; i < nh * nv; ++i) text += std::to_string(i + 1) + " ";
  return text + "\r\n";
}

TEST(IesRead, TypesAAndB) {
  const IesFile b = parse_ok(type_ab(2, "-90 -45 0 45 90", 5, "0 45 90", 3));
  EXPECT_EQ(b.distribution.type, PhotometricType::B);
  EXPECT_EQ(b.distribution.symmetry, Symmetry::Lateral);
  EXPECT_TRUE(b.findings.empty());
  EXPECT_EQ(b.distribution.at(2, 4), 15.0);

  const IesFile a = parse_ok(type_ab(3, "-90 0 90", 3, "-90 -30 30 90", 4));
  EXPECT_EQ(a.distribution.type, PhotometricType::A);
  EXPECT_EQ(a.distribution.symmetry, Symmetry::None);
  EXPECT_TRUE(a.findings.empty());
  EXPECT_TRUE(photometry::validate(a.distribution).ok());

  const IesFile partial = parse_ok(type_ab(3, "0 45 90", 3, "-45 0 45", 3));
  EXPECT_EQ(partial.distribution.symmetry, Symmetry::None);
  EXPECT_TRUE(has_finding(partial, "horizontal-range", 11));

  Error e = parse_error(type_ab(2, "-90 0 90", 3, "10 45 90", 3));
  EXPECT_EQ(e.where.line, 11);
  EXPECT_TRUE(contains(e.message, "must start at -90 or 0")) << e.message;
  e = parse_error(type_ab(2, "-90 0 100", 3, "0 45 90", 3));
  EXPECT_EQ(e.where.line, 10);
  EXPECT_TRUE(contains(e.message, "outside -90 to 90")) << e.message;
  e = parse_error(type_ab(3, "-90 0 90", 3, "0 45 120", 3));
  EXPECT_TRUE(contains(e.message, "outside -90 to 90")) << e.message;
}

// ---------------------------------------------------------------------------
// Reading: luminous opening

struct OpeningCase {
  const char* dims;
  OpeningShape shape;
  double width, length, height;  // [file units]
};

LengthUnit unit_of(const IesFile& f) { return f.distribution.opening.file_unit; }

void expect_opening(const std::string& version, const OpeningCase& c, int units = 2) {
  SCOPED_TRACE(version + " " + c.dims);
  const std::string text =
      version +
      "\r\n[TEST] 1\r\n[TESTLAB] L\r\n[ISSUEDATE] D\r\n[MANUFAC] M\r\nTILT=NONE\r\n"
      "1 1000 1 2 1 1 " +
      std::to_string(units) + " " + c.dims + "\r\n1 1 10\r\n0 90\r\n0\r\n1 2\r\n";
  const IesFile f = parse_ok(text);
  EXPECT_FALSE(has_finding(f, "opening-shape"));
  const auto& o = f.distribution.opening;
  const double k = units == 1 ? 0.3048 : 1.0;
  EXPECT_EQ(o.shape, c.shape) << photometry::to_string(o.shape);
  EXPECT_DOUBLE_EQ(o.width_m, c.width * k);
  EXPECT_DOUBLE_EQ(o.length_m, c.length * k);
  EXPECT_DOUBLE_EQ(o.height_m, c.height * k);
  EXPECT_EQ(unit_of(f), units == 1 ? LengthUnit::Foot : LengthUnit::Metre);
}

// LM-63-2019 §5.11 Table 1, also used for LM-63-2002.
const std::vector<OpeningCase> kTable2019 = {
    {"0 0 0", OpeningShape::Point, 0, 0, 0},
    {"0.5 1.2 0", OpeningShape::Rectangular, 0.5, 1.2, 0},
    {"0.5 1.2 0.1", OpeningShape::RectangularWithSides, 0.5, 1.2, 0.1},
    {"-0.3 -0.3 0", OpeningShape::Circular, 0.3, 0.3, 0},
    {"-0.3 -0.5 0", OpeningShape::Ellipse, 0.3, 0.5, 0},
    {"-0.3 -0.3 0.2", OpeningShape::VerticalCylinder, 0.3, 0.3, 0.2},
    {"-0.3 -0.5 0.2", OpeningShape::VerticalEllipticalCylinder, 0.3, 0.5, 0.2},
    {"-0.3 -0.3 -0.3", OpeningShape::Sphere, 0.3, 0.3, 0.3},
    {"-0.3 -0.5 -0.2", OpeningShape::Ellipsoid, 0.3, 0.5, 0.2},
    {"-0.1 1.2 -0.1", OpeningShape::HorizontalCylinderAlongLength, 0.1, 1.2, 0.1},
    {"-0.1 1.2 -0.2", OpeningShape::HorizontalEllipticalCylinderAlongLength, 0.1, 1.2, 0.2},
    {"1.2 -0.1 -0.1", OpeningShape::HorizontalCylinderAlongWidth, 1.2, 0.1, 0.1},
    {"1.2 -0.1 -0.2", OpeningShape::HorizontalEllipticalCylinderAlongWidth, 1.2, 0.1, 0.2},
    {"-0.3 0 -0.3", OpeningShape::VerticalCircle, 0.3, 0, 0.3},
    {"-0.3 0 -0.4", OpeningShape::VerticalEllipse, 0.3, 0, 0.4},
};

// The LM-63-1995 table, used for 1986–1995 files.
const std::vector<OpeningCase> kTable1995 = {
    {"0 0 0", OpeningShape::Point, 0, 0, 0},
    {"0.5 1.2 0", OpeningShape::Rectangular, 0.5, 1.2, 0},
    {"0.5 1.2 0.1", OpeningShape::RectangularWithSides, 0.5, 1.2, 0.1},
    {"-0.3 0 0", OpeningShape::Circular, 0.3, 0.3, 0},
    {"-0.3 0 -0.3", OpeningShape::Sphere, 0.3, 0.3, 0.3},
    {"-0.3 0 0.2", OpeningShape::VerticalCylinder, 0.3, 0.3, 0.2},
    {"0 1.2 -0.1", OpeningShape::HorizontalCylinderAlongLength, 0.1, 1.2, 0.1},
    {"1.2 0 -0.1", OpeningShape::HorizontalCylinderAlongWidth, 1.2, 0.1, 0.1},
    {"-0.3 0.5 0", OpeningShape::Ellipse, 0.3, 0.5, 0},
    {"0.3 -0.5 0", OpeningShape::Ellipse, 0.3, 0.5, 0},
    {"-0.3 0.5 0.2", OpeningShape::VerticalEllipticalCylinder, 0.3, 0.5, 0.2},
    {"0.3 -0.5 0.2", OpeningShape::VerticalEllipticalCylinder, 0.3, 0.5, 0.2},
    {"-0.3 0.5 -0.2", OpeningShape::Ellipsoid, 0.3, 0.5, 0.2},
    {"0.3 -0.5 -0.2", OpeningShape::Ellipsoid, 0.3, 0.5, 0.2},
};

TEST(IesRead, LuminousOpeningTable2019) {
  for (const auto& c : kTable2019) {
    expect_opening("IES:LM-63-2019", c);
    expect_opening("IESNA:LM-63-2002", c);
    expect_opening("IES:LM-63-2019", c, 1);  // feet
  }
}

TEST(IesRead, LuminousOpeningTable1995) {
  for (const auto& c : kTable1995) {
    expect_opening("IESNA:LM-63-1995", c);
    expect_opening("IESNA91", c, 1);
  }
}

TEST(IesRead, LuminousOpeningOutsideTheTables) {
  const auto read = [](const std::string& version, const std::string& dims) {
    return parse_ok(version + "\r\n[TEST] 1\r\n[MANUFAC] M\r\nTILT=NONE\r\n1 1000 1 2 1 1 2 " +
                    dims + "\r\n1 1 10\r\n0 90\r\n0\r\n1 2\r\n");
  };
  // A 1995 encoding in a 2002 file: read by the 1995 table, with a warning.
  IesFile f = read("IESNA:LM-63-2002", "-0.3 0 0");
  EXPECT_TRUE(has_finding(f, "opening-shape", 5));
  EXPECT_EQ(f.distribution.opening.shape, OpeningShape::Circular);
  EXPECT_EQ(f.distribution.opening.length_m, 0.3);
  // A 2019 encoding in a 1995 file, likewise.
  f = read("IESNA:LM-63-1995", "-0.3 -0.3 -0.3");
  EXPECT_TRUE(has_finding(f, "opening-shape", 5));
  EXPECT_EQ(f.distribution.opening.shape, OpeningShape::Sphere);
  // In neither table: one negative horizontal dimension → circle.
  f = read("IESNA91", "0 -0.32 0");
  EXPECT_TRUE(has_finding(f, "opening-shape", 5));
  EXPECT_EQ(f.distribution.opening.shape, OpeningShape::Circular);
  EXPECT_EQ(f.distribution.opening.width_m, 0.32);
  // Anything else → rectangle of the absolute values.
  f = read("IES:LM-63-2019", "0.5 0.5 -0.2");
  EXPECT_TRUE(has_finding(f, "opening-shape", 5));
  EXPECT_EQ(f.distribution.opening.shape, OpeningShape::RectangularWithSides);
  EXPECT_EQ(f.distribution.opening.height_m, 0.2);
}

// ---------------------------------------------------------------------------
// Reading: TILT

const std::string kTiltData = "1\r\n5\r\n0 15 30 60 90\r\n1 0.98 0.95 0.9 0.85\r\n";

TEST(IesRead, TiltInclude) {
  const std::string text =
      "IESNA:LM-63-2002\r\n[TEST] 1\r\n[TESTLAB] L\r\n[ISSUEDATE] D\r\n[MANUFAC] "
      "M\r\nTILT=INCLUDE\r\n" +
      kTiltData + kData;
  const IesFile f = parse_ok(text);
  const Tilt& t = f.distribution.tilt;
  EXPECT_EQ(t.kind, Tilt::Kind::Include);
  EXPECT_EQ(t.lamp_geometry, 1);
  EXPECT_EQ(t.angles_deg, (std::vector<double>{0, 15, 30, 60, 90}));
  EXPECT_EQ(t.factors, (std::vector<double>{1, 0.98, 0.95, 0.9, 0.85}));
  EXPECT_EQ(f.distribution.candela.size(), 6u);
  EXPECT_TRUE(f.findings.empty());

  Error e = parse_error("IESNA:LM-63-2002\r\nTILT=INCLUDE\r\n4\r\n2\r\n0 90\r\n1 1\r\n" + kData);
  EXPECT_EQ(e.where.line, 3);
  EXPECT_TRUE(contains(e.message, "lamp-to-luminaire geometry")) << e.message;
  e = parse_error("IESNA:LM-63-2002\r\nTILT=INCLUDE\r\n1\r\n3\r\n0 90 45\r\n1 1 1\r\n" + kData);
  EXPECT_EQ(e.where.line, 5);
  EXPECT_TRUE(contains(e.message, "TILT angles must increase")) << e.message;
  e = parse_error("IESNA:LM-63-2002\r\nTILT=INCLUDE\r\n1\r\n2\r\n0 90\r\n1 -1\r\n" + kData);
  EXPECT_EQ(e.where.line, 6);
}

TEST(IesRead, TiltFileResolvedBesideTheIesFile) {
  test::TempDir dir;
  test::write_file(dir / "lamp.tlt", kTiltData);
  const std::string text =
      "IESNA:LM-63-2002\r\n[TEST] 1\r\n[TESTLAB] L\r\n[ISSUEDATE] D\r\n[MANUFAC] M\r\n"
      "TILT=lamp.tlt\r\n" +
      kData;
  test::write_file(dir / "a.ies", text);
  auto r = read_ies((dir / "a.ies").string());
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  const Tilt& t = r->distribution.tilt;
  EXPECT_EQ(t.kind, Tilt::Kind::File);
  EXPECT_EQ(t.file, "lamp.tlt");
  EXPECT_EQ(t.lamp_geometry, 1);
  EXPECT_EQ(t.factors.back(), 0.85);
  EXPECT_EQ(r->distribution.candela.size(), 6u);

  // The same bytes through parse_ies with the directory.
  EXPECT_TRUE(parse_ies(text, "a.ies", dir.path().string()).ok());
}

TEST(IesRead, MissingOrBadTiltFileNamesBothFiles) {
  test::TempDir dir;
  const std::string text = "IESNA:LM-63-2002\r\n[TEST] 1\r\nTILT=missing.tlt\r\n" + kData;
  test::write_file(dir / "a.ies", text);
  const std::string ies_path = (dir / "a.ies").string();
  auto r = read_ies(ies_path);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where.file, ies_path);
  EXPECT_EQ(r.error().where.line, 3);
  EXPECT_TRUE(contains(r.error().message, "missing.tlt")) << r.error().message;
  EXPECT_TRUE(contains(r.error().message, (dir / "missing.tlt").string())) << r.error().message;

  // A tilt file with bad data: the error is in the tilt file and names the IES file.
  test::write_file(dir / "bad.tlt", "1\r\n3\r\n0 45 x\r\n1 1 1\r\n");
  test::write_file(dir / "b.ies", "IESNA:LM-63-2002\r\nTILT=bad.tlt\r\n" + kData);
  r = read_ies((dir / "b.ies").string());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where.file, (dir / "bad.tlt").string());
  EXPECT_EQ(r.error().where.line, 3);
  EXPECT_TRUE(contains(r.error().message, "'x'")) << r.error().message;
  EXPECT_TRUE(contains(r.error().message, (dir / "b.ies").string() + ":2")) << r.error().message;

  // Bytes without a directory cannot resolve a tilt file.
  Error e = parse_error("IESNA:LM-63-2002\r\nTILT=lamp.tlt\r\n" + kData);
  EXPECT_EQ(e.where.line, 2);
  EXPECT_TRUE(contains(e.message, "no directory")) << e.message;
}

// ---------------------------------------------------------------------------
// Hostile input: every one an Error naming the file and the line.

void expect_error(const std::string& text, int line, const std::string& part) {
  SCOPED_TRACE(part);
  const Error e = parse_error(text);
  EXPECT_EQ(e.where.file, kName);
  EXPECT_EQ(e.where.line, line) << e.message;
  EXPECT_TRUE(contains(e.message, part)) << e.message;
}

TEST(IesHostile, EmptyBinaryAndUtf16) {
  expect_error("", 1, "empty file");
  expect_error("  \r\n\r\n\t\n", 1, "empty file");
  expect_error(std::string("IESNA:LM-63-2002\r\n[TEST] a\0b\r\n", 30), 2, "binary");
  std::string junk;
  std::mt19937 rng(7);
  for (int i = 0; i < 4096; ++i) junk.push_back(static_cast<char>(rng() & 0xff));
  const Error e = parse_error(junk);
  EXPECT_EQ(e.where.file, kName);
  EXPECT_GT(e.where.line, 0);
  expect_error(std::string("\xff\xfeI\0E\0S\0", 8), 1, "UTF-16");
}

TEST(IesHostile, MissingTiltLine) {
  expect_error("IESNA:LM-63-2002\r\n[TEST] 1\r\n" + kData, 3, "missing TILT line");
  expect_error("IESNA:LM-63-2002\r\n[TEST] 1\r\n[MANUFAC] M\r\n", 3, "missing TILT line");
  expect_error("IESNA:LM-63-2002\r\nTILT=\r\n" + kData, 2, "TILT= names nothing");
}

TEST(IesHostile, TruncatedFiles) {
  const std::string full = kHead2002 + kData;
  expect_error(full.substr(0, full.size() - 3), 13,
               "unexpected end of file: expected candela value 3 of 3");
  expect_error(kHead2002, 7, "unexpected end of file: expected number of lamps");
  expect_error(kHead2002 + "1 1000 1 3 2 1 2 0 0 0\r\n1 1", 9, "expected input watts");
  // Every prefix of a valid file either parses or fails with a located error.
  for (std::size_t n = 0; n < full.size(); ++n) {
    auto r = parse(full.substr(0, n));
    if (!r.ok()) {
      EXPECT_EQ(r.error().where.file, kName);
      EXPECT_GT(r.error().where.line, 0) << n << ": " << r.error().message;
    }
  }
}

TEST(IesHostile, AbsurdCountsFailBeforeAllocating) {
  // 10^9 × 10^9 angles in a file of a few hundred bytes: refused at once.
  expect_error(kHead2002 + "1 1000 1 1000000000 1000000000 1 2 0 0 0\r\n1 1 10\r\n0 45 90\r\n", 8,
               "more than the");
  expect_error(kHead2002 + "1 1000 1 3 1000000 1 2 0 0 0\r\n1 1 10\r\n0 45 90\r\n", 8,
               "more than the");
  expect_error(kHead2002 + "1 1000 1 3 1e300 1 2 0 0 0\r\n1 1 10\r\n", 8,
               "number of horizontal angles");
  expect_error(kHead2002 + "1 1000 1 -3 2 1 2 0 0 0\r\n1 1 10\r\n", 8, "number of vertical angles");
  expect_error(kHead2002 + "1 1000 1 0 2 1 2 0 0 0\r\n1 1 10\r\n", 8, "an integer from 1");
  expect_error(kHead2002 + "1 1000 1 2.5 2 1 2 0 0 0\r\n1 1 10\r\n", 8, "found 2.5");
  expect_error(kHead2002 + "-1 1000 1 3 2 1 2 0 0 0\r\n1 1 10\r\n", 8, "number of lamps");
  expect_error("IESNA:LM-63-2002\r\nTILT=INCLUDE\r\n1\r\n2000000000\r\n0 1\r\n", 4,
               "TILT angles need");
}

// kHead2002 and a photometric line for 3 vertical × 2 horizontal angles,
// then the given angle and candela lines.
std::string with_lists(const std::string& v, const std::string& h, const std::string& cd) {
  return kHead2002 + "1 1000 1 3 2 1 2 0 0 0\r\n1 1 10\r\n" + v + "\r\n" + h + "\r\n" + cd + "\r\n";
}

TEST(IesHostile, BadTokens) {
  expect_error(with_lists("0 4x5 90", "0 90", "100 80 10 100 70 5"), 10,
               "expected vertical angle 2 of 3, found '4x5'");
  expect_error(with_lists("0 45 90", "0 90", "100 nan 10\r\n100 70 5"), 12, "not a finite number");
  expect_error(with_lists("0 45 90", "0 90", "100 80 10\r\n100 inf 5"), 13,
               "candela value 2 of 3 of horizontal angle 90 (2 of 2)");
  expect_error(with_lists("0 45 90", "0 90", "100 1e999 10\r\n100 70 5"), 12, "found '1e999'");
  expect_error(kHead2002 + "1 1000 1 3 2 4 2 0 0 0\r\n", 8, "photometric type");
  expect_error(kHead2002 + "1 1000 1 3 2 1 3 0 0 0\r\n", 8, "units type");
  expect_error(kHead2002 + "1 0 1 3 2 1 2 0 0 0\r\n1 1 10\r\n0 45 90\r\n0 90\r\n1 2 3 4 5 6\r\n", 8,
               "lumens per lamp must be positive");
  expect_error(kHead2002 + "1 1000 0 3 2 1 2 0 0 0\r\n", 8, "multiplier must be positive");
  std::string long_token(100000, '7');
  long_token += "x";
  expect_error(kHead2002 + long_token + "\r\n", 8, "expected number of lamps");
}

TEST(IesHostile, UnsortedAndDuplicateAngles) {
  expect_error(with_lists("0\r\n90\r\n45", "0 90", "1 2 3 4 5 6"), 12,
               "vertical angles must increase: 45 follows 90");
  expect_error(with_lists("0 45 90", "90 0", "1 2 3 4 5 6"), 11, "horizontal angles must increase");
  expect_error(with_lists("0 45 45", "0 90", "1 2 3 4 5 6"), 10, "vertical angles must increase");
}

TEST(IesHostile, FilesOnDisk) {
  test::TempDir dir;
  auto r = read_ies(dir.path().string());
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error().message, "directory"));
  r = read_ies((dir / "nope.ies").string());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where.file, (dir / "nope.ies").string());
  // Larger than the limit: refused without reading (a sparse file).
  {
    std::ofstream(dir / "huge.ies").put('x');
    std::filesystem::resize_file(dir / "huge.ies", kMaxIesFileBytes + 1);
  }
  r = read_ies((dir / "huge.ies").string());
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error().message, "too large")) << r.error().message;
}

TEST(IesHostile, RandomMutationsNeverCrash) {
  const std::string base = "IESNA:LM-63-2002\r\n[TEST] 1\r\nTILT=INCLUDE\r\n" + kTiltData + kData;
  std::mt19937 rng(12345);
  const std::string alphabet = "0123456789 .-+eE,\r\n\tx[]=";
  int parsed = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::string s = base;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int k = 0; k < edits; ++k) {
      const std::size_t at = rng() % s.size();
      switch (rng() % 3) {
        case 0: s[at] = alphabet[rng() % alphabet.size()]; break;
        case 1: s.erase(at, 1 + rng() % 3); break;
        default: s.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
      }
      if (s.empty()) s = "x";
    }
    auto r = parse(s);
    if (r.ok()) {
      ++parsed;
      EXPECT_TRUE(photometry::validate(r->distribution).ok());
    } else {
      EXPECT_EQ(r.error().where.file, kName);
      EXPECT_FALSE(r.error().message.empty());
    }
  }
  EXPECT_GT(parsed, 0);
}

// ---------------------------------------------------------------------------
// Numbers as written

TEST(IesNumber, Format) {
  EXPECT_EQ(format_ies_number(0.0), "0");
  EXPECT_EQ(format_ies_number(-0.0), "0");
  EXPECT_EQ(format_ies_number(1.0), "1");
  EXPECT_EQ(format_ies_number(-2.5), "-2.5");
  EXPECT_EQ(format_ies_number(100.0), "100");
  EXPECT_EQ(format_ies_number(1234.5), "1234.5");
  EXPECT_EQ(format_ies_number(0.1), "0.1");
  EXPECT_EQ(format_ies_number(0.00001), "0.00001");
  EXPECT_EQ(format_ies_number(1.0 / 3.0), "0.333333333333333");
  EXPECT_EQ(format_ies_number(2.0 / 3.0 * 1000.0), "666.666666666667");
  EXPECT_EQ(format_ies_number(1e15), "1000000000000000");
  EXPECT_EQ(format_ies_number(1e16), "1e16");
  EXPECT_EQ(format_ies_number(1.5e-11), "1.5e-11");
  EXPECT_EQ(format_ies_number(0.12 * 0.3048 / 0.3048), "0.12");
  EXPECT_EQ(format_ies_number(185.10000000000002), "185.1");
}

TEST(IesNumber, ReadingBackGivesWhatWasWrittenAndIsStable) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> mantissa(1.0, 10.0);
  std::uniform_int_distribution<int> exponent(-10, 15);
  for (int i = 0; i < 20000; ++i) {
    const double x = (i % 2 ? -1 : 1) * mantissa(rng) * std::pow(10.0, exponent(rng));
    const std::string s = format_ies_number(x);
    const auto y = parse_number(s);
    ASSERT_TRUE(y.has_value()) << s;
    EXPECT_LE(std::abs(*y - x), 5e-15 * std::abs(x)) << s;
    EXPECT_EQ(format_ies_number(*y), s);  // stable
    EXPECT_EQ(*parse_number(format_ies_number(*y)), *y);
  }
  // Decimals of at most 15 significant digits come back as written.
  std::uniform_int_distribution<long long> digits(1, 999999999999999LL);
  std::uniform_int_distribution<int> point(0, 15);
  for (int i = 0; i < 20000; ++i) {
    std::string d = std::to_string(digits(rng));
    const int p = point(rng) % static_cast<int>(d.size() + 1);
    std::string s = d;
    if (p > 0 && p < static_cast<int>(d.size()))
      s.insert(d.size() - static_cast<std::size_t>(p), ".");
    while (s.find('.') != std::string::npos && (s.back() == '0' || s.back() == '.')) s.pop_back();
    EXPECT_EQ(format_ies_number(*parse_number(s)), s);
  }
}

// ---------------------------------------------------------------------------
// Writing

Distribution sample(Symmetry symmetry = Symmetry::C0_C180) {
  Distribution d;
  d.type = PhotometricType::C;
  d.symmetry = symmetry;
  for (double g = 0; g <= 180; g += 7.5) d.vertical_deg.push_back(g);
  switch (symmetry) {
    case Symmetry::Rotational: d.horizontal_deg = {0}; break;
    case Symmetry::Quadrant: d.horizontal_deg = {0, 22.5, 45, 67.5, 90}; break;
    case Symmetry::C0_C180: d.horizontal_deg = {0, 30, 60, 90, 120, 150, 180}; break;
    case Symmetry::C90_C270: d.horizontal_deg = {90, 135, 180, 225, 270}; break;
    default: d.horizontal_deg = {0, 45, 90, 135, 180, 225, 270, 315, 360}; break;
  }
  for (double c : d.horizontal_deg)
    for (double g : d.vertical_deg)
      d.candela.push_back(
          1000.0 / 3.0 * std::cos(g * std::numbers::pi / 360.0) * (1.0 + c / 1000.0) + g / 7.0);
  d.lamps = {photometry::LampSet{2, "LED", 3000.0, "", "", kNaN}};
  d.input_watts = 31.5;
  d.keywords = {{"TEST", "R-17"},
                {"TESTLAB", "Lab"},
                {"ISSUEDATE", "2024-05-01"},
                {"MANUFAC", "ACME"},
                {"LUMINAIRE", "Downlight\nwith two lines"},
                {"_COLOUR", "warm"}};
  d.file_generation = FileGenerationType::ComputerSimulation;
  return d;
}

IesFile write_and_read(const Distribution& d, std::vector<Finding>* warnings = nullptr,
                       IesVersion version = IesVersion::LM63_2019) {
  IesWriteOptions options;
  options.version = version;
  const std::string text = write_ies(d, options, warnings);
  auto r = parse_ies(text, "written.ies", "");
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : to_string(r.error())) << "\n" << text;
  return r.ok() ? std::move(r).value() : IesFile{};
}

// The values a reader gets back for what the writer printed.
std::vector<double> as_written(const std::vector<double>& v) {
  std::vector<double> out;
  for (double x : v) out.push_back(*parse_number(format_ies_number(x)));
  return out;
}

// Found by tests/fuzz/ies_fuzzer.cpp: a keyword whose name alone fills a
// line sent the writer's line wrapping out of range (an uncaught
// std::out_of_range), and control characters the reader accepts in keywords
// were written back, so that the written file read as binary data.
TEST(IesWrite, FuzzFoundKeywordsLongerThanALineOrWithControlCharactersRoundTrip) {
  const std::string long_key = "_" + std::string(300, 'K');  // a user keyword keeps its name
  const std::string text = "IESNA:LM-63-2002\r\n[TEST] T-1\r\n[" + long_key + "] value\r\n[_NOTE] a" +
                           std::string(9, '\x14') + "b " + std::string(1200, 'x') + "\r\nTILT=NONE\r\n" + kData;
  const IesFile f = parse_ok(text);
  std::vector<Finding> notes;
  const std::string written = write_ies(f.distribution, {}, &notes);
  EXPECT_TRUE(has_warning(notes, "control-characters"));
  EXPECT_EQ(std::count_if(written.begin(), written.end(),
                          [](char c) { return static_cast<unsigned char>(c) < 0x20 && c != '\r' && c != '\n'; }),
            0);
  const IesFile again = parse_ok(written);
  const photometry::Keyword* k = again.distribution.find_keyword(long_key);
  ASSERT_NE(k, nullptr);
  EXPECT_EQ(k->value, "value");
  EXPECT_EQ(again.distribution.candela, f.distribution.candela);
}

TEST(IesWrite, Lm63_2019Layout) {
  std::vector<Finding> warnings;
  const std::string text = write_ies(sample(), {}, &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front().message;
  const auto lines = lines_of(text);
  ASSERT_GT(lines.size(), 12u);
  EXPECT_EQ(lines[0], "IES:LM-63-2019");
  EXPECT_EQ(lines[1], "[TEST] R-17");
  EXPECT_EQ(lines[2], "[TESTLAB] Lab");
  EXPECT_EQ(lines[3], "[ISSUEDATE] 2024-05-01");
  EXPECT_EQ(lines[4], "[MANUFAC] ACME");
  EXPECT_EQ(lines[5].rfind("[FILEGENINFO] Written by Gonio ", 0), 0u);
  EXPECT_EQ(lines[6], "[LUMINAIRE] Downlight");
  EXPECT_EQ(lines[7], "[MORE] with two lines");
  EXPECT_EQ(lines[8], "[_COLOUR] warm");
  EXPECT_EQ(lines[9], "[LAMP] LED");
  EXPECT_EQ(lines[10], "TILT=NONE");
  EXPECT_EQ(lines[11], "2 1500 1 25 7 1 2 0 0 0");
  EXPECT_EQ(lines[12], "1 1.00010 31.5");
  // CR LF everywhere, short lines.
  std::size_t crlf = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') {
      ASSERT_GT(i, 0u);
      EXPECT_EQ(text[i - 1], '\r');
      ++crlf;
    }
  }
  EXPECT_EQ(crlf, lines.size());
  for (std::size_t i = 11; i < lines.size(); ++i) EXPECT_LE(lines[i].size(), 128u) << lines[i];
  // Each plane's candela values start on a new line.
  const IesFile f = parse_ok(text);
  EXPECT_TRUE(f.findings.empty()) << f.findings.front().message;
}

TEST(IesWrite, Lm63_2002Layout) {
  Distribution d = sample();
  d.keywords.push_back({"FILEGENINFO", "from a simulation"});
  std::vector<Finding> warnings;
  IesWriteOptions options;
  options.version = IesVersion::LM63_2002;
  const std::string text = write_ies(d, options, &warnings);
  const auto lines = lines_of(text);
  EXPECT_EQ(lines[0], "IESNA:LM-63-2002");
  EXPECT_FALSE(contains(text, "[FILEGENINFO]"));
  EXPECT_TRUE(contains(text, "[OTHER] from a simulation"));
  EXPECT_TRUE(has_warning(warnings, "keyword-renamed"));
  const auto tilt = std::find(lines.begin(), lines.end(), "TILT=NONE");
  ASSERT_NE(tilt, lines.end());
  EXPECT_EQ(*(tilt + 2), "1 1 31.5");
  const IesFile f = parse_ok(text);
  EXPECT_EQ(f.version, IesVersion::LM63_2002);
  EXPECT_TRUE(f.findings.empty()) << f.findings.front().message;
}

void expect_same(const Distribution& a, const Distribution& b) {
  EXPECT_EQ(a.type, b.type);
  EXPECT_EQ(a.symmetry, b.symmetry);
  EXPECT_EQ(as_written(a.vertical_deg), b.vertical_deg);
  EXPECT_EQ(as_written(a.horizontal_deg), b.horizontal_deg);
  EXPECT_EQ(as_written(a.candela), b.candela);
  EXPECT_EQ(a.absolute, b.absolute);
}

TEST(IesWrite, RoundTripKeepsTheModel) {
  for (Symmetry s : {Symmetry::Rotational, Symmetry::Quadrant, Symmetry::C0_C180, Symmetry::None}) {
    SCOPED_TRACE(photometry::to_string(s));
    const Distribution d = sample(s);
    std::vector<Finding> warnings;
    const IesFile f = write_and_read(d, &warnings);
    EXPECT_TRUE(warnings.empty());
    const Distribution& e = f.distribution;
    expect_same(d, e);
    EXPECT_EQ(f.version, IesVersion::LM63_2019);
    EXPECT_EQ(e.lamps[0].count, 2);
    EXPECT_EQ(e.lamps[0].flux_lm, 3000.0);
    EXPECT_EQ(e.lamps[0].type, "LED");
    EXPECT_EQ(e.input_watts, 31.5);
    EXPECT_EQ(e.file_generation, FileGenerationType::ComputerSimulation);
    EXPECT_EQ(e.find_keyword("LUMINAIRE")->value, "Downlight\nwith two lines");
    EXPECT_EQ(e.find_keyword("_COLOUR")->value, "warm");
    // Stable: the second generation is byte for byte the first.
    EXPECT_EQ(write_ies(e, {}, nullptr), write_ies(d, {}, nullptr));
  }
}

TEST(IesWrite, SmallestHorizontalRange) {
  // Rotational: one plane at 0, whatever angle the model stored.
  Distribution rot = sample(Symmetry::Rotational);
  rot.horizontal_deg = {45.0};
  IesFile f = write_and_read(rot);
  EXPECT_EQ(f.distribution.horizontal_deg, (std::vector<double>{0.0}));
  EXPECT_EQ(f.distribution.symmetry, Symmetry::Rotational);
  // Quadrant stays 0–90, C0-C180 stays 0–180.
  EXPECT_EQ(write_and_read(sample(Symmetry::Quadrant)).distribution.horizontal_deg.back(), 90.0);
  EXPECT_EQ(write_and_read(sample(Symmetry::C0_C180)).distribution.horizontal_deg.back(), 180.0);
}

TEST(IesWrite, C90C270IsExpandedToTheFullCircle) {
  const Distribution d = sample(Symmetry::C90_C270);
  std::vector<Finding> warnings;
  for (IesVersion v : {IesVersion::LM63_2019, IesVersion::LM63_2002}) {
    warnings.clear();
    const IesFile f = write_and_read(d, &warnings, v);
    EXPECT_TRUE(has_warning(warnings, "symmetry-expanded"));
    EXPECT_EQ(f.distribution.symmetry, Symmetry::None);
    EXPECT_EQ(f.distribution.horizontal_deg.front(), 0.0);
    EXPECT_EQ(f.distribution.horizontal_deg.back(), 360.0);
    const Distribution a = photometry::expand_symmetry(d);
    const Distribution b = photometry::expand_symmetry(f.distribution);
    for (double c = 0; c < 360; c += 15)
      for (double g = 0; g <= 180; g += 7.5)
        EXPECT_NEAR(photometry::interpolate(a, c, g), photometry::interpolate(b, c, g), 1e-9)
            << c << " " << g;
  }
}

TEST(IesWrite, FullRangeNotStartingAtZeroIsClosed) {
  Distribution d = sample(Symmetry::None);
  d.horizontal_deg = {10, 100, 190, 280};
  d.candela.resize(4 * d.vertical_deg.size());
  std::vector<Finding> warnings;
  const IesFile f = write_and_read(d, &warnings);
  EXPECT_TRUE(has_warning(warnings, "symmetry-expanded"));
  EXPECT_EQ(f.distribution.horizontal_deg.front(), 0.0);
  EXPECT_EQ(f.distribution.horizontal_deg.back(), 360.0);
}

TEST(IesWrite, FullRangeEndingAt180IsClosed) {
  // Symmetry::None on 0–180 would read back as C0-C180 symmetry.
  Distribution d = sample(Symmetry::None);
  d.horizontal_deg = {0, 60, 120, 180};
  d.candela.resize(4 * d.vertical_deg.size());
  std::vector<Finding> warnings;
  const IesFile f = write_and_read(d, &warnings);
  EXPECT_TRUE(has_warning(warnings, "symmetry-expanded"));
  EXPECT_EQ(f.distribution.symmetry, Symmetry::None);
  EXPECT_EQ(f.distribution.horizontal_deg.back(), 360.0);
  const Distribution a = photometry::expand_symmetry(d);
  for (double c = 0; c < 360; c += 10)
    EXPECT_NEAR(photometry::interpolate(a, c, 45), photometry::interpolate(f.distribution, c, 45),
                1e-9);
}

TEST(IesWrite, TypesAAndBRoundTrip) {
  for (PhotometricType t : {PhotometricType::A, PhotometricType::B}) {
    Distribution d = sample();
    d.type = t;
    d.symmetry = Symmetry::Lateral;
    d.vertical_deg = {-90, -45, 0, 45, 90};
    d.horizontal_deg = {0, 30, 60, 90};
    d.candela.clear();
    for (int i = 0; i < 20; ++i) d.candela.push_back(10.0 + i / 7.0);
    IesFile f = write_and_read(d);
    expect_same(d, f.distribution);
    d.symmetry = Symmetry::None;
    d.horizontal_deg = {-90, -30, 30, 90};
    std::vector<Finding> warnings;
    f = write_and_read(d, &warnings);
    expect_same(d, f.distribution);
    EXPECT_TRUE(warnings.empty());
    // No symmetry on H ≥ 0 only: LM-63 cannot say so; reported.
    d.horizontal_deg = {0, 30, 60, 90};
    f = write_and_read(d, &warnings);
    EXPECT_TRUE(has_warning(warnings, "lateral-range"));
    EXPECT_EQ(f.distribution.symmetry, Symmetry::Lateral);
  }
}

TEST(IesWrite, TiltRoundTripAndFileTiltIsIncluded) {
  Distribution d = sample();
  d.tilt.kind = Tilt::Kind::Include;
  d.tilt.lamp_geometry = 2;
  d.tilt.angles_deg = {0, 30, 60, 90};
  d.tilt.factors = {1, 0.97, 0.9, 0.8};
  std::vector<Finding> warnings;
  IesFile f = write_and_read(d, &warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(f.distribution.tilt.kind, Tilt::Kind::Include);
  EXPECT_EQ(f.distribution.tilt.lamp_geometry, 2);
  EXPECT_EQ(f.distribution.tilt.angles_deg, d.tilt.angles_deg);
  EXPECT_EQ(f.distribution.tilt.factors, d.tilt.factors);

  d.tilt.kind = Tilt::Kind::File;
  d.tilt.file = "lamp.tlt";
  f = write_and_read(d, &warnings);
  EXPECT_TRUE(has_warning(warnings, "tilt-file-included"));
  EXPECT_EQ(f.distribution.tilt.kind, Tilt::Kind::Include);
  EXPECT_EQ(f.distribution.tilt.factors, d.tilt.factors);
}

TEST(IesWrite, LuminousOpeningEncodingsRoundTrip) {
  // Every shape, in both units: written by the 2019 table and read back
  // as the same shape and dimensions; in feet the file shows the feet.
  for (const auto& c : kTable2019) {
    for (LengthUnit unit : {LengthUnit::Metre, LengthUnit::Foot}) {
      SCOPED_TRACE(std::string(c.dims) + (unit == LengthUnit::Foot ? " ft" : " m"));
      const double k = unit == LengthUnit::Foot ? 0.3048 : 1.0;
      Distribution d = sample();
      d.opening.shape = c.shape;
      d.opening.width_m = c.width * k;
      d.opening.length_m = c.length * k;
      d.opening.height_m = c.height * k;
      d.opening.file_unit = unit;
      const std::string text = write_ies(d, {}, nullptr);
      EXPECT_TRUE(
          contains(text, std::string(unit == LengthUnit::Foot ? " 1 " : " 2 ") + c.dims + "\r\n"))
          << text.substr(0, 600);
      const IesFile f = parse_ok(text);
      EXPECT_FALSE(has_finding(f, "opening-shape"));
      EXPECT_EQ(f.distribution.opening.shape, c.shape);
      EXPECT_DOUBLE_EQ(f.distribution.opening.width_m, d.opening.width_m);
      EXPECT_DOUBLE_EQ(f.distribution.opening.length_m, d.opening.length_m);
      EXPECT_DOUBLE_EQ(f.distribution.opening.height_m, d.opening.height_m);
      EXPECT_EQ(f.distribution.opening.file_unit, unit);
    }
  }
  // A 1995 file written as 2019 changes encoding, not geometry.
  const IesFile old = parse_ok(
      "IESNA:LM-63-1995\r\n[TEST] 1\r\n[MANUFAC] M\r\nTILT=NONE\r\n"
      "1 1000 1 2 1 1 1 -0.5 0 0.25\r\n1 1 10\r\n0 90\r\n0\r\n1 2\r\n");
  EXPECT_TRUE(contains(write_ies(old.distribution, {}, nullptr), " 1 1 -0.5 -0.5 0.25\r\n"));
}

TEST(IesWrite, LongAndMultiLineKeywords) {
  Distribution d = sample();
  std::string long_value;
  for (int i = 0; i < 120; ++i) long_value += "word" + std::to_string(i) + " ";
  d.keywords.push_back({"OTHER", long_value});
  std::vector<Finding> warnings;
  const std::string text = write_ies(d, {}, &warnings);
  EXPECT_TRUE(has_warning(warnings, "keyword-wrapped"));
  for (const std::string& l : lines_of(text)) EXPECT_LE(l.size() + 2, 256u);  // with CR LF
  const IesFile f = parse_ok(text);
  std::string back = f.distribution.keywords[f.distribution.keywords.size() - 2].value;
  std::replace(back.begin(), back.end(), '\n', ' ');
  EXPECT_EQ(back + " ", long_value);
}

TEST(IesWrite, Latin1Text) {
  Distribution d = sample();
  d.set_keyword("MANUFAC", "Leuchten M\xc3\xbcller 55\xc2\xb0");
  d.keywords.push_back({"OTHER", "price in \xe2\x82\xac"});
  std::vector<Finding> warnings;
  const std::string text = write_ies(d, {}, &warnings);
  EXPECT_TRUE(contains(text, "[MANUFAC] Leuchten M\xfcller 55\xb0\r\n"));
  EXPECT_TRUE(contains(text, "[OTHER] price in ?\r\n"));
  EXPECT_TRUE(has_warning(warnings, "non-latin1"));
  EXPECT_EQ(parse_ok(text).distribution.find_keyword("MANUFAC")->value,
            "Leuchten M\xc3\xbcller 55\xc2\xb0");
}

TEST(IesWrite, DefaultsAreFilledAndReported) {
  Distribution d = sample();
  d.keywords = {{"DATE", "1995-02-21"}, {"FOO BAR", "x"}};
  d.input_watts = kNaN;
  std::vector<Finding> warnings;
  IesWriteOptions options;
  options.file_generation_info = "gonio simulate, 10^8 photons";
  const std::string text = write_ies(d, options, &warnings);
  EXPECT_TRUE(contains(text, "[TEST] not stated\r\n"));
  EXPECT_TRUE(contains(text, "[ISSUEDATE] 1995-02-21\r\n"));  // the old [DATE]
  EXPECT_TRUE(contains(text, "[FILEGENINFO] gonio simulate, 10^8 photons\r\n"));
  EXPECT_TRUE(contains(text, "[_FOO_BAR] x\r\n"));
  EXPECT_EQ(std::count_if(warnings.begin(), warnings.end(),
                          [](const Finding& w) { return w.code == "default-keyword"; }),
            3);  // TEST, TESTLAB, MANUFAC
  EXPECT_TRUE(has_warning(warnings, "keyword-renamed"));
  EXPECT_TRUE(has_warning(warnings, "input-watts-unknown"));
  EXPECT_TRUE(contains(text, "\r\n1 1.00010 0\r\n"));

  options.issue_date = "2025-01-31";
  EXPECT_TRUE(contains(write_ies(d, options, nullptr), "[ISSUEDATE] 2025-01-31\r\n"));
}

// Each writer finding fires on a model crafted for it, alone, and the file
// holds what the finding says was written.
struct WriteCase {
  const char* what;
  const char* code;
  void (*edit)(Distribution&);
  void (*expect)(const Distribution& back);
};

TEST(IesWrite, EachFindingFiresOnItsModel) {
  const WriteCase cases[] = {
      {"lamp power against input watts", "lamp-power",
       [](Distribution& d) { d.lamps[0].power_w = 20.0; },  // input watts 31.5
       [](const Distribution& back) { EXPECT_EQ(back.input_watts, 31.5); }},
      {"relative photometry without lamps", "no-lamp-flux",
       [](Distribution& d) { d.lamps.clear(); },
       [](const Distribution& back) {
         EXPECT_TRUE(back.absolute);
         ASSERT_EQ(back.lamps.size(), 1u);
         EXPECT_EQ(back.lamps[0].count, 1);
       }},
      {"tilt without angles", "tilt-invalid",
       [](Distribution& d) {
         d.tilt.kind = Tilt::Kind::Include;
         d.tilt.lamp_geometry = 1;
       },
       [](const Distribution& back) { EXPECT_EQ(back.tilt.kind, Tilt::Kind::None); }},
      {"tilt factors that do not match the angles", "tilt-invalid",
       [](Distribution& d) {
         d.tilt.kind = Tilt::Kind::Include;
         d.tilt.lamp_geometry = 1;
         d.tilt.angles_deg = {0, 45, 90};
         d.tilt.factors = {1, 0.9};
       },
       [](const Distribution& back) { EXPECT_EQ(back.tilt.kind, Tilt::Kind::None); }},
      {"tilt lamp geometry 4", "tilt-invalid",
       [](Distribution& d) {
         d.tilt.kind = Tilt::Kind::File;
         d.tilt.file = "lamp.tlt";
         d.tilt.lamp_geometry = 4;
         d.tilt.angles_deg = {0, 90};
         d.tilt.factors = {1, 0.8};
       },
       [](const Distribution& back) { EXPECT_EQ(back.tilt.kind, Tilt::Kind::None); }},
      {"unknown ballast factor", "ballast-factor-unknown",
       [](Distribution& d) { d.ballast_factor = kNaN; },
       [](const Distribution& back) { EXPECT_EQ(back.ballast_factor, 1.0); }},
  };
  std::vector<Finding> warnings;
  write_and_read(sample(), &warnings);
  ASSERT_TRUE(warnings.empty()) << warnings[0].message;
  for (const WriteCase& c : cases) {
    SCOPED_TRACE(c.what);
    Distribution d = sample();
    c.edit(d);
    ASSERT_TRUE(photometry::validate(d).ok());
    warnings.clear();
    const IesFile f = write_and_read(d, &warnings);
    ASSERT_EQ(warnings.size(), 1u) << warnings[0].code << ": " << warnings[0].message;
    EXPECT_EQ(warnings[0].code, c.code) << warnings[0].message;
    EXPECT_EQ(warnings[0].severity, Severity::Warning);
    EXPECT_TRUE(f.findings.empty()) << f.findings[0].message;  // a clean file all the same
    c.expect(f.distribution);
  }
}

TEST(IesWrite, WhatIesCannotCarryIsReported) {
  Distribution d = sample();
  d.lamps = {photometry::LampSet{2, "T5 28W", 5200.0, "3000 K", "1B", 32.0},
             photometry::LampSet{1, "T5 14W", 1350.0, "", "", 17.0}};
  d.input_watts = kNaN;
  d.declared_lor_percent = 72.0;
  d.declared_dff_percent = 95.0;
  d.measurement_tilt_deg = 5.0;
  d.direct_ratios = std::vector<double>(10, 0.5);
  d.luminaire.length_m = 1.2;
  d.opening.side_height_m[0] = 0.02;
  d.ballast_lamp_factor = 0.95;
  std::vector<Finding> warnings;
  const IesFile f = write_and_read(d, &warnings);
  for (const char* code : {"lamp-sets-merged", "lamp-color", "lamp-color-rendering",
                           "ldt-only-field", "ballast-lamp-factor"})
    EXPECT_TRUE(has_warning(warnings, code)) << code;
  EXPECT_EQ(std::count_if(warnings.begin(), warnings.end(),
                          [](const Finding& w) { return w.code == "ldt-only-field"; }),
            6);
  // Merged: total count and flux, the power of both sets as input watts.
  EXPECT_EQ(f.distribution.lamps[0].count, 3);
  EXPECT_NEAR(f.distribution.lamps[0].flux_lm, 6550.0, 1e-10);  // 3 × 2183.33333333333
  EXPECT_EQ(f.distribution.input_watts, 49.0);
  EXPECT_FALSE(has_warning(warnings, "input-watts-unknown"));
}

TEST(IesWrite, LdtFieldsThatCarryNothingAreNotReported) {
  // What an LDT reader gives for fields that hold nothing: tilt 0, body 0 × 0
  // × 0, side heights equal to the opening's height, the Ityp an LDT writer
  // would derive again.
  Distribution d = sample();
  d.measurement_tilt_deg = 0.0;
  d.luminaire = {0.0, 0.0, 0.0};
  d.opening.shape = photometry::OpeningShape::RectangularWithSides;
  d.opening.length_m = 0.5;
  d.opening.width_m = 0.1;
  d.opening.height_m = 0.03;
  for (double& h : d.opening.side_height_m) h = 0.03;
  d.ldt_type_indicator = 3;
  std::vector<Finding> warnings;
  write_and_read(d, &warnings);
  EXPECT_FALSE(has_warning(warnings, "ldt-only-field"));
  EXPECT_FALSE(has_warning(warnings, "alternative-lamps"));

  // Each of them with content is reported once.
  d.measurement_tilt_deg = 10.0;
  d.luminaire.height_m = 0.05;
  d.opening.side_height_m[2] = 0.01;
  d.ldt_type_indicator = 2;
  d.alternative_lamps = {photometry::LampSet{1, "LED 2", 2000.0, "", "", 20.0}};
  warnings.clear();
  const IesFile f = write_and_read(d, &warnings);
  EXPECT_EQ(std::count_if(warnings.begin(), warnings.end(),
                          [](const Finding& w) { return w.code == "ldt-only-field"; }),
            4);
  EXPECT_TRUE(has_warning(warnings, "alternative-lamps"));
  // The first lamp set stays the one the intensities refer to.
  EXPECT_EQ(f.distribution.lamps[0].flux_lm, d.lamps[0].flux_lm);
  EXPECT_EQ(f.distribution.candela, as_written(d.candela));
}

TEST(IesWriteDeathTest, BrokenPreconditionsStop) {
  IesWriteOptions options;
  options.version = IesVersion::LM63_1995;
  EXPECT_DEATH(write_ies(sample(), options, nullptr), "LM-63-2019 or LM-63-2002");
  Distribution broken = sample();
  broken.candela.pop_back();
  EXPECT_DEATH(write_ies(broken, {}, nullptr), "valid distribution");
}

TEST(IesWrite, AbsolutePhotometryRoundTrip) {
  Distribution d = sample();
  d.absolute = true;
  d.lamps[0].flux_lm = kNaN;
  const IesFile f = write_and_read(d);
  EXPECT_TRUE(f.distribution.absolute);
  EXPECT_TRUE(contains(write_ies(d, {}, nullptr), "\r\n2 -1 1 25 7 1 2 0 0 0\r\n"));
}

}  // namespace
}  // namespace gonio::io
