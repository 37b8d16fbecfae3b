#include "io/model/cad_model.h"

#include <cstring>
#include <type_traits>

#include "io/support/bytes.h"

namespace gonio::io {
namespace {

constexpr char kMagic[8] = {'G', 'O', 'N', 'I', 'O', 'C', 'A', 'D'};

class Writer {
 public:
  template <class T>
  void value(const T& v) { append_bytes(out_, v); }
  void text(const std::string& s) {
    value(static_cast<std::uint64_t>(s.size()));
    out_ += s;
  }
  template <class T>
  void values(const std::vector<T>& v) {
    value(static_cast<std::uint64_t>(v.size()));
    append_all_bytes(out_, v);
  }
  void colour(const std::optional<sim::Vec3f>& c) {
    value(static_cast<std::uint8_t>(c ? 1 : 0));
    if (c) value(*c);
  }
  void texts(const std::vector<std::string>& v) {
    value(static_cast<std::uint64_t>(v.size()));
    for (const std::string& s : v) text(s);
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

// Reads what Writer wrote; every count is checked against the bytes left.
class Reader {
 public:
  Reader(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  template <class T>
  bool value(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (bytes_.size() - pos_ < sizeof v) return fail("truncated");
    std::memcpy(&v, bytes_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return true;
  }
  bool count(std::uint64_t& n, std::size_t element_bytes) {
    if (!value(n)) return false;
    if (element_bytes > 0 && n > (bytes_.size() - pos_) / element_bytes) return fail("a count exceeds the file");
    return true;
  }
  bool text(std::string& s) {
    std::uint64_t n = 0;
    if (!count(n, 1)) return false;
    s.assign(bytes_.data() + pos_, static_cast<std::size_t>(n));
    pos_ += static_cast<std::size_t>(n);
    return true;
  }
  template <class T>
  bool values(std::vector<T>& v) {
    std::uint64_t n = 0;
    if (!count(n, sizeof(T))) return false;
    v.resize(static_cast<std::size_t>(n));
    if (n > 0) std::memcpy(v.data(), bytes_.data() + pos_, v.size() * sizeof(T));
    pos_ += v.size() * sizeof(T);
    return true;
  }
  bool colour(std::optional<sim::Vec3f>& c) {
    std::uint8_t has = 0;
    if (!value(has)) return false;
    if (has > 1) return fail("a colour flag is neither 0 nor 1");
    if (has == 0) return true;
    sim::Vec3f v;
    if (!value(v)) return false;
    c = v;
    return true;
  }
  bool texts(std::vector<std::string>& v) {
    std::uint64_t n = 0;
    if (!count(n, sizeof(std::uint64_t))) return false;
    v.resize(static_cast<std::size_t>(n));
    for (std::string& s : v)
      if (!text(s)) return false;
    return true;
  }
  bool at_end() const { return pos_ == bytes_.size(); }
  bool fail(const std::string& why) {
    if (error_.empty()) error_ = why + " at byte " + std::to_string(pos_);
    return false;
  }
  Error error() const { return make_error(name_, "not a readable tessellated CAD model: " + error_); }

 private:
  std::string_view bytes_;
  const std::string& name_;
  std::size_t pos_ = 0;
  std::string error_;
};

}  // namespace

std::size_t CadModel::unique_triangle_count() const {
  std::size_t n = 0;
  for (const CadPart& p : parts) n += p.triangle_count();
  return n;
}

std::size_t CadModel::placed_triangle_count() const {
  std::size_t n = 0;
  for (const CadPlacement& p : placements)
    if (p.part < parts.size()) n += parts[p.part].triangle_count();
  return n;
}

std::string serialize_cad_model(const CadModel& m) {
  Writer w;
  for (char c : kMagic) w.value(c);
  w.value(kCadModelFormat);
  w.text(m.format);
  w.text(m.file_unit);
  w.value(m.file_unit_m);
  w.value(m.tessellation.angular_deflection_deg);
  w.value(m.tessellation.chordal_relative);
  w.value(m.tessellation.chordal_min_m);
  w.value(m.tessellation.chordal_m);
  w.value(static_cast<std::uint8_t>(m.tessellation.exact_normals));
  w.value(static_cast<std::uint64_t>(m.parts.size()));
  for (const CadPart& p : m.parts) {
    w.text(p.name);
    w.colour(p.colour);
    w.texts(p.layers);
    w.value(p.faces);
    w.value(p.solids);
    w.value(p.size_m);
    w.value(p.chordal_m);
    w.value(static_cast<std::uint64_t>(p.surfaces.size()));
    for (const CadSurface& s : p.surfaces) {
      w.colour(s.colour);
      w.values(s.positions);
      w.values(s.normals);
      w.values(s.indices);
    }
  }
  w.value(static_cast<std::uint64_t>(m.placements.size()));
  for (const CadPlacement& p : m.placements) {
    w.value(p.part);
    w.value(p.to_world);
    w.text(p.path);
    w.colour(p.colour);
    w.texts(p.layers);
  }
  w.value(static_cast<std::uint64_t>(m.findings.size()));
  for (const Finding& f : m.findings) {
    w.value(static_cast<std::uint8_t>(f.severity));
    w.text(f.code);
    w.text(f.message);
    w.text(f.where.file);
    w.value(static_cast<std::int32_t>(f.where.line));
  }
  return w.take();
}

Result<CadModel> parse_cad_model(std::string_view bytes, const std::string& name) {
  Reader r(bytes, name);
  CadModel m;
  char magic[sizeof kMagic] = {};
  for (char& c : magic)
    if (!r.value(c)) return r.error();
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) {
    r.fail("no GONIOCAD signature");
    return r.error();
  }
  std::uint32_t format = 0;
  if (!r.value(format)) return r.error();
  if (format != kCadModelFormat) {
    r.fail("format " + std::to_string(format) + ", not " + std::to_string(kCadModelFormat));
    return r.error();
  }
  std::uint8_t exact = 0;
  std::uint64_t parts = 0;
  if (!r.text(m.format) || !r.text(m.file_unit) || !r.value(m.file_unit_m) ||
      !r.value(m.tessellation.angular_deflection_deg) || !r.value(m.tessellation.chordal_relative) ||
      !r.value(m.tessellation.chordal_min_m) || !r.value(m.tessellation.chordal_m) || !r.value(exact) ||
      !r.count(parts, 8 * 6))
    return r.error();
  m.tessellation.exact_normals = exact != 0;
  m.parts.resize(static_cast<std::size_t>(parts));
  for (CadPart& p : m.parts) {
    std::uint64_t surfaces = 0;
    if (!r.text(p.name) || !r.colour(p.colour) || !r.texts(p.layers) || !r.value(p.faces) ||
        !r.value(p.solids) || !r.value(p.size_m) || !r.value(p.chordal_m) || !r.count(surfaces, 8 * 3 + 1))
      return r.error();
    p.surfaces.resize(static_cast<std::size_t>(surfaces));
    for (CadSurface& s : p.surfaces) {
      if (!r.colour(s.colour) || !r.values(s.positions) || !r.values(s.normals) || !r.values(s.indices))
        return r.error();
      if (s.indices.size() % 3 != 0) {
        r.fail("a surface of part " + std::to_string(&p - m.parts.data()) + " has a partial triangle");
        return r.error();
      }
      if (!s.normals.empty() && s.normals.size() != s.positions.size()) {
        r.fail("a surface's normals and positions differ in number");
        return r.error();
      }
      for (std::uint32_t i : s.indices)
        if (i >= s.positions.size()) {
          r.fail("a triangle index is out of range");
          return r.error();
        }
    }
  }
  std::uint64_t placements = 0;
  if (!r.count(placements, 4 + sizeof(sim::Affine) + 8 + 1 + 8)) return r.error();
  m.placements.resize(static_cast<std::size_t>(placements));
  for (CadPlacement& p : m.placements) {
    if (!r.value(p.part) || !r.value(p.to_world) || !r.text(p.path) || !r.colour(p.colour) ||
        !r.texts(p.layers))
      return r.error();
    if (p.part >= m.parts.size()) {
      r.fail("a placement names part " + std::to_string(p.part) + " of " + std::to_string(m.parts.size()));
      return r.error();
    }
  }
  std::uint64_t findings = 0;
  if (!r.count(findings, 1 + 8 * 3 + 4)) return r.error();
  m.findings.resize(static_cast<std::size_t>(findings));
  for (Finding& f : m.findings) {
    std::uint8_t severity = 0;
    std::int32_t line = 0;
    if (!r.value(severity) || !r.text(f.code) || !r.text(f.message) || !r.text(f.where.file) ||
        !r.value(line))
      return r.error();
    if (severity > static_cast<std::uint8_t>(Severity::Error)) {
      r.fail("a finding's severity is out of range");
      return r.error();
    }
    f.severity = static_cast<Severity>(severity);
    f.where.line = line;
  }
  if (!r.at_end()) {
    r.fail("bytes follow the model");
    return r.error();
  }
  return m;
}

}  // namespace gonio::io
