// The only file that includes pugixml (see io/support/xml.h).
#include "io/support/xml.h"

#include <algorithm>

#include <pugixml.hpp>

#include "photometry/error_at.h"

namespace gonio::io {
namespace {

// Line of a byte offset, from the sorted offsets of every '\n'.
int line_of(const std::vector<std::size_t>& newlines, std::ptrdiff_t offset) {
  if (offset < 0) return 0;
  return static_cast<int>(std::upper_bound(newlines.begin(), newlines.end(),
                                           static_cast<std::size_t>(offset)) -
                          newlines.begin()) +
         1;
}

struct Converter {
  const std::vector<std::size_t>& newlines;
  const std::string& name;
  Error error;
  bool failed = false;

  void fail(int line, std::string message) {
    if (failed) return;
    failed = true;
    error = make_error(name, line, std::move(message));
  }

  void convert(const pugi::xml_node& node, XmlElement& out, int depth) {
    out.name = node.name();
    out.line = line_of(newlines, node.offset_debug());
    if (depth > kMaxXmlDepth) {
      fail(out.line, "elements nested deeper than " + std::to_string(kMaxXmlDepth) + " levels");
      return;
    }
    for (const pugi::xml_attribute& a : node.attributes()) out.attributes.emplace_back(a.name(), a.value());
    for (const pugi::xml_node& c : node.children()) {
      if (failed) return;
      switch (c.type()) {
        case pugi::node_pcdata:
        case pugi::node_cdata:
          out.text += c.value();
          break;
        case pugi::node_element:
          out.children.emplace_back();
          convert(c, out.children.back(), depth + 1);
          break;
        default:
          break;  // comments, processing instructions
      }
    }
  }
};

void build(const XmlElement& element, pugi::xml_node node) {
  for (const auto& [key, value] : element.attributes) node.append_attribute(key.c_str()).set_value(value.c_str());
  if (!element.text.empty()) node.append_child(pugi::node_pcdata).set_value(element.text.c_str());
  for (const XmlElement& c : element.children) build(c, node.append_child(c.name.c_str()));
}

}  // namespace

const XmlElement* XmlElement::child(std::string_view child_name) const {
  for (const XmlElement& c : children)
    if (c.name == child_name) return &c;
  return nullptr;
}

std::vector<const XmlElement*> XmlElement::children_named(std::string_view child_name) const {
  std::vector<const XmlElement*> out;
  for (const XmlElement& c : children)
    if (c.name == child_name) out.push_back(&c);
  return out;
}

const std::string* XmlElement::attribute(std::string_view attribute_name) const {
  for (const auto& [key, value] : attributes)
    if (key == attribute_name) return &value;
  return nullptr;
}

XmlElement& XmlElement::add(std::string child_name, std::string child_text) {
  children.emplace_back();
  children.back().name = std::move(child_name);
  children.back().text = std::move(child_text);
  return children.back();
}

XmlElement& XmlElement::set(std::string attribute_name, std::string value) {
  attributes.emplace_back(std::move(attribute_name), std::move(value));
  return *this;
}

Result<XmlElement> parse_xml(std::string_view bytes, const std::string& name) {
  if (bytes.size() > kMaxXmlBytes)
    return make_error(name, "XML document too large (" + std::to_string(bytes.size()) +
                                " bytes, at most " + std::to_string(kMaxXmlBytes) +
                                " accepted)");
  std::vector<std::size_t> newlines;
  for (std::size_t i = 0; i < bytes.size(); ++i)
    if (bytes[i] == '\n') newlines.push_back(i);

  pugi::xml_document doc;
  // parse_default without parse_doctype: the DTD is skipped, custom entities
  // are never declared, let alone expanded.
  const unsigned options = pugi::parse_cdata | pugi::parse_escapes | pugi::parse_wconv_attribute |
                           pugi::parse_eol;
  const pugi::xml_parse_result result =
      doc.load_buffer(bytes.data(), bytes.size(), options, pugi::encoding_auto);
  if (!result) {
    const int line = line_of(newlines, result.offset);
    std::size_t line_start = 0;
    if (line > 1) line_start = newlines[static_cast<std::size_t>(line - 2)] + 1;
    const int column = static_cast<int>(static_cast<std::size_t>(result.offset) - line_start) + 1;
    return Error{SourceLoc{name, line, column},
                 std::string("malformed XML: ") + result.description()};
  }
  const pugi::xml_node root = doc.document_element();
  if (!root) return make_error(name, "malformed XML: no root element");
  Converter converter{newlines, name, {}, false};
  XmlElement out;
  converter.convert(root, out, 1);
  if (converter.failed) return converter.error;
  return out;
}

std::string write_xml(const XmlElement& root) {
  pugi::xml_document doc;
  pugi::xml_node decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version").set_value("1.0");
  decl.append_attribute("encoding").set_value("UTF-8");
  build(root, doc.append_child(root.name.c_str()));
  // Straight into the string (an ostringstream held the text twice).
  struct ToString : pugi::xml_writer {
    std::string text;
    void write(const void* data, std::size_t size) override {
      text.append(static_cast<const char*>(data), size);
    }
  } out;
  doc.save(out, "  ", pugi::format_indent, pugi::encoding_utf8);
  return std::move(out.text);
}

}  // namespace gonio::io
