// The CAD sidecar (io/model/parts_file.h), read from the TOML tree of
// io/model/toml_tree.h (toml++ is included there only).
#include "io/model/parts_file.h"

#include <fnmatch.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "io/support/file_io.h"
#include "io/support/text.h"
#include "photometry/error_at.h"

namespace gonio::io {
namespace {

using nlohmann::json;

int line_of(const TomlNode& n) { return n.line; }

// A TOML value as the JSON that extras.gonio would hold.
json to_json(const TomlNode& n) {
  switch (n.type) {
    case TomlNode::Type::Table: {
      json out = json::object();
      for (const auto& [k, v] : n.table) out[k] = to_json(v);
      return out;
    }
    case TomlNode::Type::Array: {
      json out = json::array();
      for (const TomlNode& v : n.array) out.push_back(to_json(v));
      return out;
    }
    case TomlNode::Type::String: return n.string;
    case TomlNode::Type::Integer: return n.integer;
    case TomlNode::Type::Float: return n.floating;
    case TomlNode::Type::Boolean: return n.boolean;
    case TomlNode::Type::Other: break;
  }
  return n.string;  // dates and times: their TOML text (no Gonio key takes one)
}

class Parser {
 public:
  explicit Parser(std::string name) : name_(std::move(name)) {}

  Result<PartsFile> parse(const TomlNode& root, const std::vector<std::string>& root_keys, const std::string& what);

 private:
  Error fail(int line, std::string message) const { return make_error(name_, line, std::move(message)); }
  Status keys(const TomlNode& t, std::initializer_list<const char*> known, const std::string& what) const;
  Result<std::string> string(const TomlNode& t, const char* key, const std::string& what) const;
  Result<std::optional<double>> number(const TomlNode& t, const char* key, const std::string& what) const;
  Result<std::optional<Vec3>> vec3(const TomlNode& t, const char* key, const std::string& what,
                                   bool direction) const;
  Result<std::optional<Vec3>> colour(const TomlNode& t, const std::string& what) const;

  std::string name_;
};

Status Parser::keys(const TomlNode& t, std::initializer_list<const char*> known, const std::string& what) const {
  return check_keys(t, known, what, name_);
}

Result<std::string> Parser::string(const TomlNode& t, const char* key, const std::string& what) const {
  const TomlNode* n = t.get(key);
  if (!n) return std::string();
  if (!n->is_string()) return fail(line_of(*n), what + ": '" + key + "' must be a string");
  return n->string;
}

Result<std::optional<double>> Parser::number(const TomlNode& t, const char* key, const std::string& what) const {
  const TomlNode* n = t.get(key);
  if (!n) return std::optional<double>();
  const std::optional<double> v = n->number();
  if (!v) return fail(line_of(*n), what + ": '" + key + "' must be a number");
  if (!std::isfinite(*v)) return fail(line_of(*n), what + ": '" + key + "' is not finite");
  return v;
}

Result<std::optional<Vec3>> Parser::vec3(const TomlNode& t, const char* key, const std::string& what,
                                         bool direction) const {
  const TomlNode* n = t.get(key);
  if (!n) return std::optional<Vec3>();
  const std::optional<std::array<double, 3>> v = n->three_numbers();
  if (!v) return fail(line_of(*n), what + ": '" + key + "' must be an array of three finite numbers");
  const Vec3 out{(*v)[0], (*v)[1], (*v)[2]};
  if (direction && !(length(out) > 0.0)) return fail(line_of(*n), what + ": '" + key + "' is a zero vector");
  return std::optional<Vec3>(out);
}

// "#rrggbb" or [r, g, b] in 0..1.
Result<std::optional<Vec3>> Parser::colour(const TomlNode& t, const std::string& what) const {
  const TomlNode* n = t.get("colour");
  if (!n) return std::optional<Vec3>();
  if (n->is_string()) {
    const std::string& text = n->string;
    auto hex = [](char c) {
      return std::isdigit(static_cast<unsigned char>(c)) ? c - '0' : std::tolower(static_cast<unsigned char>(c)) - 'a' + 10;
    };
    const bool ok = text.size() == 7 && text[0] == '#' &&
                    std::all_of(text.begin() + 1, text.end(), [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); });
    if (!ok) return fail(line_of(*n), what + ": 'colour' " + shown(text) + " is not #rrggbb");
    double v[3];
    for (int i = 0; i < 3; ++i) v[i] = (hex(text[1 + 2 * i]) * 16 + hex(text[2 + 2 * i])) / 255.0;
    return std::optional<Vec3>(Vec3{v[0], v[1], v[2]});
  }
  Result<std::optional<Vec3>> c = vec3(t, "colour", what, false);
  if (!c.ok()) return c.error();
  const Vec3& v = **c;
  if (!(v.x >= 0 && v.x <= 1 && v.y >= 0 && v.y <= 1 && v.z >= 0 && v.z <= 1))
    return fail(line_of(*n), what + ": 'colour' components must lie in 0..1 (or write \"#rrggbb\")");
  return c;
}

Result<PartsFile> Parser::parse(const TomlNode& root, const std::vector<std::string>& root_keys,
                                const std::string& document) {
  PartsFile out;
  out.path = name_;
  for (const auto& [key, v] : root.table)
    if (std::find(root_keys.begin(), root_keys.end(), key) == root_keys.end()) {
      std::string list;
      for (const std::string& n : root_keys) list += (list.empty() ? "" : ", ") + n;
      return fail(line_of(v), document + ": unknown key " + shown(key) + " (known: " + list + ")");
    }

  Result<std::string> unit = string(root, "length_unit", document);
  if (!unit.ok()) return unit.error();
  if (!unit->empty()) {
    out.length_unit_m = length_unit_m(*unit);
    if (!out.length_unit_m)
      return fail(line_of(*root.get("length_unit")),
                  "length_unit " + shown(*unit) + " is not a unit Gonio knows (mm, cm, m, in, ft, µm)");
  }
  Result<std::string> def = string(root, "default_material", document);
  if (!def.ok()) return def.error();
  out.default_material = *def;

  if (const TomlNode* f = root.get("frame")) {
    const TomlNode* t = f->is_table() ? f : nullptr;
    if (!t) return fail(line_of(*f), "[frame] must be a table");
    if (Status s = keys(*t, {"up", "c0"}, "[frame]"); !s.ok()) return s.error();
    Result<std::optional<Vec3>> up = vec3(*t, "up", "[frame]", true);
    if (!up.ok()) return up.error();
    Result<std::optional<Vec3>> c0 = vec3(*t, "c0", "[frame]", true);
    if (!c0.ok()) return c0.error();
    out.frame_up = *up;
    out.frame_c0 = *c0;
    if (out.frame_up && out.frame_c0 &&
        length(cross(normalize(*out.frame_up), normalize(*out.frame_c0))) < 1e-3)
      return fail(line_of(*f), "[frame]: up and c0 are parallel");
  }

  if (const TomlNode* m = root.get("materials")) {
    if (!m->is_table()) return fail(line_of(*m), "[materials] must be a table of tables ([materials.NAME])");
    for (const auto& [k, v] : m->table) {
      if (!v.is_table()) return fail(line_of(v), "materials." + k + " must be a table");
      out.materials.push_back({k, to_json(v), line_of(v)});
    }
  }

  if (const TomlNode* p = root.get("parts")) {
    if (!p->is_array_of_tables()) return fail(line_of(*p), "'parts' must be an array of tables ([[parts]])");
    for (const TomlNode& n : p->array) {
      const TomlNode& t = n;
      const std::string what = "[[parts]] at line " + std::to_string(line_of(n));
      if (Status s = keys(t, {"match", "colour", "layer", "material"}, what); !s.ok()) return s.error();
      PartsRule r;
      r.line = line_of(n);
      Result<std::string> match = string(t, "match", what);
      if (!match.ok()) return match.error();
      Result<std::string> layer = string(t, "layer", what);
      if (!layer.ok()) return layer.error();
      Result<std::string> material = string(t, "material", what);
      if (!material.ok()) return material.error();
      Result<std::optional<Vec3>> c = colour(t, what);
      if (!c.ok()) return c.error();
      r.match = *match;
      r.layer = *layer;
      r.material = *material;
      r.colour = *c;
      if (r.material.empty()) return fail(r.line, what + ": 'material' is missing");
      if (r.match.empty() && r.layer.empty() && !r.colour)
        return fail(r.line, what + ": give 'match', 'colour' or 'layer' (use default_material for the rest)");
      out.rules.push_back(std::move(r));
    }
  }

  if (const TomlNode* e = root.get("emitters")) {
    if (!e->is_array_of_tables())
      return fail(line_of(*e), "'emitters' must be an array of tables ([[emitters]])");
    for (const TomlNode& n : e->array) {
      const TomlNode& t = n;
      const std::string what = "[[emitters]] at line " + std::to_string(line_of(n));
      if (Status s = keys(t, {"name", "at", "position", "nadir", "c0", "profile", "ray_file", "flux_lm", "spectrum"},
                          what);
          !s.ok())
        return s.error();
      PartsEmitter em;
      em.line = line_of(n);
      for (auto [key, target] : {std::pair{"name", &em.name}, std::pair{"at", &em.at},
                                 std::pair{"profile", &em.profile}, std::pair{"ray_file", &em.ray_file}}) {
        Result<std::string> v = string(t, key, what);
        if (!v.ok()) return v.error();
        *target = *v;
      }
      Result<std::optional<Vec3>> pos = vec3(t, "position", what, false);
      if (!pos.ok()) return pos.error();
      em.position = *pos;
      Result<std::optional<Vec3>> nadir = vec3(t, "nadir", what, true);
      if (!nadir.ok()) return nadir.error();
      em.nadir = *nadir;
      Result<std::optional<Vec3>> c0 = vec3(t, "c0", what, true);
      if (!c0.ok()) return c0.error();
      em.c0 = *c0;
      Result<std::optional<double>> flux = number(t, "flux_lm", what);
      if (!flux.ok()) return flux.error();
      em.flux_lm = *flux;
      if (em.flux_lm && !(*em.flux_lm > 0.0)) return fail(em.line, what + ": 'flux_lm' must be > 0");
      if (const TomlNode* s = t.get("spectrum")) em.spectrum = json{{"spectrum", to_json(*s)}};
      if (!em.profile.empty() && !em.ray_file.empty())
        return fail(em.line, what + ": give a profile or a ray_file, not both");
      if (em.profile.empty() && em.ray_file.empty() && !em.flux_lm)
        return fail(em.line, what + ": an isotropic emitter (no profile, no ray_file) needs 'flux_lm'");
      if (em.at.empty() && !em.position)
        return fail(em.line, what + ": say where it is: 'at' (parts) and/or 'position'");
      if (em.nadir && em.c0 && length(cross(normalize(*em.nadir), normalize(*em.c0))) < 1e-3)
        return fail(em.line, what + ": nadir and c0 are parallel");
      if (em.name.empty()) em.name = em.at.empty() ? "emitter at line " + std::to_string(em.line) : em.at;
      out.emitters.push_back(std::move(em));
    }
  }
  for (const PartsRule& r : out.rules)
    if (!out.material(r.material))
      return fail(r.line, "[[parts]] at line " + std::to_string(r.line) + ": material " + shown(r.material) +
                              " is not defined ([materials." + r.material + "])");
  if (!out.default_material.empty() && !out.material(out.default_material))
    return fail(line_of(*root.get("default_material")),
                "default_material " + shown(out.default_material) + " is not defined ([materials." +
                    out.default_material + "])");
  return out;
}

}  // namespace

std::optional<double> length_unit_m(std::string_view name) {
  std::string n;
  for (char c : name)
    if (!std::isspace(static_cast<unsigned char>(c))) n += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  static const std::pair<const char*, double> units[] = {
      {"mm", 1e-3},        {"millimetre", 1e-3}, {"millimeter", 1e-3}, {"cm", 1e-2},   {"centimetre", 1e-2},
      {"centimeter", 1e-2}, {"m", 1.0},           {"metre", 1.0},       {"meter", 1.0}, {"in", 0.0254},
      {"inch", 0.0254},     {"inches", 0.0254},   {"ft", 0.3048},       {"foot", 0.3048}, {"feet", 0.3048},
      {"um", 1e-6},         {"µm", 1e-6},         {"micrometre", 1e-6}, {"micrometer", 1e-6}, {"micron", 1e-6},
      {"km", 1e3},          {"kilometre", 1e3},   {"mil", 2.54e-5},     {"dm", 0.1},    {"decimetre", 0.1}};
  for (const auto& [unit, m] : units)
    if (n == unit) return m;
  return std::nullopt;
}

bool glob_match(const std::string& pattern, const std::string& text) {
  return ::fnmatch(pattern.c_str(), text.c_str(), FNM_CASEFOLD) == 0;
}

Result<PartsFile> parse_parts_file(std::string_view text, const std::string& name) {
  Result<TomlNode> root = parse_toml(text, name);
  if (!root.ok()) return root.error();
  return parse_parts_tree(*root, name, {"length_unit", "default_material", "frame", "materials", "parts", "emitters"},
                          "the sidecar");
}

Result<PartsFile> parse_parts_tree(const TomlNode& root, const std::string& name,
                                   const std::vector<std::string>& root_keys, const std::string& what) {
  Parser p(name);
  return p.parse(root, root_keys, what);
}

Result<PartsFile> read_parts_file(const std::string& path) {
  Result<std::string> text = read_file(path, std::size_t{16} << 20);
  if (!text.ok()) return text.error();
  return parse_parts_file(*text, path);
}

}  // namespace gonio::io
