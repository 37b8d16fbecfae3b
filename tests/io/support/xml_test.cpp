#include "io/support/xml.h"

#include <gtest/gtest.h>

#include <string>

namespace gonio::io {
namespace {

TEST(Xml, WrittenDocumentsParseBackWithEscapesAndLines) {
  XmlElement root;
  root.name = "Root";
  root.set("a", "x < y & \"z\"");
  root.add("Text", "1 < 2 & 3 > 2 'quoted'");
  root.add("Empty");
  XmlElement& nested = root.add("Nested");
  nested.add("Leaf", "é ü 漢");
  const std::string text = write_xml(root);
  EXPECT_EQ(text.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n", 0), 0u) << text;

  auto back = parse_xml(text, "doc.xml");
  ASSERT_TRUE(back.ok()) << to_string(back.error());
  EXPECT_EQ(back->name, "Root");
  EXPECT_EQ(*back->attribute("a"), "x < y & \"z\"");
  EXPECT_EQ(back->child("Text")->text, "1 < 2 & 3 > 2 'quoted'");
  EXPECT_EQ(back->child("Nested")->child("Leaf")->text, "é ü 漢");
  EXPECT_EQ(back->line, 2);
  EXPECT_EQ(back->child("Text")->line, 3);
  EXPECT_EQ(back->child("Nested")->child("Leaf")->line, 6);
  EXPECT_EQ(back->children_named("Empty").size(), 1u);
  EXPECT_EQ(back->child("Missing"), nullptr);
  EXPECT_EQ(write_xml(*back), text);
}

TEST(Xml, BadDocumentsNameFileLineAndColumn) {
  auto r = parse_xml("<a>\n  <b>\n</a>\n", "bad.xml");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where.file, "bad.xml");
  EXPECT_EQ(r.error().where.line, 3);
  EXPECT_GT(r.error().where.column, 0);
  EXPECT_NE(r.error().message.find("malformed XML"), std::string::npos);
  EXPECT_FALSE(parse_xml("", "empty.xml").ok());
  EXPECT_FALSE(parse_xml("just text", "text.xml").ok());
  std::string deep;
  for (int i = 0; i < kMaxXmlDepth + 1; ++i) deep += "<a>";
  for (int i = 0; i < kMaxXmlDepth + 1; ++i) deep += "</a>";
  auto d = parse_xml(deep, "deep.xml");
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("nested deeper"), std::string::npos);
  std::string ok_depth;
  for (int i = 0; i < kMaxXmlDepth; ++i) ok_depth += "<a>";
  for (int i = 0; i < kMaxXmlDepth; ++i) ok_depth += "</a>";
  EXPECT_TRUE(parse_xml(ok_depth, "ok.xml").ok());
}

// pugixml processes no DTD: a declared entity, internal or external, is
// never expanded; the reference stays literal text, and nothing is read
// from the file it names.
TEST(Xml, EntitiesAreNeverExpanded) {
  const std::string doc =
      "<?xml version=\"1.0\"?>\n"
      "<!DOCTYPE r [\n"
      "  <!ENTITY a \"aaaaaaaaaa\">\n"
      "  <!ENTITY b \"&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;\">\n"
      "  <!ENTITY x SYSTEM \"file:///etc/hostname\">\n"
      "]>\n"
      "<r at=\"&b;\">&b;|&x;|&amp;&#65;</r>\n";
  auto r = parse_xml(doc, "bomb.xml");
  ASSERT_TRUE(r.ok()) << to_string(r.error());
  EXPECT_EQ(r->text, "&b;|&x;|&A");  // predefined and character references only
  EXPECT_EQ(*r->attribute("at"), "&b;");
}

}  // namespace
}  // namespace gonio::io
