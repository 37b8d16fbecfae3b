// The CAD sidecar (io/model/parts_file.h): TOML to plain data, with errors
// that name the file and line.
#include "io/model/parts_file.h"

#include <gtest/gtest.h>

namespace gonio::io {
namespace {

TEST(PartsFile, FullExampleReadsEverySection) {
  const char* text = R"(
length_unit = "in"
default_material = "black"

[frame]
up = [0, 1, 0]
c0 = [1, 0, 0]

[materials.black]
kd = 0.05

[materials.mirror]
reflectance = 0.95
diffuse_reflectance = 0.02

[[parts]]
match = "Lamp/Reflector*"
material = "mirror"

[[parts]]
colour = [0.5, 0.5, 0.5]
layer = "OPT*"
material = "black"

[[emitters]]
name = "LED"
at = "LED*"
position = [0, 0, 0.5]
nadir = [0, 0, -1]
c0 = [1, 0, 0]
profile = "led.ies"
flux_lm = 1200
spectrum = { blackbody_k = 4000 }
)";
  Result<PartsFile> p = parse_parts_file(text, "lamp.gonio.toml");
  ASSERT_TRUE(p.ok()) << to_string(p.error());
  EXPECT_DOUBLE_EQ(*p->length_unit_m, 0.0254);
  EXPECT_EQ(p->default_material, "black");
  EXPECT_DOUBLE_EQ(p->frame_up->y, 1.0);
  ASSERT_EQ(p->materials.size(), 2u);
  EXPECT_EQ(p->materials[1].name, "mirror");
  EXPECT_DOUBLE_EQ(p->materials[1].extras.at("reflectance").get<double>(), 0.95);
  ASSERT_EQ(p->rules.size(), 2u);
  EXPECT_EQ(p->rules[0].match, "Lamp/Reflector*");
  EXPECT_EQ(p->rules[0].line, 16);
  EXPECT_DOUBLE_EQ(p->rules[1].colour->x, 0.5);
  EXPECT_EQ(p->rules[1].layer, "OPT*");
  ASSERT_EQ(p->emitters.size(), 1u);
  const PartsEmitter& e = p->emitters[0];
  EXPECT_EQ(e.at, "LED*");
  EXPECT_DOUBLE_EQ(e.position->z, 0.5);
  EXPECT_DOUBLE_EQ(*e.flux_lm, 1200.0);
  EXPECT_EQ(e.profile, "led.ies");
  EXPECT_DOUBLE_EQ(e.spectrum.at("spectrum").at("blackbody_k").get<double>(), 4000.0);
}

TEST(PartsFile, HexColourIsEightBitSrgb) {
  Result<PartsFile> p = parse_parts_file(R"(
[materials.m]
kd = 1
[[parts]]
colour = "#FF8000"
material = "m"
)", "s.toml");
  ASSERT_TRUE(p.ok()) << to_string(p.error());
  EXPECT_DOUBLE_EQ(p->rules[0].colour->x, 1.0);
  EXPECT_DOUBLE_EQ(p->rules[0].colour->y, 128.0 / 255.0);
  EXPECT_DOUBLE_EQ(p->rules[0].colour->z, 0.0);
}

struct Bad {
  const char* text;
  int line;
  const char* says;
};

TEST(PartsFile, MistakesAreErrorsWithTheirLine) {
  const Bad cases[] = {
      {"x = [1,\n", 1, "not a readable TOML file"},
      {"colour_typo = 1\n", 1, "unknown key"},
      {"[materials.m]\nkd = 1\n[[parts]]\nmatch = \"A\"\nmaterial = \"n\"\n", 3, "not defined"},
      {"[materials.m]\nkd = 1\n[[parts]]\nmatch = \"A\"\nmaterail = \"m\"\n", 5, "unknown key"},
      {"[materials.m]\nkd = 1\n[[parts]]\nmaterial = \"m\"\n", 3, "give 'match'"},
      {"[materials.m]\nkd = 1\n[[parts]]\ncolour = \"#12345\"\nmaterial = \"m\"\n", 4, "#rrggbb"},
      {"[materials.m]\nkd = 1\n[[parts]]\ncolour = [2, 0, 0]\nmaterial = \"m\"\n", 4, "0..1"},
      {"[[emitters]]\nat = \"LED\"\n", 1, "needs 'flux_lm'"},
      {"[[emitters]]\nflux_lm = 1\n", 1, "say where"},
      {"[[emitters]]\nat = \"x\"\nflux_lm = -1\n", 1, "> 0"},
      {"[[emitters]]\nat = \"x\"\nflux_lm = 1\nposition = [1, 2]\n", 4, "three finite numbers"},
      {"[[emitters]]\nat = \"x\"\nflux_lm = 1\nnadir = [0, 0, 0]\n", 4, "zero vector"},
      {"[[emitters]]\nat = \"x\"\nprofile = \"a.ies\"\nray_file = \"b.tm25ray\"\n", 1, "not both"},
      {"length_unit = \"furlong\"\n", 1, "not a unit"},
      {"default_material = \"none\"\n", 1, "not defined"},
      {"[frame]\nup = [0, 0, 1]\nc0 = [0, 0, 2]\n", 1, "parallel"},
      {"materials = 3\n", 1, "table of tables"},
  };
  for (const Bad& b : cases) {
    Result<PartsFile> p = parse_parts_file(b.text, "s.toml");
    ASSERT_FALSE(p.ok()) << b.text;
    EXPECT_EQ(p.error().where.file, "s.toml");
    EXPECT_EQ(p.error().where.line, b.line) << b.text << " → " << p.error().message;
    EXPECT_NE(p.error().message.find(b.says), std::string::npos) << b.text << " → " << p.error().message;
  }
}

TEST(PartsFile, LengthUnitsAndGlobs) {
  EXPECT_DOUBLE_EQ(*length_unit_m("millimetre"), 1e-3);
  EXPECT_DOUBLE_EQ(*length_unit_m("INCH"), 0.0254);
  EXPECT_DOUBLE_EQ(*length_unit_m("metre"), 1.0);
  EXPECT_FALSE(length_unit_m("parsec").has_value());
  EXPECT_TRUE(glob_match("LED*", "LED12"));
  EXPECT_TRUE(glob_match("Lamp/*/Lens", "Lamp/Optic/Lens"));
  EXPECT_TRUE(glob_match("Lamp/*", "Lamp/Optic/Lens"));  // '*' crosses '/'
  EXPECT_FALSE(glob_match("LED?", "LED12"));
  EXPECT_TRUE(glob_match("LED\\[2\\]", "LED[2]"));
  // Blind to the case of letters (docs/cad.md): a case-sensitive match
  // would leave `led*` without the part named LED.
  EXPECT_TRUE(glob_match("led*", "LED1"));
  EXPECT_TRUE(glob_match("LED*", "led1"));
  EXPECT_TRUE(glob_match("lamp/optic/*", "Lamp/Optic/Lens"));
  EXPECT_TRUE(glob_match("[l]ens", "Lens"));
  EXPECT_FALSE(glob_match("led*", "Lens"));
}

}  // namespace
}  // namespace gonio::io
