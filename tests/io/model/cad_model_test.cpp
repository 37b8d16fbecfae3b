// The tessellated CAD model's binary form (io/model/cad_model.h): what the
// helper process hands gonio and what the cache keeps.
#include "io/model/cad_model.h"

#include "io/model/cad.h"

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

TEST(CadModelBytes, EveryTruncationAndByteFlipIsAnErrorNotACrash) {
  CadModel m;
  m.format = "STEP";
  m.file_unit = "MM";
  CadPart p;
  p.name = "P";
  p.colour = sim::Vec3f{1, 0, 0};
  p.layers = {"L"};
  CadSurface s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  s.indices = {0, 1, 2};
  p.surfaces.push_back(s);
  m.parts.push_back(p);
  m.placements.push_back({0, sim::translation({1, 2, 3}), "A/P", std::nullopt, {}});
  m.findings.push_back({Severity::Info, "c", "m", {"f", 1, 0}});
  const std::string bytes = serialize_cad_model(m);
  Result<CadModel> back = parse_cad_model(bytes, "x");
  ASSERT_TRUE(back.ok()) << to_string(back.error());
  EXPECT_EQ(serialize_cad_model(*back), bytes);
  for (std::size_t n = 0; n < bytes.size(); ++n)
    EXPECT_FALSE(parse_cad_model(std::string_view(bytes).substr(0, n), "x").ok()) << n;
  // A corrupted index or placement is refused (an index past the vertices
  // would be read out of bounds later).
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    std::string flipped = bytes;
    flipped[i] = static_cast<char>(flipped[i] ^ 0x40);
    Result<CadModel> r = parse_cad_model(flipped, "x");
    if (!r.ok()) continue;
    for (const CadSurface& q : r->parts.at(0).surfaces)
      for (std::uint32_t k : q.indices) EXPECT_LT(k, q.positions.size());
  }
}

TEST(CadOptions, TessellationFollowsTheGridAndTheOption) {
  // A finer grid asks a finer mesh: a reflected ray turns by twice the
  // facet's error, so the deflection scales with the step.
  EXPECT_DOUBLE_EQ(tessellation_for_grid(2.5).angular_deflection_deg, kDeflectionPerGammaStep * 2.5);
  EXPECT_DOUBLE_EQ(tessellation_for_grid(1.0).angular_deflection_deg, kDeflectionPerGammaStep * 1.0);
  EXPECT_TRUE(tessellation_for_grid(1.0).exact_normals);
  Result<CadTessellation> t = parse_tessellation("0.5", {});
  ASSERT_TRUE(t.ok());
  EXPECT_DOUBLE_EQ(t->angular_deflection_deg, 0.5);
  EXPECT_DOUBLE_EQ(t->chordal_m, 0.0);
  t = parse_tessellation("3,0.02", {});
  ASSERT_TRUE(t.ok());
  EXPECT_DOUBLE_EQ(t->chordal_m, 2e-5);
  for (const char* bad : {"", "0", "-1", "91", "2,", "2,0", "x", "2,abc", "nan"}) {
    Result<CadTessellation> r = parse_tessellation(bad, {});
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.error().message.find("--tessellation"), std::string::npos);
  }
}

TEST(CadOptions, CadPathsByExtension) {
  EXPECT_TRUE(is_cad_path("lamp.step"));
  EXPECT_TRUE(is_cad_path("dir/LAMP.STP"));
  EXPECT_TRUE(is_cad_path("a.p21"));
  EXPECT_TRUE(is_cad_path("a.IGS"));
  EXPECT_TRUE(is_cad_path("a.iges"));
  EXPECT_FALSE(is_cad_path("a.glb"));
  EXPECT_FALSE(is_cad_path("step"));
  EXPECT_EQ(default_parts_path("dir/lamp.step"), "dir/lamp.gonio.toml");
}

TEST(CadOptions, WithoutItsReaderACadFileIsAnErrorSayingWhy) {
  test::TempDir dir;
  const std::string model = (dir / "lamp.step").string();
  test::write_file(model, "ISO-10303-21;\n");
  CadLoadOptions o;
  if (cad_supported()) o.helper = (dir / "no-such-gonio-cad").string();  // a helper gone missing
  Result<CadModel> m = tessellate_cad(model, o);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.error().where.file, model);
  EXPECT_NE(m.error().message.find(cad_supported() ? "no-such-gonio-cad" : "without OpenCASCADE"), std::string::npos)
      << m.error().message;
}

}  // namespace
}  // namespace gonio::io
