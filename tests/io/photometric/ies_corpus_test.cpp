// Every IES file of the shared corpus (real manufacturers' files from 1986
// to 2002): read, checked against what the files say, and round-tripped.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "io/photometric/ies.h"
#include "io/support/text.h"
#include "photometry/flux.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

namespace fs = std::filesystem;
using photometry::Distribution;
using photometry::LengthUnit;
using photometry::OpeningShape;
using photometry::PhotometricType;
using photometry::Symmetry;

IesFile read_ok(const fs::path& p) {
  auto r = read_ies(p.string());
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : to_string(r.error()));
  return r.ok() ? std::move(r).value() : IesFile{};
}

fs::path corpus(const std::string& relative) { return test::corpus_dir() / relative; }

bool has_finding(const IesFile& f, const std::string& code) {
  for (const Finding& x : f.findings)
    if (x.code == code) return true;
  return false;
}

TEST(IesCorpus, EveryFileReads) {
  GONIO_REQUIRE_CORPUS();
  const auto files = test::corpus_files({".ies"});
  ASSERT_GE(files.size(), 60u);
  std::map<IesVersion, int> versions;
  for (const fs::path& p : files) {
    SCOPED_TRACE(p.string());
    const IesFile f = read_ok(p);
    ++versions[f.version];
    const Distribution& d = f.distribution;
    EXPECT_TRUE(photometry::validate(d).ok());
    EXPECT_EQ(d.type, PhotometricType::C);  // SOURCES.md: every corpus file is Type C
    ASSERT_EQ(d.lamps.size(), 1u);
    for (const Finding& x : f.findings) {
      EXPECT_EQ(x.severity, Severity::Warning);
      EXPECT_EQ(x.where.file, p.string());
      EXPECT_GT(x.where.line, 0) << x.message;
    }
    // Flux is finite and positive: candela were read, not zeros.
    EXPECT_GT(photometry::total_flux_lm(d), 0.0);
  }
  // The corpus spans 1986 to 2002 (SOURCES.md).
  EXPECT_GT(versions[IesVersion::LM63_1986], 0);
  EXPECT_GT(versions[IesVersion::LM63_1991], 0);
  EXPECT_GT(versions[IesVersion::LM63_1995], 0);
  EXPECT_GT(versions[IesVersion::LM63_2002], 0);
}

TEST(IesCorpus, LuminousOpeningShapes) {
  GONIO_REQUIRE_CORPUS();
  struct Case {
    const char* file;
    OpeningShape shape;
    double width, length, height;  // [m]
  };
  // photometric-viewer/*.ies are LM-63-1995: its table of signed dimensions.
  const std::vector<Case> cases = {
      {"point_opening.ies", OpeningShape::Point, 0, 0, 0},
      {"rectangular_opening.ies", OpeningShape::Rectangular, 0.12, 0.34, 0},
      {"rectangular_opening_with_height.ies", OpeningShape::RectangularWithSides, 0.12, 0.34, 0.56},
      {"round_opening.ies", OpeningShape::Circular, 0.12, 0.12, 0},  // -0.12 0 0
      {"round_opening_with_height.ies", OpeningShape::VerticalCylinder, 0.12, 0.12, 0.34},
      {"sphere_opening.ies", OpeningShape::Sphere, 0.12, 0.12, 0.12},  // -0.12 0 -0.12
      {"horizontal_cylinder_opening_along_length.ies", OpeningShape::HorizontalCylinderAlongLength,
       0.34, 0.12, 0.34},  // 0 0.12 -0.34
      {"horizontal_cylinder_opening_along_width.ies", OpeningShape::HorizontalCylinderAlongWidth,
       0.12, 0.34, 0.34},  // 0.12 0 -0.34
      {"ellipse_opening_along_length.ies", OpeningShape::VerticalEllipticalCylinder, 0.12, 0.34,
       0.56},  // -0.12 0.34 0.56
      {"ellipse_opening_along_width.ies", OpeningShape::VerticalEllipticalCylinder, 0.12, 0.34,
       0.56},  // 0.12 -0.34 0.56
      {"ellipsoid_opening_along_length.ies", OpeningShape::Ellipsoid, 0.12, 0.34, 0.56},
      {"ellipsoid_opening_along_width.ies", OpeningShape::Ellipsoid, 0.12, 0.34, 0.56},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const IesFile f = read_ok(corpus(std::string("photometric-viewer/") + c.file));
    EXPECT_FALSE(has_finding(f, "opening-shape"));
    const auto& o = f.distribution.opening;
    EXPECT_EQ(o.shape, c.shape) << photometry::to_string(o.shape);
    EXPECT_DOUBLE_EQ(o.width_m, c.width);
    EXPECT_DOUBLE_EQ(o.length_m, c.length);
    EXPECT_DOUBLE_EQ(o.height_m, c.height);
  }
  // LM-63-2002 files use the newer table: -0.49 -0.49 0.406 ft is a
  // vertical cylinder, -0.127 -0.127 0 m a disc.
  const IesFile bollard = read_ok(corpus("renderpipeline/bollard.ies"));
  EXPECT_EQ(bollard.distribution.opening.shape, OpeningShape::VerticalCylinder);
  EXPECT_DOUBLE_EQ(bollard.distribution.opening.width_m, 0.49 * 0.3048);
  EXPECT_DOUBLE_EQ(bollard.distribution.opening.height_m, 0.406 * 0.3048);
  const IesFile beam = read_ok(corpus("renderpipeline/parallel_beam.ies"));
  EXPECT_EQ(beam.distribution.opening.shape, OpeningShape::Circular);
  EXPECT_DOUBLE_EQ(beam.distribution.opening.length_m, 0.127);
  // "0 -0.32 0" (an LM-63-1991 file) is in neither table: read as a disc.
  const IesFile arrow = read_ok(corpus("renderpipeline/soft_arrow.ies"));
  EXPECT_TRUE(has_finding(arrow, "opening-shape"));
  EXPECT_EQ(arrow.distribution.opening.shape, OpeningShape::Circular);
}

TEST(IesCorpus, UnitsMultiplierAndAbsolutePhotometry) {
  GONIO_REQUIRE_CORPUS();
  const IesFile metric = read_ok(corpus("photometric-viewer/metric_units.ies"));
  const IesFile imperial = read_ok(corpus("photometric-viewer/imperial_units.ies"));
  EXPECT_EQ(metric.distribution.opening.file_unit, LengthUnit::Metre);
  EXPECT_EQ(imperial.distribution.opening.file_unit, LengthUnit::Foot);
  EXPECT_DOUBLE_EQ(imperial.distribution.opening.length_m,
                   metric.distribution.opening.length_m * 0.3048);
  EXPECT_EQ(imperial.distribution.candela, metric.distribution.candela);

  // The same file with multiplier 1 and 1.5: candela × 1.5, flux × 1.5.
  for (const std::string kind : {"absolute", "relative"}) {
    SCOPED_TRACE(kind);
    const IesFile one = read_ok(corpus("photometric-viewer/" + kind + "_photometry.ies"));
    const IesFile more =
        read_ok(corpus("photometric-viewer/" + kind + "_photometry_with_multiplier.ies"));
    ASSERT_EQ(one.distribution.candela.size(), more.distribution.candela.size());
    for (std::size_t i = 0; i < one.distribution.candela.size(); ++i)
      EXPECT_EQ(more.distribution.candela[i], 1.5 * one.distribution.candela[i]);
    EXPECT_NEAR(photometry::total_flux_lm(more.distribution), 1.5 * photometry::total_flux_lm(one.distribution),
                1e-9 * photometry::total_flux_lm(more.distribution));
    EXPECT_EQ(one.distribution.absolute, kind == "absolute");
    if (kind == "absolute") {
      EXPECT_TRUE(std::isnan(one.distribution.lamps[0].flux_lm));
    } else {
      EXPECT_EQ(one.distribution.lamps[0].flux_lm, 500.0);
    }
  }
}

TEST(IesCorpus, QuirksOfRealFiles) {
  GONIO_REQUIRE_CORPUS();
  // [MORE] lines joined with '\n'.
  const IesFile label = read_ok(corpus("photometric-viewer/label_lines.ies"));
  const photometry::Keyword* multi = label.distribution.find_keyword("MULTILINE");
  ASSERT_NE(multi, nullptr);
  EXPECT_EQ(multi->value,
            "Test multiline metadata\nShould contain three lines\nDivided by LF characters");
  EXPECT_EQ(label.distribution.lamps[0].type, "Generic 15W LED module");

  // "IESNA95", a label line without brackets, keywords beyond the standard.
  const IesFile radiance = read_ok(corpus("radiance/examp1.ies"));
  EXPECT_EQ(radiance.version, IesVersion::LM63_1995);
  EXPECT_TRUE(has_finding(radiance, "nonstandard-version"));
  EXPECT_TRUE(has_finding(radiance, "label-line"));
  EXPECT_TRUE(has_finding(radiance, "unknown-keyword"));
  EXPECT_EQ(radiance.distribution.symmetry, Symmetry::Quadrant);
  EXPECT_EQ(radiance.distribution.lamps[0].count, 2);
  EXPECT_EQ(radiance.distribution.lamps[0].flux_lm, 5800.0);

  // An LM-63-1986 file: label lines, a Latin-1 degree sign, "END" and a DOS
  // end-of-file byte after the data.
  const IesFile erco = read_ok(corpus("renderpipeline/defined_diffuse.ies"));
  EXPECT_EQ(erco.version, IesVersion::LM63_1986);
  EXPECT_TRUE(has_finding(erco, "trailing-data"));
  EXPECT_EQ(erco.distribution.keywords.front().value, "ERCO Leuchten GmbH");
  const IesFile vee = read_ok(corpus("renderpipeline/vee.ies"));
  EXPECT_EQ(vee.version, IesVersion::LM63_1986);
  EXPECT_NE(vee.distribution.keywords[1].value.find("70\xc2\xb0"), std::string::npos)
      << vee.distribution.keywords[1].value;

  // Lines longer than 256 characters.
  EXPECT_TRUE(has_finding(read_ok(corpus("renderpipeline/x_arrow.ies")), "long-line"));

  // The largest file: 361 × 721 angles.
  const IesFile full = read_ok(corpus("photompy/write_test_full.ies"));
  EXPECT_EQ(full.distribution.vertical_count(), 361u);
  EXPECT_EQ(full.distribution.horizontal_count(), 721u);
  EXPECT_EQ(full.distribution.symmetry, Symmetry::None);
}

// IES → IES: the values read back are exactly the values written (each the
// 15-significant-digit form of the original), the flux agrees, and writing
// the read-back model again gives the same bytes.
TEST(IesCorpus, RoundTripsKeepIntensitiesAndFlux) {
  GONIO_REQUIRE_CORPUS();
  for (const fs::path& p : test::corpus_files({".ies"})) {
    SCOPED_TRACE(p.string());
    const IesFile original = read_ok(p);
    const Distribution& d = original.distribution;
    for (IesVersion version : {IesVersion::LM63_2019, IesVersion::LM63_2002}) {
      SCOPED_TRACE(to_string(version));
      IesWriteOptions options;
      options.version = version;
      std::vector<Finding> warnings;
      const std::string text = write_ies(d, options, &warnings);
      for (const Finding& w : warnings)  // a real file has nothing IES cannot carry
        EXPECT_TRUE(w.code == "default-keyword" || w.code == "keyword-renamed" ||
                    w.code == "ballast-lamp-factor" || w.code == "vertical-range")
            << w.code << ": " << w.message;
      auto back = parse_ies(text, "roundtrip.ies", "");
      ASSERT_TRUE(back.ok()) << to_string(back.error());
      const Distribution& e = back->distribution;
      EXPECT_EQ(back->version, version);
      EXPECT_EQ(e.symmetry, d.symmetry);
      ASSERT_EQ(e.candela.size(), d.candela.size());
      EXPECT_EQ(e.vertical_deg, d.vertical_deg);
      EXPECT_EQ(e.horizontal_deg, d.horizontal_deg);
      for (std::size_t i = 0; i < d.candela.size(); ++i) {
        ASSERT_EQ(e.candela[i], *parse_number(format_ies_number(d.candela[i]))) << i;
        ASSERT_LE(std::abs(e.candela[i] - d.candela[i]), 5e-15 * std::abs(d.candela[i])) << i;
      }
      const double flux = photometry::total_flux_lm(d);
      EXPECT_NEAR(photometry::total_flux_lm(e), flux, 1e-12 * flux);
      EXPECT_EQ(e.absolute, d.absolute);
      EXPECT_EQ(e.lamps[0].count, d.lamps[0].count);
      if (!d.absolute) {
        EXPECT_NEAR(e.lamps[0].flux_lm, d.lamps[0].flux_lm, 1e-12 * d.lamps[0].flux_lm);
      }
      EXPECT_EQ(e.opening.shape, d.opening.shape);
      EXPECT_NEAR(e.opening.width_m, d.opening.width_m, 1e-12);
      EXPECT_NEAR(e.opening.length_m, d.opening.length_m, 1e-12);
      EXPECT_NEAR(e.opening.height_m, d.opening.height_m, 1e-12);
      EXPECT_EQ(e.opening.file_unit, d.opening.file_unit);
      EXPECT_EQ(write_ies(e, options, nullptr), text);
    }
  }
}

}  // namespace
}  // namespace gonio::io
