#include "io/support/zip.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

// Archive bytes with one entry's name replaced by another of the same length
// (in the local header and the central directory alike): how a hostile name
// is made from a well-formed archive.
std::string renamed(std::string zip, const std::string& from, const std::string& to) {
  EXPECT_EQ(from.size(), to.size());
  int n = 0;
  for (auto at = zip.find(from); at != std::string::npos; at = zip.find(from, at + 1), ++n)
    zip.replace(at, from.size(), to);
  EXPECT_EQ(n, 2) << "the name is in the local header and the central directory";
  return zip;
}

void put32(std::string& s, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s[at + i] = static_cast<char>((v >> (8 * i)) & 0xff);
}

// Declared uncompressed size of every entry set to `size`, in both headers.
std::string declaring(std::string zip, std::uint32_t size) {
  for (auto at = zip.find("PK\x03\x04"); at != std::string::npos; at = zip.find("PK\x03\x04", at + 4))
    put32(zip, at + 22, size);
  for (auto at = zip.find("PK\x01\x02"); at != std::string::npos; at = zip.find("PK\x01\x02", at + 4))
    put32(zip, at + 24, size);
  return zip;
}

TEST(Zip, WritesAndReadsEntriesInOrder) {
  const std::vector<ZipEntry> entries = {
      {"product.xml", "<Root/>"}, {"ldc/a.ldt", std::string(100000, 'x')}, {"geo/b.l3d", std::string("\0\1\2", 3)}};
  auto zip = write_zip(entries, 1700000000);
  ASSERT_TRUE(zip.ok()) << to_string(zip.error());
  EXPECT_LT(zip->size(), 2000u);  // deflated
  EXPECT_EQ(*write_zip(entries, 1700000000), *zip);  // same entries and time, same bytes
  auto back = read_zip(*zip, "t.zip");
  ASSERT_TRUE(back.ok()) << to_string(back.error());
  ASSERT_EQ(back->size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ((*back)[i].name, entries[i].name);
    EXPECT_EQ((*back)[i].bytes, entries[i].bytes);
  }
  EXPECT_FALSE(write_zip({{"../x", "1"}}, 0).ok());
  EXPECT_FALSE(write_zip({{"a", "1"}, {"a", "2"}}, 0).ok());
}

TEST(Zip, EntryNamesThatLeaveTheArchiveAreRefused) {
  for (const char* bad : {"../evil", "a/../../b", "/etc/passwd", "C:/x", "a\\..\\b", "./a", "a//b", ""})
    EXPECT_FALSE(is_safe_entry_name(bad)) << bad;
  for (const char* good : {"product.xml", "ldc/a.ldt", "geo/luminaire.l3d", "a..b/c"})
    EXPECT_TRUE(is_safe_entry_name(good)) << good;

  const std::string zip = *write_zip({{"product.xml", "<Root/>"}, {"xx/evil.ldt", "1"}}, 0);
  for (const auto& [to, says] : {std::pair{"../evil.ldt", "'../evil.ldt' leaves the archive"},
                                 std::pair{"/x/evil.ldt", "'/x/evil.ldt' leaves the archive"}}) {
    const std::string evil = renamed(zip, "xx/evil.ldt", to);
    test::offer_fuzz_seed("gldf", evil);
    auto r = read_zip(evil, "evil.gldf");
    ASSERT_FALSE(r.ok()) << to;
    EXPECT_EQ(r.error().where.file, "evil.gldf");
    EXPECT_NE(r.error().message.find(says), std::string::npos) << r.error().message;
  }
  auto twice = read_zip(renamed(zip, "xx/evil.ldt", "product.xml"), "twice.gldf");
  ASSERT_FALSE(twice.ok());
  EXPECT_NE(twice.error().message.find("appears twice"), std::string::npos) << twice.error().message;
}

TEST(Zip, BombsAreRefusedBeforeOrWhileInflating) {
  // 64 MiB of zeros deflate to ~64 KB.
  const std::string zip = *write_zip({{"ldc/zeros.ldt", std::string(std::size_t{64} << 20, '\0')}}, 0);
  ASSERT_LT(zip.size(), std::size_t{200} << 10);
  // A header that declares 1000 bytes: refused after 1001 bytes inflated.
  auto lies = read_zip(declaring(zip, 1000), "bomb.gldf");
  ASSERT_FALSE(lies.ok());
  EXPECT_NE(lies.error().message.find("inflates beyond the 1000 bytes it declares"), std::string::npos)
      << lies.error().message;
  // An honest header above the cap: refused before anything is inflated.
  ZipLimits small;
  small.max_entry_bytes = std::size_t{16} << 20;
  auto big = read_zip(zip, "big.gldf", small);
  ASSERT_FALSE(big.ok());
  EXPECT_NE(big.error().message.find("declares 67108864 bytes, at most 16777216"), std::string::npos)
      << big.error().message;
  ZipLimits total;
  total.max_total_bytes = std::size_t{1} << 20;
  EXPECT_FALSE(read_zip(zip, "t.gldf", total).ok());
  ZipLimits few;
  few.max_entries = 0;
  EXPECT_FALSE(read_zip(zip, "t.gldf", few).ok());
  // Not an archive at all; an archive cut short.
  EXPECT_FALSE(read_zip("not a zip", "x.gldf").ok());
  EXPECT_FALSE(read_zip(zip.substr(0, zip.size() / 2), "cut.gldf").ok());
}

}  // namespace
}  // namespace gonio::io
