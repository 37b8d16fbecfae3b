// Radiance/WINDOW BSDF XML: Klems matrices and tensor trees (io/materials/bsdf_file.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/materials/bsdf_file.h"
#include "io/support/text.h"
#include "io/support/xml.h"
#include "photometry/error_at.h"
#include "photometry/format.h"

namespace gonio::io {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr std::size_t kMaxPatches = 20000;
constexpr int kMaxTreeLog2 = 7;  // finest tensor-tree grid: 128 cells per side
constexpr int kMaxTreeDepth = 16;

std::string_view local_name(std::string_view name) {
  const auto colon = name.rfind(':');
  return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

const XmlElement* child(const XmlElement* e, std::string_view name) {
  if (!e) return nullptr;
  for (const XmlElement& c : e->children)
    if (local_name(c.name) == name) return &c;
  return nullptr;
}

std::vector<const XmlElement*> children(const XmlElement* e, std::string_view name) {
  std::vector<const XmlElement*> out;
  if (!e) return out;
  for (const XmlElement& c : e->children)
    if (local_name(c.name) == name) out.push_back(&c);
  return out;
}

std::string trimmed(std::string_view s) {
  const auto a = s.find_first_not_of(" \t\r\n");
  if (a == std::string_view::npos) return {};
  const auto b = s.find_last_not_of(" \t\r\n");
  return std::string(s.substr(a, b - a + 1));
}

std::string text_of(const XmlElement* e) { return e ? trimmed(e->text) : std::string(); }

bool same_name(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

class Reader {
 public:
  Reader(const std::string& name, std::vector<Finding>& findings) : name_(name), findings_(findings) {}

  Result<sim::TabulatedBsdf> read(std::string_view bytes);

 private:
  Error fail(const XmlElement* at, std::string message) const {
    return make_error(name_, at ? at->line : 0, std::move(message));
  }
  void note(Severity s, const char* code, std::string message, const XmlElement* at) {
    findings_.push_back({s, code, std::move(message), SourceLoc{name_, at ? at->line : 0, 0}});
  }

  // Numbers of a ScatteringData text (whitespace or commas between them).
  Result<std::vector<float>> numbers(const XmlElement& data, std::size_t expected);

  // The blocks of the photopic WavelengthData, each with its direction.
  struct Block {
    const XmlElement* element;
    std::string direction;  // as written, for messages
    bool transmission, front;
  };
  Result<std::vector<Block>> visible_blocks(const XmlElement& layer);
  Status read_klems(const XmlElement& layer, const XmlElement& definition, bool rows_are_incidence);
  Status read_tree(const XmlElement& layer, int dimensions);
  Status check_wavelength(const XmlElement& wd, bool* visible);

  const std::string& name_;
  std::vector<Finding>& findings_;
  sim::TabulatedBsdf out_;
};

Result<std::vector<float>> Reader::numbers(const XmlElement& data, std::size_t expected) {
  std::vector<float> v;
  v.reserve(expected);
  const std::string& t = data.text;
  std::size_t i = 0;
  int line = data.line;
  while (i < t.size()) {
    const char c = t[i];
    if (c == '\n') ++line;
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ',') {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < t.size() && !(t[j] == ' ' || t[j] == '\t' || t[j] == '\r' || t[j] == '\n' || t[j] == ',')) ++j;
    const std::string_view token(t.data() + i, j - i);
    if (v.size() == expected)
      return make_error(name_, line, "ScatteringData holds more than the " + std::to_string(expected) +
                                         " values its angle bases call for");
    const std::optional<double> x = parse_number(token);
    if (!x) return make_error(name_, line, "ScatteringData: " + shown(token) + " is not a number");
    if (*x < 0.0 || *x > 1e30)
      return make_error(name_, line, "ScatteringData: " + shown(token) + " is negative or too large for a BSDF");
    v.push_back(static_cast<float>(*x));
    i = j;
  }
  if (v.size() != expected)
    return fail(&data, "ScatteringData holds " + std::to_string(v.size()) + " values, its angle bases call for " +
                           std::to_string(expected));
  return v;
}

Result<std::vector<Reader::Block>> Reader::visible_blocks(const XmlElement& layer) {
  std::vector<Block> out;
  for (const XmlElement* wd : children(&layer, "WavelengthData")) {
    bool visible = false;
    if (Status s = check_wavelength(*wd, &visible); !s.ok()) return s.error();
    if (!visible) continue;
    for (const XmlElement* block : children(wd, "WavelengthDataBlock")) {
      const std::string direction = text_of(child(block, "WavelengthDataDirection"));
      const bool transmission = same_name(direction, "Transmission Front") || same_name(direction, "Transmission Back");
      const bool reflection = same_name(direction, "Reflection Front") || same_name(direction, "Reflection Back");
      if (!transmission && !reflection)
        return fail(block, "WavelengthDataDirection " + shown(direction) +
                               " is not Transmission Front/Back or Reflection Front/Back");
      const bool front = same_name(std::string_view(direction).substr(direction.size() - 5), "Front");
      out.push_back({block, direction, transmission, front});
    }
  }
  return out;
}

Status Reader::check_wavelength(const XmlElement& wd, bool* visible) {
  const std::string w = text_of(child(&wd, "Wavelength"));
  *visible = same_name(w, "Visible");
  if (!*visible)
    note(Severity::Info, "bsdf-data-skipped",
         name_ + ": WavelengthData " + shown(w) + " skipped; Gonio reads the photopic (Visible) data", &wd);
  return Ok{};
}

// The angle bases a Klems file defines, by name.
struct KlemsBasis {
  sim::PatchBasis basis;
  std::vector<double> ring_centre_deg;
  std::vector<std::size_t> ring_first;  // index of each ring's first patch (φ = 0)
};

Result<KlemsBasis> basis_from(const XmlElement& ab, const std::string& file) {
  KlemsBasis k;
  const std::vector<const XmlElement*> blocks = children(&ab, "AngleBasisBlock");
  const std::string name = text_of(child(&ab, "AngleBasisName"));
  if (blocks.empty()) {
    k.basis = sim::PatchBasis::klems(name);
    if (k.basis.size() == 0)
      return make_error(file, ab.line, "angle basis " + shown(name) + " has no AngleBasisBlock and is not a built-in Klems basis");
  } else {
    if (blocks.size() > 90)
      return make_error(file, ab.line, "angle basis " + shown(name) + " has more than 90 rings");
    double last = 0.0;
    std::size_t patches = 0;
    for (const XmlElement* b : blocks) {
      const XmlElement* bounds = child(b, "ThetaBounds");
      const std::optional<double> lo = parse_number(text_of(child(bounds, "LowerTheta")));
      const std::optional<double> hi = parse_number(text_of(child(bounds, "UpperTheta")));
      const std::optional<double> n = parse_number(text_of(child(b, "nPhis")));
      if (!lo || !hi || !n)
        return make_error(file, b->line, "AngleBasisBlock needs ThetaBounds (LowerTheta, UpperTheta) and nPhis");
      if (std::abs(*lo - last) > 1e-6 || !(*hi > *lo) || *hi > 90.0 + 1e-9)
        return make_error(file, b->line, "AngleBasisBlock: theta bounds must follow on from " +
                                              format_number(last) + " and increase up to 90 degrees");
      if (!(*n >= 1.0 && *n <= 1000.0 && *n == std::floor(*n)))
        return make_error(file, b->line, "AngleBasisBlock: nPhis must be a whole number in 1..1000");
      patches += static_cast<std::size_t>(*n);
      if (patches > kMaxPatches)
        return make_error(file, b->line, "angle basis " + shown(name) + " has more than " +
                                              std::to_string(kMaxPatches) + " patches");
      k.basis.ring_theta_deg.push_back(*lo);
      std::vector<double> phi;
      const int count = static_cast<int>(*n);
      for (int j = 0; j <= count; ++j) phi.push_back((j - 0.5) * 360.0 / count);
      k.basis.ring_phi_deg.push_back(std::move(phi));
      last = *hi;
    }
    if (std::abs(last - 90.0) > 1e-6)
      return make_error(file, ab.line, "angle basis " + shown(name) + " stops at " + format_number(last) +
                                           " degrees, not 90");
    k.basis.ring_theta_deg.push_back(90.0);
  }
  std::size_t first = 0;
  for (std::size_t r = 0; r + 1 < k.basis.ring_theta_deg.size(); ++r) {
    const double lo = k.basis.ring_theta_deg[r], hi = k.basis.ring_theta_deg[r + 1];
    k.ring_centre_deg.push_back(lo == 0.0 ? 0.0 : 0.5 * (lo + hi));
    k.ring_first.push_back(first);
    first += k.basis.ring_phi_deg[r].size() - 1;
  }
  return k;
}

Status Reader::read_klems(const XmlElement& layer, const XmlElement& definition, bool rows_are_incidence) {
  std::map<std::string, KlemsBasis> bases;
  for (const XmlElement* ab : children(&definition, "AngleBasis")) {
    Result<KlemsBasis> b = basis_from(*ab, name_);
    if (!b.ok()) return b.error();
    bases[text_of(child(ab, "AngleBasisName"))] = std::move(*b);
  }
  const auto basis_named = [&](const std::string& n) -> const KlemsBasis* {
    for (const auto& [key, b] : bases)
      if (same_name(key, n)) return &b;
    if (sim::PatchBasis::klems(n).size() > 0) {
      const XmlElement fake{"AngleBasis", {}, {}, {XmlElement{"AngleBasisName", {}, n, {}, 0}}, 0};
      Result<KlemsBasis> b = basis_from(fake, name_);
      if (b.ok()) return &(bases[n] = std::move(*b));
    }
    return nullptr;
  };
  const sim::PatchBasis* outgoing = nullptr;
  Result<std::vector<Block>> blocks = visible_blocks(layer);
  if (!blocks.ok()) return blocks.error();
  for (const Block& b : *blocks) {
    const XmlElement* block = b.element;
    const std::string& direction = b.direction;
    const bool transmission = b.transmission, front = b.front;
    const std::string column_name = text_of(child(block, "ColumnAngleBasis"));
    const std::string row_name = text_of(child(block, "RowAngleBasis"));
    const KlemsBasis* columns = basis_named(column_name);
    const KlemsBasis* rows = basis_named(row_name);
    if (!columns || !rows)
      return fail(block, "angle basis " + shown(columns ? row_name : column_name) + " is not defined in the file");
    // Columns layout: data[o · ninc + i] (a line per outgoing patch); Rows: data[i · nout + o].
    const KlemsBasis& inc = rows_are_incidence ? *rows : *columns;
    const KlemsBasis& out = rows_are_incidence ? *columns : *rows;
    if (!outgoing) {
      outgoing = &out.basis;
      out_.basis = out.basis;
    } else if (outgoing->ring_theta_deg != out.basis.ring_theta_deg ||
               outgoing->ring_phi_deg != out.basis.ring_phi_deg) {
      return fail(block, "every block must scatter into the same outgoing angle basis");
    }
    const std::size_t ninc = inc.basis.size(), nout = out.basis.size();
    const XmlElement* data = child(block, "ScatteringData");
    if (!data) return fail(block, "WavelengthDataBlock without ScatteringData");
    Result<std::vector<float>> v = numbers(*data, ninc * nout);
    if (!v.ok()) return v.error();
    const auto at = [&](std::size_t i, std::size_t o) {
      return (*v)[rows_are_incidence ? i * nout + o : o * ninc + i];
    };
    sim::TabulatedBsdf::Side& side = front ? out_.front : out_.back;
    if (side.rows.empty()) {
      for (double c : inc.ring_centre_deg) {
        sim::TabulatedBsdf::Row r;
        r.theta_deg = c;
        side.rows.push_back(std::move(r));
      }
    } else if (side.rows.size() != inc.ring_centre_deg.size()) {
      return fail(block, "reflection and transmission of one side must share an incidence basis");
    }
    for (std::size_t ring = 0; ring < inc.ring_first.size(); ++ring) {
      std::vector<float>& row = transmission ? side.rows[ring].transmit : side.rows[ring].reflect;
      row.resize(nout);
      for (std::size_t o = 0; o < nout; ++o) row[o] = at(inc.ring_first[ring], o);
    }
    // Anisotropy: the directional albedo of every incidence patch of a ring.
    double worst = 0.0, at_ring = 0.0;
    for (std::size_t ring = 0; ring < inc.ring_first.size(); ++ring) {
      const std::size_t count = inc.basis.ring_phi_deg[ring].size() - 1;
      double lo = 1e300, hi = 0.0;
      for (std::size_t k = 0; k < count; ++k) {
        double a = 0.0;
        for (std::size_t o = 0; o < nout; ++o)
          a += static_cast<double>(at(inc.ring_first[ring] + k, o)) * out.basis.projected_solid_angle(o);
        lo = std::min(lo, a);
        hi = std::max(hi, a);
      }
      if (hi > 1e-3 && (hi - lo) / hi > worst) {
        worst = (hi - lo) / hi;
        at_ring = inc.ring_centre_deg[ring];
      }
    }
    if (worst > 0.05)
      note(Severity::Info, "bsdf-anisotropic",
           name_ + ": " + direction + " scatters up to " + format_number(100.0 * worst, 3) +
               " % differently across the azimuths of one incidence ring (at " + format_number(at_ring) +
               " degrees); Gonio reads it as isotropic, along azimuth 0",
           block);
  }
  if (blocks->empty()) return fail(&layer, "no Visible WavelengthData with a Klems matrix");
  return Ok{};
}

// A tensor tree as read: a node is either 2^d children or a grid of
// (2^k)^d values (dimension 0 slowest in the grid; child index bit i is
// dimension i, as in Radiance's bsdf_t.c).
struct TreeNode {
  std::vector<TreeNode> children;
  std::vector<float> values;
  int log2 = 0;
};

class TreeParser {
 public:
  TreeParser(std::string_view text, int dimensions) : t_(text), d_(dimensions) {}

  Result<TreeNode> parse(int depth, int* finest_log2) {
    if (depth > kMaxTreeDepth) return error("nested deeper than " + std::to_string(kMaxTreeDepth) + " levels");
    if (!eat('{')) return error("'{' expected");
    TreeNode n;
    skip();
    if (peek() == '{') {
      n.children.reserve(std::size_t{1} << d_);
      for (int c = 0; c < (1 << d_); ++c) {
        Result<TreeNode> sub = parse(depth + 1, finest_log2);
        if (!sub.ok()) return sub.error();
        n.children.push_back(std::move(*sub));
      }
    } else {
      while (true) {
        skip();
        const char c = peek();
        if (c == '}' || c == '\0') break;
        std::size_t j = i_;
        while (j < t_.size() && !(std::isspace(static_cast<unsigned char>(t_[j])) || t_[j] == ',' || t_[j] == '}' || t_[j] == '{')) ++j;
        const std::string_view token = t_.substr(i_, j - i_);
        const std::optional<double> x = parse_number(token);
        if (!x) return error(shown(token) + " is not a number");
        if (*x < 0.0 || *x > 1e30) return error(shown(token) + " is negative or too large for a BSDF");
        if (n.values.size() >= (std::size_t{1} << (d_ * kMaxTreeLog2)))
          return error("a leaf grid finer than 2^" + std::to_string(kMaxTreeLog2) + " per side");
        n.values.push_back(static_cast<float>(*x));
        i_ = j;
        skip();
        if (peek() == ',') ++i_;
      }
      int k = 0;
      while (k <= kMaxTreeLog2 && (std::size_t{1} << (d_ * k)) != n.values.size()) ++k;
      if (k > kMaxTreeLog2)
        return error("a leaf holds " + std::to_string(n.values.size()) + " values, not a power of 2^" +
                     std::to_string(d_));
      n.log2 = k;
      *finest_log2 = std::max(*finest_log2, depth + k);
      if (*finest_log2 > kMaxTreeLog2)
        return error("the tree is finer than 2^" + std::to_string(kMaxTreeLog2) + " cells per side");
    }
    if (!eat('}')) return error("'}' expected");
    skip();
    if (peek() == ',') ++i_;
    return n;
  }
  bool at_end() {
    skip();
    return i_ >= t_.size();
  }
  std::string where() const {
    return "at byte " + std::to_string(i_) + " of ScatteringData";
  }

 private:
  Error error(std::string message) const { return make_error(message + " (" + where() + ")"); }
  void skip() {
    while (i_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[i_]))) ++i_;
  }
  char peek() const { return i_ < t_.size() ? t_[i_] : '\0'; }
  bool eat(char c) {
    skip();
    if (peek() != c) return false;
    ++i_;
    return true;
  }

  std::string_view t_;
  int d_;
  std::size_t i_ = 0;
};

float lookup(const TreeNode& root, int dims, const double* pos_in) {
  double pos[4];
  for (int i = 0; i < dims; ++i) pos[i] = pos_in[i];
  const TreeNode* n = &root;
  while (!n->children.empty()) {
    int idx = 0;
    for (int i = 0; i < dims; ++i) {
      pos[i] *= 2.0;
      const int t = pos[i] >= 1.0 ? 1 : 0;
      idx |= t << i;
      pos[i] -= t;
    }
    n = &n->children[static_cast<std::size_t>(idx)];
  }
  const int res = 1 << n->log2;
  std::size_t index = 0;
  for (int i = 0; i < dims; ++i)
    index = index * static_cast<std::size_t>(res) + static_cast<std::size_t>(std::clamp(static_cast<int>(pos[i] * res), 0, res - 1));
  return n->values[index];
}

Status Reader::read_tree(const XmlElement& layer, int dims) {
  struct Read {
    TreeNode tree;
    bool transmission, front;
  };
  std::vector<Read> trees;
  int finest = 0;
  Result<std::vector<Block>> blocks = visible_blocks(layer);
  if (!blocks.ok()) return blocks.error();
  for (const Block& b : *blocks) {
    const XmlElement* block = b.element;
    const std::string basis = text_of(child(block, "AngleBasis"));
    if (!same_name(basis, "LBNL/Shirley-Chiu"))
      return fail(block, "a tensor tree needs the angle basis LBNL/Shirley-Chiu, not " + shown(basis));
    const XmlElement* data = child(block, "ScatteringData");
    if (!data) return fail(block, "WavelengthDataBlock without ScatteringData");
    TreeParser p(data->text, dims);
    Result<TreeNode> t = p.parse(0, &finest);
    if (!t.ok()) return fail(data, "tensor tree: " + t.error().message);
    if (!p.at_end()) return fail(data, "tensor tree: text after the tree's last '}' (" + p.where() + ")");
    trees.push_back({std::move(*t), b.transmission, b.front});
  }
  if (trees.empty()) return fail(&layer, "no Visible WavelengthData with a tensor tree");
  // At least 2 cells per side so that the incidence half has a row.
  const int n = 1 << std::max(finest, 1);
  out_.basis.kind = sim::PatchBasis::Kind::Square;
  out_.basis.square_n = n;
  if (dims == 4)
    note(Severity::Info, "bsdf-anisotropic",
         name_ + ": a TensorTree4 (anisotropic) BSDF is read as isotropic, along the incidence azimuth 0", &layer);
  for (const Read& r : trees) {
    sim::TabulatedBsdf::Side& side = r.front ? out_.front : out_.back;
    // Incidence rows: TT3 along x0 = ½ − ½ sin θi (bins of x0 below ½,
    // normal incidence last); TT4 along disc_to_square(sin θi, 0) =
    // (½ + ½ sin θi, ½).
    const int rows = n / 2;
    if (side.rows.empty()) {
      for (int k = 0; k < rows; ++k) {
        sim::TabulatedBsdf::Row row;
        const double x = (k + 0.5) / n;  // distance from the square's middle along dim 0
        row.theta_deg = std::asin(std::clamp(2.0 * x, 0.0, 1.0)) / kDeg;
        side.rows.push_back(std::move(row));
      }
    }
    for (int k = 0; k < rows; ++k) {
      const double s = (k + 0.5) / n;
      std::vector<float>& v = r.transmission ? side.rows[static_cast<std::size_t>(k)].transmit
                                             : side.rows[static_cast<std::size_t>(k)].reflect;
      v.assign(static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0f);
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          double pos[4];
          if (dims == 3) {
            pos[0] = 0.5 - s;
            pos[1] = (i + 0.5) / n;
            pos[2] = (j + 0.5) / n;
          } else {
            pos[0] = 0.5 + s;
            pos[1] = 0.5 + 0.5 / n;
            pos[2] = (i + 0.5) / n;
            pos[3] = (j + 0.5) / n;
          }
          v[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)] = lookup(r.tree, dims, pos);
        }
      }
    }
  }
  return Ok{};
}

Result<sim::TabulatedBsdf> Reader::read(std::string_view bytes) {
  Result<XmlElement> doc = parse_xml(bytes, name_);
  if (!doc.ok()) return doc.error();
  const XmlElement& root = *doc;
  if (local_name(root.name) != "WindowElement")
    return fail(&root, "not a BSDF XML document: the root element is " + shown(root.name) + ", not WindowElement");
  const XmlElement* layer = child(child(&root, "Optical"), "Layer");
  if (!layer) return fail(&root, "no Optical/Layer element");
  const XmlElement* definition = child(layer, "DataDefinition");
  const std::string structure = text_of(child(definition, "IncidentDataStructure"));
  out_.name = name_;
  if (const std::string m = text_of(child(child(layer, "Material"), "Name")); !m.empty()) out_.name += " (" + m + ")";
  Status s = Ok{};
  if (same_name(structure, "Columns") || same_name(structure, "Rows")) {
    s = read_klems(*layer, *definition, same_name(structure, "Rows"));
  } else if (same_name(structure, "TensorTree3")) {
    s = read_tree(*layer, 3);
  } else if (same_name(structure, "TensorTree4")) {
    s = read_tree(*layer, 4);
  } else {
    return fail(definition ? definition : layer,
                "IncidentDataStructure " + shown(structure) + " is not Columns, Rows, TensorTree3 or TensorTree4");
  }
  if (!s.ok()) return s.error();
  if (Status f = finish_bsdf(out_, name_, findings_); !f.ok()) return f.error();
  return std::move(out_);
}

}  // namespace

Result<sim::TabulatedBsdf> read_bsdf_xml(std::string_view bytes, const std::string& name,
                                         std::vector<Finding>& findings) {
  return Reader(name, findings).read(bytes);
}

}  // namespace gonio::io
