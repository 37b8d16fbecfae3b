#include "io/support/content_hash.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gonio::io {
namespace {

TEST(ContentHash, IsXxh3SixtyFourWithSeedZero) {
  // xxHash's XXH3_64bits of the empty input and of "abc".
  EXPECT_EQ(content_hash_hex(""), "2d06800538d394c2");
  EXPECT_EQ(content_hash_hex("abc"), "78af5f94892f3950");
  EXPECT_EQ(ContentHash().hex(), "2d06800538d394c2");
  EXPECT_EQ(to_hex(0x1234), "0000000000001234");
}

TEST(ContentHash, PiecesHashAsTheWhole) {
  std::string whole;
  for (int i = 0; i < 5000; ++i) whole.push_back(static_cast<char>((i * 131) ^ (i >> 3)));
  const std::string expected = content_hash_hex(whole);
  for (std::size_t piece : {1u, 3u, 64u, 255u, 256u, 1000u, 4999u}) {
    ContentHash h;
    for (std::size_t at = 0; at < whole.size(); at += piece)
      h.bytes(whole.data() + at, std::min(piece, whole.size() - at));
    h.bytes(nullptr, 0);
    EXPECT_EQ(h.hex(), expected) << piece;
  }
}

TEST(ContentHash, DigestMidwayLeavesTheStreamGoing) {
  ContentHash h;
  h.text("first");
  const std::uint64_t early = h.digest();
  EXPECT_EQ(h.digest(), early);
  h.text("second");
  ContentHash g;
  g.text("first");
  g.text("second");
  EXPECT_EQ(h.digest(), g.digest());
  EXPECT_NE(h.digest(), early);
}

TEST(ContentHash, CountsAndLengthsSeparateTheirContents) {
  // The same bytes split differently are different contents.
  ContentHash a, b;
  a.values(std::vector<std::uint32_t>{1, 2});
  a.values(std::vector<std::uint32_t>{3});
  b.values(std::vector<std::uint32_t>{1});
  b.values(std::vector<std::uint32_t>{2, 3});
  EXPECT_NE(a.digest(), b.digest());
  ContentHash c, d;
  c.text("ab");
  c.text("c");
  d.text("a");
  d.text("bc");
  EXPECT_NE(c.digest(), d.digest());
}

TEST(ContentHash, ASealComesOffOnlyWhereItMatches) {
  std::string bytes = "cache body";
  append_digest(bytes);
  ASSERT_EQ(bytes.size(), 10u + 8u);
  // The seal is the body's digest, in the machine's (little-endian) order.
  std::uint64_t seal = 0;
  for (int i = 7; i >= 0; --i) seal = (seal << 8) | static_cast<unsigned char>(bytes[10 + i]);
  EXPECT_EQ(to_hex(seal), content_hash_hex("cache body"));
  const std::optional<std::string_view> body = without_digest(bytes);
  ASSERT_TRUE(body);
  EXPECT_EQ(*body, "cache body");
  // One changed byte, of the body or of the seal, and nothing comes back.
  for (std::size_t at : {std::size_t{0}, std::size_t{9}, std::size_t{10}, bytes.size() - 1}) {
    std::string damaged = bytes;
    damaged[at] = static_cast<char>(damaged[at] ^ 1);
    EXPECT_FALSE(without_digest(damaged)) << at;
  }
  EXPECT_FALSE(without_digest(bytes.substr(0, bytes.size() - 1)));
  EXPECT_FALSE(without_digest("short"));
  std::string empty;
  append_digest(empty);
  ASSERT_TRUE(without_digest(empty));
  EXPECT_TRUE(without_digest(empty)->empty());
}

}  // namespace
}  // namespace gonio::io
