// The only file that includes toml++ (io/model/toml_tree.h).
#include "io/model/toml_tree.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <toml++/toml.h>

#include "io/support/text.h"
#include "photometry/error_at.h"

namespace gonio::io {
namespace {

TomlNode convert(const toml::node& n) {
  TomlNode out;
  out.line = static_cast<int>(n.source().begin.line);
  if (const toml::table* t = n.as_table()) {
    out.type = TomlNode::Type::Table;
    for (const auto& [k, v] : *t) out.table.push_back(TomlMember{std::string(k.str()), convert(v)});
  } else if (const toml::array* a = n.as_array()) {
    out.type = TomlNode::Type::Array;
    for (const toml::node& v : *a) out.array.push_back(convert(v));
  } else if (const auto* s = n.as_string()) {
    out.type = TomlNode::Type::String;
    out.string = s->get();
  } else if (const auto* i = n.as_integer()) {
    out.type = TomlNode::Type::Integer;
    out.integer = i->get();
  } else if (const auto* f = n.as_floating_point()) {
    out.type = TomlNode::Type::Float;
    out.floating = f->get();
  } else if (const auto* b = n.as_boolean()) {
    out.type = TomlNode::Type::Boolean;
    out.boolean = b->get();
  } else {
    out.type = TomlNode::Type::Other;  // dates and times: their TOML text
    out.string = n.visit([](const auto& v) {
      std::ostringstream text;
      text << v;
      return text.str();
    });
  }
  return out;
}

}  // namespace

bool TomlNode::is_array_of_tables() const {
  return type == Type::Array && !array.empty() &&
         std::all_of(array.begin(), array.end(), [](const TomlNode& n) { return n.is_table(); });
}

std::optional<double> TomlNode::number() const {
  if (type == Type::Integer) return static_cast<double>(integer);
  if (type == Type::Float) return floating;
  return std::nullopt;
}

std::optional<std::array<double, 3>> TomlNode::three_numbers() const {
  if (!is_array() || array.size() != 3) return std::nullopt;
  std::array<double, 3> out{};
  for (std::size_t i = 0; i < 3; ++i) {
    const std::optional<double> x = array[i].number();
    if (!x || !std::isfinite(*x)) return std::nullopt;
    out[i] = *x;
  }
  return out;
}

const TomlNode* TomlNode::get(std::string_view key) const {
  for (const auto& [k, v] : table)
    if (k == key) return &v;
  return nullptr;
}

TomlNode* TomlNode::get(std::string_view key) {
  for (auto& [k, v] : table)
    if (k == key) return &v;
  return nullptr;
}

Result<TomlNode> parse_toml(std::string_view text, const std::string& name) {
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    return Error{{name, static_cast<int>(e.source().begin.line), static_cast<int>(e.source().begin.column)},
                 "not a readable TOML file: " + std::string(e.description())};
  }
  TomlNode out = convert(root);
  out.line = 0;
  return out;
}

Status check_keys(const TomlNode& t, std::initializer_list<const char*> known, const std::string& what,
                  const std::string& file) {
  for (const TomlMember& member : t.table) {
    if (std::none_of(known.begin(), known.end(), [&member](const char* n) { return member.first == n; })) {
      std::string list;
      for (const char* n : known) list += (list.empty() ? "" : ", ") + std::string(n);
      return make_error(file, member.second.line,
                        what + ": unknown key " + shown(member.first) + " (known: " + list + ")");
    }
  }
  return Ok{};
}

}  // namespace gonio::io
