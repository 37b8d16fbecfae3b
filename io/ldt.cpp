#include "io/ldt.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <concepts>
#include <optional>
#include <utility>

#include "io/file_io.h"
#include "io/text.h"
#include "photometry/direct_ratios.h"
#include "photometry/flux.h"

namespace gonio::io {
namespace {

using photometry::Distribution;
using photometry::LampSet;
using photometry::OpeningShape;
using photometry::Symmetry;

constexpr double kAngleTol = 1e-6;  // [deg] two C angles closer than this are one angle
constexpr double kFluxTol = 1e-12;  // relative: planes this close are copies of each other

// Standard field lengths [characters].
constexpr std::size_t kTextChars = 78;
// Field 11 has 8 characters: a DOS file name. Files name it with its
// extension ("BD0150.ldt"), so the 8.3 form, 12 characters, is allowed.
constexpr std::size_t kFileNameChars = 12;
constexpr std::size_t kLampTypeChars = 24;
constexpr std::size_t kColorChars = 16;
constexpr std::size_t kColorRenderingChars = 6;

std::string_view trim(std::string_view s) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; };
  while (!s.empty() && blank(s.front())) s.remove_prefix(1);
  while (!s.empty() && blank(s.back())) s.remove_suffix(1);
  return s;
}

std::size_t utf8_chars(std::string_view s) {
  std::size_t n = 0;
  for (char c : s) n += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  return n;
}

// A token as messages show it: quoted, printable, at most 40 characters.
std::string shown(std::string_view token) {
  std::string out = "'";
  std::size_t n = 0;
  for (char c : token) {
    if (++n > 40) {
      out += "...";
      break;
    }
    const auto u = static_cast<unsigned char>(c);
    out += (u < 0x20 || u == 0x7F) ? '?' : c;
  }
  return out + "'";
}

std::string deg(double a) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", a);
  return buf;
}

double mirror_c90_c270(double c) {
  double m = 180.0 - c;
  if (m < 0.0) m += 360.0;
  return m;
}

// 0-based indices into the C list of the planes field 30 stores, in file
// order; empty if Mc does not suit Isym.
std::vector<std::size_t> stored_plane_indices(int isym, std::size_t mc, LdtIsym3Order order) {
  std::vector<std::size_t> idx;
  const auto range = [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i <= last; ++i) idx.push_back(i % mc);
  };
  switch (isym) {
    case 0: range(0, mc - 1); break;
    case 1: idx.push_back(0); break;
    case 2:
      if (mc >= 2 && mc % 2 == 0) range(0, mc / 2);
      break;
    case 3:
      if (mc >= 4 && mc % 4 == 0) {
        if (order == LdtIsym3Order::C270_C0_C90)
          range(3 * mc / 4, 3 * mc / 4 + mc / 2);
        else
          range(mc / 4, 3 * mc / 4);
      }
      break;
    case 4:
      if (mc >= 4 && mc % 4 == 0) range(0, mc / 4);
      break;
    default: break;
  }
  return idx;
}

// The C angles Isym needs at fixed indices of the C list: (index, angle).
std::vector<std::pair<std::size_t, double>> anchor_planes(int isym, std::size_t mc) {
  switch (isym) {
    case 2: return {{0, 0.0}, {mc / 2, 180.0}};
    case 3: return {{0, 0.0}, {mc / 4, 90.0}, {mc / 2, 180.0}, {3 * mc / 4, 270.0}};
    case 4: return {{0, 0.0}, {mc / 4, 90.0}};
    default: return {};
  }
}

const char* isym_name(int isym) {
  switch (isym) {
    case 0: return "no symmetry";
    case 1: return "symmetry about the vertical axis";
    case 2: return "symmetry to the C0-C180 plane";
    case 3: return "symmetry to the C90-C270 plane";
    case 4: return "symmetry to the C0-C180 and C90-C270 planes";
    default: return "?";
  }
}

// ---------------------------------------------------------------- reading

class FieldReader {
 public:
  FieldReader(std::vector<TextLine> lines, const std::string& name)
      : lines_(std::move(lines)), name_(name) {}

  // The 1-based number of the line the next field is read from.
  int line() const {
    if (next_ < lines_.size()) return lines_[next_].number;
    return lines_.empty() ? 1 : lines_.back().number + 1;
  }
  std::size_t remaining() const { return lines_.size() - next_; }
  const Error& error() const { return error_; }
  std::vector<Finding>& findings() { return findings_; }

  void note(Severity severity, std::string code, std::string message, int line) {
    findings_.push_back({severity, std::move(code), std::move(message), SourceLoc{name_, line, 0}});
  }

  bool fail(int line, std::string message) {
    error_ = Error{SourceLoc{name_, line, 0}, std::move(message)};
    return false;
  }

  // A text field, trimmed; longer than `max_chars` is a note, not an error.
  bool text(std::string* out, const std::string& what, std::size_t max_chars) {
    const TextLine* l = take(what);
    if (!l) return false;
    *out = std::string(trim(l->text));
    if (utf8_chars(*out) > max_chars)
      note(Severity::Info, "ldt-field-too-long",
           what + " has " + std::to_string(utf8_chars(*out)) +
               " characters; the standard's field holds " + std::to_string(max_chars),
           l->number);
    return true;
  }

  // One number on its own line (decimal comma allowed), within [lo, hi].
  // `what` is a string or, where building it for every value would cost, a
  // function returning it, called only for the message.
  template <class What>
  bool number(double* out, const What& what, double lo = -HUGE_VAL, double hi = HUGE_VAL) {
    const TextLine* l = take(what);
    if (!l) return false;
    const std::string_view token = trim(l->text);
    const std::optional<double> v = parse_number(token, true);
    if (!v || *v < lo || *v > hi) {
      if (token.empty())
        return fail(l->number, "expected " + describe(what) + ", found an empty line");
      return fail(l->number, "expected " + describe(what) + ", found " + shown(token));
    }
    *out = *v;
    return true;
  }

  // A whole number within [lo, hi] ("36", "36.0" and "36,0" alike).
  bool integer(long* out, const std::string& what, long lo, long hi) {
    const int at = line();
    double v = 0.0;
    if (!number(&v, what)) return false;
    if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi))
      return fail(at, "expected " + what + ", found " + shown(trim(lines_[next_ - 1].text)));
    *out = static_cast<long>(v);
    return true;
  }

  // The first line after the data that is not blank, if any.
  const TextLine* first_trailing() const {
    for (std::size_t i = next_; i < lines_.size(); ++i)
      if (!trim(lines_[i].text).empty()) return &lines_[i];
    return nullptr;
  }

 private:
  static std::string describe(std::string_view what) { return std::string(what); }
  template <class F>
  requires std::invocable<const F&>
  static std::string describe(const F& what) { return what(); }

  template <class What>
  const TextLine* take(const What& what) {
    if (next_ >= lines_.size()) {
      fail(line(), "expected " + describe(what) + ", found the end of the file");
      return nullptr;
    }
    return &lines_[next_++];
  }

  std::vector<TextLine> lines_;
  std::size_t next_ = 0;
  std::string name_;
  Error error_;
  std::vector<Finding> findings_;
};

struct RawLampSet {
  long count = 0;
  LampSet set;
  int line = 0;  // of the lamp count
};

}  // namespace

Result<LdtFile> parse_ldt(std::string_view bytes, const std::string& name,
                          const LdtReadOptions& options) {
  const auto fail = [&](int line, std::string message) {
    return Error{SourceLoc{name, line, 0}, std::move(message)};
  };
  if (bytes.empty()) return fail(1, "empty file: expected an EULUMDAT file");
  if (looks_binary(bytes))
    return fail(first_binary_line(bytes), "binary data, not an EULUMDAT (.ldt) text file");
  if (bytes.size() >= 3 && bytes.substr(0, 3) == "\xEF\xBB\xBF") bytes.remove_prefix(3);

  std::size_t line_count = 0;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (bytes[i] == '\n' || (bytes[i] == '\r' && (i + 1 == bytes.size() || bytes[i + 1] != '\n')))
      ++line_count;
  }
  if (line_count > kMaxLdtLines)
    return fail(0, "more than " + std::to_string(kMaxLdtLines) +
                       " lines: longer than any EULUMDAT file can be (" +
                       std::to_string(kMaxLdtCPlanes) + " C-planes by " +
                       std::to_string(kMaxLdtGammaAngles) + " gamma angles)");

  const std::string text = decode_text(bytes);
  FieldReader r(split_lines(text), name);
  Distribution d;
  d.type = photometry::PhotometricType::C;

  // 1-12: identification.
  std::string company;
  if (!r.text(&company, "the company identification", kTextChars)) return r.error();
  if (company.rfind("IESNA", 0) == 0 || company.rfind("IES:LM-63", 0) == 0)
    return fail(1, "this is an IES LM-63 file (" + shown(company) + "), not EULUMDAT");

  long ityp = 0, isym = 0, mc = 0, ng = 0;
  double dc = 0.0, dg = 0.0;
  if (!r.integer(&ityp, "the type indicator Ityp (0-3)", 0, 3)) return r.error();
  const int isym_line = r.line();
  if (!r.integer(&isym, "the symmetry indicator Isym (0-4)", 0, 4)) return r.error();
  const int mc_line = r.line();
  if (!r.integer(&mc, "the number of C-planes Mc (1-" + std::to_string(kMaxLdtCPlanes) + ")", 1,
                 kMaxLdtCPlanes))
    return r.error();
  const std::size_t nc = static_cast<std::size_t>(mc);
  const std::vector<std::size_t> stored =
      stored_plane_indices(static_cast<int>(isym), nc, options.isym3_order);
  if (stored.empty()) {
    const char* need = isym == 2 ? "an even Mc" : "an Mc divisible by 4";
    return fail(mc_line, "Isym " + std::to_string(isym) + " (" + isym_name(static_cast<int>(isym)) +
                             ") needs " + need + ", found Mc = " + std::to_string(mc));
  }
  const int dc_line = r.line();
  if (!r.number(&dc, "the distance between C-planes Dc [deg] (0-360)", 0.0, 360.0))
    return r.error();
  if (!r.integer(&ng,
                 "the number of luminous intensities per C-plane Ng (1-" +
                     std::to_string(kMaxLdtGammaAngles) + ")",
                 1, kMaxLdtGammaAngles))
    return r.error();
  const int dg_line = r.line();
  if (!r.number(&dg, "the distance between luminous intensities Dg [deg] (0-180)", 0.0, 180.0))
    return r.error();

  std::string report, lum_name, lum_number, file_name, date_user;
  if (!r.text(&report, "the measurement report number", kTextChars) ||
      !r.text(&lum_name, "the luminaire name", kTextChars) ||
      !r.text(&lum_number, "the luminaire number", kTextChars) ||
      !r.text(&file_name, "the file name", kFileNameChars) ||
      !r.text(&date_user, "the date/user", kTextChars))
    return r.error();

  // 13-25: dimensions and photometric factors.
  double dims[9];
  static const char* const kDimNames[9] = {
      "the length/diameter of the luminaire [mm]",
      "the width of the luminaire [mm] (0 for round)",
      "the height of the luminaire [mm]",
      "the length/diameter of the luminous area [mm]",
      "the width of the luminous area [mm] (0 for round)",
      "the height of the luminous area in the C0-plane [mm]",
      "the height of the luminous area in the C90-plane [mm]",
      "the height of the luminous area in the C180-plane [mm]",
      "the height of the luminous area in the C270-plane [mm]"};
  for (int i = 0; i < 9; ++i)
    if (!r.number(&dims[i], std::string(kDimNames[i]) + " (>= 0)", 0.0)) return r.error();

  double dff = 0.0, lorl = 0.0, cfli = 0.0, tilt = 0.0;
  const int dff_line = r.line();
  if (!r.number(&dff, "the downward flux fraction DFF [%]")) return r.error();
  const int lorl_line = r.line();
  if (!r.number(&lorl, "the light output ratio LORL [%]")) return r.error();
  const int cfli_line = r.line();
  if (!r.number(&cfli, "the conversion factor for luminous intensities (>= 0)", 0.0))
    return r.error();
  if (!r.number(&tilt, "the tilt of the luminaire during measurement [deg] (-180-180)", -180.0,
                180.0))
    return r.error();
  if (dff < 0.0 || dff > 100.0)
    r.note(Severity::Warning, "ldt-dff-range",
           "downward flux fraction " + deg(dff) + " % lies outside 0-100 %", dff_line);
  if (lorl < 0.0 || lorl > 100.0)
    r.note(Severity::Warning, "ldt-lorl-range",
           "light output ratio " + deg(lorl) + " % lies outside 0-100 %", lorl_line);
  if (cfli == 0.0) {
    r.note(Severity::Warning, "ldt-conversion-factor-zero",
           "conversion factor 0 would erase every intensity; read as 1", cfli_line);
    cfli = 1.0;
  } else if (cfli != 1.0) {
    r.note(Severity::Info, "ldt-conversion-factor",
           "conversion factor " + deg(cfli) + " applied to the intensities", cfli_line);
  }

  // 26: lamp sets.
  long nsets = 0;
  if (!r.integer(&nsets, "the number of lamp sets (1-" + std::to_string(kMaxLdtLampSets) + ")", 1,
                 kMaxLdtLampSets))
    return r.error();
  std::vector<RawLampSet> sets(static_cast<std::size_t>(nsets));
  for (std::size_t i = 0; i < sets.size(); ++i) {
    RawLampSet& s = sets[i];
    const std::string k = " of lamp set " + std::to_string(i + 1);
    s.line = r.line();
    if (!r.integer(&s.count,
                   "the number of lamps" + k + " (non-zero; negative for absolute photometry)",
                   -1000000, 1000000))
      return r.error();
    if (s.count == 0)
      return fail(s.line, "expected the number of lamps" + k + " (non-zero), found '0'");
    const int flux_line = r.line() + 1;
    if (!r.text(&s.set.type, "the type of lamps" + k, kLampTypeChars)) return r.error();
    if (!r.number(&s.set.flux_lm, "the total luminous flux" + k + " [lm] (>= 0)", 0.0))
      return r.error();
    if (i == 0 && !(s.set.flux_lm > 0.0))
      return fail(flux_line,
                  std::string("expected the total luminous flux of lamp set 1 [lm] ") +
                      (s.count < 0 ? "(for absolute photometry: the luminaire's flux) " : "") +
                      "(> 0), found 0");
    if (!r.text(&s.set.color, "the colour appearance" + k, kColorChars) ||
        !r.text(&s.set.color_rendering, "the colour rendering" + k, kColorRenderingChars) ||
        !r.number(&s.set.power_w, "the wattage including ballast" + k + " [W] (>= 0)", 0.0))
      return r.error();
    s.set.count = static_cast<int>(std::abs(s.count));
    if (i > 0 && (s.count < 0) != (sets[0].count < 0))
      r.note(Severity::Warning, "ldt-lamp-count-sign",
             "the sign of the lamp count of set " + std::to_string(i + 1) +
                 " differs from set 1, which alone decides absolute photometry",
             s.line);
  }

  // 27: direct ratios.
  d.direct_ratios.resize(10);
  for (int i = 0; i < 10; ++i)
    if (!r.number(&d.direct_ratios[static_cast<std::size_t>(i)],
                  "direct ratio " + std::to_string(i + 1) + " of 10"))
      return r.error();

  // 28-29: angles. Counts are bounded above, and nothing larger than the
  // lines left in the file is reserved.
  const int c_first_line = r.line();
  const std::size_t nv = static_cast<std::size_t>(ng);
  std::vector<double> c_angles;
  c_angles.reserve(std::min(nc, r.remaining()));
  for (std::size_t i = 0; i < nc; ++i) {
    const int at = r.line();
    double c = 0.0;
    const auto what = [&] {
      return "C angle " + std::to_string(i + 1) + " of " + std::to_string(nc) + " [deg] (0-360)";
    };
    if (!r.number(&c, what, 0.0, 360.0)) return r.error();
    if (i > 0 && !(c > c_angles.back()))
      return fail(at, "C angles must increase: " + deg(c) + " follows " + deg(c_angles.back()));
    c_angles.push_back(c);
  }
  std::vector<double> gammas;
  gammas.reserve(std::min(nv, r.remaining()));
  for (std::size_t i = 0; i < nv; ++i) {
    const int at = r.line();
    double g = 0.0;
    const auto what = [&] {
      return "gamma angle " + std::to_string(i + 1) + " of " + std::to_string(nv) +
             " [deg] (0-180)";
    };
    if (!r.number(&g, what, 0.0, 180.0)) return r.error();
    if (i > 0 && !(g > gammas.back()))
      return fail(at, "gamma angles must increase: " + deg(g) + " follows " + deg(gammas.back()));
    gammas.push_back(g);
  }

  // The C list must hold the planes the symmetry refers to.
  for (const auto& [index, angle] : anchor_planes(static_cast<int>(isym), nc)) {
    if (std::abs(c_angles[index] - angle) > kAngleTol)
      return fail(c_first_line + static_cast<int>(index),
                  "Isym " + std::to_string(isym) + " (" + isym_name(static_cast<int>(isym)) +
                      ") with Mc = " + std::to_string(mc) + " needs C angle " +
                      std::to_string(index + 1) + " to be " + deg(angle) + ", found " +
                      deg(c_angles[index]));
  }
  if (isym == 3 && c_angles.back() >= 360.0 - kAngleTol)
    return fail(c_first_line + static_cast<int>(nc) - 1,
                "Isym 3 needs C angles below 360 (C0 and C360 are one plane), found " +
                    deg(c_angles.back()));
  if (isym == 0 && c_angles.front() > kAngleTol)
    r.note(Severity::Warning, "ldt-first-plane-not-c0",
           "the C angles begin at " + deg(c_angles.front()) + ", not at 0", c_first_line);
  if (dc > 0.0) {
    for (std::size_t i = 0; i < nc; ++i)
      if (std::abs(c_angles[i] - c_angles[0] - static_cast<double>(i) * dc) > kAngleTol) {
        r.note(
            Severity::Warning, "ldt-dc-mismatch",
            "Dc = " + deg(dc) + " but C angle " + std::to_string(i + 1) + " is " + deg(c_angles[i]),
            dc_line);
        break;
      }
  }
  if (dg > 0.0) {
    for (std::size_t i = 0; i < nv; ++i)
      if (std::abs(gammas[i] - gammas[0] - static_cast<double>(i) * dg) > kAngleTol) {
        r.note(Severity::Warning, "ldt-dg-mismatch",
               "Dg = " + deg(dg) + " but gamma angle " + std::to_string(i + 1) + " is " +
                   deg(gammas[i]),
               dg_line);
        break;
      }
  }

  // 30: intensities, file order, converted to candela.
  const bool absolute = sets[0].count < 0;
  const double scale = cfli * sets[0].set.flux_lm / 1000.0;  // [cd per cd/klm]
  const std::size_t nstored = stored.size();
  std::vector<double> values;
  values.reserve(std::min(nstored * nv, r.remaining()));
  std::size_t negative = 0;
  int negative_line = 0;
  std::string negative_at;  // where the first negative value lies
  for (std::size_t p = 0; p < nstored; ++p) {
    const double c = c_angles[stored[p]];
    for (std::size_t v = 0; v < nv; ++v) {
      const int at = r.line();
      double x = 0.0;
      const auto what = [&] {
        return "the intensity at C " + deg(c) + ", gamma " + deg(gammas[v]) + " [cd/klm]";
      };
      if (!r.number(&x, what)) return r.error();
      if (x < 0.0) {
        if (negative++ == 0) {
          negative_line = at;
          negative_at = "C " + deg(c) + ", gamma " + deg(gammas[v]);
        }
        x = 0.0;
      }
      values.push_back(x * scale);
    }
  }
  if (negative > 0)
    r.note(Severity::Warning, "ldt-negative-intensity",
           std::to_string(negative) + " negative intensity value(s) read as 0 (the first at " +
               negative_at + ")",
           negative_line);
  if (const TextLine* extra = r.first_trailing())
    r.note(Severity::Warning, "ldt-trailing-lines",
           "lines after the last intensity are ignored, beginning with " + shown(trim(extra->text)),
           extra->number);

  // The model: stored planes in the order the model's symmetry defines.
  d.vertical_deg = gammas;
  switch (isym) {
    case 0:
      if (nc == 1) {
        r.note(Severity::Warning, "ldt-single-plane",
               "Isym 0 (no symmetry) with a single C-plane: read as symmetric about the vertical "
               "axis",
               isym_line);
        d.symmetry = Symmetry::Rotational;
      } else {
        d.symmetry = Symmetry::None;
      }
      d.horizontal_deg = c_angles;
      d.candela = std::move(values);
      break;
    case 1:
      d.symmetry = Symmetry::Rotational;
      d.horizontal_deg = {c_angles[0]};
      d.candela = std::move(values);
      break;
    case 2:
    case 4:
      d.symmetry = isym == 2 ? Symmetry::C0_C180 : Symmetry::Quadrant;
      for (std::size_t i : stored) d.horizontal_deg.push_back(c_angles[i]);
      d.candela = std::move(values);
      break;
    case 3: {
      d.symmetry = Symmetry::C90_C270;
      if (options.isym3_order == LdtIsym3Order::C90_C180_C270) {
        for (std::size_t i : stored) d.horizontal_deg.push_back(c_angles[i]);
        d.candela = std::move(values);
      } else {
        // Stored C270 … C0 … C90 hold the model's planes 270 … 180 … 90.
        d.candela.reserve(values.size());
        for (std::size_t p = nstored; p-- > 0;) {
          d.horizontal_deg.push_back(mirror_c90_c270(c_angles[stored[p]]));
          d.candela.insert(d.candela.end(), values.begin() + static_cast<std::ptrdiff_t>(p * nv),
                           values.begin() + static_cast<std::ptrdiff_t>((p + 1) * nv));
        }
      }
      break;
    }
    default: break;
  }

  if ((ityp == 1) != (isym == 1) || (ityp == 0 && isym != 0))
    r.note(Severity::Warning, "ldt-ityp-isym-mismatch",
           "type indicator Ityp " + std::to_string(ityp) + " does not fit Isym " +
               std::to_string(isym) + " (" + isym_name(static_cast<int>(isym)) + ")",
           isym_line);
  d.ldt_type_indicator = static_cast<int>(ityp);

  // Lamps.
  d.absolute = absolute;
  for (std::size_t i = 0; i < sets.size(); ++i) {
    LampSet s = sets[i].set;
    if (i == 0) {
      if (absolute) s.flux_lm = photometry::kNaN;
      d.lamps.push_back(std::move(s));
    } else {
      d.alternative_lamps.push_back(std::move(s));
    }
  }
  d.input_watts = sets[0].set.power_w;

  // Geometry.
  d.luminaire = {dims[0] / 1000.0, dims[1] / 1000.0, dims[2] / 1000.0};
  auto& o = d.opening;
  o.length_m = dims[3] / 1000.0;
  o.width_m = dims[4] / 1000.0;
  double height = 0.0;
  for (int i = 0; i < 4; ++i) {
    o.side_height_m[i] = dims[5 + i] / 1000.0;
    height = std::max(height, o.side_height_m[i]);
  }
  o.height_m = height;
  if (o.length_m == 0.0 && o.width_m == 0.0) {
    o.shape = OpeningShape::Point;
  } else if (o.width_m == 0.0) {
    o.width_m = o.length_m;
    o.shape = height > 0.0 ? OpeningShape::VerticalCylinder : OpeningShape::Circular;
  } else {
    o.shape = height > 0.0 ? OpeningShape::RectangularWithSides : OpeningShape::Rectangular;
  }
  d.declared_dff_percent = dff;
  d.declared_lor_percent = lorl;
  d.measurement_tilt_deg = tilt;

  // Header strings, in the order LM-63 lists its keywords.
  const std::pair<const char*, const std::string*> keys[] = {
      {"TEST", &report},        {"MANUFAC", &company},     {"LUMCAT", &lum_number},
      {"LUMINAIRE", &lum_name}, {"ISSUEDATE", &date_user}, {kLdtFileNameKeyword, &file_name}};
  for (const auto& [key, value] : keys)
    if (!value->empty()) d.keywords.push_back({key, *value});

  if (Status s = photometry::validate(d); !s.ok())
    return fail(0, "inconsistent EULUMDAT data: " + s.error().message);
  return LdtFile{std::move(d), std::move(r.findings())};
}

Result<LdtFile> read_ldt(const std::string& path, const LdtReadOptions& options) {
  Result<std::string> bytes = read_file(path, kMaxLdtBytes);
  if (!bytes.ok()) return bytes.error();
  return parse_ldt(bytes.value(), path, options);
}

// ---------------------------------------------------------------- writing

namespace {

// Plain decimal notation rounded to `digits` significant digits, trailing
// zeros dropped: "2200", "0.68625", "-3.5".
std::string format_number(double x, int digits) {
  if (x == 0.0 || !std::isfinite(x)) return "0";
  const int exponent = static_cast<int>(std::floor(std::log10(std::abs(x))));
  const int decimals = std::clamp(digits - 1 - exponent, 0, 60);
  char buf[512];
  const auto res = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::fixed, decimals);
  std::string s(buf, res.ptr);
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  // Beyond 1e63 (only hostile files hold such values; found by
  // tests/fuzz/ldt_fuzzer.cpp) the digits would pass the 64 characters a
  // number may have (io/text.h parse_number): exponent form instead.
  if (s.size() > 64) {
    const auto sci = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific,
                                   std::clamp(digits - 1, 0, 16));
    s.assign(buf, sci.ptr);
  }
  return s;
}

class LdtWriter {
 public:
  LdtWriter(const LdtWriteOptions& options, std::vector<Finding>* warnings)
      : options_(options), warnings_(warnings) {}

  void warn(Severity severity, std::string code, std::string message) {
    if (warnings_) warnings_->push_back({severity, std::move(code), std::move(message), {}});
  }

  void line(std::string_view latin1) {
    out_.append(latin1);
    out_ += "\r\n";
  }
  void number(double x) { line(format_number(x, options_.significant_digits)); }
  void integer(long long n) { line(std::to_string(n)); }

  // A text field: one line, Latin-1, at most `max_chars`.
  void text(std::string_view utf8, std::size_t max_chars, const std::string& what) {
    std::string value(utf8);
    if (value.find_first_of("\r\n") != std::string::npos) {
      for (char& c : value)
        if (c == '\r' || c == '\n') c = ' ';
      warn(Severity::Warning, "ldt-multiline",
           what + " spans several lines; written as one, line breaks replaced by spaces");
    }
    // Other control characters would make a reader take the file for binary
    // data (found by tests/fuzz/ldt_fuzzer.cpp).
    bool control = false;
    for (char& c : value) {
      if (static_cast<unsigned char>(c) < 0x20 && c != '\t') {
        c = ' ';
        control = true;
      }
    }
    if (control)
      warn(Severity::Warning, "ldt-control-characters",
           what + " holds control characters; written as spaces");
    std::string latin1 = utf8_to_latin1(value);
    if (is_valid_utf8(value) && latin1_to_utf8(latin1) != value)
      warn(Severity::Warning, "ldt-not-latin1",
           what + " has characters outside Latin-1, written as '?'");
    if (latin1.size() > max_chars) {
      warn(Severity::Warning, "ldt-truncated",
           what + " truncated to the standard's " + std::to_string(max_chars) +
               " characters: " + shown(latin1_to_utf8(latin1)));
      latin1.resize(max_chars);
    }
    line(latin1);
  }

  std::string take() { return std::move(out_); }
  const LdtWriteOptions& options() const { return options_; }

 private:
  LdtWriteOptions options_;
  std::vector<Finding>* warnings_;
  std::string out_;
};

// How the model's planes go into the file: Isym, the complete C list, and for
// each stored plane (in file order) the model row and its C angle in the file.
struct Layout {
  int isym = 0;
  std::vector<double> c_list;
  std::vector<std::size_t> rows;
  std::vector<double> file_angles;
};

std::vector<double> unique_sorted(std::vector<double> angles) {
  for (double& a : angles) {
    a = std::fmod(a, 360.0);
    if (a < 0.0) a += 360.0;
    if (a > 360.0 - kAngleTol) a = 0.0;
  }
  std::sort(angles.begin(), angles.end());
  std::vector<double> out;
  for (double a : angles)
    if (out.empty() || a - out.back() > kAngleTol) out.push_back(a);
  return out;
}

// Whether the layout reads back as written: the stored planes sit at the
// indices Isym implies.
bool consistent(const Layout& l, LdtIsym3Order order) {
  const std::vector<std::size_t> idx = stored_plane_indices(l.isym, l.c_list.size(), order);
  if (idx.size() != l.rows.size()) return false;
  for (std::size_t k = 0; k < idx.size(); ++k)
    if (std::abs(l.c_list[idx[k]] - l.file_angles[k]) > kAngleTol) return false;
  for (const auto& [index, angle] : anchor_planes(l.isym, l.c_list.size()))
    if (std::abs(l.c_list[index] - angle) > kAngleTol) return false;
  return true;
}

Layout layout_for(const Distribution& d, LdtIsym3Order order) {
  const auto& h = d.horizontal_deg;
  const std::size_t n = h.size();
  Layout l;
  std::vector<double> all;
  switch (d.symmetry) {
    case Symmetry::Rotational:
      l.isym = 1;
      l.c_list = {0.0};
      l.rows = {0};
      l.file_angles = {0.0};
      return l;
    case Symmetry::C0_C180:
      l.isym = 2;
      for (double c : h) all.insert(all.end(), {c, 360.0 - c});
      break;
    case Symmetry::Quadrant:
      l.isym = 4;
      for (double c : h) all.insert(all.end(), {c, 180.0 - c, 180.0 + c, 360.0 - c});
      break;
    case Symmetry::C90_C270:
      l.isym = 3;
      for (double c : h) all.insert(all.end(), {c, mirror_c90_c270(c)});
      l.c_list = unique_sorted(all);
      if (order == LdtIsym3Order::C90_C180_C270) {
        for (std::size_t j = 0; j < n; ++j) {
          l.rows.push_back(j);
          l.file_angles.push_back(h[j]);
        }
      } else {
        for (std::size_t j = n; j-- > 0;) {
          l.rows.push_back(j);
          double a = mirror_c90_c270(h[j]);
          if (a > 360.0 - kAngleTol) a = 0.0;
          l.file_angles.push_back(a);
        }
      }
      return l;
    default:  // None
      l.isym = 0;
      for (std::size_t j = 0; j < n; ++j) {
        l.rows.push_back(j);
        l.file_angles.push_back(h[j]);
      }
      l.c_list = h;
      return l;
  }
  l.c_list = unique_sorted(all);
  for (std::size_t j = 0; j < n; ++j) {
    l.rows.push_back(j);
    l.file_angles.push_back(h[j]);
  }
  return l;
}

// Ityp for a model that has none.
int derived_type_indicator(const Distribution& d) {
  return d.symmetry == Symmetry::Rotational ? 1 : 3;
}

// Spacing of an equidistant list, 0 otherwise.
double spacing(const std::vector<double>& a) {
  if (a.size() < 2) return 0.0;
  const double step = a[1] - a[0];
  for (std::size_t i = 1; i < a.size(); ++i)
    if (std::abs(a[i] - a[0] - static_cast<double>(i) * step) > 1e-9) return 0.0;
  return step;
}

}  // namespace

Result<std::string> write_ldt(const Distribution& input, const LdtWriteOptions& options,
                              std::vector<Finding>* warnings) {
  const auto fail = [](std::string message) { return Error{{}, std::move(message)}; };
  if (options.significant_digits < 1 || options.significant_digits > 17)
    return fail("significant digits must lie in 1-17, found " +
                std::to_string(options.significant_digits));
  if (options.type_indicator < -1 || options.type_indicator > 3)
    return fail("the type indicator Ityp must lie in 0-3, found " +
                std::to_string(options.type_indicator));
  if (input.type != photometry::PhotometricType::C)
    return fail(std::string("EULUMDAT holds Type C photometry only; this distribution is Type ") +
                photometry::to_string(input.type) + ": resample it to Type C first");
  if (Status s = photometry::validate(input); !s.ok())
    return fail("cannot write an invalid distribution: " + s.error().message);
  for (std::size_t i = 0; i < input.candela.size(); ++i)
    if (input.candela[i] < 0.0) {
      const std::size_t nv = input.vertical_count();
      return fail("intensity " + deg(input.candela[i]) + " cd at C " +
                  deg(input.horizontal_deg[i / nv]) + ", gamma " + deg(input.vertical_deg[i % nv]) +
                  " is negative; EULUMDAT holds intensities >= 0");
    }
  if (!input.absolute && input.lamps.empty())
    return fail("relative photometry needs a lamp set with a rated flux");

  LdtWriter w(options, warnings);
  Distribution d = input;

  // Plane layout; grids the symmetry indicator cannot express are expanded.
  Layout layout = layout_for(d, options.isym3_order);
  if (!consistent(layout, options.isym3_order)) {
    w.warn(Severity::Warning, "ldt-symmetry-expanded",
           std::string("the C-planes of this ") + photometry::to_string(d.symmetry) +
               " distribution do not fit Isym " + std::to_string(layout.isym) +
               " (it needs 0, 90, 180 and 270 on a grid symmetric about them); written without "
               "symmetry");
    d = photometry::expand_symmetry(d);
    layout = layout_for(d, options.isym3_order);
  }
  if (layout.isym == 0) {
    // C 360 is C 0 again: keep one of them.
    const std::size_t nv = d.vertical_count();
    if (layout.c_list.size() >= 2 && layout.c_list.back() > 360.0 - kAngleTol) {
      if (layout.c_list.front() < kAngleTol) {
        const std::size_t last = layout.rows.back();
        bool same = true;
        for (std::size_t v = 0; v < nv; ++v) {
          const double a = d.at(0, v), b = d.at(last, v);
          same = same && std::abs(a - b) <= kFluxTol * std::max(std::abs(a), std::abs(b));
        }
        if (!same)
          w.warn(Severity::Warning, "ldt-plane-360-dropped",
                 "the C 360 plane differs from C 0 and is not written (EULUMDAT lists C 0 once)");
        layout.c_list.pop_back();
        layout.rows.pop_back();
        layout.file_angles.pop_back();
      } else {
        // No C 0 plane: the 360 plane becomes the first.
        layout.c_list.pop_back();
        layout.c_list.insert(layout.c_list.begin(), 0.0);
        layout.rows.insert(layout.rows.begin(), layout.rows.back());
        layout.rows.pop_back();
        layout.file_angles = layout.c_list;
      }
    }
    if (layout.c_list.size() == 1) {
      layout.isym = 1;  // a single plane left: rotational
    } else if (layout.c_list.front() > kAngleTol) {
      w.warn(
          Severity::Warning, "ldt-first-plane-not-c0",
          "the C-planes begin at " + deg(layout.c_list.front()) + ", not at 0 as EULUMDAT expects");
    }
  }

  // Lamp sets: lamps[] becomes set 1, alternatives follow.
  LampSet first;
  first.count = 1;
  if (!d.lamps.empty()) first = d.lamps[0];
  if (d.lamps.size() > 1) {
    for (std::size_t i = 1; i < d.lamps.size(); ++i) {
      const LampSet& s = d.lamps[i];
      first.count += s.count;
      first.type += " + " + s.type;
      first.flux_lm += s.flux_lm;
      first.power_w += s.power_w;
    }
    w.warn(Severity::Warning, "ldt-lamp-sets-merged",
           std::to_string(d.lamps.size()) +
               " lamp sets that light together are written as one set: EULUMDAT sets are "
               "alternatives");
  }
  // Photometric scale: cd = value × flux / 1000.
  const photometry::ZonalFlux zones(d);
  const double total_flux = zones.total_lm();
  const double down_flux = zones.zone_lm(0.0, 90.0);
  double set1_flux = 0.0;
  if (d.absolute) {
    set1_flux = total_flux;
    if (!(set1_flux > 0.0)) {
      set1_flux = 1000.0;
      w.warn(Severity::Warning, "ldt-no-flux",
             "the distribution emits no flux; written relative to 1000 lm");
    } else {
      w.warn(Severity::Info, "ldt-computed-flux",
             "absolute photometry: luminaire flux " + format_number(set1_flux, 6) +
                 " lm computed from the distribution for lamp set 1");
    }
  } else {
    set1_flux = first.flux_lm;  // the merged sets' flux when several light together
  }
  // The scale uses the flux as the file will state it, so that a reader
  // multiplies by exactly what was divided here. A computed luminaire flux is
  // stated to 6 digits: written values rounded to 12 digits change the
  // integral in its 12th digit, and a coarser flux keeps rewriting stable
  // (the candela do not depend on it).
  const int flux_digits = std::min(options.significant_digits, d.absolute ? 6 : 17);
  set1_flux = parse_number(format_number(set1_flux, flux_digits)).value_or(set1_flux);
  const double scale = set1_flux / 1000.0;  // the reader's conversion factor 1 × Φ / 1000

  // LM-63 fields without an EULUMDAT counterpart.
  if (d.tilt.kind != photometry::Tilt::Kind::None)
    w.warn(Severity::Warning, "ldt-tilt-dropped",
           "TILT data (" + std::to_string(d.tilt.angles_deg.size()) +
               " tilt angles, lamp geometry " + std::to_string(d.tilt.lamp_geometry) +
               ") has no EULUMDAT field and is not written");
  if (d.ballast_factor != 1.0)
    w.warn(Severity::Warning, "ldt-ballast-factor",
           "ballast factor " + format_number(d.ballast_factor, 6) +
               " has no EULUMDAT field and is not written (it was not applied to the intensities)");
  if (d.ballast_lamp_factor != 1.0)
    w.warn(Severity::Warning, "ldt-ballast-factor",
           "ballast-lamp photometric factor " + format_number(d.ballast_lamp_factor, 6) +
               " has no EULUMDAT field and is not written (it was not applied to the intensities)");
  if (d.file_generation != photometry::FileGenerationType::Undefined)
    w.warn(Severity::Warning, "ldt-file-generation",
           std::string("LM-63-2019 file generation type '") +
               photometry::to_string(d.file_generation) + "' has no EULUMDAT field");
  if (std::isfinite(first.power_w) && std::isfinite(d.input_watts) && d.input_watts > 0.0 &&
      std::abs(first.power_w - d.input_watts) > 1e-9 * std::max(first.power_w, d.input_watts))
    w.warn(Severity::Warning, "ldt-input-watts",
           "input watts " + format_number(d.input_watts, 6) +
               " W differ from the lamp set's wattage " + format_number(first.power_w, 6) +
               " W, which EULUMDAT keeps");

  // [LAMP] fills an empty lamp type.
  const photometry::Keyword* lamp_kw = d.find_keyword("LAMP");
  if (first.type.empty() && lamp_kw) first.type = lamp_kw->value;
  if (!std::isfinite(first.power_w)) first.power_w = d.input_watts;
  std::vector<LampSet> sets = {first};
  sets.insert(sets.end(), d.alternative_lamps.begin(), d.alternative_lamps.end());
  if (sets.size() > static_cast<std::size_t>(kMaxLdtLampSets)) {
    w.warn(Severity::Warning, "ldt-too-many-lamp-sets",
           std::to_string(sets.size()) + " lamp sets; only the first " +
               std::to_string(kMaxLdtLampSets) + " are written");
    sets.resize(kMaxLdtLampSets);
  }

  // Header strings from the keywords; the rest are reported.
  struct Slot {
    const char* key;
    std::string value;
    bool set = false;
  };
  Slot slots[] = {{"MANUFAC", {}}, {"TEST", {}},      {"LUMINAIRE", {}},
                  {"LUMCAT", {}},  {"ISSUEDATE", {}}, {kLdtFileNameKeyword, {}}};
  const photometry::Keyword* date_kw = nullptr;
  for (const photometry::Keyword& k : d.keywords) {
    bool used = false, repeated = false;
    for (Slot& s : slots) {
      if (k.key != s.key) continue;
      repeated = s.set;
      if (!s.set) {
        s.value = k.value;
        s.set = used = true;
      }
    }
    if (repeated) {
      w.warn(Severity::Warning, "ldt-keyword-dropped",
             "a repeated keyword [" + k.key +
                 "] is not written: its field holds the first: " + shown(k.value));
      continue;
    }
    if (!used && k.key == "DATE" && !date_kw) {
      date_kw = &k;
      used = true;
    }
    if (!used && k.key == "LAMP" && &k == lamp_kw && first.type == k.value) used = true;
    if (!used)
      w.warn(Severity::Warning, "ldt-keyword-dropped",
             "keyword [" + k.key + "] has no EULUMDAT field and is not written: " + shown(k.value));
  }
  if (date_kw) {
    if (slots[4].set)
      w.warn(Severity::Warning, "ldt-keyword-dropped",
             "keyword [DATE] is not written: the date/user field holds [ISSUEDATE]");
    else
      slots[4].value = date_kw->value;
  }

  int ityp = options.type_indicator;
  if (ityp < 0) ityp = d.ldt_type_indicator.value_or(derived_type_indicator(d));

  // 1-12.
  w.text(slots[0].value, kTextChars, "the company (MANUFAC)");
  w.integer(ityp);
  w.integer(layout.isym);
  w.integer(static_cast<long long>(layout.c_list.size()));
  w.number(spacing(layout.c_list));
  w.integer(static_cast<long long>(d.vertical_count()));
  w.number(spacing(d.vertical_deg));
  w.text(slots[1].value, kTextChars, "the measurement report number (TEST)");
  w.text(slots[2].value, kTextChars, "the luminaire name (LUMINAIRE)");
  w.text(slots[3].value, kTextChars, "the luminaire number (LUMCAT)");
  w.text(slots[5].value, kFileNameChars,
         "the file name (" + std::string(kLdtFileNameKeyword) + ")");
  w.text(slots[4].value, kTextChars, "the date/user (ISSUEDATE)");

  // 13-21: dimensions [mm].
  const auto mm = [&](double m) { w.number(std::isfinite(m) ? m * 1000.0 : 0.0); };
  const auto& lum = d.luminaire;
  if (!std::isfinite(lum.length_m) || !std::isfinite(lum.width_m) || !std::isfinite(lum.height_m))
    w.warn(Severity::Info, "ldt-dimensions-unknown",
           "unknown luminaire dimensions are written as 0");
  mm(lum.length_m);
  mm(lum.width_m);
  mm(lum.height_m);
  const auto& o = d.opening;
  double area_length = o.length_m, area_width = o.width_m;
  bool has_height = false;
  switch (o.shape) {
    case OpeningShape::Point: area_length = area_width = 0.0; break;
    case OpeningShape::Rectangular: break;
    case OpeningShape::RectangularWithSides: has_height = true; break;
    case OpeningShape::Circular: area_width = 0.0; break;
    case OpeningShape::VerticalCylinder:
      area_width = 0.0;
      has_height = true;
      break;
    default:
      area_length = std::max(o.length_m, o.width_m);
      area_width = o.shape == OpeningShape::Sphere ? 0.0 : std::min(o.length_m, o.width_m);
      if (o.shape == OpeningShape::Sphere) area_length = std::max(o.length_m, o.height_m);
      has_height = o.height_m > 0.0;
      w.warn(Severity::Warning, "ldt-opening-approximated",
             std::string("EULUMDAT has no ") + photometry::to_string(o.shape) +
                 " luminous area; written as " + (area_width == 0.0 ? "a circle" : "a rectangle") +
                 " of the same extent");
      break;
  }
  mm(area_length);
  mm(area_width);
  for (int i = 0; i < 4; ++i) {
    const double s = o.side_height_m[i];
    mm(std::isfinite(s) ? s : (has_height ? o.height_m : 0.0));
  }

  // 22-25.
  double dff = d.declared_dff_percent, lorl = d.declared_lor_percent;
  if (!std::isfinite(lorl)) {
    lorl = d.absolute ? 100.0 : 100.0 * total_flux / set1_flux;
    w.warn(Severity::Info, "ldt-computed-lorl",
           "light output ratio " + format_number(lorl, 6) + " % computed from the distribution");
  }
  if (!std::isfinite(dff)) {
    dff = total_flux > 0.0 ? 100.0 * down_flux / total_flux : 0.0;
    w.warn(Severity::Info, "ldt-computed-dff",
           "downward flux fraction " + format_number(dff, 6) + " % computed from the distribution");
  }
  w.number(dff);
  w.number(lorl);
  w.number(1.0);
  w.number(std::isfinite(d.measurement_tilt_deg) ? d.measurement_tilt_deg : 0.0);

  // 26.
  w.integer(static_cast<long long>(sets.size()));
  for (std::size_t i = 0; i < sets.size(); ++i) {
    const LampSet& s = sets[i];
    const std::string k = " of lamp set " + std::to_string(i + 1);
    w.integer(d.absolute ? -static_cast<long long>(s.count) : s.count);
    w.text(s.type, kLampTypeChars, "the lamp type" + k);
    w.number(i == 0 ? set1_flux : (std::isfinite(s.flux_lm) ? s.flux_lm : 0.0));
    w.text(s.color, kColorChars, "the colour" + k);
    w.text(s.color_rendering, kColorRenderingChars, "the colour rendering" + k);
    w.number(std::isfinite(s.power_w) ? s.power_w : 0.0);
  }

  // 27.
  if (d.direct_ratios.size() == 10) {
    for (double x : d.direct_ratios) w.number(x);
  } else {
    const std::string why = d.direct_ratios.empty()
                                ? std::string("unknown")
                                : std::to_string(d.direct_ratios.size()) + " instead of 10";
    w.warn(d.direct_ratios.empty() ? Severity::Info : Severity::Warning, "ldt-direct-ratios",
           "direct ratios " + why +
               ": computed from the distribution with Gonio's room model "
               "(photometry/direct_ratios.h, not CIE 52's tables)");
    for (double x : photometry::direct_ratios(d)) w.number(x);
  }

  // 28-30.
  for (double c : layout.c_list) w.number(c);
  for (double g : d.vertical_deg) w.number(g);
  for (std::size_t row : layout.rows)
    for (std::size_t v = 0; v < d.vertical_count(); ++v) w.number(d.at(row, v) / scale);
  return w.take();
}

}  // namespace gonio::io
