#include "design/design_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/support/file_io.h"
#include "io/support/text.h"
#include "photometry/error_at.h"
#include "photometry/format.h"

namespace gonio::design {
namespace {

using io::TomlNode;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// A table that stands for a number: its keys among value, min, max and name,
// `value` among them.
bool is_variable(const TomlNode& n) {
  if (!n.is_table() || !n.get("value")) return false;
  return std::all_of(n.table.begin(), n.table.end(), [](const auto& kv) {
    return kv.first == "value" || kv.first == "min" || kv.first == "max" || kv.first == "name";
  });
}

std::string path_text(const std::vector<Variable::Step>& path) {
  std::string out;
  for (const Variable::Step& s : path) {
    if (s.key.empty())
      out += "[" + std::to_string(s.index) + "]";
    else
      out += (out.empty() ? "" : ".") + s.key;
  }
  return out;
}

class VariableFinder {
 public:
  explicit VariableFinder(const std::string& file) : file_(file) {}

  Status walk(const TomlNode& n, std::vector<Variable::Step>& path) {
    if (is_variable(n)) return add(n, path);
    if (n.is_table()) {
      for (const auto& [k, v] : n.table) {
        path.push_back({k, 0});
        if (Status s = walk(v, path); !s.ok()) return s;
        path.pop_back();
      }
    } else if (n.is_array()) {
      for (std::size_t i = 0; i < n.array.size(); ++i) {
        path.push_back({std::string(), i});
        if (Status s = walk(n.array[i], path); !s.ok()) return s;
        path.pop_back();
      }
    }
    return Ok{};
  }

  std::vector<Variable> variables;

 private:
  Result<double> number(const TomlNode& v, const char* key, const std::string& what) const {
    const TomlNode* n = v.get(key);
    const std::optional<double> x = n ? n->number() : std::nullopt;
    if (!x || !std::isfinite(*x)) return make_error(file_, n ? n->line : v.line, what + ": '" + key + "' must be a finite number");
    return *x;
  }

  Status add(const TomlNode& n, const std::vector<Variable::Step>& path) {
    Variable v;
    v.path = path;
    v.line = n.line;
    v.name = path_text(path);
    if (const TomlNode* name = n.get("name")) {
      if (!name->is_string() || name->string.empty())
        return make_error(file_, name->line, "variable " + io::shown(v.name) + ": 'name' must be a non-empty string");
      v.name = name->string;
    }
    const std::string what = "variable " + io::shown(v.name);
    Result<double> value = number(n, "value", what);
    if (!value.ok()) return value.error();
    v.value = *value;
    for (auto [key, bound] : {std::pair{"min", &v.min}, std::pair{"max", &v.max}})
      if (n.get(key)) {
        Result<double> b = number(n, key, what);
        if (!b.ok()) return b.error();
        *bound = *b;
      }
    if (v.min && v.max && !(*v.min <= *v.max))
      return make_error(file_, v.line, what + ": min " + format_number(*v.min) + " is above max " + format_number(*v.max));
    if ((v.min && v.value < *v.min) || (v.max && v.value > *v.max))
      return make_error(file_, v.line,
                        what + ": value " + format_number(v.value) + " is outside its bounds [" +
                            (v.min ? format_number(*v.min) : std::string("-inf")) + ", " +
                            (v.max ? format_number(*v.max) : std::string("inf")) + "]");
    for (const Variable& other : variables)
      if (other.name == v.name)
        return make_error(file_, v.line, what + ": the name is taken by the variable at line " + std::to_string(other.line));
    variables.push_back(std::move(v));
    return Ok{};
  }

  const std::string& file_;
};

TomlNode* node_at(TomlNode& root, const std::vector<Variable::Step>& path) {
  TomlNode* n = &root;
  for (const Variable::Step& s : path) {
    if (s.key.empty()) {
      if (!n->is_array() || s.index >= n->array.size()) return nullptr;
      n = &n->array[s.index];
    } else {
      n = n->get(s.key);
      if (!n) return nullptr;
    }
  }
  return n;
}

// TOML text ------------------------------------------------------------------

std::string key_text(const std::string& key) {
  const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  if (bare) return key;
  std::string out = "\"";
  for (char c : key) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string string_text(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

std::string float_text(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  if (v == std::trunc(v) && std::abs(v) < 1e15) return format_number(v, 17) + ".0";
  std::string s = format_number(v, 17);
  // The shortest text that reads back as the same double.
  for (int digits = 1; digits <= 17; ++digits) {
    std::string t = format_number(v, digits);
    if (std::strtod(t.c_str(), nullptr) == v) {
      s = t;
      break;
    }
  }
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string inline_text(const TomlNode& n);

std::string inline_table_text(const TomlNode& n) {
  std::string out = "{ ";
  bool first = true;
  for (const auto& [k, v] : n.table) {
    out += (first ? "" : ", ") + key_text(k) + " = " + inline_text(v);
    first = false;
  }
  return out + (first ? "}" : " }");
}

std::string inline_text(const TomlNode& n) {
  switch (n.type) {
    case TomlNode::Type::Table: return inline_table_text(n);
    case TomlNode::Type::Array: {
      std::string out = "[";
      for (std::size_t i = 0; i < n.array.size(); ++i) out += (i ? ", " : "") + inline_text(n.array[i]);
      return out + "]";
    }
    case TomlNode::Type::String: return string_text(n.string);
    case TomlNode::Type::Integer: return std::to_string(n.integer);
    case TomlNode::Type::Float: return float_text(n.floating);
    case TomlNode::Type::Boolean: return n.boolean ? "true" : "false";
    case TomlNode::Type::Other: return n.string;
  }
  return {};
}

// A table's members written as `key = value` lines (those that are values),
// then its sub-tables ([path]) and arrays of tables ([[path]]). Variables
// and tables inside arrays of tables are written inline.
void write_table(std::string& out, const TomlNode& t, const std::string& path, bool inline_children) {
  auto is_header_table = [&](const TomlNode& v) { return !inline_children && v.is_table() && !is_variable(v); };
  auto is_table_array = [&](const TomlNode& v) {
    return v.is_array_of_tables() &&
           std::none_of(v.array.begin(), v.array.end(), [](const TomlNode& e) { return is_variable(e); });
  };
  for (const auto& [k, v] : t.table)
    if (!is_header_table(v) && !is_table_array(v)) out += key_text(k) + " = " + inline_text(v) + "\n";
  for (const auto& [k, v] : t.table) {
    const std::string sub = (path.empty() ? "" : path + ".") + key_text(k);
    if (is_header_table(v)) {
      // A table of tables alone needs no header of its own.
      const bool only_tables = !v.table.empty() && std::all_of(v.table.begin(), v.table.end(), [&](const auto& kv) {
        return is_header_table(kv.second) || is_table_array(kv.second);
      });
      if (!only_tables) out += "\n[" + sub + "]\n";
      write_table(out, v, sub, false);
    } else if (is_table_array(v)) {
      for (const TomlNode& e : v.array) {
        out += "\n[[" + sub + "]]\n";
        write_table(out, e, sub, true);
      }
    }
  }
}

}  // namespace

bool is_design_path(const std::string& path) {
  const std::string name = lower(std::filesystem::path(path).filename().string());
  const std::string suffix = ".design.toml";
  return name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string model_stem(const std::string& path) {
  const std::filesystem::path p(path);
  if (!is_design_path(path)) return p.stem().string();
  const std::string name = p.filename().string();
  return name.substr(0, name.size() - std::string(".design.toml").size());
}

const Variable* Design::variable(const std::string& name) const {
  for (const Variable& v : variables)
    if (v.name == name) return &v;
  return nullptr;
}

Result<Design> parse_design(std::string_view text, const std::string& name) {
  Result<TomlNode> root = io::parse_toml(text, name);
  if (!root.ok()) return root.error();
  Design d;
  d.path = name;
  d.document = std::move(*root);
  VariableFinder finder(name);
  std::vector<Variable::Step> path;
  if (Status s = finder.walk(d.document, path); !s.ok()) return s.error();
  d.variables = std::move(finder.variables);
  return d;
}

Result<Design> read_design_file(const std::string& path) {
  Result<std::string> text = io::read_file(path, std::size_t{16} << 20);
  if (!text.ok()) return text.error();
  return parse_design(*text, path);
}

Status set_variable(Design& design, const std::string& name, double value) {
  auto it = std::find_if(design.variables.begin(), design.variables.end(),
                         [&](const Variable& v) { return v.name == name; });
  if (it == design.variables.end()) return make_error(design.path, "no variable " + io::shown(name));
  if (!std::isfinite(value) || (it->min && value < *it->min) || (it->max && value > *it->max))
    return make_error(design.path, "variable " + io::shown(name) + ": " + format_number(value) +
                                       " is outside its bounds [" +
                                       (it->min ? format_number(*it->min) : std::string("-inf")) + ", " +
                                       (it->max ? format_number(*it->max) : std::string("inf")) + "]");
  it->value = value;
  TomlNode* node = node_at(design.document, it->path);
  if (node) toml_set(*node, "value", toml_number(value));
  return Ok{};
}

TomlNode resolved_document(const Design& design) {
  TomlNode out = design.document;
  for (const Variable& v : design.variables)
    if (TomlNode* n = node_at(out, v.path)) {
      const int line = n->line;
      *n = toml_number(v.value);
      n->line = line;
    }
  return out;
}

std::string write_design(const TomlNode& document, const std::vector<std::string>& header) {
  std::string out;
  for (const std::string& line : header) out += "#" + (line.empty() ? std::string() : " " + line) + "\n";
  if (!header.empty()) out += "\n";
  write_table(out, document, "", false);
  return out;
}

TomlNode toml_string(std::string value) {
  TomlNode n;
  n.type = TomlNode::Type::String;
  n.string = std::move(value);
  return n;
}

TomlNode toml_number(double value) {
  TomlNode n;
  n.type = TomlNode::Type::Float;
  n.floating = value;
  return n;
}

TomlNode toml_variable(double value, std::optional<double> min, std::optional<double> max) {
  TomlNode n = toml_table();
  toml_set(n, "value", toml_number(value));
  if (min) toml_set(n, "min", toml_number(*min));
  if (max) toml_set(n, "max", toml_number(*max));
  return n;
}

TomlNode toml_array(std::vector<TomlNode> items) {
  TomlNode n;
  n.type = TomlNode::Type::Array;
  n.array = std::move(items);
  return n;
}

TomlNode toml_table() { return TomlNode{}; }

void toml_set(TomlNode& table, const std::string& key, TomlNode value) {
  if (TomlNode* existing = table.get(key)) {
    *existing = std::move(value);
    return;
  }
  table.table.push_back(io::TomlMember{key, std::move(value)});
}

}  // namespace gonio::design
