// Every file of the shared corpus survives conversion into the other format
// and back, through io/photometric/photometric_file.h as `gonio convert` does it:
// IES → LDT → IES and LDT → IES → LDT keep the intensities (to the written
// precision), the flux, and the fields both formats carry; whatever does
// not come back was reported by the writers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "io/photometric/ies.h"
#include "io/photometric/ldt.h"
#include "io/photometric/photometric_file.h"
#include "io/support/text.h"
#include "photometry/flux.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

namespace fs = std::filesystem;
using photometry::Distribution;
using photometry::OpeningShape;

// LDT writes 12 significant digits of cd/klm, IES 15 of cd: a value read back
// differs by at most a few parts in 10^12.
constexpr double kWrittenPrecision = 1e-11;

bool has(const std::vector<Finding>& w, const std::string& code) {
  return std::any_of(w.begin(), w.end(), [&](const Finding& f) { return f.code == code; });
}

bool mentions(const std::vector<Finding>& w, const std::string& code, const std::string& part) {
  return std::any_of(w.begin(), w.end(), [&](const Finding& f) {
    return f.code == code && f.message.find(part) != std::string::npos;
  });
}

std::string encode(const Distribution& d, PhotometricFormat format, std::vector<Finding>* w) {
  auto bytes = encode_photometric_file(d, format, {}, w);
  EXPECT_TRUE(bytes.ok()) << (bytes.ok() ? "" : bytes.error().message);
  return bytes.ok() ? *bytes : std::string();
}

Distribution parse(const std::string& bytes, PhotometricFormat format) {
  if (format == PhotometricFormat::Ies) {
    auto r = parse_ies(bytes, "back.ies", "");
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : to_string(r.error()));
    return r.ok() ? r->distribution : Distribution{};
  }
  auto r = parse_ldt(bytes, "back.ldt");
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : to_string(r.error()));
  return r.ok() ? r->distribution : Distribution{};
}

// Every stored intensity of `original` is found at the same (C, γ) in
// `back`, on a plane and γ angle of its own (no interpolation), equal to the
// written precision. `back` may store more planes (a symmetry expanded) or
// leave out C 360 where it copies C 0.
void expect_same_intensities(const Distribution& original, const Distribution& back) {
  ASSERT_EQ(back.vertical_deg.size(), original.vertical_deg.size());
  for (std::size_t v = 0; v < original.vertical_count(); ++v)
    ASSERT_NEAR(back.vertical_deg[v], original.vertical_deg[v], 1e-9);
  const Distribution e = photometry::expand_symmetry(back);
  const std::size_t nv = original.vertical_count();
  for (std::size_t h = 0; h < original.horizontal_count(); ++h) {
    const double c = original.horizontal_deg[h];
    std::size_t row = e.horizontal_count();
    for (std::size_t k = 0; k < e.horizontal_count(); ++k)
      if (std::abs(e.horizontal_deg[k] - c) < 1e-9) row = k;
    ASSERT_LT(row, e.horizontal_count()) << "plane C " << c << " is missing";
    for (std::size_t v = 0; v < nv; ++v) {
      const double a = original.at(h, v), b = e.at(row, v);
      ASSERT_LE(std::abs(a - b), kWrittenPrecision * std::abs(a))
          << "C " << c << ", gamma " << original.vertical_deg[v] << ": " << a << " -> " << b;
    }
  }
}

void expect_same_flux(const Distribution& original, const Distribution& back, double tolerance) {
  const double a = photometry::total_flux_lm(original), b = photometry::total_flux_lm(back);
  EXPECT_GT(a, 0.0);
  EXPECT_NEAR(b, a, 1e-3 * a);  // the requirement: 0.1 %
  EXPECT_NEAR(b, a, tolerance * a);
}

// What an LDT text field holds of a value: one line, Latin-1, at most
// `chars` characters (io/photometric/ldt.h), read back without surrounding blanks.
std::string as_ldt_field(std::string value, std::size_t chars) {
  for (char& c : value)
    if (c == '\r' || c == '\n') c = ' ';
  std::string latin1 = utf8_to_latin1(value);
  if (latin1.size() > chars) latin1.resize(chars);
  // The reader trims blanks around a field.
  const auto blank = [](char c) { return c == ' ' || c == '\t'; };
  while (!latin1.empty() && blank(latin1.back())) latin1.pop_back();
  latin1.erase(latin1.begin(), std::find_if_not(latin1.begin(), latin1.end(), blank));
  return latin1_to_utf8(latin1);
}

std::string keyword(const Distribution& d, const char* key) {
  const photometry::Keyword* k = d.find_keyword(key);
  return k ? k->value : std::string();
}

bool ldt_holds(OpeningShape s) {
  return s == OpeningShape::Point || s == OpeningShape::Rectangular ||
         s == OpeningShape::RectangularWithSides || s == OpeningShape::Circular ||
         s == OpeningShape::VerticalCylinder;
}

void expect_same_opening(const photometry::LuminousOpening& a,
                         const photometry::LuminousOpening& b) {
  EXPECT_EQ(b.shape, a.shape) << photometry::to_string(a.shape) << " -> "
                              << photometry::to_string(b.shape);
  EXPECT_NEAR(b.length_m, a.length_m, 1e-9);
  EXPECT_NEAR(b.width_m, a.width_m, 1e-9);
  EXPECT_NEAR(b.height_m, a.height_m, 1e-9);
}

// What EULUMDAT, which lists C 0 once, holds of a full circle of planes:
// C 360 as a copy of C 0.
Distribution with_c360_as_c0(Distribution d) {
  const std::size_t last = d.horizontal_count() - 1;
  if (d.symmetry != photometry::Symmetry::None || d.horizontal_deg.front() > 1e-9 ||
      d.horizontal_deg.back() < 360.0 - 1e-9)
    return d;
  for (std::size_t v = 0; v < d.vertical_count(); ++v) d.at(last, v) = d.at(0, v);
  return d;
}

// IES -> LDT -> IES of one file as read: what comes back and what was reported.
void expect_ies_round_trip(const Distribution& d0) {
  std::vector<Finding> to_ldt, to_ies;
  const Distribution d1 =
      parse(encode(d0, PhotometricFormat::Ldt, &to_ldt), PhotometricFormat::Ldt);
  const Distribution d2 =
      parse(encode(d1, PhotometricFormat::Ies, &to_ies), PhotometricFormat::Ies);
  EXPECT_FALSE(has(to_ldt, "type-c-resampled"));  // every corpus file is Type C

  // The one change the LDT writer makes to the intensities: a C 360 plane
  // that differs from C 0 is dropped (reported), C 0 standing for both.
  // Everything else comes back to the written precision.
  const bool c360_dropped = has(to_ldt, "ldt-plane-360-dropped");
  const Distribution kept = c360_dropped ? with_c360_as_c0(d0) : d0;
  EXPECT_EQ(c360_dropped, kept.candela != d0.candela);
  expect_same_intensities(kept, d1);
  expect_same_intensities(kept, d2);
  expect_same_flux(kept, d2, 1e-9);
  if (c360_dropped) expect_same_flux(d0, d2, 1e-3);  // against the file: the requirement

  EXPECT_EQ(d2.type, d0.type);
  EXPECT_EQ(d2.absolute, d0.absolute);
  ASSERT_EQ(d2.lamps.size(), 1u);
  EXPECT_EQ(d2.lamps[0].count, d0.lamps[0].count);
  if (!d0.absolute) {
    EXPECT_NEAR(d2.lamps[0].flux_lm, d0.lamps[0].flux_lm, 1e-9 * d0.lamps[0].flux_lm);
  }
  if (!d0.lamps[0].type.empty()) {
    const std::string expected = as_ldt_field(d0.lamps[0].type, 24);
    EXPECT_EQ(d2.lamps[0].type, expected);
    if (expected != d0.lamps[0].type) {
      EXPECT_TRUE(has(to_ldt, "ldt-truncated"));
    }
  }
  if (std::isfinite(d0.input_watts) && d0.input_watts > 0.0) {
    EXPECT_NEAR(d2.input_watts, d0.input_watts, 1e-9 * d0.input_watts);
  }
  if (ldt_holds(d0.opening.shape)) {
    expect_same_opening(d0.opening, d2.opening);
  } else {
    EXPECT_TRUE(has(to_ldt, "ldt-opening-approximated"));
  }

  // Header strings: the keywords EULUMDAT has a field for come back as
  // that field holds them; a required IES keyword that was never there
  // comes back as the writer's reported default.
  for (const char* key : {"MANUFAC", "TEST", "LUMINAIRE", "LUMCAT", "ISSUEDATE"}) {
    SCOPED_TRACE(key);
    std::string value = keyword(d0, key);
    if (value.empty() && std::string(key) == "ISSUEDATE") value = keyword(d0, "DATE");
    if (value.empty()) {
      if (std::string(key) == "LUMINAIRE" || std::string(key) == "LUMCAT") {
        EXPECT_EQ(d2.find_keyword(key), nullptr);
      } else {
        EXPECT_EQ(keyword(d2, key), "not stated");
        EXPECT_TRUE(mentions(to_ies, "default-keyword", std::string("[") + key + "]"));
      }
      continue;
    }
    const std::string expected = as_ldt_field(value, 78);
    EXPECT_EQ(keyword(d2, key), expected);
    if (expected != value) {
      EXPECT_TRUE(has(to_ldt, "ldt-truncated") || has(to_ldt, "ldt-multiline"));
    }
  }
  // Every other keyword was reported as not written.
  for (const photometry::Keyword& k : d0.keywords) {
    if (k.key == "MANUFAC" || k.key == "TEST" || k.key == "LUMINAIRE" || k.key == "LUMCAT" ||
        k.key == "ISSUEDATE" || k.key == "DATE" || k.key == "LAMP" ||
        k.key == kLdtFileNameKeyword)
      continue;
    EXPECT_TRUE(mentions(to_ldt, "ldt-keyword-dropped", "[" + k.key + "]")) << k.key;
  }
}

TEST(RoundTripCorpus, IesToLdtToIes) {
  GONIO_REQUIRE_CORPUS();
  const auto files = test::corpus_files({".ies"});
  ASSERT_EQ(files.size(), 61u);
  for (const fs::path& p : files) {
    SCOPED_TRACE(p.string());
    auto read = read_photometric_file(p.string());
    ASSERT_TRUE(read.ok()) << to_string(read.error());
    expect_ies_round_trip(read->distribution);
  }
}

// No corpus file has a C 360 plane that differs from C 0; this one does, so
// that the branch above is known to work.
TEST(RoundTripCorpus, IesWithC360UnlikeC0) {
  const std::string text =
      "IESNA:LM-63-2002\r\n[TEST] T-360\r\n[TESTLAB] Lab\r\n[ISSUEDATE] 2024-01-01\r\n"
      "[MANUFAC] ACME\r\nTILT=NONE\r\n1 1000 1 3 5 1 2 0 0 0\r\n1 1 10\r\n0 45 90\r\n"
      "0 90 180 270 360\r\n100 80 10\r\n110 85 12\r\n120 90 14\r\n110 85 12\r\n"
      "100 80 11\r\n";
  const Distribution d0 = parse(text, PhotometricFormat::Ies);
  std::vector<Finding> to_ldt;
  encode(d0, PhotometricFormat::Ldt, &to_ldt);
  ASSERT_TRUE(has(to_ldt, "ldt-plane-360-dropped"));
  expect_ies_round_trip(d0);
}

TEST(RoundTripCorpus, LdtToIesToLdt) {
  GONIO_REQUIRE_CORPUS();
  const auto files = test::corpus_files({".ldt"});
  ASSERT_EQ(files.size(), 50u);
  for (const fs::path& p : files) {
    SCOPED_TRACE(p.string());
    auto read = read_photometric_file(p.string());
    ASSERT_TRUE(read.ok()) << to_string(read.error());
    const Distribution& d0 = read->distribution;
    std::vector<Finding> to_ies, to_ldt;
    const Distribution d1 =
        parse(encode(d0, PhotometricFormat::Ies, &to_ies), PhotometricFormat::Ies);
    const Distribution d2 =
        parse(encode(d1, PhotometricFormat::Ldt, &to_ldt), PhotometricFormat::Ldt);

    expect_same_intensities(d0, d1);
    expect_same_intensities(d0, d2);
    expect_same_flux(d0, d2, 1e-9);

    // C90-C270 exists in IES only as LM-63-1995's range: written over 0-360.
    if (has(to_ies, "symmetry-expanded")) {
      EXPECT_EQ(d0.symmetry, photometry::Symmetry::C90_C270);
      EXPECT_EQ(d2.symmetry, photometry::Symmetry::None);
    } else {
      EXPECT_EQ(d2.symmetry, d0.symmetry);
    }
    if (d0.ldt_type_indicator != d2.ldt_type_indicator) {
      EXPECT_TRUE(mentions(to_ies, "ldt-only-field", "Ityp"));
    }

    EXPECT_EQ(d2.absolute, d0.absolute);
    ASSERT_EQ(d2.lamps.size(), 1u);
    EXPECT_EQ(d2.lamps[0].count, d0.lamps[0].count);
    if (!d0.absolute) {
      EXPECT_NEAR(d2.lamps[0].flux_lm, d0.lamps[0].flux_lm, 1e-9 * d0.lamps[0].flux_lm);
    }
    EXPECT_EQ(d2.lamps[0].type, as_ldt_field(d0.lamps[0].type, 24));
    EXPECT_EQ(d2.lamps[0].power_w, d0.lamps[0].power_w);
    if (!d0.lamps[0].color.empty()) {
      EXPECT_TRUE(has(to_ies, "lamp-color"));
    }
    if (!d0.alternative_lamps.empty()) {
      EXPECT_TRUE(has(to_ies, "alternative-lamps"));
    }
    EXPECT_TRUE(d2.alternative_lamps.empty());

    expect_same_opening(d0.opening, d2.opening);
    for (int i = 0; i < 4; ++i) {
      const double s0 = d0.opening.side_height_m[i], s2 = d2.opening.side_height_m[i];
      if (std::abs(s0 - s2) > 1e-9) {
        EXPECT_TRUE(mentions(to_ies, "ldt-only-field", "side heights"));
      }
    }

    // The six header strings travel as IES keywords and come back; an empty
    // one that IES requires comes back as the reported default.
    for (const char* key :
         {"MANUFAC", "TEST", "LUMINAIRE", "LUMCAT", "ISSUEDATE", kLdtFileNameKeyword}) {
      SCOPED_TRACE(key);
      const std::string value = keyword(d0, key);
      const bool required = std::string(key) == "MANUFAC" || std::string(key) == "TEST" ||
                            std::string(key) == "ISSUEDATE";
      if (value.empty() && required) {
        EXPECT_EQ(keyword(d2, key), "not stated");
        EXPECT_TRUE(mentions(to_ies, "default-keyword", std::string("[") + key + "]"));
      } else {
        EXPECT_EQ(keyword(d2, key),
                  as_ldt_field(value, std::string(key) == kLdtFileNameKeyword ? 12 : 78));
      }
    }

    // What IES cannot hold was reported; the LDT writer computed it again.
    if (std::isfinite(d0.declared_lor_percent)) {
      EXPECT_TRUE(mentions(to_ies, "ldt-only-field", "light output ratio"));
      EXPECT_TRUE(has(to_ldt, "ldt-computed-lorl"));
    }
    if (!d0.direct_ratios.empty()) {
      EXPECT_TRUE(mentions(to_ies, "ldt-only-field", "direct ratios"));
      EXPECT_TRUE(has(to_ldt, "ldt-direct-ratios"));
    }
  }
}

}  // namespace
}  // namespace gonio::io
