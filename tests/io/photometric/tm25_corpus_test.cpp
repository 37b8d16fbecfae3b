// The OSRAM ray file of the shared corpus (rayfiles/, see its SOURCES.md):
// 100,000 rays of the blue chip of a LERTDUW S2WP, radiant flux per ray, one
// spectral table for all rays — read in place, checked against what OSRAM
// states in it and in SOURCES.md, and written back.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "io/photometric/tm25.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

std::filesystem::path osram_file() {
  return test::corpus_dir() / "rayfiles" / "rayfile_LERTDUW_S2WP_blue_100k_20161013_IES_TM25.TM25RAY";
}

#define REQUIRE_OSRAM()                                                                    \
  do {                                                                                     \
    GONIO_REQUIRE_CORPUS();                                                                \
    if (!std::filesystem::exists(osram_file()))                                            \
      GONIO_MISSING("the OSRAM ray file " + osram_file().string() + " of the shared corpus"); \
  } while (false)

TEST(Tm25Corpus, OsramRaySetReadsAsPublished) {
  REQUIRE_OSRAM();
  auto r = read_tm25_file(osram_file().string());
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  const Tm25RaySet& s = *r;
  for (const Finding& f : s.findings) ADD_FAILURE() << f.code << ": " << f.message;
  const Tm25Header& h = s.header;
  EXPECT_EQ(s.ray_count(), 100000u);
  EXPECT_EQ(h.creation_method, 1);  // measured
  EXPECT_EQ(h.light_source, "LERTDUW_S2WP");
  EXPECT_EQ(h.manufacturer, "OSRAM Opto Semiconductors GmbH");
  EXPECT_EQ(h.equipment, "Rigo 801");
  EXPECT_EQ(h.created, "2016-10-13 13:24:12");
  EXPECT_EQ(h.spectrum, Tm25Spectrum::OneTable);
  EXPECT_TRUE(h.radiant_flux);
  EXPECT_FALSE(h.luminous_flux);
  ASSERT_EQ(h.spectral_tables.size(), 1u);
  EXPECT_EQ(h.spectral_tables[0].wavelength_nm.front(), 390.0f);
  EXPECT_EQ(h.spectral_tables[0].wavelength_nm.back(), 510.0f);
  // SOURCES.md: radiant flux per ray summing to the header's 1.68 W; header
  // luminous flux 54.6 lm.
  EXPECT_NEAR(h.radiant_flux_w, 1.68, 1e-6);
  EXPECT_NEAR(h.luminous_flux_lm, 54.6, 0.05);
  EXPECT_NEAR(s.total_radiant_flux_w(), 1.68, 1.68e-6);
  EXPECT_NEAR(s.total_luminous_flux_lm(), h.luminous_flux_lm, 1e-4);
  // SOURCES.md: positions over a 5.9 × 6.5 mm emitter, z from −1.15 to 0.02.
  Vec3 lo{1e30, 1e30, 1e30}, hi{-1e30, -1e30, -1e30};
  double worst = 0.0;
  for (std::size_t i = 0; i < s.ray_count(); ++i) {
    const Vec3 p = s.position_mm(i);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    worst = std::max(worst, std::abs(length(s.direction(i)) - 1.0));
  }
  EXPECT_NEAR(hi.x - lo.x, 5.9, 0.1);
  EXPECT_NEAR(hi.y - lo.y, 6.5, 0.1);
  EXPECT_NEAR(lo.z, -1.15, 0.01);
  EXPECT_NEAR(hi.z, 0.02, 0.001);
  EXPECT_LT(worst, 1e-6);
}

TEST(Tm25Corpus, OsramRaySetWrittenAgainIsTheSameFile) {
  REQUIRE_OSRAM();
  auto r = read_tm25_file(osram_file().string());
  ASSERT_TRUE(r.ok());
  auto bytes = write_tm25(*r);
  ASSERT_TRUE(bytes.ok());
  const std::string original = test::read_file(osram_file());
  ASSERT_EQ(bytes->size(), original.size());
  // OSRAM's directions are unit to float rounding: nothing is normalised, and
  // the file comes back byte for byte.
  EXPECT_TRUE(*bytes == original);
  auto again = parse_tm25(*bytes, "again");
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->items, r->items);
  EXPECT_EQ(bytes->substr(0, 36928), original.substr(0, 36928));
}

// The corpus file's layout, by TM-25's rules as the reference reader
// (Muschaweck's TM25RaySetTools) applies them: no additional text (size 0,
// a multiple of 32), one spectral table of 76 pairs (612 bytes) padded with
// NULs to 640, the rays from byte 36 928. The same set written with an
// additional text grows by a whole number of 32-byte blocks, the text's
// size in the header, the rays unchanged after it.
TEST(Tm25Corpus, OsramLayoutAndAnAddedTextFollowTm25sPadding) {
  REQUIRE_OSRAM();
  const std::string original = test::read_file(osram_file());
  const auto i32 = [](const std::string& b, std::size_t at) {
    std::int32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
  };
  EXPECT_EQ(i32(original, 84), 0);
  EXPECT_EQ(i32(original, 76), 1);
  EXPECT_EQ(i32(original, static_cast<std::size_t>(kTm25FixedBytes)), 76);
  EXPECT_EQ(original.substr(kTm25FixedBytes + 612, 28), std::string(28, '\0'));
  EXPECT_EQ(original.size(), 36928u + 100000u * 7u * 4u);

  auto r = read_tm25_file(osram_file().string());
  ASSERT_TRUE(r.ok());
  r->header.additional_text = "LERTDUW S2WP, 100k rays (45 ASCII characters)";
  auto bytes = write_tm25(*r);
  ASSERT_TRUE(bytes.ok());
  const std::size_t text = 4 * r->header.additional_text.size();  // 180 bytes, padded to 192
  ASSERT_EQ(text, 180u);
  EXPECT_EQ(i32(*bytes, 84), 192);
  EXPECT_EQ(bytes->size(), original.size() + 192);
  EXPECT_EQ(bytes->substr(36928 + text, 192 - text), std::string(192 - text, '\0'));
  EXPECT_EQ(bytes->substr(36928 + 192), original.substr(36928));
  auto again = parse_tm25(*bytes, "again");
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->header.additional_text, r->header.additional_text);
}

}  // namespace
}  // namespace gonio::io
