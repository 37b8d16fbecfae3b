#include "io/photometric/ldt.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <concepts>
#include <optional>
#include <utility>

#include "io/support/file_io.h"
#include "io/support/text.h"
#include "photometry/direct_ratios.h"
#include "photometry/error_at.h"
#include "photometry/flux.h"
#include "photometry/format.h"

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

// Whether a first line starts with IES LM-63's format identifier.
bool starts_like_ies(std::string_view line) {
  return line.rfind("IESNA", 0) == 0 || line.rfind("IES:LM-63", 0) == 0;
}

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
  // The next line as it stands in the file, untrimmed ("" at the end).
  std::string_view next_raw() const { return next_ < lines_.size() ? std::string_view(lines_[next_].text) : ""; }
  const Error& error() const { return error_; }
  std::vector<Finding>& findings() { return findings_; }

  void note(Severity severity, std::string code, std::string message, int line) {
    findings_.push_back({severity, std::move(code), std::move(message), SourceLoc{name_, line, 0}});
  }

  bool fail(int line, std::string message) {
    error_ = make_error(name_, line, std::move(message));
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

// Reads an EULUMDAT file by the standard's field groups (numbered 1-30 as
// in the format's description), as the IES reader reads LM-63's: each group
// reads and checks its fields and notes what is odd; model() builds the
// distribution from them.
class LdtReader {
 public:
  LdtReader(std::vector<TextLine> lines, const std::string& name, const LdtReadOptions& options)
      : r_(std::move(lines), name), name_(name), options_(options) {
    d_.type = photometry::PhotometricType::C;
  }

  Result<LdtFile> read() {
    for (Status (LdtReader::*group)() :
         {&LdtReader::identification, &LdtReader::dimensions_and_factors, &LdtReader::lamp_sets,
          &LdtReader::direct_ratios, &LdtReader::angles, &LdtReader::intensities,
          &LdtReader::model})
      if (Status s = (this->*group)(); !s.ok()) return s.error();
    return LdtFile{std::move(d_), std::move(r_.findings())};
  }

 private:
  Error fail(int line, std::string message) const { return make_error(name_, line, std::move(message)); }

  // 1-12: identification, symmetry, the counts and steps of the grid.
  Status identification() {
    // An IES file's first line starts with its format identifier; a company
    // name with those letters after a space is EULUMDAT's (what the writer
    // makes of one).
    if (starts_like_ies(r_.next_raw()))
      return fail(1, "this is an IES LM-63 file (" + shown(std::string(trim(r_.next_raw()))) + "), not EULUMDAT");
    if (!r_.text(&company_, "the company identification", kTextChars)) return r_.error();

    if (!r_.integer(&ityp_, "the type indicator Ityp (0-3)", 0, 3)) return r_.error();
    isym_line_ = r_.line();
    if (!r_.integer(&isym_, "the symmetry indicator Isym (0-4)", 0, 4)) return r_.error();
    mc_line_ = r_.line();
    if (!r_.integer(&mc_, "the number of C-planes Mc (1-" + std::to_string(kMaxLdtCPlanes) + ")", 1,
                    kMaxLdtCPlanes))
      return r_.error();
    nc_ = static_cast<std::size_t>(mc_);
    stored_ = stored_plane_indices(static_cast<int>(isym_), nc_, options_.isym3_order);
    if (stored_.empty()) {
      const char* need = isym_ == 2 ? "an even Mc" : "an Mc divisible by 4";
      return fail(mc_line_, "Isym " + std::to_string(isym_) + " (" +
                                isym_name(static_cast<int>(isym_)) + ") needs " + need +
                                ", found Mc = " + std::to_string(mc_));
    }
    dc_line_ = r_.line();
    if (!r_.number(&dc_, "the distance between C-planes Dc [deg] (0-360)", 0.0, 360.0))
      return r_.error();
    if (!r_.integer(&ng_,
                    "the number of luminous intensities per C-plane Ng (1-" +
                        std::to_string(kMaxLdtGammaAngles) + ")",
                    1, kMaxLdtGammaAngles))
      return r_.error();
    dg_line_ = r_.line();
    if (!r_.number(&dg_, "the distance between luminous intensities Dg [deg] (0-180)", 0.0, 180.0))
      return r_.error();

    if (!r_.text(&report_, "the measurement report number", kTextChars) ||
        !r_.text(&lum_name_, "the luminaire name", kTextChars) ||
        !r_.text(&lum_number_, "the luminaire number", kTextChars) ||
        !r_.text(&file_name_, "the file name", kFileNameChars) ||
        !r_.text(&date_user_, "the date/user", kTextChars))
      return r_.error();
    return Ok{};
  }

  // 13-25: dimensions and photometric factors.
  Status dimensions_and_factors() {
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
      if (!r_.number(&dims_[i], std::string(kDimNames[i]) + " (>= 0)", 0.0)) return r_.error();

    const int dff_line = r_.line();
    if (!r_.number(&dff_, "the downward flux fraction DFF [%]")) return r_.error();
    const int lorl_line = r_.line();
    if (!r_.number(&lorl_, "the light output ratio LORL [%]")) return r_.error();
    const int cfli_line = r_.line();
    if (!r_.number(&cfli_, "the conversion factor for luminous intensities (>= 0)", 0.0))
      return r_.error();
    if (!r_.number(&tilt_, "the tilt of the luminaire during measurement [deg] (-180-180)", -180.0,
                   180.0))
      return r_.error();
    if (dff_ < 0.0 || dff_ > 100.0)
      r_.note(Severity::Warning, "ldt-dff-range",
              "downward flux fraction " + format_number(dff_) + " % lies outside 0-100 %",
              dff_line);
    if (lorl_ < 0.0 || lorl_ > 100.0)
      r_.note(Severity::Warning, "ldt-lorl-range",
              "light output ratio " + format_number(lorl_) + " % lies outside 0-100 %", lorl_line);
    if (cfli_ == 0.0) {
      r_.note(Severity::Warning, "ldt-conversion-factor-zero",
              "conversion factor 0 would erase every intensity; read as 1", cfli_line);
      cfli_ = 1.0;
    } else if (cfli_ != 1.0) {
      r_.note(Severity::Info, "ldt-conversion-factor",
              "conversion factor " + format_number(cfli_) + " applied to the intensities",
              cfli_line);
    }
    return Ok{};
  }

  // 26: lamp sets.
  Status lamp_sets() {
    long nsets = 0;
    if (!r_.integer(&nsets, "the number of lamp sets (1-" + std::to_string(kMaxLdtLampSets) + ")",
                    1, kMaxLdtLampSets))
      return r_.error();
    sets_.resize(static_cast<std::size_t>(nsets));
    for (std::size_t i = 0; i < sets_.size(); ++i) {
      RawLampSet& s = sets_[i];
      const std::string k = " of lamp set " + std::to_string(i + 1);
      s.line = r_.line();
      if (!r_.integer(&s.count,
                      "the number of lamps" + k + " (non-zero; negative for absolute photometry)",
                      -1000000, 1000000))
        return r_.error();
      if (s.count == 0)
        return fail(s.line, "expected the number of lamps" + k + " (non-zero), found '0'");
      const int flux_line = r_.line() + 1;
      if (!r_.text(&s.set.type, "the type of lamps" + k, kLampTypeChars)) return r_.error();
      if (!r_.number(&s.set.flux_lm, "the total luminous flux" + k + " [lm] (>= 0)", 0.0))
        return r_.error();
      if (i == 0 && !(s.set.flux_lm > 0.0))
        return fail(flux_line,
                    std::string("expected the total luminous flux of lamp set 1 [lm] ") +
                        (s.count < 0 ? "(for absolute photometry: the luminaire's flux) " : "") +
                        "(> 0), found 0");
      if (!r_.text(&s.set.color, "the colour appearance" + k, kColorChars) ||
          !r_.text(&s.set.color_rendering, "the colour rendering" + k, kColorRenderingChars) ||
          !r_.number(&s.set.power_w, "the wattage including ballast" + k + " [W] (>= 0)", 0.0))
        return r_.error();
      s.set.count = static_cast<int>(std::abs(s.count));
      if (i > 0 && (s.count < 0) != (sets_[0].count < 0))
        r_.note(Severity::Warning, "ldt-lamp-count-sign",
                "the sign of the lamp count of set " + std::to_string(i + 1) +
                    " differs from set 1, which alone decides absolute photometry",
                s.line);
    }
    return Ok{};
  }

  // 27: direct ratios.
  Status direct_ratios() {
    d_.direct_ratios.resize(10);
    for (int i = 0; i < 10; ++i)
      if (!r_.number(&d_.direct_ratios[static_cast<std::size_t>(i)],
                     "direct ratio " + std::to_string(i + 1) + " of 10"))
        return r_.error();
    return Ok{};
  }

  // 28-29: C and gamma angles, and the planes the symmetry refers to. Counts
  // are bounded above, and nothing larger than the lines left in the file is
  // reserved.
  Status angles() {
    const int c_first_line = r_.line();
    nv_ = static_cast<std::size_t>(ng_);
    c_angles_.reserve(std::min(nc_, r_.remaining()));
    for (std::size_t i = 0; i < nc_; ++i) {
      const int at = r_.line();
      double c = 0.0;
      const auto what = [&] {
        return "C angle " + std::to_string(i + 1) + " of " + std::to_string(nc_) + " [deg] (0-360)";
      };
      if (!r_.number(&c, what, 0.0, 360.0)) return r_.error();
      if (i > 0 && !(c > c_angles_.back()))
        return fail(at, "C angles must increase: " + format_number(c) + " follows " +
                            format_number(c_angles_.back()));
      c_angles_.push_back(c);
    }
    gammas_.reserve(std::min(nv_, r_.remaining()));
    for (std::size_t i = 0; i < nv_; ++i) {
      const int at = r_.line();
      double g = 0.0;
      const auto what = [&] {
        return "gamma angle " + std::to_string(i + 1) + " of " + std::to_string(nv_) +
               " [deg] (0-180)";
      };
      if (!r_.number(&g, what, 0.0, 180.0)) return r_.error();
      if (i > 0 && !(g > gammas_.back()))
        return fail(at, "gamma angles must increase: " + format_number(g) + " follows " +
                            format_number(gammas_.back()));
      gammas_.push_back(g);
    }

    // The C list must hold the planes the symmetry refers to.
    for (const auto& [index, angle] : anchor_planes(static_cast<int>(isym_), nc_)) {
      if (std::abs(c_angles_[index] - angle) > kAngleTol)
        return fail(c_first_line + static_cast<int>(index),
                    "Isym " + std::to_string(isym_) + " (" + isym_name(static_cast<int>(isym_)) +
                        ") with Mc = " + std::to_string(mc_) + " needs C angle " +
                        std::to_string(index + 1) + " to be " + format_number(angle) + ", found " +
                        format_number(c_angles_[index]));
    }
    if (isym_ == 3 && c_angles_.back() >= 360.0 - kAngleTol)
      return fail(c_first_line + static_cast<int>(nc_) - 1,
                  "Isym 3 needs C angles below 360 (C0 and C360 are one plane), found " +
                      format_number(c_angles_.back()));
    if (isym_ == 0 && c_angles_.front() > kAngleTol)
      r_.note(Severity::Warning, "ldt-first-plane-not-c0",
              "the C angles begin at " + format_number(c_angles_.front()) + ", not at 0",
              c_first_line);
    if (dc_ > 0.0) {
      for (std::size_t i = 0; i < nc_; ++i)
        if (std::abs(c_angles_[i] - c_angles_[0] - static_cast<double>(i) * dc_) > kAngleTol) {
          r_.note(Severity::Warning, "ldt-dc-mismatch",
                  "Dc = " + format_number(dc_) + " but C angle " + std::to_string(i + 1) + " is " +
                      format_number(c_angles_[i]),
                  dc_line_);
          break;
        }
    }
    if (dg_ > 0.0) {
      for (std::size_t i = 0; i < nv_; ++i)
        if (std::abs(gammas_[i] - gammas_[0] - static_cast<double>(i) * dg_) > kAngleTol) {
          r_.note(Severity::Warning, "ldt-dg-mismatch",
                  "Dg = " + format_number(dg_) + " but gamma angle " + std::to_string(i + 1) +
                      " is " + format_number(gammas_[i]),
                  dg_line_);
          break;
        }
    }
    return Ok{};
  }

  // 30: intensities, file order, converted to candela.
  Status intensities() {
    const double scale = cfli_ * sets_[0].set.flux_lm / 1000.0;  // [cd per cd/klm]
    const std::size_t nstored = stored_.size();
    values_.reserve(std::min(nstored * nv_, r_.remaining()));
    std::size_t negative = 0;
    int negative_line = 0;
    std::string negative_at;  // where the first negative value lies
    for (std::size_t p = 0; p < nstored; ++p) {
      const double c = c_angles_[stored_[p]];
      for (std::size_t v = 0; v < nv_; ++v) {
        const int at = r_.line();
        double x = 0.0;
        const auto what = [&] {
          return "the intensity at C " + format_number(c) + ", gamma " + format_number(gammas_[v]) +
                 " [cd/klm]";
        };
        if (!r_.number(&x, what)) return r_.error();
        if (x < 0.0) {
          if (negative++ == 0) {
            negative_line = at;
            negative_at = "C " + format_number(c) + ", gamma " + format_number(gammas_[v]);
          }
          x = 0.0;
        }
        values_.push_back(x * scale);
      }
    }
    if (negative > 0)
      r_.note(Severity::Warning, "ldt-negative-intensity",
              std::to_string(negative) + " negative intensity value(s) read as 0 (the first at " +
                  negative_at + ")",
              negative_line);
    if (const TextLine* extra = r_.first_trailing())
      r_.note(
          Severity::Warning, "ldt-trailing-lines",
          "lines after the last intensity are ignored, beginning with " + shown(trim(extra->text)),
          extra->number);
    return Ok{};
  }

  // The model: stored planes in the order the model's symmetry defines,
  // lamps, geometry, header strings; then the whole is validated.
  Status model() {
    const bool absolute = sets_[0].count < 0;
    const std::size_t nstored = stored_.size();
    // The model: stored_ planes in the order the model's symmetry defines.
    d_.vertical_deg = gammas_;
    switch (isym_) {
      case 0:
        if (nc_ == 1) {
          r_.note(
              Severity::Warning, "ldt-single-plane",
              "Isym 0 (no symmetry) with a single C-plane: read as symmetric about the vertical "
              "axis",
              isym_line_);
          d_.symmetry = Symmetry::Rotational;
        } else {
          d_.symmetry = Symmetry::None;
        }
        d_.horizontal_deg = c_angles_;
        d_.candela = std::move(values_);
        break;
      case 1:
        d_.symmetry = Symmetry::Rotational;
        d_.horizontal_deg = {c_angles_[0]};
        d_.candela = std::move(values_);
        break;
      case 2:
      case 4:
        d_.symmetry = isym_ == 2 ? Symmetry::C0_C180 : Symmetry::Quadrant;
        for (std::size_t i : stored_) d_.horizontal_deg.push_back(c_angles_[i]);
        d_.candela = std::move(values_);
        break;
      case 3: {
        d_.symmetry = Symmetry::C90_C270;
        if (options_.isym3_order == LdtIsym3Order::C90_C180_C270) {
          for (std::size_t i : stored_) d_.horizontal_deg.push_back(c_angles_[i]);
          d_.candela = std::move(values_);
        } else {
          // Stored C270 … C0 … C90 hold the model's planes 270 … 180 … 90.
          d_.candela.reserve(values_.size());
          for (std::size_t p = nstored; p-- > 0;) {
            d_.horizontal_deg.push_back(mirror_c90_c270(c_angles_[stored_[p]]));
            d_.candela.insert(d_.candela.end(),
                              values_.begin() + static_cast<std::ptrdiff_t>(p * nv_),
                              values_.begin() + static_cast<std::ptrdiff_t>((p + 1) * nv_));
          }
        }
        break;
      }
      default:
        break;
    }

    if ((ityp_ == 1) != (isym_ == 1) || (ityp_ == 0 && isym_ != 0))
      r_.note(Severity::Warning, "ldt-ityp-isym-mismatch",
              "type indicator Ityp " + std::to_string(ityp_) + " does not fit Isym " +
                  std::to_string(isym_) + " (" + isym_name(static_cast<int>(isym_)) + ")",
              isym_line_);
    d_.ldt_type_indicator = static_cast<int>(ityp_);

    // Lamps.
    d_.absolute = absolute;
    for (std::size_t i = 0; i < sets_.size(); ++i) {
      LampSet s = sets_[i].set;
      if (i == 0) {
        if (absolute) s.flux_lm = photometry::kNaN;
        d_.lamps.push_back(std::move(s));
      } else {
        d_.alternative_lamps.push_back(std::move(s));
      }
    }
    d_.input_watts = sets_[0].set.power_w;

    // Geometry.
    // EULUMDAT's lengths (fields 13 and 16) lie along C90–C270, its widths
    // (14 and 17) along C0–C180; the model's length runs along C0–C180
    // (LM-63's convention), so the two change places. A width of 0: round.
    const double lum_length = dims_[0] / 1000.0, lum_width = dims_[1] / 1000.0;
    d_.luminaire = {lum_width == 0.0 ? lum_length : lum_width, lum_width == 0.0 ? 0.0 : lum_length,
                    dims_[2] / 1000.0};
    auto& o = d_.opening;
    const double area_length = dims_[3] / 1000.0, area_width = dims_[4] / 1000.0;
    o.length_m = area_width;
    o.width_m = area_length;
    double height = 0.0;
    for (int i = 0; i < 4; ++i) {
      o.side_height_m[i] = dims_[5 + i] / 1000.0;
      height = std::max(height, o.side_height_m[i]);
    }
    o.height_m = height;
    if (area_length == 0.0 && area_width == 0.0) {
      o.shape = OpeningShape::Point;
    } else if (area_width == 0.0) {
      o.length_m = o.width_m = area_length;
      o.shape = height > 0.0 ? OpeningShape::VerticalCylinder : OpeningShape::Circular;
    } else {
      o.shape = height > 0.0 ? OpeningShape::RectangularWithSides : OpeningShape::Rectangular;
    }
    d_.declared_dff_percent = dff_;
    d_.declared_lor_percent = lorl_;
    d_.measurement_tilt_deg = tilt_;

    // Header strings, in the order LM-63 lists its keywords.
    const std::pair<const char*, const std::string*> keys[] = {
        {"TEST", &report_},        {"MANUFAC", &company_},     {"LUMCAT", &lum_number_},
        {"LUMINAIRE", &lum_name_}, {"ISSUEDATE", &date_user_}, {kLdtFileNameKeyword, &file_name_}};
    for (const auto& [key, value] : keys)
      if (!value->empty()) d_.keywords.push_back({key, *value});
    if (Status s = photometry::validate(d_); !s.ok())
      return fail(0, "inconsistent EULUMDAT data: " + s.error().message);
    return Ok{};
  }

  FieldReader r_;
  std::string name_;
  LdtReadOptions options_;
  Distribution d_;
  // 1-12
  std::string company_, report_, lum_name_, lum_number_, file_name_, date_user_;
  long ityp_ = 0, isym_ = 0, mc_ = 0, ng_ = 0;
  double dc_ = 0.0, dg_ = 0.0;
  int isym_line_ = 0, mc_line_ = 0, dc_line_ = 0, dg_line_ = 0;
  std::size_t nc_ = 0, nv_ = 0;
  std::vector<std::size_t> stored_;  // the stored planes' indices into the C list
  // 13-25
  double dims_[9] = {};
  double dff_ = 0.0, lorl_ = 0.0, cfli_ = 0.0, tilt_ = 0.0;
  // 26
  std::vector<RawLampSet> sets_;
  // 28-29
  std::vector<double> c_angles_, gammas_;
  // 30
  std::vector<double> values_;  // candela, file order
};

}  // namespace

Result<LdtFile> parse_ldt(std::string_view bytes, const std::string& name,
                          const LdtReadOptions& options) {
  const auto fail = [&](int line, std::string message) { return make_error(name, line, std::move(message)); };
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

  const std::string text = decode_text(bytes);  // the lines are views into it
  return LdtReader(split_lines(text), name, options).read();
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
std::string ldt_number(double x, int digits) {
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
  // number may have (io/support/text.h parse_number): exponent form instead.
  if (s.size() > 64) {
    const auto sci = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific,
                                   std::clamp(digits - 1, 0, 16));
    s.assign(buf, sci.ptr);
  }
  return s;
}

class LdtFieldWriter {
 public:
  LdtFieldWriter(const LdtWriteOptions& options, std::vector<Finding>* warnings)
      : options_(options), warnings_(warnings) {}

  void warn(Severity severity, std::string code, std::string message) {
    if (warnings_) warnings_->push_back({severity, std::move(code), std::move(message), {}});
  }

  void line(std::string_view latin1) {
    out_.append(latin1);
    out_ += "\r\n";
  }
  void number(double x) { line(ldt_number(x, options_.significant_digits)); }
  void integer(long long n) { line(std::to_string(n)); }

  // A text field: one line, Latin-1, at most `max_chars`.
  // The first line (first_line) is written after a space when its bytes
  // would make a reader take the file for something else: an IES file's
  // first line, or Latin-1 "\xEF\xBB\xBF" (a UTF-8 byte order mark, which
  // the reader drops). The reader trims the space: the text reads back the same.
  void text(std::string_view utf8, std::size_t max_chars, const std::string& what,
            bool first_line = false) {
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
    if (first_line && (starts_like_ies(latin1) || latin1.rfind("\xEF\xBB\xBF", 0) == 0))
      latin1.insert(latin1.begin(), ' ');
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

// Writes an EULUMDAT file by the standard's field groups, as the IES writer
// writes LM-63's: first the plan (plane layout, lamp sets and the intensity
// scale, header strings), reporting what EULUMDAT cannot hold; then the
// fields, group by group (1-12, 13-21, 22-25, 26, 27, 28-30).
class LdtWriter {
 public:
  LdtWriter(const Distribution& d, const LdtWriteOptions& options, std::vector<Finding>* warnings)
      : w_(options, warnings), d_(d), options_(options) {}

  std::string write() {
    plan_layout();
    plan_lamps_and_scale();
    report_unwritable_fields();
    plan_lamp_sets();
    plan_header();
    identification();
    dimensions();
    factors();
    lamp_sets();
    direct_ratios();
    angles_and_intensities();
    return w_.take();
  }

 private:
  struct Slot {
    const char* key;
    std::string value;
    bool set = false;
  };

  // The plane layout; grids the symmetry indicator cannot express are
  // expanded.
  void plan_layout() {
    layout_ = layout_for(d_, options_.isym3_order);
    if (!consistent(layout_, options_.isym3_order)) {
      w_.warn(Severity::Warning, "ldt-symmetry-expanded",
              std::string("the C-planes of this ") + photometry::to_string(d_.symmetry) +
                  " distribution do not fit Isym " + std::to_string(layout_.isym) +
                  " (it needs 0, 90, 180 and 270 on a grid symmetric about them); written without "
                  "symmetry");
      d_ = photometry::expand_symmetry(d_);
      layout_ = layout_for(d_, options_.isym3_order);
    }
    if (layout_.isym == 0) {
      // C 360 is C 0 again: keep one of them.
      const std::size_t nv = d_.vertical_count();
      if (layout_.c_list.size() >= 2 && layout_.c_list.back() > 360.0 - kAngleTol) {
        if (layout_.c_list.front() < kAngleTol) {
          const std::size_t last = layout_.rows.back();
          bool same = true;
          for (std::size_t v = 0; v < nv; ++v) {
            const double a = d_.at(0, v), b = d_.at(last, v);
            same = same && std::abs(a - b) <= kFluxTol * std::max(std::abs(a), std::abs(b));
          }
          if (!same)
            w_.warn(
                Severity::Warning, "ldt-plane-360-dropped",
                "the C 360 plane differs from C 0 and is not written (EULUMDAT lists C 0 once)");
          layout_.c_list.pop_back();
          layout_.rows.pop_back();
          layout_.file_angles.pop_back();
        } else {
          // No C 0 plane: the 360 plane becomes the first.
          layout_.c_list.pop_back();
          layout_.c_list.insert(layout_.c_list.begin(), 0.0);
          layout_.rows.insert(layout_.rows.begin(), layout_.rows.back());
          layout_.rows.pop_back();
          layout_.file_angles = layout_.c_list;
        }
      }
      if (layout_.c_list.size() == 1) {
        layout_.isym = 1;  // a single plane left: rotational
      } else if (layout_.c_list.front() > kAngleTol) {
        w_.warn(Severity::Warning, "ldt-first-plane-not-c0",
                "the C-planes begin at " + format_number(layout_.c_list.front()) +
                    ", not at 0 as EULUMDAT expects");
      }
    }
  }

  // Lamp sets: lamps[] becomes set 1, alternatives follow; and the
  // photometric scale: cd = value × flux / 1000.
  void plan_lamps_and_scale() {
    first_.count = 1;
    if (!d_.lamps.empty()) first_ = d_.lamps[0];
    if (d_.lamps.size() > 1) {
      for (std::size_t i = 1; i < d_.lamps.size(); ++i) {
        const LampSet& s = d_.lamps[i];
        first_.count += s.count;
        first_.type += " + " + s.type;
        first_.flux_lm += s.flux_lm;
        first_.power_w += s.power_w;
      }
      w_.warn(Severity::Warning, "ldt-lamp-sets-merged",
              std::to_string(d_.lamps.size()) +
                  " lamp sets that light together are written as one set: EULUMDAT sets are "
                  "alternatives");
    }
    // Photometric scale: cd = value × flux / 1000.
    const photometry::ZonalFlux zones(d_);
    total_flux_ = zones.total_lm();
    down_flux_ = zones.zone_lm(0.0, 90.0);
    if (d_.absolute) {
      set1_flux_ = total_flux_;
      if (!(set1_flux_ > 0.0)) {
        set1_flux_ = 1000.0;
        w_.warn(Severity::Warning, "ldt-no-flux",
                "the distribution emits no flux; written relative to 1000 lm");
      } else {
        w_.warn(Severity::Info, "ldt-computed-flux",
                "absolute photometry: luminaire flux " + ldt_number(set1_flux_, 6) +
                    " lm computed from the distribution for lamp set 1");
      }
    } else {
      set1_flux_ = first_.flux_lm;  // the merged sets' flux when several light together
    }
    // The scale uses the flux as the file will state it, so that a reader
    // multiplies by exactly what was divided here. A computed luminaire flux is
    // stated to 6 digits: written values rounded to 12 digits change the
    // integral in its 12th digit, and a coarser flux keeps rewriting stable
    // (the candela do not depend on it).
    const int flux_digits = std::min(options_.significant_digits, d_.absolute ? 6 : 17);
    set1_flux_ = parse_number(ldt_number(set1_flux_, flux_digits)).value_or(set1_flux_);
    scale_ = set1_flux_ / 1000.0;  // the reader's conversion factor 1 × Φ / 1000
  }

  // LM-63 fields without an EULUMDAT counterpart.
  void report_unwritable_fields() {
    if (d_.tilt.kind != photometry::Tilt::Kind::None)
      w_.warn(Severity::Warning, "ldt-tilt-dropped",
              "TILT data (" + std::to_string(d_.tilt.angles_deg.size()) +
                  " tilt angles, lamp geometry " + std::to_string(d_.tilt.lamp_geometry) +
                  ") has no EULUMDAT field and is not written");
    if (d_.ballast_factor != 1.0)
      w_.warn(
          Severity::Warning, "ldt-ballast-factor",
          "ballast factor " + ldt_number(d_.ballast_factor, 6) +
              " has no EULUMDAT field and is not written (it was not applied to the intensities)");
    if (d_.ballast_lamp_factor != 1.0)
      w_.warn(
          Severity::Warning, "ldt-ballast-factor",
          "ballast-lamp photometric factor " + ldt_number(d_.ballast_lamp_factor, 6) +
              " has no EULUMDAT field and is not written (it was not applied to the intensities)");
    if (d_.file_generation != photometry::FileGenerationType::Undefined)
      w_.warn(Severity::Warning, "ldt-file-generation",
              std::string("LM-63-2019 file generation type '") +
                  photometry::to_string(d_.file_generation) + "' has no EULUMDAT field");
    if (std::isfinite(first_.power_w) && std::isfinite(d_.input_watts) && d_.input_watts > 0.0 &&
        std::abs(first_.power_w - d_.input_watts) > 1e-9 * std::max(first_.power_w, d_.input_watts))
      w_.warn(Severity::Warning, "ldt-input-watts",
              "input watts " + ldt_number(d_.input_watts, 6) +
                  " W differ from the lamp set's wattage " + ldt_number(first_.power_w, 6) +
                  " W, which EULUMDAT keeps");
  }

  // [LAMP] fills an empty lamp type; at most kMaxLdtLampSets sets.
  void plan_lamp_sets() {
    lamp_kw_ = d_.find_keyword("LAMP");
    if (first_.type.empty() && lamp_kw_) first_.type = lamp_kw_->value;
    if (!std::isfinite(first_.power_w)) first_.power_w = d_.input_watts;
    sets_ = {first_};
    sets_.insert(sets_.end(), d_.alternative_lamps.begin(), d_.alternative_lamps.end());
    if (sets_.size() > static_cast<std::size_t>(kMaxLdtLampSets)) {
      w_.warn(Severity::Warning, "ldt-too-many-lamp-sets",
              std::to_string(sets_.size()) + " lamp sets; only the first " +
                  std::to_string(kMaxLdtLampSets) + " are written");
      sets_.resize(kMaxLdtLampSets);
    }
  }

  // Header strings from the keywords (the rest are reported) and Ityp.
  void plan_header() {
    const photometry::Keyword* date_kw = nullptr;
    for (const photometry::Keyword& k : d_.keywords) {
      bool used = false, repeated = false;
      for (Slot& s : slots_) {
        if (k.key != s.key) continue;
        repeated = s.set;
        if (!s.set) {
          s.value = k.value;
          s.set = used = true;
        }
      }
      if (repeated) {
        w_.warn(Severity::Warning, "ldt-keyword-dropped",
                "a repeated keyword [" + k.key +
                    "] is not written: its field holds the first: " + shown(k.value));
        continue;
      }
      if (!used && k.key == "DATE" && !date_kw) {
        date_kw = &k;
        used = true;
      }
      if (!used && k.key == "LAMP" && &k == lamp_kw_ && first_.type == k.value) used = true;
      if (!used)
        w_.warn(
            Severity::Warning, "ldt-keyword-dropped",
            "keyword [" + k.key + "] has no EULUMDAT field and is not written: " + shown(k.value));
    }
    if (date_kw) {
      if (slots_[4].set)
        w_.warn(Severity::Warning, "ldt-keyword-dropped",
                "keyword [DATE] is not written: the date/user field holds [ISSUEDATE]");
      else
        slots_[4].value = date_kw->value;
    }

    ityp_ = options_.type_indicator;
    if (ityp_ < 0) ityp_ = d_.ldt_type_indicator.value_or(derived_type_indicator(d_));
  }

  // 1-12: identification, symmetry, the counts and steps of the grid.
  void identification() {
    w_.text(slots_[0].value, kTextChars, "the company (MANUFAC)", /*first_line=*/true);
    w_.integer(ityp_);
    w_.integer(layout_.isym);
    w_.integer(static_cast<long long>(layout_.c_list.size()));
    w_.number(spacing(layout_.c_list));
    w_.integer(static_cast<long long>(d_.vertical_count()));
    w_.number(spacing(d_.vertical_deg));
    w_.text(slots_[1].value, kTextChars, "the measurement report number (TEST)");
    w_.text(slots_[2].value, kTextChars, "the luminaire name (LUMINAIRE)");
    w_.text(slots_[3].value, kTextChars, "the luminaire number (LUMCAT)");
    w_.text(slots_[5].value, kFileNameChars,
            "the file name (" + std::string(kLdtFileNameKeyword) + ")");
    w_.text(slots_[4].value, kTextChars, "the date/user (ISSUEDATE)");
  }

  // 13-21: dimensions [mm].
  void dimensions() {
    const auto mm = [&](double m) { w_.number(std::isfinite(m) ? m * 1000.0 : 0.0); };
    const auto& lum = d_.luminaire;
    if (!std::isfinite(lum.length_m) || !std::isfinite(lum.width_m) || !std::isfinite(lum.height_m))
      w_.warn(Severity::Info, "ldt-dimensions-unknown",
              "unknown luminaire dimensions are written as 0");
    // EULUMDAT's length lies along C90–C270, the model's along C0–C180 (a
    // round luminaire: the diameter and a width of 0).
    const bool round = std::isfinite(lum.width_m) && lum.width_m == 0.0;
    mm(round ? lum.length_m : lum.width_m);
    mm(round ? 0.0 : lum.length_m);
    mm(lum.height_m);
    const auto& o = d_.opening;
    double area_length = o.width_m, area_width = o.length_m;
    bool has_height = false;
    switch (o.shape) {
      case OpeningShape::Point:
        area_length = area_width = 0.0;
        break;
      case OpeningShape::Rectangular:
        break;
      case OpeningShape::RectangularWithSides:
        has_height = true;
        break;
      case OpeningShape::Circular:
        area_length = std::max(o.length_m, o.width_m);
        area_width = 0.0;
        break;
      case OpeningShape::VerticalCylinder:
        area_length = std::max(o.length_m, o.width_m);
        area_width = 0.0;
        has_height = true;
        break;
      default:
        area_length = std::max(o.length_m, o.width_m);
        area_width = o.shape == OpeningShape::Sphere ? 0.0 : std::min(o.length_m, o.width_m);
        if (o.shape == OpeningShape::Sphere) area_length = std::max(o.length_m, o.height_m);
        has_height = o.height_m > 0.0;
        w_.warn(Severity::Warning, "ldt-opening-approximated",
                std::string("EULUMDAT has no ") + photometry::to_string(o.shape) +
                    " luminous area; written as " +
                    (area_width == 0.0 ? "a circle" : "a rectangle") + " of the same extent");
        break;
    }
    mm(area_length);
    mm(area_width);
    for (int i = 0; i < 4; ++i) {
      const double s = o.side_height_m[i];
      mm(std::isfinite(s) ? s : (has_height ? o.height_m : 0.0));
    }
  }

  // 22-25: DFF, LORL, conversion factor, tilt.
  void factors() {
    double dff = d_.declared_dff_percent, lorl = d_.declared_lor_percent;
    if (!std::isfinite(lorl)) {
      lorl = d_.absolute ? 100.0 : 100.0 * total_flux_ / set1_flux_;
      w_.warn(Severity::Info, "ldt-computed-lorl",
              "light output ratio " + ldt_number(lorl, 6) + " % computed from the distribution");
    }
    if (!std::isfinite(dff)) {
      dff = total_flux_ > 0.0 ? 100.0 * down_flux_ / total_flux_ : 0.0;
      w_.warn(Severity::Info, "ldt-computed-dff",
              "downward flux fraction " + ldt_number(dff, 6) + " % computed from the distribution");
    }
    w_.number(dff);
    w_.number(lorl);
    w_.number(1.0);
    w_.number(std::isfinite(d_.measurement_tilt_deg) ? d_.measurement_tilt_deg : 0.0);
  }

  // 26: lamp sets.
  void lamp_sets() {
    w_.integer(static_cast<long long>(sets_.size()));
    for (std::size_t i = 0; i < sets_.size(); ++i) {
      const LampSet& s = sets_[i];
      const std::string k = " of lamp set " + std::to_string(i + 1);
      w_.integer(d_.absolute ? -static_cast<long long>(s.count) : s.count);
      w_.text(s.type, kLampTypeChars, "the lamp type" + k);
      w_.number(i == 0 ? set1_flux_ : (std::isfinite(s.flux_lm) ? s.flux_lm : 0.0));
      w_.text(s.color, kColorChars, "the colour" + k);
      w_.text(s.color_rendering, kColorRenderingChars, "the colour rendering" + k);
      w_.number(std::isfinite(s.power_w) ? s.power_w : 0.0);
    }
  }

  // 27: direct ratios.
  void direct_ratios() {
    if (d_.direct_ratios.size() == 10) {
      for (double x : d_.direct_ratios) w_.number(x);
    } else {
      const std::string why = d_.direct_ratios.empty()
                                  ? std::string("unknown")
                                  : std::to_string(d_.direct_ratios.size()) + " instead of 10";
      w_.warn(d_.direct_ratios.empty() ? Severity::Info : Severity::Warning, "ldt-direct-ratios",
              "direct ratios " + why +
                  ": computed from the distribution with Gonio's room model "
                  "(photometry/direct_ratios.h, not CIE 52's tables)");
      for (double x : photometry::direct_ratios(d_)) w_.number(x);
    }
  }

  // 28-30: C and gamma angles, intensities [cd/klm].
  void angles_and_intensities() {
    for (double c : layout_.c_list) w_.number(c);
    for (double g : d_.vertical_deg) w_.number(g);
    for (std::size_t row : layout_.rows)
      for (std::size_t v = 0; v < d_.vertical_count(); ++v) w_.number(d_.at(row, v) / scale_);
  }

  LdtFieldWriter w_;
  Distribution d_;  // the input, expanded where its symmetry does not fit
  LdtWriteOptions options_;
  Layout layout_;
  LampSet first_;                                 // set 1: the lamps that light together
  std::vector<LampSet> sets_;                     // as written: set 1, then the alternatives
  double total_flux_ = 0.0, down_flux_ = 0.0;     // [lm]
  double set1_flux_ = 0.0;                        // lamp set 1's flux as the file states it [lm]
  double scale_ = 1.0;                            // [cd per cd/klm]
  const photometry::Keyword* lamp_kw_ = nullptr;  // [LAMP], into d_
  Slot slots_[6] = {{"MANUFAC", {}, false},   {"TEST", {}, false},
                    {"LUMINAIRE", {}, false}, {"LUMCAT", {}, false},
                    {"ISSUEDATE", {}, false}, {kLdtFileNameKeyword, {}, false}};
  int ityp_ = 0;
};

}  // namespace

Result<std::string> write_ldt(const Distribution& input, const LdtWriteOptions& options,
                              std::vector<Finding>* warnings) {
  if (options.significant_digits < 1 || options.significant_digits > 17)
    return make_error("significant digits must lie in 1-17, found " +
                      std::to_string(options.significant_digits));
  if (options.type_indicator < -1 || options.type_indicator > 3)
    return make_error("the type indicator Ityp must lie in 0-3, found " +
                      std::to_string(options.type_indicator));
  if (input.type != photometry::PhotometricType::C)
    return make_error(std::string("EULUMDAT holds Type C photometry only; this distribution is Type ") +
                      photometry::to_string(input.type) + ": resample it to Type C first");
  if (Status s = photometry::validate(input); !s.ok())
    return make_error("cannot write an invalid distribution: " + s.error().message);
  for (std::size_t i = 0; i < input.candela.size(); ++i)
    if (input.candela[i] < 0.0) {
      const std::size_t nv = input.vertical_count();
      return make_error("intensity " + format_number(input.candela[i]) + " cd at C " +
                        format_number(input.horizontal_deg[i / nv]) + ", gamma " +
                        format_number(input.vertical_deg[i % nv]) +
                        " is negative; EULUMDAT holds intensities >= 0");
    }
  if (!input.absolute && input.lamps.empty())
    return make_error("relative photometry needs a lamp set with a rated flux");

  return LdtWriter(input, options, warnings).write();
}

}  // namespace gonio::io
