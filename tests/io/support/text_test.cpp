#include "io/support/text.h"

#include <gtest/gtest.h>

namespace gonio::io {
namespace {

TEST(Text, SplitsEveryLineEnding) {
  const auto lines = split_lines("a\r\nb\nc\rd\n\ne");
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0].text, "a");
  EXPECT_EQ(lines[2].text, "c");
  EXPECT_EQ(lines[3].text, "d");
  EXPECT_EQ(lines[4].text, "");
  EXPECT_EQ(lines[5].text, "e");
  EXPECT_EQ(lines[5].number, 6);
  EXPECT_EQ(split_lines("x\n").size(), 1u);
  EXPECT_TRUE(split_lines("").empty());
}

TEST(Text, Latin1BecomesUtf8) {
  const std::string latin1 = "Beleuchtungsst\xe4rke \xb0";
  EXPECT_FALSE(is_valid_utf8(latin1));
  const std::string utf8 = decode_text(latin1);
  EXPECT_EQ(utf8, "Beleuchtungsst\xc3\xa4rke \xc2\xb0");
  EXPECT_TRUE(is_valid_utf8(utf8));
  EXPECT_EQ(decode_text(utf8), utf8);  // already UTF-8: unchanged
  EXPECT_EQ(utf8_to_latin1(utf8), latin1);
  EXPECT_EQ(utf8_to_latin1("\xe2\x82\xac"), "?");  // the euro sign is not Latin-1
}

TEST(Text, RejectsMalformedUtf8) {
  EXPECT_FALSE(is_valid_utf8("\xc0\xaf"));      // overlong '/'
  EXPECT_FALSE(is_valid_utf8("\xed\xa0\x80"));  // surrogate
  EXPECT_FALSE(is_valid_utf8("\xe2\x82"));      // truncated
  EXPECT_TRUE(is_valid_utf8("plain ascii"));
}

TEST(Text, ParsesNumbersStrictly) {
  EXPECT_EQ(parse_number("12"), 12.0);
  EXPECT_EQ(parse_number("-1.5"), -1.5);
  EXPECT_EQ(parse_number("+4."), 4.0);
  EXPECT_EQ(parse_number(".5"), 0.5);
  EXPECT_EQ(parse_number("3e2"), 300.0);
  EXPECT_EQ(parse_number("1,25", true), 1.25);
  EXPECT_FALSE(parse_number("1,25"));
  EXPECT_FALSE(parse_number(""));
  EXPECT_FALSE(parse_number("12a"));
  EXPECT_FALSE(parse_number("nan"));
  EXPECT_FALSE(parse_number("inf"));
  EXPECT_FALSE(parse_number("1e999"));
  EXPECT_FALSE(parse_number("0x10"));
  EXPECT_FALSE(parse_number("1.2.3"));
  EXPECT_FALSE(parse_number("-"));
}

TEST(Text, RecognisesBinary) {
  EXPECT_TRUE(looks_binary(std::string("abc\0def", 7)));
  EXPECT_FALSE(looks_binary("IESNA:LM-63-2002\r\n[TEST] 1\tx\r\n"));
  std::string junk(200, '\x01');
  EXPECT_TRUE(looks_binary(junk));
}

TEST(Text, NamesTheLineOfTheFirstBinaryByte) {
  EXPECT_EQ(first_binary_line(std::string("\0abc", 4)), 1);
  EXPECT_EQ(first_binary_line(std::string("a\r\nb\nc\rd\x01", 9)), 4);  // CRLF, LF, CR
  EXPECT_EQ(first_binary_line("line\tone\f\ntwo\x1a"), 0);              // none
}

TEST(Shown, QuotesCutsAndKeepsMessagesPrintableUtf8) {
  EXPECT_EQ(shown("12.5"), "'12.5'");
  EXPECT_EQ(shown("a\tb\x7f"), "'a?b?'");
  EXPECT_EQ(shown(std::string(40, 'x')), "'" + std::string(40, 'x') + "'");
  EXPECT_EQ(shown(std::string(41, 'x')), "'" + std::string(40, 'x') + "...'");
  // UTF-8 is kept and cut at a character boundary (é is two bytes).
  EXPECT_EQ(shown("Lumin\xC3\xA4re"), "'Lumin\xC3\xA4re'");
  EXPECT_EQ(shown(std::string(39, 'x') + "\xC3\xA9zz"), "'" + std::string(39, 'x') + "...'");
  // Latin-1 bytes (not UTF-8) become '?'.
  EXPECT_EQ(shown("Leuchte \xE9"), "'Leuchte ?'");
}

}  // namespace
}  // namespace gonio::io
