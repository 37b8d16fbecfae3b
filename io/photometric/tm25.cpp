#include "io/photometric/tm25.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <tuple>

#include "io/support/bytes.h"
#include "io/support/file_io.h"
#include "io/support/text.h"
#include "photometry/format.h"

namespace gonio::io {
namespace {

// TM-25 is little-endian; so are the machines Gonio runs on.
static_assert(std::endian::native == std::endian::little);

constexpr std::int32_t kTm25Version = 2013;
constexpr std::size_t kAdditionalItemNameBytes = 512;
constexpr std::size_t kDateBytes = 28;
// Directions whose length is off 1 by more than this are reported (and
// normalised either way).
constexpr double kUnitTolerance = 1e-3;
constexpr double kRenormalise = 1e-6;
// Header flux against the rays' sum: a warning beyond this relative difference.
constexpr double kFluxTolerance = 0.01;

// UTF-32 code points to UTF-8, up to the first NUL; invalid code points
// (surrogates, beyond U+10FFFF) become '?'.
std::string utf32_to_utf8(std::string_view bytes) {
  std::string out;
  for (std::size_t i = 0; i + 4 <= bytes.size(); i += 4) {
    std::uint32_t c = 0;
    std::memcpy(&c, bytes.data() + i, 4);
    if (c == 0) break;
    if (c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) c = '?';
    if (c < 0x80) {
      out += static_cast<char>(c);
    } else if (c < 0x800) {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
      out += static_cast<char>(0xE0 | (c >> 12));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (c >> 18));
      out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

// UTF-8 to UTF-32 code points (invalid bytes as '?'), at most `max_chars`.
std::vector<std::uint32_t> utf8_to_utf32(std::string_view s, std::size_t max_chars) {
  std::vector<std::uint32_t> out;
  std::size_t i = 0;
  while (i < s.size() && out.size() < max_chars) {
    const auto b = static_cast<unsigned char>(s[i]);
    int len = b < 0x80 ? 1 : (b >> 5) == 0x6 ? 2 : (b >> 4) == 0xE ? 3 : (b >> 3) == 0x1E ? 4 : 0;
    std::uint32_t c = len == 1 ? b : len == 2 ? (b & 0x1Fu) : len == 3 ? (b & 0x0Fu) : (b & 0x07u);
    bool ok = len > 0 && i + static_cast<std::size_t>(len) <= s.size();
    for (int k = 1; ok && k < len; ++k) {
      const auto cb = static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]);
      if ((cb & 0xC0) != 0x80) ok = false;
      c = (c << 6) | (cb & 0x3Fu);
    }
    if (!ok) {
      out.push_back('?');
      ++i;
      continue;
    }
    if (c == 0) break;
    out.push_back(c);
    i += static_cast<std::size_t>(len);
  }
  return out;
}

std::string printable_ascii(std::string_view bytes) {
  std::string out;
  for (char ch : bytes) {
    if (ch == '\0') break;
    out += (ch >= 0x20 && ch < 0x7F) ? ch : '?';
  }
  return out;
}

std::string at_byte(std::size_t offset) { return "byte " + std::to_string(offset) + ": "; }

class Tm25Reader {
 public:
  Tm25Reader(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  Result<Tm25RaySet> read() {
    Tm25RaySet set;
    if (auto s = header(set.header); !s.ok()) return s.error();
    set.columns = tm25_columns(set.header);
    if (auto s = rays(set); !s.ok()) return s.error();
    luminous(set);
    set.findings = std::move(findings_);
    return set;
  }

 private:
  Error error_at(std::size_t offset, const std::string& message) const {
    return make_error(name_, at_byte(offset) + message);
  }
  void warn(std::size_t offset, const char* code, const std::string& message,
            Severity severity = Severity::Warning) {
    findings_.push_back(Finding{severity, code, at_byte(offset) + message, SourceLoc{name_, 0, 0}});
  }
  bool have(std::size_t n) const { return n <= bytes_.size() - pos_; }
  Error truncated(const std::string& what, std::size_t n) const {
    return error_at(pos_, "the file ends inside " + what + " (" + std::to_string(n) + " bytes needed, " +
                              std::to_string(bytes_.size() - pos_) + " left); truncated?");
  }
  template <class T>
  T take() {
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }

  Status flag(const char* what, bool* out) {
    const std::size_t at = pos_;
    const auto v = take<std::int32_t>();
    if (v != 0 && v != 1)
      return error_at(at, std::string("the ") + what + " flag is " + std::to_string(v) + "; it must be 0 or 1");
    *out = v == 1;
    return Ok{};
  }

  Status header(Tm25Header& h) {
    if (!have(kTm25FixedBytes)) {
      if (bytes_.size() >= 4 && bytes_.substr(0, 4) != "TM25")
        return error_at(0, "not a TM-25 ray file: it does not start with 'TM25'");
      return truncated("the fixed header (TM-25-13 4.7.1-4.7.3)", kTm25FixedBytes);
    }
    if (bytes_.substr(0, 4) != "TM25")
      return error_at(0, "not a TM-25 ray file: it starts with " + shown(bytes_.substr(0, 4)) +
                             ", not 'TM25'");
    pos_ = 4;
    h.version = take<std::int32_t>();
    if (h.version != kTm25Version)
      return error_at(4, "file version " + std::to_string(h.version) +
                             "; Gonio reads TM-25-13 files (version 2013)");
    h.creation_method = take<std::int32_t>();
    if (h.creation_method != 0 && h.creation_method != 1)
      warn(8, "tm25-header-value",
           "creation method " + std::to_string(h.creation_method) + " (0 simulation, 1 measurement)");
    h.luminous_flux_lm = take<float>();
    h.radiant_flux_w = take<float>();
    for (const auto& [value, at, what] : {std::tuple{h.luminous_flux_lm, 12, "luminous"},
                                          std::tuple{h.radiant_flux_w, 16, "radiant"}})
      if (!std::isnan(value) && !(value >= 0.0f && std::isfinite(value)))
        return error_at(static_cast<std::size_t>(at), std::string("the total ") + what + " flux is " +
                                                          format_number(static_cast<double>(value)) +
                                                          "; it must be non-negative or NaN (not stated)");
    ray_count_ = take<std::uint64_t>();
    h.created = printable_ascii(bytes_.substr(pos_, kDateBytes));
    pos_ += kDateBytes;
    h.start_position = take<std::int32_t>();
    if (h.start_position < 0 || h.start_position > 7)
      warn(56, "tm25-header-value", "ray start position " + std::to_string(h.start_position) + " (0 to 7)");
    const auto spectrum = take<std::int32_t>();
    if (spectrum < 0 || spectrum > 4)
      return error_at(60, "spectral data identifier " + std::to_string(spectrum) + "; it must be 0 to 4");
    h.spectrum = static_cast<Tm25Spectrum>(spectrum);
    h.wavelength_nm = take<float>();
    if (h.spectrum == Tm25Spectrum::SingleWavelength && !(h.wavelength_nm > 0.0f && std::isfinite(h.wavelength_nm)))
      return error_at(64, "the single wavelength is " + format_number(static_cast<double>(h.wavelength_nm)) +
                              " nm; spectral identifier 1 needs a positive one");
    h.min_wavelength_nm = take<float>();
    h.max_wavelength_nm = take<float>();
    const auto tables = take<std::int32_t>();
    if (tables < 0) return error_at(76, "the number of spectral tables is " + std::to_string(tables));
    if ((h.spectrum == Tm25Spectrum::OneTable || h.spectrum == Tm25Spectrum::TablePerRay) && tables == 0)
      return error_at(76, "spectral identifier " + std::to_string(spectrum) + " needs spectral tables; the file has none");
    const auto additional = take<std::int32_t>();
    if (additional < 0)
      return error_at(80, "the number of additional ray items is " + std::to_string(additional));
    const auto text_bytes = take<std::int32_t>();
    if (text_bytes < 0 || text_bytes % 4 != 0)
      return error_at(84, "the additional text block's size is " + std::to_string(text_bytes) +
                              " bytes; it must be a non-negative multiple of 4");
    if (text_bytes % 32 != 0)
      warn(84, "tm25-header-value",
           "the additional text block's size is " + std::to_string(text_bytes) +
               " bytes, not a multiple of 32 as TM-25 asks (4.7.1.15); read as stated, written padded");
    pos_ = kTm25FileHeaderBytes;

    // 4.7.2
    for (const char* what : {"position", "direction"}) {
      const std::size_t at = pos_;
      if (const auto v = take<std::int32_t>(); v != 1)
        return error_at(at, std::string("the ") + what + " flag is " + std::to_string(v) + "; it must be 1");
    }
    if (auto s = flag("radiant flux", &h.radiant_flux); !s.ok()) return s;
    if (auto s = flag("wavelength", &h.wavelength); !s.ok()) return s;
    if (auto s = flag("luminous flux", &h.luminous_flux); !s.ok()) return s;
    if (auto s = flag("Stokes", &h.stokes); !s.ok()) return s;
    if (auto s = flag("tristimulus", &h.tristimulus); !s.ok()) return s;
    if (auto s = flag("spectrum index", &h.spectrum_index); !s.ok()) return s;
    const std::size_t flags_at = kTm25FileHeaderBytes;
    if (!h.radiant_flux && !h.luminous_flux)
      return error_at(flags_at, "neither radiant nor luminous flux per ray: one of the two flags must be 1");
    if (h.spectrum == Tm25Spectrum::PerRayWavelength && !h.wavelength)
      return error_at(flags_at, "spectral identifier 2 (a wavelength per ray) without the wavelength flag");
    if ((h.spectrum == Tm25Spectrum::PerRayWavelength || h.spectrum == Tm25Spectrum::TablePerRay) &&
        (!h.radiant_flux || h.luminous_flux))
      return error_at(flags_at, "spectral identifier " + std::to_string(spectrum) +
                                    " requires radiant flux and no luminous flux per ray");
    if (h.stokes && !h.radiant_flux)
      return error_at(flags_at, "Stokes parameters without radiant flux per ray");
    if (h.tristimulus && (!h.luminous_flux || h.spectrum != Tm25Spectrum::None))
      return error_at(flags_at, "tristimulus values require luminous flux per ray and spectral identifier 0");
    if (h.spectrum_index != (h.spectrum == Tm25Spectrum::TablePerRay))
      return error_at(flags_at, "the spectrum index flag must be set exactly when the spectral identifier is 4");

    // 4.7.3
    std::string* texts[] = {&h.light_source, &h.manufacturer, &h.model_creator,
                            &h.ray_file_creator, &h.equipment, &h.camera,
                            &h.operation, &h.additional_info, &h.data_reference};
    for (std::string* t : texts) {
      *t = utf32_to_utf8(bytes_.substr(pos_, kTm25TextBytes));
      pos_ += kTm25TextBytes;
    }

    // 4.7.4: each count checked against what is left before anything is kept.
    const std::size_t tables_at = pos_;
    for (std::int32_t t = 0; t < tables; ++t) {
      if (!have(4)) return truncated("spectral table " + std::to_string(t + 1), 4);
      const std::size_t at = pos_;
      const auto pairs = take<std::int32_t>();
      if (pairs <= 0)
        return error_at(at, "spectral table " + std::to_string(t + 1) + " has " + std::to_string(pairs) +
                                " pairs; it needs at least one");
      const std::size_t need = static_cast<std::size_t>(pairs) * 8;
      if (!have(need))
        return error_at(at, "spectral table " + std::to_string(t + 1) + " claims " + std::to_string(pairs) +
                                " pairs (" + std::to_string(need) + " bytes), more than the " +
                                std::to_string(bytes_.size() - pos_) + " bytes left");
      Tm25SpectralTable table;
      table.wavelength_nm.reserve(static_cast<std::size_t>(pairs));
      table.weight.reserve(static_cast<std::size_t>(pairs));
      for (std::int32_t p = 0; p < pairs; ++p) {
        const std::size_t pair_at = pos_;
        const auto wl = take<float>();
        const auto w = take<float>();
        if (!(wl > 0.0f && std::isfinite(wl)) || !(w >= 0.0f && std::isfinite(w)))
          return error_at(pair_at, "spectral table " + std::to_string(t + 1) + ", pair " + std::to_string(p + 1) +
                                       ": wavelength " + format_number(static_cast<double>(wl)) + " nm, weight " + format_number(static_cast<double>(w)) +
                                       " (a positive wavelength and a non-negative weight are required)");
        table.wavelength_nm.push_back(wl);
        table.weight.push_back(w);
      }
      h.spectral_tables.push_back(std::move(table));
    }
    if (const std::size_t used = pos_ - tables_at; used % 32 != 0) {
      const std::size_t pad = 32 - used % 32;
      if (!have(pad)) return truncated("the spectral tables' padding", pad);
      pos_ += pad;
    }

    // 4.7.5 and 4.7.6
    const std::size_t names = static_cast<std::size_t>(additional) * kAdditionalItemNameBytes;
    if (!have(names))
      return error_at(pos_, std::to_string(additional) + " additional ray items' names need " +
                                std::to_string(names) + " bytes; " + std::to_string(bytes_.size() - pos_) + " are left");
    for (std::int32_t a = 0; a < additional; ++a) {
      h.additional_items.push_back(utf32_to_utf8(bytes_.substr(pos_, kAdditionalItemNameBytes)));
      pos_ += kAdditionalItemNameBytes;
    }
    if (!have(static_cast<std::size_t>(text_bytes)))
      return truncated("the additional text block", static_cast<std::size_t>(text_bytes));
    h.additional_text = utf32_to_utf8(bytes_.substr(pos_, static_cast<std::size_t>(text_bytes)));
    pos_ += static_cast<std::size_t>(text_bytes);
    return Ok{};
  }

  Status rays(Tm25RaySet& set) {
    const auto stride = static_cast<std::size_t>(set.columns.count);
    const std::size_t ray_bytes = stride * 4;
    const std::size_t left = bytes_.size() - pos_;
    // The count against the bytes that follow, before any allocation.
    if (ray_count_ > left / ray_bytes)
      return error_at(pos_, "the header (byte 20) declares " + std::to_string(ray_count_) + " rays of " +
                                std::to_string(ray_bytes) + " bytes, but only " + std::to_string(left) +
                                " bytes follow (" + std::to_string(left / ray_bytes) + " rays); truncated?");
    const std::size_t n = static_cast<std::size_t>(ray_count_);
    if (n == 0) warn(20, "tm25-no-rays", "the file holds no rays");
    if (left > n * ray_bytes)
      warn(pos_ + n * ray_bytes, "tm25-trailing-bytes",
           std::to_string(left - n * ray_bytes) + " bytes after the last ray are ignored");
    set.items.resize(n * stride);
    if (n > 0) std::memcpy(set.items.data(), bytes_.data() + pos_, n * ray_bytes);
    const Tm25Columns& c = set.columns;
    std::size_t not_unit = 0, first_not_unit = 0;
    double worst_length = 1.0;
    for (std::size_t i = 0; i < n; ++i) {
      float* r = set.items.data() + i * stride;
      const std::size_t at = pos_ + i * ray_bytes;
      for (std::size_t k = 0; k < stride; ++k)
        if (!std::isfinite(r[k]))
          return error_at(at + 4 * k, "ray " + std::to_string(i + 1) + ", item " + std::to_string(k + 1) + " is " +
                                          format_number(static_cast<double>(r[k])) + ": every ray item must be a finite number");
      for (int col : {c.radiant_flux, c.tri_y})
        if (col >= 0 && r[col] < 0.0f)
          return error_at(at + 4 * static_cast<std::size_t>(col),
                          "ray " + std::to_string(i + 1) + " has a negative flux (" + format_number(static_cast<double>(r[col])) + ")");
      const double kx = static_cast<double>(r[3]), ky = static_cast<double>(r[4]), kz = static_cast<double>(r[5]);
      const double len = std::sqrt(kx * kx + ky * ky + kz * kz);
      if (!(len > 0.0))
        return error_at(at + 12, "ray " + std::to_string(i + 1) + " has a zero direction vector");
      if (std::abs(len - 1.0) > kUnitTolerance) {
        if (not_unit++ == 0) first_not_unit = i;
        if (std::abs(len - 1.0) > std::abs(worst_length - 1.0)) worst_length = len;
      }
      // Normalised where |k| is off 1 by more than float rounding, so that a
      // set read, written and read again keeps its bytes.
      if (std::abs(len - 1.0) > kRenormalise)
        for (int k = 3; k < 6; ++k) r[k] = static_cast<float>(static_cast<double>(r[k]) / len);
      if (c.spectrum_index >= 0) {
        const float idx = r[c.spectrum_index];
        if (idx != std::floor(idx) || idx < 1.0f || idx > static_cast<float>(set.header.spectral_tables.size()))
          return error_at(at + 4 * static_cast<std::size_t>(c.spectrum_index),
                          "ray " + std::to_string(i + 1) + " names spectral table " + format_number(static_cast<double>(idx)) + " of " +
                              std::to_string(set.header.spectral_tables.size()));
      }
    }
    if (not_unit > 0)
      warn(pos_ + first_not_unit * ray_bytes + 12, "tm25-direction-not-unit",
           std::to_string(not_unit) + " ray direction" + (not_unit == 1 ? " is" : "s are") +
               " not unit vectors (first: ray " + std::to_string(first_not_unit + 1) + "; worst length " +
               format_number(worst_length) + "); normalised");
    return Ok{};
  }

  void luminous(Tm25RaySet& set) {
    const Tm25Header& h = set.header;
    const double radiant_sum = set.columns.radiant_flux >= 0 ? set.total_radiant_flux_w() : 0.0;
    const auto compare = [&](double header_value, double sum, std::size_t at, const char* what, const char* unit) {
      if (std::isnan(header_value) || set.ray_count() == 0) return;
      const double scale = std::max(std::abs(header_value), std::abs(sum));
      if (scale > 0.0 && std::abs(header_value - sum) > kFluxTolerance * scale)
        warn(at, "tm25-flux-mismatch",
             std::string("the header's ") + what + " flux " + format_number(header_value) + " " + unit +
                 " differs from the rays' sum " + format_number(sum) + " " + unit + " by " +
                 format_fixed(100.0 * (sum - header_value) / header_value, 2) + " %");
    };
    if (set.columns.radiant_flux >= 0) compare(static_cast<double>(h.radiant_flux_w), radiant_sum, 16, "radiant", "W");
    if (set.columns.tri_y >= 0) {
      compare(static_cast<double>(h.luminous_flux_lm), set.total_luminous_flux_lm(), 12, "luminous", "lm");
      return;
    }
    const bool header_ratio = std::isfinite(h.luminous_flux_lm) && std::isfinite(h.radiant_flux_w) &&
                              h.radiant_flux_w > 0.0f;
    if (!header_ratio) {
      warn(12, "tm25-no-luminous-flux",
           "radiant flux per ray without both header fluxes: the rays' luminous flux is unknown", Severity::Info);
      return;
    }
    set.efficacy_lm_per_w = static_cast<double>(h.luminous_flux_lm) / static_cast<double>(h.radiant_flux_w);
    if (h.spectrum == Tm25Spectrum::PerRayWavelength || h.spectrum == Tm25Spectrum::TablePerRay)
      warn(12, "tm25-luminous-from-header",
           "the rays' spectra differ, but their luminous flux is taken as radiant flux times the header's mean "
           "efficacy " + format_number(set.efficacy_lm_per_w) + " lm/W",
           Severity::Info);
  }

  std::string_view bytes_;
  const std::string& name_;
  std::size_t pos_ = 0;
  std::uint64_t ray_count_ = 0;
  std::vector<Finding> findings_;
};

class Tm25Writer {
 public:
  explicit Tm25Writer(std::string& out) : out_(out) {}
  template <class T>
  void put(T v) {
    append_bytes(out_, v);
  }
  void zeros(std::size_t n) { out_.append(n, '\0'); }
  void text(const std::string& s, std::size_t bytes) {
    const std::vector<std::uint32_t> chars = utf8_to_utf32(s, bytes / 4);
    for (std::uint32_t c : chars) put(c);
    zeros(bytes - chars.size() * 4);
  }

 private:
  std::string& out_;
};

}  // namespace

Tm25Columns tm25_columns(const Tm25Header& h) {
  Tm25Columns c;
  int next = 6;
  if (h.radiant_flux) c.radiant_flux = next++;
  if (h.wavelength) c.wavelength = next++;
  if (h.luminous_flux) c.tri_y = next++;
  if (h.stokes) {
    c.stokes = next;
    next += 6;  // S1 S2 S3 and the polarisation ellipse's reference vector
  }
  if (h.tristimulus) {
    c.tri_x = next++;
    c.tri_z = next++;
  }
  if (h.spectrum_index) c.spectrum_index = next++;
  if (!h.additional_items.empty()) {
    c.additional = next;
    next += static_cast<int>(h.additional_items.size());
  }
  c.count = next;
  return c;
}

double Tm25RaySet::total_luminous_flux_lm() const {
  if (!has_luminous_flux()) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (std::size_t i = 0, n = ray_count(); i < n; ++i) sum += luminous_flux_lm(i);
  return sum;
}

double Tm25RaySet::total_radiant_flux_w() const {
  if (columns.radiant_flux < 0) return std::numeric_limits<double>::quiet_NaN();
  double sum = 0.0;
  for (std::size_t i = 0, n = ray_count(); i < n; ++i) sum += static_cast<double>(ray(i)[columns.radiant_flux]);
  return sum;
}

bool looks_like_tm25(std::string_view bytes) { return bytes.substr(0, 4) == "TM25"; }

Result<Tm25RaySet> parse_tm25(std::string_view bytes, const std::string& name) {
  return Tm25Reader(bytes, name).read();
}

Result<Tm25RaySet> read_tm25_file(const std::string& path) {
  auto bytes = read_file(path, kMaxTm25Bytes);
  if (!bytes.ok()) return bytes.error();
  return parse_tm25(*bytes, path);
}

Result<std::string> write_tm25(const Tm25RaySet& set) {
  const Tm25Header& h = set.header;
  const Tm25Columns expected = tm25_columns(h);
  if (expected.count != set.columns.count || expected.radiant_flux != set.columns.radiant_flux ||
      expected.tri_y != set.columns.tri_y)
    return make_error("TM-25: the ray items' columns do not match the header's flags");
  if (set.items.size() % static_cast<std::size_t>(set.columns.count) != 0)
    return make_error("TM-25: " + std::to_string(set.items.size()) + " ray items are not a whole number of rays of " +
                      std::to_string(set.columns.count));
  std::string out;
  std::size_t table_bytes = 0;
  for (const auto& t : h.spectral_tables) table_bytes += 4 + 8 * t.wavelength_nm.size();
  const std::size_t padded_tables = (table_bytes + 31) / 32 * 32;
  out.reserve(kTm25FixedBytes + padded_tables + h.additional_items.size() * kAdditionalItemNameBytes +
              set.items.size() * 4 + 4 * h.additional_text.size() + 32);
  Tm25Writer w(out);
  out += "TM25";
  w.put<std::int32_t>(kTm25Version);
  w.put<std::int32_t>(h.creation_method);
  w.put<float>(h.luminous_flux_lm);
  w.put<float>(h.radiant_flux_w);
  w.put<std::uint64_t>(set.ray_count());
  const std::string date = printable_ascii(h.created).substr(0, kDateBytes);
  out += date;
  w.zeros(kDateBytes - date.size());
  w.put<std::int32_t>(h.start_position);
  w.put<std::int32_t>(static_cast<std::int32_t>(h.spectrum));
  w.put<float>(h.wavelength_nm);
  w.put<float>(h.min_wavelength_nm);
  w.put<float>(h.max_wavelength_nm);
  w.put<std::int32_t>(static_cast<std::int32_t>(h.spectral_tables.size()));
  w.put<std::int32_t>(static_cast<std::int32_t>(h.additional_items.size()));
  // 4.7.1.15: the additional text block's size is a multiple of 32 bytes
  // (as the spectral tables' block), the text NUL-padded to it.
  const std::vector<std::uint32_t> text = utf8_to_utf32(h.additional_text, 1u << 28);
  const std::size_t text_bytes = (text.size() * 4 + 31) / 32 * 32;
  w.put<std::int32_t>(static_cast<std::int32_t>(text_bytes));
  w.zeros(kTm25FileHeaderBytes - out.size());
  for (bool f : {true, true, h.radiant_flux, h.wavelength, h.luminous_flux, h.stokes, h.tristimulus,
                 h.spectrum_index})
    w.put<std::int32_t>(f ? 1 : 0);
  for (const std::string* t : {&h.light_source, &h.manufacturer, &h.model_creator, &h.ray_file_creator,
                               &h.equipment, &h.camera, &h.operation, &h.additional_info, &h.data_reference})
    w.text(*t, kTm25TextBytes);
  for (const auto& t : h.spectral_tables) {
    w.put<std::int32_t>(static_cast<std::int32_t>(t.wavelength_nm.size()));
    for (std::size_t p = 0; p < t.wavelength_nm.size(); ++p) {
      w.put<float>(t.wavelength_nm[p]);
      w.put<float>(p < t.weight.size() ? t.weight[p] : 0.0f);
    }
  }
  w.zeros(padded_tables - table_bytes);
  for (const std::string& name : h.additional_items) w.text(name, kAdditionalItemNameBytes);
  for (std::uint32_t c : text) w.put(c);
  w.zeros(text_bytes - text.size() * 4);
  const std::size_t ray_start = out.size();
  out.resize(ray_start + set.items.size() * 4);
  if (!set.items.empty()) std::memcpy(out.data() + ray_start, set.items.data(), set.items.size() * 4);
  return out;
}

Status write_tm25_file(const std::string& path, const Tm25RaySet& set) {
  auto bytes = write_tm25(set);
  if (!bytes.ok()) return make_error(path, bytes.error().message);
  return write_file_atomic(path, *bytes);
}

Tm25RaySet make_luminous_ray_set(std::vector<float> rays) {
  Tm25RaySet set;
  set.header.luminous_flux = true;
  set.header.creation_method = 0;
  set.columns = tm25_columns(set.header);
  set.items = std::move(rays);
  set.header.luminous_flux_lm = static_cast<float>(set.total_luminous_flux_lm());
  return set;
}

}  // namespace gonio::io
