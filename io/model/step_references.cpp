#include "io/model/step_references.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "photometry/error_at.h"

namespace gonio::io {
namespace {

struct Instance {
  std::uint64_t id = 0;
  int line = 0;
  std::size_t first_ref = 0, end_ref = 0;  // range in Scan::ref_ids
  bool shape = false;                      // of a type shapes are made of (shape_type)
};

// The entity types shapes are made of, by the words of their names (a
// complex instance's partial types count each): the geometry and topology
// of ISO 10303-42 (curves and surfaces, which OpenCASCADE's translators
// follow by recursion to their basis curves and surfaces, replicas, points,
// placements; edges, loops, faces, shells, solids), the mapped items of
// ISO 10303-43, the assembly structure of ISO 10303-44 (XCAF's tree), the
// shape representations, and the units and representation contexts that
// scale them. Other entities (properties, presentation, text) are looked
// up without recursion: a cycle among them only (a measured file has one,
// docs/cad.md) is reported, not refused, and so is damage OpenCASCADE
// finds in them.
bool shape_type(std::string_view name) {
  static constexpr std::string_view kWords[] = {
      "CURVE", "SURFACE", "LINE", "CIRCLE", "ELLIPSE", "PARABOLA", "HYPERBOLA", "PLANE", "POINT",
      "PLACEMENT", "DIRECTION", "VECTOR", "REPLICA", "VERTEX", "EDGE", "LOOP", "FACE", "SHELL", "SOLID",
      "BREP", "MAPPED_ITEM", "REPRESENTATION_MAP", "USAGE_OCCURRENCE", "REPRESENTATION_RELATIONSHIP",
      "PRODUCT_DEFINITION", "SHAPE", "UNIT", "REPRESENTATION_CONTEXT"};
  for (std::string_view w : kWords)
    if (name.find(w) != std::string_view::npos) return true;
  return false;
}

struct Scan {
  std::vector<Instance> instances;
  std::vector<std::uint64_t> ref_ids;  // the `#M` of each instance, in order
};

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }
bool is_letter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
bool is_name_char(char c) { return is_letter(c) || is_digit(c) || c == '_' || c == '-'; }

// One pass over the text: the instances and the references inside them.
class Scanner {
 public:
  Scanner(std::string_view text, const std::string& file) : s_(text), file_(file) {}

  Result<Scan> run() {
    while (i_ < s_.size()) {
      if (Status st = skip_gap(); !st.ok()) return st.error();
      if (i_ >= s_.size()) break;
      // A statement: `#N = …;` is an instance; anything else (the section
      // keywords, HEADER entities) is passed over to its `;`.
      std::uint64_t id = 0;
      const int line = line_;
      bool instance = false;
      if (s_[i_] == '#' && i_ + 1 < s_.size() && is_digit(s_[i_ + 1])) {
        const std::size_t save = i_;
        const int save_line = line_;
        ++i_;
        Result<std::uint64_t> n = number();
        if (!n.ok()) return n.error();
        if (Status st = skip_gap(); !st.ok()) return st.error();
        if (i_ < s_.size() && s_[i_] == '=') {
          ++i_;
          id = *n;
          instance = true;
        } else {
          i_ = save;
          line_ = save_line;
        }
      }
      Instance in;
      in.id = id;
      in.line = line;
      in.first_ref = scan_.ref_ids.size();
      if (Status st = statement(instance, in.shape); !st.ok()) return st.error();
      in.end_ref = scan_.ref_ids.size();
      if (instance) scan_.instances.push_back(in);
    }
    return std::move(scan_);
  }

 private:
  Error error_at(int line, std::string message) const { return make_error(file_, line, std::move(message)); }

  // Whitespace and comments.
  Status skip_gap() {
    while (i_ < s_.size()) {
      const char c = s_[i_];
      if (c == '\n') {
        ++line_;
        ++i_;
      } else if (is_space(c)) {
        ++i_;
      } else if (c == '/' && i_ + 1 < s_.size() && s_[i_ + 1] == '*') {
        const int opened = line_;
        i_ += 2;
        for (;;) {
          if (i_ + 1 >= s_.size()) return error_at(opened, "a comment (/*) that is never closed");
          if (s_[i_] == '*' && s_[i_ + 1] == '/') {
            i_ += 2;
            break;
          }
          if (s_[i_] == '\n') ++line_;
          ++i_;
        }
      } else {
        break;
      }
    }
    return Ok{};
  }

  Result<std::uint64_t> number() {
    std::uint64_t n = 0;
    std::size_t digits = 0;
    while (i_ < s_.size() && is_digit(s_[i_])) {
      if (++digits > 18) return error_at(line_, "an entity number of more than 18 digits");
      n = n * 10 + static_cast<std::uint64_t>(s_[i_] - '0');
      ++i_;
    }
    return n;
  }

  // To the `;` that ends the statement, outside strings, binaries and
  // comments; the references on the way are recorded where `instance`, and
  // `shape` set where one of its types is (a simple instance's type name
  // stands before its parentheses, a complex instance's partial types just
  // inside its outer ones).
  Status statement(bool instance, bool& shape) {
    int depth = 0;
    bool complex = false, typed = false;
    while (i_ < s_.size()) {
      const char c = s_[i_];
      if (c == ';') {
        ++i_;
        return Ok{};
      }
      if (c == '\'') {
        const int at = line_;
        ++i_;
        for (;;) {
          if (i_ >= s_.size()) return error_at(at, "a string (') that is never closed");
          if (s_[i_] == '\'') {
            if (i_ + 1 < s_.size() && s_[i_ + 1] == '\'') {
              i_ += 2;
              continue;
            }
            ++i_;
            break;
          }
          if (s_[i_] == '\n') ++line_;
          ++i_;
        }
      } else if (c == '"') {
        const int at = line_;
        const std::size_t close = s_.find('"', i_ + 1);
        if (close == std::string_view::npos) return error_at(at, "a binary value (\") that is never closed");
        line_ += static_cast<int>(std::count(s_.begin() + static_cast<std::ptrdiff_t>(i_),
                                             s_.begin() + static_cast<std::ptrdiff_t>(close), '\n'));
        i_ = close + 1;
      } else if (c == '/' && i_ + 1 < s_.size() && s_[i_ + 1] == '*') {
        if (Status st = skip_gap(); !st.ok()) return st;
      } else if (c == '#' && i_ + 1 < s_.size() && is_digit(s_[i_ + 1])) {
        ++i_;
        Result<std::uint64_t> n = number();
        if (!n.ok()) return n.error();
        if (instance) scan_.ref_ids.push_back(*n);
      } else if (is_letter(c) && depth == (complex ? 1 : 0)) {
        const std::size_t start = i_;
        while (i_ < s_.size() && is_name_char(s_[i_])) ++i_;
        if (instance && shape_type(s_.substr(start, i_ - start))) shape = true;
        typed = true;
      } else {
        if (c == '(') {
          if (depth == 0 && !typed) complex = true;
          ++depth;
        } else if (c == ')') {
          --depth;
        } else if (c == '\n') {
          ++line_;
        }
        ++i_;
      }
    }
    // The last statement ran into the end of the file: OpenCASCADE says so
    // in its own words (the references read so far are still checked).
    return Ok{};
  }

  std::string_view s_;
  const std::string& file_;
  std::size_t i_ = 0;
  int line_ = 1;
  Scan scan_;
};

std::string named(const Instance& in) {
  return "#" + std::to_string(in.id) + " (line " + std::to_string(in.line) + ")";
}

}  // namespace

bool has_step_header(std::string_view text) {
  text = text.substr(0, 256);
  std::size_t i = 0;
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  return text.substr(i).substr(0, 13) == "ISO-10303-21;";
}

bool StepReferenceStats::is_shape_entity(std::uint64_t id) const {
  return std::binary_search(shape_entities.begin(), shape_entities.end(), id);
}

Result<StepReferenceStats> check_step_references(std::string_view text, const std::string& file,
                                                 std::size_t max_depth) {
  Result<Scan> scanned = Scanner(text, file).run();
  if (!scanned.ok()) return scanned.error();
  const Scan& scan = *scanned;
  const std::size_t n = scan.instances.size();

  // Entity numbers to instances (the first of a number defined twice), and
  // each instance's references as instance indices (CSR).
  std::unordered_map<std::uint64_t, std::uint32_t> index;
  index.reserve(n);
  for (std::size_t k = 0; k < n; ++k) index.emplace(scan.instances[k].id, static_cast<std::uint32_t>(k));
  std::vector<std::size_t> first(n + 1, 0);
  std::vector<std::uint32_t> to;
  to.reserve(scan.ref_ids.size());
  for (std::size_t k = 0; k < n; ++k) {
    first[k] = to.size();
    const Instance& in = scan.instances[k];
    for (std::size_t r = in.first_ref; r < in.end_ref; ++r) {
      const auto it = index.find(scan.ref_ids[r]);
      if (it != index.end()) to.push_back(it->second);
    }
  }
  first[n] = to.size();

  // Depth-first, without recursion: colour 0 unseen, 1 on the path, 2 done;
  // depth[k] is the longest chain from k, k included.
  std::vector<std::uint8_t> colour(n, 0);
  std::vector<std::uint32_t> depth(n, 0);
  std::vector<std::pair<std::uint32_t, std::size_t>> path;  // instance, next reference
  StepReferenceStats stats;
  stats.entities = n;
  stats.references = to.size();
  for (const Instance& in : scan.instances)
    if (in.shape) stats.shape_entities.push_back(in.id);
  std::sort(stats.shape_entities.begin(), stats.shape_entities.end());
  for (std::uint32_t root = 0; root < n; ++root) {
    if (colour[root] != 0) continue;
    colour[root] = 1;
    path.emplace_back(root, first[root]);
    while (!path.empty()) {
      auto& [k, next] = path.back();
      if (next < first[k + 1]) {
        const std::uint32_t m = to[next++];
        if (colour[m] == 1) {
          // A cycle: from m's place on the path to its end, back to m.
          const Instance& head = scan.instances[m];
          std::size_t from = path.size();
          while (path[from - 1].first != m) --from;
          --from;
          bool shape = false;
          for (std::size_t p = from; p < path.size(); ++p) shape |= scan.instances[path[p].first].shape;
          std::string what;
          if (m == k) {
            what = "entity " + named(head) + " refers to itself";
          } else {
            what = "entities refer to each other in a circle: ";
            const std::size_t shown = 8;
            for (std::size_t p = from; p < path.size(); ++p) {
              if (p - from == shown) {
                what += " → … (" + std::to_string(path.size() - from - shown) + " more)";
                break;
              }
              what += (p == from ? "" : " → ") + named(scan.instances[path[p].first]);
            }
            what += " → #" + std::to_string(head.id);
          }
          if (shape) return make_error(file, head.line, std::move(what));
          // Among entities OpenCASCADE looks up without recursion: the
          // reference that closes the circle is passed over.
          if (stats.harmless_cycles++ == 0) stats.first_harmless_cycle = std::move(what);
          continue;
        }
        if (colour[m] == 0) {
          colour[m] = 1;
          path.emplace_back(m, first[m]);
        }
        continue;
      }
      std::uint32_t d = 0;
      for (std::size_t r = first[k]; r < first[k + 1]; ++r) d = std::max(d, depth[to[r]]);
      depth[k] = d + 1;
      colour[k] = 2;
      if (depth[k] > max_depth) {
        const Instance& in = scan.instances[k];
        return make_error(file, in.line,
                          "the references from entity " + named(in) + " nest " + std::to_string(depth[k]) +
                              " entities deep; gonio-cad follows at most " + std::to_string(max_depth));
      }
      stats.depth = std::max<std::size_t>(stats.depth, depth[k]);
      path.pop_back();
    }
  }
  return stats;
}

}  // namespace gonio::io
