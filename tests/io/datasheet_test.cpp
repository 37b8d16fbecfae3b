#include "io/datasheet.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

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
  if (!have_gnuplot()) {
    const char* ci = std::getenv("CI");
    if (ci && std::string(ci) == "true") FAIL() << "gnuplot is not installed";
    GTEST_SKIP() << "gnuplot not installed (scripts/setup.sh installs it)";
  }
  auto html = datasheet_html({entry()});
  ASSERT_TRUE(html.ok()) << html.error().message;
  const std::string& h = html.value();
  EXPECT_NE(h.find("<h1>Panel &lt;A&amp;B&gt;</h1>"), std::string::npos);  // escaped
  EXPECT_EQ(h.find("<A&B>"), std::string::npos);
  for (const char* part : {"<svg", "UGR table", "Coefficients of utilisation", "Spacing criterion", "BUG rating",
                           "Luminance table", "Candela table", "Zonal lumen summary"})
    EXPECT_NE(h.find(part), std::string::npos) << part;
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

}  // namespace
}  // namespace gonio::io
