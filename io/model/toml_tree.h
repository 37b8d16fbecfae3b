// A TOML document as plain data: the one place toml++ is read
// (io/model/toml_tree.cpp is the only file that includes it). The CAD sidecar
// (io/model/parts_file.h) and design files (design/design_file.h) walk this
// tree, so that both speak one vocabulary and every node keeps its line for
// messages.
#pragma once

#include <array>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::io {

struct TomlMember;

struct TomlNode {
  enum class Type { Table, Array, String, Integer, Float, Boolean, Other };
  Type type = Type::Table;
  int line = 0;                // 1-based; 0 where the node was made, not read
  std::string string;          // String; Other (dates, times): its TOML text
  std::int64_t integer = 0;    // Integer
  double floating = 0.0;       // Float
  bool boolean = false;        // Boolean
  // Table: its keys in the order toml++ keeps them (sorted by key).
  // (A member type of its own, not std::pair: a pair of an incomplete
  // TomlNode is ill-formed, which clang says and GCC lets pass.)
  std::vector<TomlMember> table;
  std::vector<TomlNode> array;  // Array

  bool is_table() const { return type == Type::Table; }
  bool is_array() const { return type == Type::Array; }
  bool is_string() const { return type == Type::String; }
  bool is_array_of_tables() const;
  // Integer or Float as a double; nothing for other types.
  std::optional<double> number() const;
  // An array of exactly three finite numbers (a position, an axis, angles);
  // nothing otherwise.
  std::optional<std::array<double, 3>> three_numbers() const;
  // A table's member; null where absent (or not a table).
  const TomlNode* get(std::string_view key) const;
  TomlNode* get(std::string_view key);
};

// A table's member: its key and its value.
struct TomlMember {
  std::string first;  // the key
  TomlNode second;    // the value
};

// Ok where every key of table t is among `known`; else the error
// "WHAT: unknown key 'K' (known: A, B, …)" naming `file` and the member's
// line (the sidecar's and the design file's one check).
Status check_keys(const TomlNode& t, std::initializer_list<const char*> known, const std::string& what,
                  const std::string& file);

// Parses TOML text; errors name `name`, the line and the column ("not a
// readable TOML file: …").
Result<TomlNode> parse_toml(std::string_view text, const std::string& name);

}  // namespace gonio::io
