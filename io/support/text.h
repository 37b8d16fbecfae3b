// Text handling shared by the IES and EULUMDAT readers: line splitting that
// keeps line numbers (LF, CRLF and lone CR endings), Latin-1 to UTF-8, and
// strict number parsing.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gonio::io {

struct TextLine {
  std::string_view text;  // without the line ending
  int number;             // 1-based
};

// Splits into lines; a trailing line ending does not start an empty line.
std::vector<TextLine> split_lines(std::string_view text);

bool is_valid_utf8(std::string_view bytes);

// Interprets bytes as ISO-8859-1 and returns UTF-8.
std::string latin1_to_utf8(std::string_view bytes);

// UTF-8 as it is, anything else as Latin-1 converted to UTF-8: what real
// photometric files carry in their labels.
std::string decode_text(std::string_view bytes);

// UTF-8 to Latin-1 for writers of formats defined in Latin-1; characters
// outside Latin-1 become '?'. Invalid UTF-8 is copied byte by byte.
std::string utf8_to_latin1(std::string_view utf8);

// Parses a whole token as a finite decimal number ("12", "-1.5", "3e2",
// "+4.", ".5"). With `decimal_comma`, one ',' is read as the decimal point.
// Returns nullopt for anything else: empty tokens, trailing garbage, "nan",
// "inf", values that overflow a double, hexadecimal.
std::optional<double> parse_number(std::string_view token, bool decimal_comma = false);

// A token as messages quote it: in single quotes, at most 40 bytes (cut at a
// character boundary, then "..."), control characters and DEL as '?', and
// bytes above 0x7F kept only where the token is valid UTF-8 (else '?'), so
// that a message is always printable UTF-8.
std::string shown(std::string_view token);

// Whether the bytes look like binary data rather than text: NUL bytes, or
// many control characters other than tab, CR, LF and form feed.
bool looks_binary(std::string_view bytes);

// The 1-based line (LF, CRLF or CR endings) of the first byte no text file
// holds: NUL or a control character other than tab, CR, LF, form feed and
// the DOS end-of-file byte 0x1A; 0 if there is none.
int first_binary_line(std::string_view bytes);

}  // namespace gonio::io
