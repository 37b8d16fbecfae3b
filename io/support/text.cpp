#include "io/support/text.h"

#include <charconv>
#include <cmath>
#include <cstdint>

namespace gonio::io {

std::vector<TextLine> split_lines(std::string_view text) {
  std::vector<TextLine> lines;
  std::size_t start = 0;
  int number = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c != '\n' && c != '\r') continue;
    lines.push_back({text.substr(start, i - start), number++});
    if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
    start = i + 1;
  }
  if (start < text.size()) lines.push_back({text.substr(start), number});
  return lines;
}

bool is_valid_utf8(std::string_view bytes) {
  std::size_t i = 0;
  while (i < bytes.size()) {
    const auto c = static_cast<unsigned char>(bytes[i]);
    int extra = 0;
    std::uint32_t cp = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xE0) == 0xC0) {
      extra = 1;
      cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      extra = 2;
      cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      extra = 3;
      cp = c & 0x07;
    } else {
      return false;
    }
    if (i + static_cast<std::size_t>(extra) >= bytes.size()) return false;
    for (int k = 1; k <= extra; ++k) {
      const auto cc = static_cast<unsigned char>(bytes[i + static_cast<std::size_t>(k)]);
      if ((cc & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (cc & 0x3F);
    }
    // Reject overlong forms, surrogates and out-of-range code points.
    static constexpr std::uint32_t kMin[4] = {0, 0x80, 0x800, 0x10000};
    if (cp < kMin[extra] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    i += static_cast<std::size_t>(extra) + 1;
  }
  return true;
}

std::string latin1_to_utf8(std::string_view bytes) {
  std::string out;
  out.reserve(bytes.size());
  for (char ch : bytes) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x80) {
      out.push_back(ch);
    } else {
      out.push_back(static_cast<char>(0xC0 | (c >> 6)));
      out.push_back(static_cast<char>(0x80 | (c & 0x3F)));
    }
  }
  return out;
}

std::string decode_text(std::string_view bytes) {
  return is_valid_utf8(bytes) ? std::string(bytes) : latin1_to_utf8(bytes);
}

std::string utf8_to_latin1(std::string_view utf8) {
  if (!is_valid_utf8(utf8)) return std::string(utf8);
  std::string out;
  out.reserve(utf8.size());
  for (std::size_t i = 0; i < utf8.size();) {
    const auto c = static_cast<unsigned char>(utf8[i]);
    if (c < 0x80) {
      out.push_back(static_cast<char>(c));
      ++i;
    } else if ((c & 0xE0) == 0xC0) {
      const std::uint32_t cp =
          ((c & 0x1Fu) << 6) | (static_cast<unsigned char>(utf8[i + 1]) & 0x3Fu);
      out.push_back(cp <= 0xFF ? static_cast<char>(cp) : '?');
      i += 2;
    } else {
      out.push_back('?');
      i += (c & 0xF0) == 0xE0 ? 3 : 4;
    }
  }
  return out;
}

std::optional<double> parse_number(std::string_view token, bool decimal_comma) {
  if (token.empty() || token.size() > 64) return std::nullopt;
  char buf[66];
  std::size_t n = 0;
  std::size_t start = 0;
  if (token[0] == '+') start = 1;  // from_chars rejects a leading '+'
  bool seen_point = false;
  for (std::size_t i = start; i < token.size(); ++i) {
    char c = token[i];
    if (decimal_comma && c == ',') c = '.';
    if (c == '.') {
      if (seen_point) return std::nullopt;
      seen_point = true;
    } else if (!((c >= '0' && c <= '9') || c == '-' || c == '+' || c == 'e' || c == 'E')) {
      return std::nullopt;  // excludes "nan", "inf", hexadecimal
    }
    buf[n++] = c;
  }
  if (n == 0) return std::nullopt;
  double value = 0.0;
  const auto [end, ec] = std::from_chars(buf, buf + n, value, std::chars_format::general);
  if (ec != std::errc() || end != buf + n || !std::isfinite(value)) return std::nullopt;
  return value;
}

bool looks_binary(std::string_view bytes) {
  std::size_t control = 0;
  for (char ch : bytes) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == 0) return true;
    if (c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f') ++control;
  }
  return control > 8 && control * 100 > bytes.size();
}

int first_binary_line(std::string_view text) {
  int line = 1;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n' || (c == '\r' && !(i + 1 < text.size() && text[i + 1] == '\n'))) ++line;
    if (c == 0 || (c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\f' && c != 0x1a))
      return line;
  }
  return 0;
}

std::string shown(std::string_view token) {
  constexpr std::size_t kMax = 40;
  const bool utf8 = is_valid_utf8(token);
  std::size_t n = token.size();
  if (n > kMax) {
    n = kMax;
    // Back off to the start of a UTF-8 character.
    while (utf8 && n > 0 && (static_cast<unsigned char>(token[n]) & 0xC0) == 0x80) --n;
  }
  std::string out = "'";
  for (char c : token.substr(0, n)) {
    const auto u = static_cast<unsigned char>(c);
    out += (u < 0x20 || u == 0x7F || (u >= 0x80 && !utf8)) ? '?' : c;
  }
  if (n < token.size()) out += "...";
  return out + "'";
}

}  // namespace gonio::io
