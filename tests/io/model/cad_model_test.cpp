// The tessellated CAD model's binary form (io/model/cad_model.h): what the
// helper process hands gonio and what the cache keeps.
#include "io/model/cad_model.h"

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

}  // namespace
}  // namespace gonio::io
