// XML documents as plain values: what the TM-33 and GLDF readers and writers
// share. io/support/xml.cpp is the only file that includes pugixml; everything else
// sees the tree below.
//
// Reading is safe on hostile input by construction:
// - No DTD is processed: a <!DOCTYPE> and its entity declarations are
//   skipped, and only XML's five predefined entities and character
//   references are expanded. A custom or external entity reference (an
//   "XML bomb", a file:// entity) stays the literal text "&name;" in the
//   value, so nothing grows and nothing outside the document is read.
// - Documents larger than kMaxXmlBytes and elements nested deeper than
//   kMaxXmlDepth are refused.
// - Errors name the document and the line (and column) where the parser
//   stopped.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "photometry/diagnostics.h"

namespace gonio::io {

inline constexpr std::size_t kMaxXmlBytes = std::size_t{64} << 20;
inline constexpr int kMaxXmlDepth = 64;

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;
  std::string text;  // the element's own character data, concatenated (CDATA included)
  std::vector<XmlElement> children;
  int line = 0;      // 1-based line of the start tag; 0 for elements built in memory

  // The first child of that name, or nullptr.
  const XmlElement* child(std::string_view child_name) const;
  // Every child of that name, in document order.
  std::vector<const XmlElement*> children_named(std::string_view child_name) const;
  // The attribute's value, or nullptr.
  const std::string* attribute(std::string_view attribute_name) const;

  // Building: appends a child and returns it.
  XmlElement& add(std::string child_name, std::string child_text = {});
  XmlElement& set(std::string attribute_name, std::string value);
};

// Parses a whole document; returns its root element. `name` is the
// document's name in errors (a path, or "archive.gldf:product.xml").
Result<XmlElement> parse_xml(std::string_view bytes, const std::string& name);

// The document as UTF-8 text: an XML declaration, then the tree indented by
// two spaces, elements with children on their own lines, text escaped.
std::string write_xml(const XmlElement& root);

}  // namespace gonio::io
