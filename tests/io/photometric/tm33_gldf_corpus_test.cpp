// The shared corpus through the exchange formats: IES -> TM-33 -> IES and
// LDT -> GLDF -> LDT, as `gonio convert` does them (io/photometric/photometric_file.h).
// Every file must come back with the same intensities (exactly, since TM-33
// writes the shortest decimal that reads back as the same double and GLDF
// holds the LDT writer's own bytes) and the same flux within 0.1 %; the
// counts and the largest flux difference are printed for docs/formats.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "io/photometric/gldf.h"
#include "io/photometric/ies.h"
#include "io/photometric/ldt.h"
#include "io/photometric/photometric_file.h"
#include "io/photometric/tm33.h"
#include "photometry/flux.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

namespace fs = std::filesystem;
using photometry::Distribution;

bool same_grid_and_values(const Distribution& a, const Distribution& b) {
  return a.type == b.type && a.symmetry == b.symmetry && a.horizontal_deg == b.horizontal_deg &&
         a.vertical_deg == b.vertical_deg && a.candela == b.candela;
}

double flux_difference(const Distribution& a, const Distribution& b) {
  const double fa = photometry::total_flux_lm(a), fb = photometry::total_flux_lm(b);
  return fa > 0.0 ? std::abs(fb - fa) / fa : std::abs(fb - fa);
}

TEST(Tm33GldfCorpus, IesToTm33ToIes) {
  GONIO_REQUIRE_CORPUS();
  const auto files = test::corpus_files({".ies"});
  ASSERT_FALSE(files.empty());
  int exact = 0, exact_tm33 = 0, as_direct = 0;
  double largest = 0.0;
  for (const fs::path& p : files) {
    SCOPED_TRACE(p.string());
    auto read = read_photometric_file(p.string());
    ASSERT_TRUE(read.ok()) << to_string(read.error());
    const Distribution& d0 = read->distribution;
    auto direct = parse_ies(*encode_photometric_file(d0, PhotometricFormat::Ies, {}, nullptr), "direct.ies", "");
    ASSERT_TRUE(direct.ok());
    auto xml = encode_photometric_file(d0, PhotometricFormat::Tm33, {}, nullptr);
    ASSERT_TRUE(xml.ok()) << to_string(xml.error());
    auto tm33 = parse_tm33(*xml, "back.xml");
    ASSERT_TRUE(tm33.ok()) << to_string(tm33.error());
    auto ies = encode_photometric_file(tm33->distribution, PhotometricFormat::Ies, {}, nullptr);
    ASSERT_TRUE(ies.ok());
    auto back = parse_ies(*ies, "back.ies", "");
    ASSERT_TRUE(back.ok()) << to_string(back.error());
    const Distribution& d2 = back->distribution;
    // TM-33 holds every value exactly; back in IES the file is what IES -> IES
    // gives (which expands symmetries IES cannot express and rounds to 15
    // digits, io/photometric/ies.h).
    EXPECT_TRUE(same_grid_and_values(d0, tm33->distribution));
    EXPECT_TRUE(same_grid_and_values(direct->distribution, d2));
    exact_tm33 += same_grid_and_values(d0, tm33->distribution);
    as_direct += same_grid_and_values(direct->distribution, d2);
    exact += same_grid_and_values(d0, d2);
    const double diff = flux_difference(d0, d2);
    EXPECT_LE(diff, 1e-3);
    largest = std::max(largest, diff);
    EXPECT_EQ(d2.absolute, d0.absolute);
    if (!d0.absolute) {
      EXPECT_NEAR(d2.lamps[0].flux_lm, d0.lamps[0].flux_lm, 1e-9 * d0.lamps[0].flux_lm);
    }
  }
  std::printf(
      "IES -> TM-33 -> IES: %zu files; TM-33 exact %d, back in IES the same as IES -> IES %d, identical to the "
      "original grid and values %d; largest flux difference %.3g %%\n",
      files.size(), exact_tm33, as_direct, exact, 100.0 * largest);
  RecordProperty("exact", exact);
}

TEST(Tm33GldfCorpus, LdtToGldfToLdt) {
  GONIO_REQUIRE_CORPUS();
  const auto files = test::corpus_files({".ldt"});
  ASSERT_FALSE(files.empty());
  int exact = 0, as_direct = 0;
  double largest = 0.0;
  PhotometricWriteOptions options;
  options.gldf_photometry = PhotometricFormat::Ldt;
  options.gldf_created_unix = 1764620000;
  for (const fs::path& p : files) {
    SCOPED_TRACE(p.string());
    auto read = read_photometric_file(p.string());
    ASSERT_TRUE(read.ok()) << to_string(read.error());
    const Distribution& d0 = read->distribution;
    auto gldf = encode_photometric_file(d0, PhotometricFormat::Gldf, options, nullptr);
    ASSERT_TRUE(gldf.ok()) << to_string(gldf.error());
    auto container = parse_gldf(*gldf, "back.gldf");
    ASSERT_TRUE(container.ok()) << to_string(container.error());
    ASSERT_EQ(container->photometries.size(), 1u);
    // The LDT inside is the LDT writer's own output: LDT -> GLDF -> LDT is
    // LDT -> LDT.
    EXPECT_EQ(container->photometries[0].bytes, *encode_photometric_file(d0, PhotometricFormat::Ldt, {}, nullptr));
    as_direct += container->photometries[0].bytes == *encode_photometric_file(d0, PhotometricFormat::Ldt, {}, nullptr);
    auto back = parse_ldt(container->photometries[0].bytes, "back.ldt");
    ASSERT_TRUE(back.ok()) << to_string(back.error());
    const Distribution& d1 = back->distribution;
    if (same_grid_and_values(d0, d1)) ++exact;
    const double diff = flux_difference(d0, d1);
    EXPECT_LE(diff, 1e-3);
    largest = std::max(largest, diff);
  }
  std::printf(
      "LDT -> GLDF -> LDT: %zu files; the same bytes as LDT -> LDT %d, identical to the original grid and values "
      "%d (the others within the LDT writer's 12 digits); largest flux difference %.3g %%\n",
      files.size(), as_direct, exact, 100.0 * largest);
  RecordProperty("exact", exact);
}

}  // namespace
}  // namespace gonio::io
