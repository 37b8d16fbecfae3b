#include "io/photometric/ies.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <span>
#include <utility>

#include "gonio/version.h"
#include "io/support/file_io.h"
#include "io/support/text.h"
#include "photometry/error_at.h"
#include "photometry/format.h"

namespace gonio::io {
namespace {

using photometry::Distribution;
using photometry::FileGenerationType;
using photometry::Keyword;
using photometry::LampSet;
using photometry::LengthUnit;
using photometry::LuminousOpening;
using photometry::OpeningShape;
using photometry::PhotometricType;
using photometry::Symmetry;
using photometry::Tilt;

constexpr std::size_t kLongLine = 256;  // LM-63-2002/2019 line limit [characters]
// Written lines, without their CR LF [characters]: keyword lines stay within
// 256 and data lines within the 132 of LM-63-1991/1995 with the line end
// counted, so that readers with fixed line buffers of those sizes cope.
constexpr std::size_t kKeywordLineWidth = 254;
constexpr std::size_t kDataLineWidth = 128;
constexpr double kMetresPerFoot = 0.3048;
constexpr double kAngleTol = 1e-9;  // [deg] as photometry::validate

// Keywords LM-63-2002 defines (LM-63-2019 adds FILEGENINFO).
constexpr std::array<std::string_view, 19> kKeywords2002 = {
    "TEST",         "TESTLAB",   "TESTDATE",     "ISSUEDATE", "MANUFAC",
    "LUMCAT",       "LUMINAIRE", "LAMPCAT",      "LAMP",      "BALLASTCAT",
    "BALLAST",      "MAINTCAT",  "DISTRIBUTION", "FLASHAREA", "COLORCONSTANT",
    "LAMPPOSITION", "NEARFIELD", "SEARCH",       "OTHER"};
// Accepted without an "unknown-keyword" warning when reading: those above,
// FILEGENINFO and the 1991/1995 keywords later versions dropped.
constexpr std::array<std::string_view, 4> kKeywordsOther = {"FILEGENINFO", "DATE", "BLOCK",
                                                            "ENDBLOCK"};

bool in(std::string_view key, std::span<const std::string_view> list) {
  return std::find(list.begin(), list.end(), key) != list.end();
}

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

bool is_separator(char c) {
  return c == ' ' || c == '\t' || c == ',' || c == '\r' || c == '\n' || c == '\f' || c == '\v' ||
         c == '\x1a';  // DOS end-of-file mark
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (is_blank(s.front()) || s.front() == '\x1a')) s.remove_prefix(1);
  while (!s.empty() && (is_blank(s.back()) || s.back() == '\x1a')) s.remove_suffix(1);
  return s;
}

std::string upper(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

bool starts_with_ci(std::string_view s, std::string_view prefix) {
  if (s.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i)
    if (std::toupper(static_cast<unsigned char>(s[i])) !=
        std::toupper(static_cast<unsigned char>(prefix[i])))
      return false;
  return true;
}

bool near(double a, double b) { return std::abs(a - b) <= kAngleTol; }

// Lines with their numbers, split as io/support/text.h does (LF, CRLF, lone CR),
// without building a list: a hostile file of line ends costs nothing.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}

  bool next(TextLine& out) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = pos_;
    while (end < text_.size() && text_[end] != '\n' && text_[end] != '\r') ++end;
    out = {text_.substr(pos_, end - pos_), number_++};
    pos_ = end;
    if (pos_ < text_.size()) {
      if (text_[pos_] == '\r' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '\n') ++pos_;
      ++pos_;
    }
    return true;
  }
  std::size_t offset() const { return pos_; }  // start of the next line
  int next_number() const { return number_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  int number_ = 1;
};

// Numbers separated by blanks, commas and line ends, with the line of each.
class NumberStream {
 public:
  // Before any token, errors point at the line before the first (the TILT
  // line for photometric data).
  NumberStream(std::string_view text, int first_line, std::string file)
      : text_(text),
        line_(first_line),
        last_line_(std::max(1, first_line - 1)),
        file_(std::move(file)) {}

  // The next number; on failure `error()` says what was expected (`what()`)
  // and what was found.
  template <class Describe>
  bool next(double& out, Describe&& what) {
    std::string_view token;
    if (!next_token(token)) {
      set_error("unexpected end of file: expected " + what());
      return false;
    }
    if (auto v = parse_number(token)) {
      out = *v;
      return true;
    }
    const std::string low = upper(token);
    const bool not_finite =
        low.find("NAN") != std::string::npos || low.find("INF") != std::string::npos;
    set_error("expected " + what() + ", found " + shown(token) +
              (not_finite ? " (not a finite number)" : ""));
    return false;
  }

  // The next number as an integer in [lo, hi].
  template <class Describe>
  bool next_int(long long& out, long long lo, long long hi, Describe&& what) {
    double v = 0.0;
    if (!next(v, what)) return false;
    if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi)) {
      set_error("expected " + what() + " (an integer from " + std::to_string(lo) + " to " +
                std::to_string(hi) + "), found " + format_number(v, 10));
      return false;
    }
    out = static_cast<long long>(v);
    return true;
  }

  // Whether `count` more numbers can possibly follow: each takes at least
  // one character and one separator. Checked before allocating for them.
  bool can_hold(double count) const {
    return count <= (static_cast<double>(text_.size() - pos_) + 1.0) / 2.0;
  }
  std::size_t remaining_bytes() const { return text_.size() - pos_; }

  // The next token, if any (used for trailing data).
  bool next_token(std::string_view& token) {
    while (pos_ < text_.size() && is_separator(text_[pos_])) {
      const char c = text_[pos_++];
      if (c == '\n') {
        ++line_;
      } else if (c == '\r') {
        ++line_;
        if (pos_ < text_.size() && text_[pos_] == '\n') ++pos_;
      }
    }
    if (pos_ >= text_.size()) return false;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_separator(text_[pos_])) ++pos_;
    token = text_.substr(start, pos_ - start);
    last_line_ = line_;
    return true;
  }

  int line() const { return last_line_; }  // line of the last token read
  const std::string& file() const { return file_; }
  const Error& error() const { return error_; }
  Error fail(int line, std::string message) const { return make_error(file_, line, std::move(message)); }

 private:
  void set_error(std::string message) { error_ = make_error(file_, last_line_, std::move(message)); }

  std::string_view text_;
  std::size_t pos_ = 0;
  int line_;
  int last_line_;
  std::string file_;
  Error error_;
};

std::string ordinal_of(std::size_t i, std::size_t n) {
  return std::to_string(i + 1) + " of " + std::to_string(n);
}

// ---------------------------------------------------------------------------
// Luminous opening tables (see io/photometric/ies.h).

bool same(double a, double b) {
  return std::abs(std::abs(a) - std::abs(b)) <= 1e-9 * std::max(std::abs(a), std::abs(b));
}

LuminousOpening opening(OpeningShape shape, double width, double length, double height) {
  LuminousOpening o;
  o.shape = shape;
  o.width_m = std::abs(width);
  o.length_m = std::abs(length);
  o.height_m = std::abs(height);
  return o;
}

std::optional<LuminousOpening> rectangle(double w, double l, double h) {
  if (w == 0.0 && l == 0.0 && h == 0.0) return opening(OpeningShape::Point, 0, 0, 0);
  if (w >= 0.0 && l >= 0.0 && h >= 0.0)
    return opening(h == 0.0 ? OpeningShape::Rectangular : OpeningShape::RectangularWithSides, w, l,
                   h);
  return std::nullopt;
}

// LM-63-2002/2019 (LM-63-2019 §5.11 Table 1).
std::optional<LuminousOpening> opening_2019(double w, double l, double h) {
  if (auto r = rectangle(w, l, h)) return r;
  if (w < 0 && l < 0) {
    if (h == 0)
      return opening(same(w, l) ? OpeningShape::Circular : OpeningShape::Ellipse, w, l, 0);
    if (h > 0)
      return opening(
          same(w, l) ? OpeningShape::VerticalCylinder : OpeningShape::VerticalEllipticalCylinder, w,
          l, h);
    return opening(same(w, l) && same(w, h) ? OpeningShape::Sphere : OpeningShape::Ellipsoid, w, l,
                   h);
  }
  if (w < 0 && l > 0 && h < 0)
    return opening(same(w, h) ? OpeningShape::HorizontalCylinderAlongLength
                              : OpeningShape::HorizontalEllipticalCylinderAlongLength,
                   w, l, h);
  if (w > 0 && l < 0 && h < 0)
    return opening(same(l, h) ? OpeningShape::HorizontalCylinderAlongWidth
                              : OpeningShape::HorizontalEllipticalCylinderAlongWidth,
                   w, l, h);
  if (w < 0 && l == 0 && h < 0)
    return opening(same(w, h) ? OpeningShape::VerticalCircle : OpeningShape::VerticalEllipse, w, 0,
                   h);
  return std::nullopt;
}

// LM-63-1986…1995 (the LM-63-1995 table).
std::optional<LuminousOpening> opening_1995(double w, double l, double h) {
  if (auto r = rectangle(w, l, h)) return r;
  if (w < 0 && l == 0) {
    if (h == 0) return opening(OpeningShape::Circular, w, w, 0);
    if (h > 0) return opening(OpeningShape::VerticalCylinder, w, w, h);
    if (same(w, h)) return opening(OpeningShape::Sphere, w, w, w);
    return std::nullopt;
  }
  if (w == 0 && l > 0 && h < 0)
    return opening(OpeningShape::HorizontalCylinderAlongLength, h, l, h);
  if (w > 0 && l == 0 && h < 0) return opening(OpeningShape::HorizontalCylinderAlongWidth, w, h, h);
  if ((w < 0 && l > 0) || (w > 0 && l < 0)) {
    if (h == 0) return opening(OpeningShape::Ellipse, w, l, 0);
    if (h > 0) return opening(OpeningShape::VerticalEllipticalCylinder, w, l, h);
    return opening(OpeningShape::Ellipsoid, w, l, h);
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------
// Reader

struct VersionLine {
  IesVersion version;
  bool standard;  // the exact string the standard prescribes
  bool known;     // names a year
};

std::optional<VersionLine> detect_version(std::string_view line) {
  std::string u = upper(trim(line));
  if (!(u.rfind("IESNA", 0) == 0 || u.rfind("IES:", 0) == 0)) return std::nullopt;
  if (u == "IESNA91") return VersionLine{IesVersion::LM63_1991, true, true};
  if (u == "IESNA:LM-63-1995") return VersionLine{IesVersion::LM63_1995, true, true};
  if (u == "IESNA:LM-63-2002") return VersionLine{IesVersion::LM63_2002, true, true};
  if (u == "IES:LM-63-2019") return VersionLine{IesVersion::LM63_2019, true, true};
  // The year it names: the last run of digits (two or four of them) once
  // the standard's name "LM-63" is out of the way.
  if (const std::size_t lm = u.find("LM-63"); lm != std::string::npos) u.erase(lm, 5);
  std::size_t end = u.size();
  while (end > 0 && !std::isdigit(static_cast<unsigned char>(u[end - 1]))) --end;
  std::size_t begin = end;
  while (begin > 0 && std::isdigit(static_cast<unsigned char>(u[begin - 1]))) --begin;
  int year = 0;
  if (end - begin == 4) {
    year = std::stoi(u.substr(begin, 4));
  } else if (end - begin == 2) {
    const int yy = std::stoi(u.substr(begin, 2));
    year = yy >= 80 ? 1900 + yy : 2000 + yy;
  } else {
    return VersionLine{IesVersion::LM63_2002, false, false};
  }
  IesVersion v = year >= 2019   ? IesVersion::LM63_2019
                 : year >= 2002 ? IesVersion::LM63_2002
                 : year >= 1995 ? IesVersion::LM63_1995
                 : year >= 1991 ? IesVersion::LM63_1991
                                : IesVersion::LM63_1986;
  return VersionLine{v, false, true};
}

// Whether a line holds nothing but (at least ten) numbers: photometric data
// where the TILT line should have been.
bool looks_like_data(std::string_view line) {
  int count = 0;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_separator(line[i])) ++i;
    if (i >= line.size()) break;
    const std::size_t start = i;
    while (i < line.size() && !is_separator(line[i])) ++i;
    if (!parse_number(line.substr(start, i - start))) return false;
    ++count;
  }
  return count >= 10;
}

class IesReader {
 public:
  IesReader(std::string_view bytes, const std::string& name, const std::string& tilt_dir)
      : bytes_(bytes), name_(name), tilt_dir_(tilt_dir) {}

  Result<IesFile> read();

 private:
  Error fail(int line, std::string message) const { return make_error(name_, line, std::move(message)); }
  void warn(int line, const char* code, std::string message) {
    result_.findings.push_back({Severity::Warning, code, std::move(message), {name_, line, 0}});
  }
  void warn_at(const std::string& file, int line, const char* code, std::string message) {
    result_.findings.push_back({Severity::Warning, code, std::move(message), {file, line, 0}});
  }

  Status check_bytes(std::string_view text);
  Status read_header(std::string_view text, std::size_t* data_offset, int* data_line);
  void add_keyword(std::string_view line, int number);
  Status read_tilt(NumberStream& in, Tilt& tilt);
  Status read_tilt_file(const std::string& file_name, int tilt_line, Tilt& tilt);
  Status read_data(NumberStream& in);
  Status set_symmetry(int first_line, int last_line);
  void set_opening(double w, double l, double h, int line);

  std::string_view bytes_;
  std::string name_;
  std::string tilt_dir_;
  IesFile result_;
  Distribution& d_ = result_.distribution;
  IesVersion version_ = IesVersion::LM63_1986;
  Tilt::Kind tilt_kind_ = Tilt::Kind::None;
  std::string tilt_spec_;
  int tilt_line_ = 0;
};

Status IesReader::check_bytes(std::string_view text) {
  if (std::all_of(text.begin(), text.end(),
                  [](char c) { return is_blank(c) || c == '\r' || c == '\n' || c == '\x1a'; }))
    return fail(1, "empty file: expected an IES LM-63 photometric file");
  if (text.size() >= 2 &&
      ((text[0] == '\xff' && text[1] == '\xfe') || (text[0] == '\xfe' && text[1] == '\xff')))
    return fail(1, "UTF-16 text: IES files are ASCII or Latin-1");
  if (looks_binary(text)) return fail(first_binary_line(text), "binary data, not an IES LM-63 text file");
  // Long lines: one warning for the file, not one per line.
  LineCursor lines(text);
  TextLine line{};
  int count = 0, first = 0;
  std::size_t longest = 0;
  while (lines.next(line)) {
    if (line.text.size() > kLongLine) {
      if (count++ == 0) first = line.number;
      longest = std::max(longest, line.text.size());
    }
  }
  if (count > 0)
    warn(first, "long-line",
         std::to_string(count) + " line(s) longer than " + std::to_string(kLongLine) +
             " characters (longest " + std::to_string(longest) + "), read anyway");
  return Ok{};
}

void IesReader::add_keyword(std::string_view t, int number) {
  auto& keywords = d_.keywords;
  if (t.front() == '[') {
    const std::size_t close = t.find(']');
    if (close != std::string_view::npos) {
      const std::string key = upper(trim(t.substr(1, close - 1)));
      std::string value = decode_text(trim(t.substr(close + 1)));
      if (key == "MORE") {
        if (keywords.empty()) {
          warn(number, "more-without-keyword", "[MORE] before any keyword; kept as [OTHER]");
          keywords.push_back({"OTHER", std::move(value)});
        } else {
          keywords.back().value += '\n';
          keywords.back().value += value;
        }
        return;
      }
      if (key.empty()) {
        warn(number, "label-line", "empty keyword []; line kept as [OTHER]");
        keywords.push_back({"OTHER", decode_text(t)});
        return;
      }
      if (key.front() != '_' && !in(key, kKeywords2002) && !in(key, kKeywordsOther))
        warn(number, "unknown-keyword",
             "[" + key + "] is not an LM-63 keyword (user keywords start with '_')");
      keywords.push_back({key, std::move(value)});
      return;
    }
  }
  // A free-form label line: the 1986 layout; later versions want keywords.
  if (version_ != IesVersion::LM63_1986)
    warn(number, "label-line", "line without a [KEYWORD]; kept as [OTHER]");
  keywords.push_back({"OTHER", decode_text(t)});
}

Status IesReader::read_header(std::string_view text, std::size_t* data_offset, int* data_line) {
  LineCursor lines(text);
  TextLine line{};
  bool pending = false;  // `line` holds a header line not yet handled
  while (lines.next(line)) {
    if (trim(line.text).empty()) continue;
    if (auto v = detect_version(line.text)) {
      version_ = v->version;
      const std::string shown_line = shown(trim(line.text));
      if (!v->known)
        warn(line.number, "unknown-version",
             "unknown version line " + shown_line + "; read as LM-63-2002");
      else if (!v->standard)
        warn(line.number, "nonstandard-version",
             "nonstandard version line " + shown_line + "; read as " + to_string(v->version));
    } else {
      version_ = IesVersion::LM63_1986;  // no version line: label lines up to TILT
      pending = true;
    }
    break;
  }
  result_.version = version_;

  int last_line = line.number;
  while (pending || lines.next(line)) {
    pending = false;
    last_line = line.number;
    const std::string_view t = trim(line.text);
    if (t.empty()) continue;
    if (starts_with_ci(t, "TILT")) {
      const std::string_view rest = trim(t.substr(4));
      if (!rest.empty() && rest.front() == '=') {
        const std::string_view spec = trim(rest.substr(1));
        tilt_line_ = line.number;
        if (spec.empty())
          return fail(line.number, "TILT= names nothing: expected NONE, INCLUDE or a file name");
        const std::string u = upper(spec);
        if (u == "NONE") {
          tilt_kind_ = Tilt::Kind::None;
        } else if (u == "INCLUDE") {
          tilt_kind_ = Tilt::Kind::Include;
        } else {
          tilt_kind_ = Tilt::Kind::File;
          tilt_spec_ = std::string(spec);
        }
        *data_offset = lines.offset();
        *data_line = lines.next_number();
        return Ok{};
      }
    }
    if (looks_like_data(t))
      return fail(line.number,
                  "missing TILT line: expected TILT=NONE, TILT=INCLUDE or TILT=<file> before the "
                  "photometric data");
    add_keyword(t, line.number);
  }
  return fail(last_line,
              "missing TILT line: expected TILT=NONE, TILT=INCLUDE or TILT=<file> after the "
              "keywords, found the end of the file");
}

Status IesReader::read_tilt(NumberStream& in, Tilt& tilt) {
  long long geometry = 0, count = 0;
  if (!in.next_int(geometry, 1, 3, [] { return std::string("TILT lamp-to-luminaire geometry"); }))
    return in.error();
  if (!in.next_int(count, 1, std::numeric_limits<int>::max(),
                   [] { return std::string("number of TILT angles"); }))
    return in.error();
  const int count_line = in.line();
  if (!in.can_hold(2.0 * static_cast<double>(count)))
    return in.fail(count_line, std::to_string(count) + " TILT angles need " +
                                   std::to_string(2 * count) + " numbers, more than the " +
                                   std::to_string(in.remaining_bytes()) +
                                   " bytes left in the file can hold");
  const auto n = static_cast<std::size_t>(count);
  tilt.lamp_geometry = static_cast<int>(geometry);
  tilt.angles_deg.clear();
  tilt.factors.clear();
  tilt.angles_deg.reserve(n);
  tilt.factors.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    double a = 0.0;
    if (!in.next(a, [&] { return "TILT angle " + ordinal_of(i, n); })) return in.error();
    if (i > 0 && !(a > tilt.angles_deg.back()))
      return in.fail(in.line(), "TILT angles must increase: " + format_number(a, 10) + " follows " +
                                    format_number(tilt.angles_deg.back(), 10));
    tilt.angles_deg.push_back(a);
  }
  for (std::size_t i = 0; i < n; ++i) {
    double f = 0.0;
    if (!in.next(f, [&] { return "TILT multiplying factor " + ordinal_of(i, n); }))
      return in.error();
    if (f < 0.0)
      return in.fail(in.line(), "TILT multiplying factor " + format_number(f, 10) + " is negative");
    tilt.factors.push_back(f);
  }
  return Ok{};
}

Status IesReader::read_tilt_file(const std::string& file_name, int tilt_line, Tilt& tilt) {
  namespace fs = std::filesystem;
  if (tilt_dir_.empty())
    return fail(tilt_line, "TILT=" + file_name +
                               " names a tilt file, but no directory to look for it was given");
  const fs::path p =
      fs::path(file_name).is_absolute() ? fs::path(file_name) : fs::path(tilt_dir_) / file_name;
  const std::string path = p.string();
  auto bytes = read_file(path, kMaxIesFileBytes);
  if (!bytes.ok())
    return fail(tilt_line,
                "TILT file '" + file_name + "' cannot be read: " + to_string(bytes.error()));
  NumberStream in(*bytes, 1, path);
  if (looks_binary(*bytes))
    return in.fail(1, "binary data, not a TILT file (named by " + name_ + ":" +
                          std::to_string(tilt_line) + ")");
  if (Status s = read_tilt(in, tilt); !s.ok()) {
    Error e = s.error();
    e.message += " (TILT file named by " + name_ + ":" + std::to_string(tilt_line) + ")";
    return e;
  }
  std::string_view extra;
  if (in.next_token(extra))
    warn_at(path, in.line(), "trailing-data",
            "data after the TILT factors ignored (first: " + shown(extra) + ")");
  return Ok{};
}

Status IesReader::set_symmetry(int first_line, int last_line) {
  const auto& h = d_.horizontal_deg;
  const double first = h.front(), last = h.back();
  if (d_.type == PhotometricType::C) {
    if (h.size() == 1) {
      d_.symmetry = Symmetry::Rotational;
      if (!near(first, 0.0))
        warn(first_line, "horizontal-range",
             "single horizontal angle " + format_number(first, 10) +
                 " (LM-63 expects 0); read as rotational");
      return Ok{};
    }
    if (near(first, 0.0)) {
      if (near(last, 90.0)) {
        d_.symmetry = Symmetry::Quadrant;
      } else if (near(last, 180.0)) {
        d_.symmetry = Symmetry::C0_C180;
      } else if (last > 180.0 && last <= 360.0 + kAngleTol) {
        d_.symmetry = Symmetry::None;
      } else {
        return fail(last_line, "Type C horizontal angles 0 to " + format_number(last, 10) +
                                   " match no LM-63 range: the last angle must be 90, 180, or "
                                   "above 180 up to 360");
      }
      return Ok{};
    }
    if (near(first, 90.0) && near(last, 270.0)) {
      d_.symmetry = Symmetry::C90_C270;
      if (version_ >= IesVersion::LM63_2002)
        warn(first_line, "horizontal-range",
             "horizontal angles 90 to 270 are an LM-63-1995 range, not one of " +
                 std::string(to_string(version_)) + "; read as symmetric about C90-C270");
      return Ok{};
    }
    return fail(first_line,
                "Type C horizontal angles must start at 0 (or run from 90 to 270), found " +
                    format_number(first, 10) + " to " + format_number(last, 10));
  }
  if (near(first, 0.0)) {
    d_.symmetry = Symmetry::Lateral;
    if (!near(last, 90.0))
      warn(last_line, "horizontal-range",
           "laterally symmetric horizontal angles end at " + format_number(last, 10) + ", not 90");
    return Ok{};
  }
  if (first < 0.0) {
    d_.symmetry = Symmetry::None;
    if (!near(first, -90.0) || !near(last, 90.0))
      warn(first_line, "horizontal-range",
           "horizontal angles " + format_number(first, 10) + " to " + format_number(last, 10) +
               " do not span -90 to 90");
    return Ok{};
  }
  return fail(first_line, std::string("Type ") + to_string(d_.type) +
                              " horizontal angles must start at -90 or 0, found " +
                              format_number(first, 10));
}

void IesReader::set_opening(double w, double l, double h, int line) {
  const bool old_table = version_ <= IesVersion::LM63_1995;
  auto o = old_table ? opening_1995(w, l, h) : opening_2019(w, l, h);
  const std::string dims =
      format_number(w, 10) + " " + format_number(l, 10) + " " + format_number(h, 10);
  if (!o) {
    o = old_table ? opening_2019(w, l, h) : opening_1995(w, l, h);
    if (o) {
      warn(line, "opening-shape",
           "luminous opening " + dims + " is not in the " + to_string(version_) +
               " table; read by the " + (old_table ? "LM-63-2019" : "LM-63-1995") + " table as " +
               photometry::to_string(o->shape));
    } else if (h == 0 && ((w < 0 && l == 0) || (w == 0 && l < 0))) {
      o = opening(OpeningShape::Circular, w + l, w + l, 0);
      warn(line, "opening-shape",
           "luminous opening " + dims + " matches no LM-63 shape; read as circular");
    } else {
      o = opening(h == 0 ? OpeningShape::Rectangular : OpeningShape::RectangularWithSides, w, l, h);
      warn(line, "opening-shape",
           "luminous opening " + dims +
               " matches no LM-63 shape; read as a rectangle of its absolute values");
    }
  }
  d_.opening = *o;
}

Status IesReader::read_data(NumberStream& in) {
  // Photometric line.
  long long lamps = 0, nv = 0, nh = 0, type = 0, units = 0;
  double lumens = 0.0, multiplier = 0.0, w = 0.0, l = 0.0, h = 0.0;
  constexpr long long kMaxCount = std::numeric_limits<int>::max();
  if (!in.next_int(lamps, 1, kMaxCount, [] { return std::string("number of lamps"); }))
    return in.error();
  if (!in.next(lumens, [] { return std::string("lumens per lamp"); })) return in.error();
  const int lumens_line = in.line();
  if (!in.next(multiplier, [] { return std::string("candela multiplier"); })) return in.error();
  if (!(multiplier > 0.0))
    return in.fail(in.line(),
                   "candela multiplier must be positive, found " + format_number(multiplier, 10));
  if (!in.next_int(nv, 1, kMaxCount, [] { return std::string("number of vertical angles"); }))
    return in.error();
  const int count_line = in.line();
  if (!in.next_int(nh, 1, kMaxCount, [] { return std::string("number of horizontal angles"); }))
    return in.error();
  if (!in.next_int(type, 1, 3,
                   [] { return std::string("photometric type (1 = C, 2 = B, 3 = A)"); }))
    return in.error();
  if (!in.next_int(units, 1, 2, [] { return std::string("units type (1 = feet, 2 = metres)"); }))
    return in.error();
  const auto dim = [](const char* what) { return [what] { return std::string(what); }; };
  if (!in.next(w, dim("luminous opening width"))) return in.error();
  if (!in.next(l, dim("luminous opening length"))) return in.error();
  if (!in.next(h, dim("luminous opening height"))) return in.error();
  const int opening_line = in.line();

  // Ballast line.
  double ballast = 0.0, second = 0.0, watts = 0.0;
  if (!in.next(ballast, dim("ballast factor"))) return in.error();
  if (!in.next(second, [this] {
        return std::string(version_ == IesVersion::LM63_2019   ? "file generation type"
                           : version_ == IesVersion::LM63_2002 ? "future-use value"
                                                               : "ballast-lamp photometric factor");
      }))
    return in.error();
  const int second_line = in.line();
  if (!in.next(watts, dim("input watts"))) return in.error();

  // Everything below is allocated from nv and nh: check first that the file
  // can hold that many numbers.
  const double needed = static_cast<double>(nv) + static_cast<double>(nh) +
                        static_cast<double>(nv) * static_cast<double>(nh);
  if (!in.can_hold(needed))
    return in.fail(count_line, std::to_string(nv) + " vertical × " + std::to_string(nh) +
                                   " horizontal angles need " + format_number(needed, 10) +
                                   " more numbers, more than the " +
                                   std::to_string(in.remaining_bytes()) +
                                   " bytes left in the file can hold");

  d_.type = static_cast<PhotometricType>(type);
  const bool c = d_.type == PhotometricType::C;
  const auto snv = static_cast<std::size_t>(nv), snh = static_cast<std::size_t>(nh);

  d_.vertical_deg.reserve(snv);
  int v_first_line = 0;
  for (std::size_t i = 0; i < snv; ++i) {
    double a = 0.0;
    if (!in.next(a, [&] { return "vertical angle " + ordinal_of(i, snv); })) return in.error();
    if (i == 0) v_first_line = in.line();
    const double lo = c ? 0.0 : -90.0, hi = c ? 180.0 : 90.0;
    if (a < lo - kAngleTol || a > hi + kAngleTol)
      return in.fail(in.line(), std::string("Type ") + to_string(d_.type) + " vertical angle " +
                                    format_number(a, 10) + " outside " + format_number(lo, 10) +
                                    " to " + format_number(hi, 10));
    if (i > 0 && !(a > d_.vertical_deg.back()))
      return in.fail(in.line(), "vertical angles must increase: " + format_number(a, 10) +
                                    " follows " + format_number(d_.vertical_deg.back(), 10));
    d_.vertical_deg.push_back(a);
  }
  if (c) {
    const double first = d_.vertical_deg.front(), last = d_.vertical_deg.back();
    if (!(near(first, 0.0) || near(first, 90.0)) || !(near(last, 90.0) || near(last, 180.0)))
      warn(v_first_line, "vertical-range",
           "vertical angles " + format_number(first, 10) + " to " + format_number(last, 10) +
               " are none of LM-63's ranges 0-90, 90-180, 0-180; outside them nothing is emitted");
  }

  d_.horizontal_deg.reserve(snh);
  int h_first_line = 0;
  for (std::size_t i = 0; i < snh; ++i) {
    double a = 0.0;
    if (!in.next(a, [&] { return "horizontal angle " + ordinal_of(i, snh); })) return in.error();
    if (i == 0) h_first_line = in.line();
    const double lo = c ? 0.0 : -90.0, hi = c ? 360.0 : 90.0;
    if (a < lo - kAngleTol || a > hi + kAngleTol)
      return in.fail(in.line(), std::string("Type ") + to_string(d_.type) + " horizontal angle " +
                                    format_number(a, 10) + " outside " + format_number(lo, 10) +
                                    " to " + format_number(hi, 10));
    if (i > 0 && !(a > d_.horizontal_deg.back()))
      return in.fail(in.line(), "horizontal angles must increase: " + format_number(a, 10) +
                                    " follows " + format_number(d_.horizontal_deg.back(), 10));
    d_.horizontal_deg.push_back(a);
  }
  if (Status s = set_symmetry(h_first_line, in.line()); !s.ok()) return s;

  d_.candela.reserve(snv * snh);
  std::size_t negative = 0;
  int negative_line = 0;
  for (std::size_t hi = 0; hi < snh; ++hi) {
    for (std::size_t vi = 0; vi < snv; ++vi) {
      double v = 0.0;
      if (!in.next(v, [&] {
            return "candela value " + ordinal_of(vi, snv) + " of horizontal angle " +
                   format_number(d_.horizontal_deg[hi], 10) + " (" + ordinal_of(hi, snh) + ")";
          }))
        return in.error();
      if (v < 0.0) {
        if (negative++ == 0) negative_line = in.line();
        v = 0.0;
      }
      d_.candela.push_back(v * multiplier);
    }
  }
  if (negative > 0)
    warn(negative_line, "negative-intensity",
         std::to_string(negative) + " negative candela value(s) read as 0");

  std::string_view extra;
  if (in.next_token(extra))
    warn(in.line(), "trailing-data",
         "data after the last candela value ignored (first: " + shown(extra) + ")");

  // The model.
  LampSet lamp;
  lamp.count = static_cast<int>(lamps);
  if (const Keyword* k = d_.find_keyword("LAMP")) lamp.type = k->value;
  if (lumens < 0.0) {
    d_.absolute = true;
    lamp.flux_lm = photometry::kNaN;
    if (lumens != -1.0)
      warn(lumens_line, "absolute-flux",
           "lumens per lamp " + format_number(lumens, 10) + " read as -1 (absolute photometry)");
  } else if (lumens == 0.0) {
    return in.fail(lumens_line,
                   "lumens per lamp must be positive, or -1 for absolute photometry; found 0");
  } else {
    lamp.flux_lm = static_cast<double>(lamps) * lumens;
  }
  d_.lamps = {lamp};
  d_.ballast_factor = ballast;
  d_.input_watts = watts;

  if (version_ == IesVersion::LM63_2019) {
    if (auto g = file_generation_from_code(second)) {
      d_.file_generation = *g;
    } else {
      warn(second_line, "file-generation-type",
           "file generation type " + format_number(second, 10) +
               " is not in the LM-63-2019 table; read as undefined");
    }
  } else {
    d_.ballast_lamp_factor = second;
    if (version_ == IesVersion::LM63_2002 && second != 1.0)
      warn(second_line, "future-use",
           "the LM-63-2002 future-use value is " + format_number(second, 10) +
               ", not 1; kept as ballast-lamp photometric factor");
  }

  const double unit = units == 1 ? kMetresPerFoot : 1.0;
  set_opening(w * unit, l * unit, h * unit, opening_line);
  d_.opening.file_unit = units == 1 ? LengthUnit::Foot : LengthUnit::Metre;
  return Ok{};
}

Result<IesFile> IesReader::read() {
  std::string_view text = bytes_;
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  if (Status s = check_bytes(text); !s.ok()) return s.error();

  std::size_t data_offset = 0;
  int data_line = 0;
  if (Status s = read_header(text, &data_offset, &data_line); !s.ok()) return s.error();

  const std::vector<std::string_view> required =
      version_ >= IesVersion::LM63_2002
          ? std::vector<std::string_view>{"TEST", "TESTLAB", "ISSUEDATE", "MANUFAC"}
      : version_ >= IesVersion::LM63_1991 ? std::vector<std::string_view>{"TEST", "MANUFAC"}
                                          : std::vector<std::string_view>{};
  for (std::string_view key : required)
    if (!d_.find_keyword(key))
      warn(tilt_line_, "missing-keyword",
           "required keyword [" + std::string(key) + "] of " + to_string(version_) + " is missing");

  NumberStream in(text.substr(data_offset), data_line, name_);
  d_.tilt.kind = tilt_kind_;
  if (tilt_kind_ == Tilt::Kind::Include) {
    if (Status s = read_tilt(in, d_.tilt); !s.ok()) return s.error();
  } else if (tilt_kind_ == Tilt::Kind::File) {
    d_.tilt.file = tilt_spec_;
    if (Status s = read_tilt_file(tilt_spec_, tilt_line_, d_.tilt); !s.ok()) return s.error();
  }
  if (Status s = read_data(in); !s.ok()) return s.error();

  if (Status s = photometry::validate(d_); !s.ok())
    return fail(0, "inconsistent photometric data: " + s.error().message);
  // File order: this file's findings by line, then the tilt file's.
  std::stable_sort(result_.findings.begin(), result_.findings.end(),
                   [this](const Finding& a, const Finding& b) {
                     const bool a_other = a.where.file != name_, b_other = b.where.file != name_;
                     if (a_other != b_other) return b_other;
                     return a.where.line < b.where.line;
                   });
  return std::move(result_);
}

// ---------------------------------------------------------------------------
// Writer

constexpr std::array<std::pair<FileGenerationType, double>, 10> kFileGeneration = {{
    {FileGenerationType::Undefined, 1.00001},
    {FileGenerationType::ComputerSimulation, 1.00010},
    {FileGenerationType::UnaccreditedLab, 1.00000},
    {FileGenerationType::UnaccreditedLabScaled, 1.00100},
    {FileGenerationType::UnaccreditedLabInterpolated, 1.01000},
    {FileGenerationType::UnaccreditedLabInterpolatedScaled, 1.01100},
    {FileGenerationType::AccreditedLab, 1.10000},
    {FileGenerationType::AccreditedLabScaled, 1.10100},
    {FileGenerationType::AccreditedLabInterpolated, 1.11000},
    {FileGenerationType::AccreditedLabInterpolatedScaled, 1.11100},
}};

// Whether UTF-8 text holds a character beyond U+00FF (lead bytes from 0xC4).
bool beyond_latin1(std::string_view utf8) {
  if (!is_valid_utf8(utf8)) return false;
  return std::any_of(utf8.begin(), utf8.end(),
                     [](char c) { return static_cast<unsigned char>(c) >= 0xC4; });
}

class IesWriter {
 public:
  IesWriter(const Distribution& d, const IesWriteOptions& options, std::vector<Finding>* warnings)
      : d_(d), options_(options), warnings_(warnings) {}

  std::string write();

 private:
  void warn(const char* code, std::string message) {
    if (warnings_) warnings_->push_back({Severity::Warning, code, std::move(message), {}});
  }
  void line(std::string_view text) {
    out_ += text;
    out_ += "\r\n";
  }
  void keyword(std::string key, std::string_view value);
  void numbers(std::span<const double> values);
  void keywords();
  void tilt();
  void unsupported_fields();
  Distribution grid();

  const Distribution& d_;
  const IesWriteOptions& options_;
  std::vector<Finding>* warnings_;
  std::string out_;
};

void IesWriter::keyword(std::string key, std::string_view value) {
  if (beyond_latin1(value))
    warn("non-latin1", "[" + key + "]: characters outside Latin-1 written as '?'");
  // Control characters other than tab and line breaks would make a reader
  // take the file for binary data (found by tests/fuzz/ies_fuzzer.cpp).
  std::string latin = utf8_to_latin1(value);
  bool control = false;
  for (std::string* text : {&key, &latin}) {
    for (char& c : *text) {
      if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && !(text == &latin && (c == '\r' || c == '\n'))) {
        c = ' ';
        control = true;
      }
    }
  }
  if (control) warn("control-characters", "[" + key + "]: control characters written as spaces");
  bool wrapped = false;
  std::string prefix = "[" + key + "]";
  std::size_t start = 0;
  while (true) {
    std::size_t end = latin.find_first_of("\r\n", start);
    std::string_view part = std::string_view(latin).substr(
        start, end == std::string::npos ? std::string::npos : end - start);
    // Longer than a line may be: continue on [MORE] lines, at a space if any.
    // (A keyword name that fills the line by itself is written whole on
    // one long line: there is no room to wrap at; found by the fuzzer.)
    while (prefix.size() + 1 + part.size() > kKeywordLineWidth && prefix.size() + 1 < kKeywordLineWidth) {
      const std::size_t room = kKeywordLineWidth - prefix.size() - 1;
      std::size_t cut = part.substr(0, room + 1).rfind(' ');
      if (cut == std::string_view::npos || cut == 0) cut = room;
      line(prefix + " " + std::string(trim(part.substr(0, cut))));
      part = trim(part.substr(cut));
      prefix = "[MORE]";
      wrapped = true;
    }
    line(part.empty() ? prefix : prefix + " " + std::string(part));
    prefix = "[MORE]";
    if (end == std::string::npos) break;
    start = end + 1;
    if (latin[end] == '\r' && start < latin.size() && latin[start] == '\n') ++start;
  }
  if (wrapped)
    warn("keyword-wrapped", "[" + key + "] is longer than a line; continued on [MORE] lines");
}

void IesWriter::numbers(std::span<const double> values) {
  std::string current;
  for (double v : values) {
    const std::string s = format_ies_number(v);
    if (!current.empty() && current.size() + 1 + s.size() > kDataLineWidth) {
      line(current);
      current.clear();
    }
    if (!current.empty()) current += ' ';
    current += s;
  }
  if (!current.empty()) line(current);
}

void IesWriter::keywords() {
  const bool v2019 = options_.version == IesVersion::LM63_2019;
  std::vector<bool> used(d_.keywords.size(), false);
  const auto take = [&](std::string_view key) -> const Keyword* {
    for (std::size_t i = 0; i < d_.keywords.size(); ++i)
      if (!used[i] && d_.keywords[i].key == key) {
        used[i] = true;
        return &d_.keywords[i];
      }
    return nullptr;
  };

  for (std::string_view key : {"TEST", "TESTLAB", "ISSUEDATE", "MANUFAC"}) {
    const Keyword* k = take(key);
    std::string value;
    if (k) {
      value = k->value;
    } else if (key == "ISSUEDATE" && !options_.issue_date.empty()) {
      value = options_.issue_date;
    } else if (const Keyword* date = key == "ISSUEDATE" ? take("DATE") : nullptr) {
      value = date->value;
    } else {
      value = "not stated";
      warn("default-keyword",
           "required keyword [" + std::string(key) + "] missing; written as '" + value + "'");
    }
    keyword(std::string(key), value);
  }
  if (v2019) {
    std::string info;
    if (const Keyword* k = take("FILEGENINFO")) {
      info = k->value;
    } else if (!options_.file_generation_info.empty()) {
      info = options_.file_generation_info;
    } else {
      info = std::string("Written by Gonio ") + kVersion;
    }
    keyword("FILEGENINFO", info);
  }

  bool lamp_written = false;
  for (std::size_t i = 0; i < d_.keywords.size(); ++i) {
    if (used[i]) continue;
    const Keyword& k = d_.keywords[i];
    std::string key = upper(k.key);
    for (char& ch : key)
      if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_')) ch = '_';
    if (key.empty()) key = "OTHER";
    if (key == "LAMP") lamp_written = true;
    if (key == "FILEGENINFO" && !v2019) {
      warn("keyword-renamed", "[FILEGENINFO] is an LM-63-2019 keyword; written as [OTHER]");
      key = "OTHER";
    } else if (key != "MORE" && key.front() != '_' && !in(key, kKeywords2002) &&
               !(v2019 && key == "FILEGENINFO")) {
      warn("keyword-renamed", "[" + key + "] is not an " +
                                  std::string(to_string(options_.version)) +
                                  " keyword; written as user keyword [_" + key + "]");
      key = "_" + key;
    }
    keyword(key, k.value);
  }
  if (!lamp_written && !d_.lamps.empty() && !d_.lamps.front().type.empty())
    keyword("LAMP", d_.lamps.front().type);
}

void IesWriter::tilt() {
  const Tilt& t = d_.tilt;
  if (t.kind == Tilt::Kind::None) {
    line("TILT=NONE");
    return;
  }
  if (t.angles_deg.empty() || t.angles_deg.size() != t.factors.size() || t.lamp_geometry < 1 ||
      t.lamp_geometry > 3) {
    warn("tilt-invalid", "TILT data incomplete (geometry " + std::to_string(t.lamp_geometry) +
                             ", " + std::to_string(t.angles_deg.size()) + " angles, " +
                             std::to_string(t.factors.size()) + " factors); written as TILT=NONE");
    line("TILT=NONE");
    return;
  }
  if (t.kind == Tilt::Kind::File)
    warn("tilt-file-included", "TILT=" + t.file + " written as TILT=INCLUDE with its data");
  line("TILT=INCLUDE");
  line(std::to_string(t.lamp_geometry));
  line(std::to_string(t.angles_deg.size()));
  numbers(t.angles_deg);
  numbers(t.factors);
}

void IesWriter::unsupported_fields() {
  if (d_.lamps.size() > 1)
    warn("lamp-sets-merged", std::to_string(d_.lamps.size()) +
                                 " lamp sets merged into one: IES holds a single lamp count and "
                                 "lumens per lamp");
  for (std::size_t i = 0; i < d_.lamps.size(); ++i) {
    const LampSet& l = d_.lamps[i];
    if (!l.color.empty())
      warn("lamp-color",
           "lamp set " + std::to_string(i + 1) + " colour '" + l.color + "' has no IES field");
    if (!l.color_rendering.empty())
      warn("lamp-color-rendering", "lamp set " + std::to_string(i + 1) + " colour rendering '" +
                                       l.color_rendering + "' has no IES field");
  }
  if (!d_.alternative_lamps.empty())
    warn("alternative-lamps",
         std::to_string(d_.alternative_lamps.size()) +
             " alternative lamp set(s) (EULUMDAT standard sets 2 and on) have no IES field; only "
             "the first set, to which the intensities refer, is written");
  const auto ldt_only = [&](bool present, const std::string& what) {
    if (present) warn("ldt-only-field", what + " has no IES field (EULUMDAT only)");
  };
  // Zero or unknown values carry nothing: a measurement tilt of 0, body
  // dimensions of 0, side heights equal to the opening's height.
  const auto nonzero = [](double x) { return std::isfinite(x) && x != 0.0; };
  ldt_only(std::isfinite(d_.declared_lor_percent), "declared light output ratio");
  ldt_only(std::isfinite(d_.declared_dff_percent), "declared downward flux fraction");
  ldt_only(nonzero(d_.measurement_tilt_deg), "measurement tilt");
  ldt_only(!d_.direct_ratios.empty(), "direct ratios");
  ldt_only(nonzero(d_.luminaire.length_m) || nonzero(d_.luminaire.width_m) ||
               nonzero(d_.luminaire.height_m),
           "luminaire body dimensions");
  ldt_only(std::any_of(std::begin(d_.opening.side_height_m), std::end(d_.opening.side_height_m),
                       [&](double x) {
                         return std::isfinite(x) && std::abs(x - d_.opening.height_m) > 1e-9;
                       }),
           "luminous area side heights (IES holds one height)");
  if (d_.ldt_type_indicator &&
      *d_.ldt_type_indicator != (d_.symmetry == Symmetry::Rotational ? 1 : 3))
    ldt_only(true, "EULUMDAT type indicator Ityp " + std::to_string(*d_.ldt_type_indicator));
  if (d_.ballast_lamp_factor != 1.0)
    warn("ballast-lamp-factor",
         "ballast-lamp photometric factor " + format_number(d_.ballast_lamp_factor, 10) +
             " (LM-63-1995) has no field in " + to_string(options_.version) + "; not written");
}

// The distribution on the horizontal range the file will hold.
Distribution IesWriter::grid() {
  if (d_.type != PhotometricType::C) {
    if (d_.symmetry == Symmetry::None && d_.horizontal_deg.front() >= -kAngleTol)
      warn("lateral-range", "horizontal angles " + format_number(d_.horizontal_deg.front(), 10) +
                                " to " + format_number(d_.horizontal_deg.back(), 10) +
                                " without symmetry will read back as lateral symmetry (LM-63 "
                                "reads a range starting at 0 so)");
    return d_;
  }
  if (d_.symmetry == Symmetry::Rotational) {
    Distribution g = d_;
    g.horizontal_deg = {0.0};
    return g;
  }
  if (d_.symmetry == Symmetry::C90_C270) {
    warn("symmetry-expanded", std::string("C90-C270 symmetry (horizontal angles 90 to 270) exists "
                                          "only in LM-63-1995; written as the full range 0 to 360 "
                                          "for ") +
                                  to_string(options_.version));
    return photometry::expand_symmetry(d_);
  }
  // Without symmetry LM-63 needs planes from 0 to beyond 180; anything else
  // is closed over the full circle as interpolate() reads it.
  if (d_.symmetry == Symmetry::None &&
      (d_.horizontal_deg.front() > kAngleTol || d_.horizontal_deg.back() <= 180.0 + kAngleTol)) {
    warn("symmetry-expanded", "horizontal angles " + format_number(d_.horizontal_deg.front(), 10) +
                                  " to " + format_number(d_.horizontal_deg.back(), 10) +
                                  " without symmetry are no LM-63 range: written as 0 to 360, "
                                  "planes added across the seam");
    return photometry::expand_symmetry(d_);
  }
  return d_;
}

std::string IesWriter::write() {
  GONIO_CHECK_MSG(
      options_.version == IesVersion::LM63_2019 || options_.version == IesVersion::LM63_2002,
      "write_ies writes LM-63-2019 or LM-63-2002");
  GONIO_CHECK_MSG(photometry::validate(d_).ok(), "write_ies needs a valid distribution");

  line(options_.version == IesVersion::LM63_2019 ? "IES:LM-63-2019" : "IESNA:LM-63-2002");
  keywords();
  tilt();
  unsupported_fields();

  const Distribution g = grid();
  if (g.type == PhotometricType::C) {
    const double first = g.vertical_deg.front(), last = g.vertical_deg.back();
    if (!(near(first, 0.0) || near(first, 90.0)) || !(near(last, 90.0) || near(last, 180.0)))
      warn("vertical-range", "vertical angles " + format_number(first, 10) + " to " +
                                 format_number(last, 10) +
                                 " are none of LM-63's ranges 0-90, 90-180, 0-180");
  }

  long long lamp_count = 0;
  double flux = 0.0, power = 0.0;
  bool power_known = !d_.lamps.empty();
  for (const LampSet& l : d_.lamps) {
    lamp_count += l.count;
    flux += l.flux_lm;
    power += l.power_w;
    power_known = power_known && std::isfinite(l.power_w);
  }
  bool absolute = d_.absolute;
  if (!absolute && d_.lamps.empty()) {
    warn("no-lamp-flux", "relative photometry without lamp data; written as absolute photometry");
    absolute = true;
  }
  if (lamp_count < 1) lamp_count = 1;

  double watts = d_.input_watts;
  if (!std::isfinite(watts)) {
    if (power_known) {
      watts = power;
    } else {
      watts = 0.0;
      warn("input-watts-unknown", "input watts unknown; written as 0");
    }
  } else if (power_known && std::abs(power - watts) > 1e-9 * std::max(power, watts)) {
    warn("lamp-power", "lamp set power " + format_number(power, 10) +
                           " W differs from the input watts " + format_number(watts, 10) +
                           " W, which IES keeps");
  }
  double ballast = d_.ballast_factor;
  if (!std::isfinite(ballast)) {
    warn("ballast-factor-unknown", "ballast factor unknown; written as 1");
    ballast = 1.0;
  }

  const bool feet = d_.opening.file_unit == LengthUnit::Foot;
  const double unit = feet ? 1.0 / kMetresPerFoot : 1.0;
  const LuminousOpening& o = d_.opening;
  double w = o.width_m * unit, l = o.length_m * unit, h = o.height_m * unit;
  using S = OpeningShape;
  switch (o.shape) {
    case S::Point: w = l = h = 0.0; break;
    case S::Rectangular: h = 0.0; break;
    case S::RectangularWithSides: break;
    case S::Circular:
      w = l = -std::max(w, l);
      h = 0.0;
      break;
    case S::Ellipse:
      w = -w;
      l = -l;
      h = 0.0;
      break;
    case S::VerticalCylinder: w = l = -std::max(w, l); break;
    case S::VerticalEllipticalCylinder:
      w = -w;
      l = -l;
      break;
    case S::Sphere: w = l = h = -std::max({w, l, h}); break;
    case S::Ellipsoid:
      w = -w;
      l = -l;
      h = -h;
      break;
    case S::HorizontalCylinderAlongLength: w = h = -std::max(w, h); break;
    case S::HorizontalEllipticalCylinderAlongLength:
      w = -w;
      h = -h;
      break;
    case S::HorizontalCylinderAlongWidth: l = h = -std::max(l, h); break;
    case S::HorizontalEllipticalCylinderAlongWidth:
      l = -l;
      h = -h;
      break;
    case S::VerticalCircle:
      w = h = -std::max(w, h);
      l = 0.0;
      break;
    case S::VerticalEllipse:
      w = -w;
      h = -h;
      l = 0.0;
      break;
  }

  const double lumens = absolute ? -1.0 : flux / static_cast<double>(lamp_count);
  line(std::to_string(lamp_count) + " " + format_ies_number(lumens) + " 1 " +
       std::to_string(g.vertical_deg.size()) + " " + std::to_string(g.horizontal_deg.size()) + " " +
       std::to_string(static_cast<int>(g.type)) + " " + (feet ? "1" : "2") + " " +
       format_ies_number(w) + " " + format_ies_number(l) + " " + format_ies_number(h));

  std::string second = "1";
  if (options_.version == IesVersion::LM63_2019) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%.5f", file_generation_code(d_.file_generation));
    second = buf;
  }
  line(format_ies_number(ballast) + " " + second + " " + format_ies_number(watts));

  numbers(g.vertical_deg);
  numbers(g.horizontal_deg);
  const std::size_t nv = g.vertical_deg.size();
  for (std::size_t hi = 0; hi < g.horizontal_deg.size(); ++hi)
    numbers(std::span<const double>(g.candela).subspan(hi * nv, nv));
  return std::move(out_);
}

}  // namespace

const char* to_string(IesVersion version) {
  switch (version) {
    case IesVersion::LM63_1986: return "LM-63-1986";
    case IesVersion::LM63_1991: return "LM-63-1991";
    case IesVersion::LM63_1995: return "LM-63-1995";
    case IesVersion::LM63_2002: return "LM-63-2002";
    case IesVersion::LM63_2019: return "LM-63-2019";
  }
  return "?";
}

Result<IesFile> read_ies(const std::string& path) {
  auto bytes = read_file(path, kMaxIesFileBytes);
  if (!bytes.ok()) return bytes.error();
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) dir = ".";
  return parse_ies(*bytes, path, dir.string());
}

Result<IesFile> parse_ies(std::string_view bytes, const std::string& name,
                          const std::string& directory_for_tilt_files) {
  return IesReader(bytes, name, directory_for_tilt_files).read();
}

std::string write_ies(const Distribution& d, const IesWriteOptions& options,
                      std::vector<Finding>* warnings) {
  return IesWriter(d, options, warnings).write();
}

double file_generation_code(FileGenerationType type) {
  for (const auto& [t, code] : kFileGeneration)
    if (t == type) return code;
  return 1.00001;
}

std::optional<FileGenerationType> file_generation_from_code(double code) {
  if (!std::isfinite(code)) return std::nullopt;
  const double scaled = std::round(code * 100000.0);
  if (std::abs(code * 100000.0 - scaled) > 1e-3) return std::nullopt;
  for (const auto& [t, c] : kFileGeneration)
    if (std::round(c * 100000.0) == scaled) return t;
  return std::nullopt;
}

std::string format_ies_number(double value) {
  GONIO_CHECK_MSG(std::isfinite(value), "format_ies_number needs a finite number");
  if (value == 0.0) return "0";
  // 15 significant digits, d.dddddddddddddde±XX, then laid out by hand.
  char buf[48];
  const auto [end, ec] =
      std::to_chars(buf, buf + sizeof buf, value, std::chars_format::scientific, 14);
  GONIO_CHECK(ec == std::errc());
  std::string_view s(buf, static_cast<std::size_t>(end - buf));
  const bool negative = s.front() == '-';
  if (negative) s.remove_prefix(1);
  const std::size_t e = s.find('e');
  std::string digits;
  for (char ch : s.substr(0, e))
    if (ch != '.') digits.push_back(ch);
  int exponent = 0;
  std::from_chars(s.data() + e + (s[e + 1] == '+' ? 2 : 1), s.data() + s.size(), exponent);
  while (digits.size() > 1 && digits.back() == '0') digits.pop_back();

  std::string out = negative ? "-" : "";
  if (exponent < -10 || exponent >= 16) {
    out += digits.substr(0, 1);
    if (digits.size() > 1) out += "." + digits.substr(1);
    out += "e" + std::to_string(exponent);
  } else if (exponent >= 0) {
    const auto int_digits = static_cast<std::size_t>(exponent) + 1;
    if (digits.size() <= int_digits) {
      out += digits + std::string(int_digits - digits.size(), '0');
    } else {
      out += digits.substr(0, int_digits) + "." + digits.substr(int_digits);
    }
  } else {
    out += "0." + std::string(static_cast<std::size_t>(-exponent - 1), '0') + digits;
  }
  return out;
}

}  // namespace gonio::io
