#include "io/support/bytes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace gonio::io {
namespace {

TEST(Bytes, WhatIsAppendedReadsBack) {
  std::string out;
  append_bytes(out, std::uint64_t{0x0102030405060708});
  append_bytes(out, -0.0);
  append_bytes(out, std::uint8_t{7});
  append_all_bytes(out, std::vector<float>{1.5f, -2.0f, 3.25f});
  append_all_bytes(out, std::vector<float>{});
  ASSERT_EQ(out.size(), 8u + 8u + 1u + 12u);
  EXPECT_EQ(static_cast<unsigned char>(out[0]), 0x08);  // little-endian, as every target Gonio builds for

  ByteReader in(out);
  std::uint64_t u = 0;
  double d = 1.0;
  std::uint8_t b = 0;
  std::vector<float> v;
  ASSERT_TRUE(in.get(&u));
  ASSERT_TRUE(in.get(&d));
  ASSERT_TRUE(in.get(&b));
  ASSERT_TRUE(in.get_all(&v, 3));
  EXPECT_EQ(u, 0x0102030405060708u);
  EXPECT_TRUE(std::signbit(d) && d == 0.0);
  EXPECT_EQ(b, 7);
  EXPECT_EQ(v, (std::vector<float>{1.5f, -2.0f, 3.25f}));
  EXPECT_EQ(in.at(), out.size());
}

TEST(Bytes, AShortReadFailsAndKeepsThePlace) {
  const std::string bytes(12, '\x01');
  ByteReader in(bytes);
  std::uint64_t u = 0;
  ASSERT_TRUE(in.get(&u));
  EXPECT_FALSE(in.get(&u));  // 4 bytes left of 8
  EXPECT_EQ(in.at(), 8u);
  std::vector<std::uint32_t> v{9, 9};
  // A count past the bytes is refused before anything is sized.
  EXPECT_FALSE(in.get_all(&v, std::uint64_t{1} << 62));
  EXPECT_FALSE(in.get_all(&v, 2));
  EXPECT_EQ(v, (std::vector<std::uint32_t>{9, 9}));
  EXPECT_EQ(in.at(), 8u);
  ASSERT_TRUE(in.get_all(&v, 1));
  EXPECT_EQ(v, (std::vector<std::uint32_t>{0x01010101u}));
  EXPECT_TRUE(in.get_all(&v, 0));
  EXPECT_TRUE(v.empty());
}

TEST(Bytes, SkipStopsAtTheEnd) {
  const std::string bytes(10, '\0');
  ByteReader in(bytes);
  in.skip(4);
  EXPECT_EQ(in.at(), 4u);
  in.skip(100);
  EXPECT_EQ(in.at(), 10u);
  in.skip(static_cast<std::size_t>(-1));
  EXPECT_EQ(in.at(), 10u);
  std::uint8_t b = 0;
  EXPECT_FALSE(in.get(&b));
}

}  // namespace
}  // namespace gonio::io
