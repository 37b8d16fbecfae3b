// The files a glTF model is made of (what gonio watch watches).
#include "io/model/gltf_files.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

TEST(GltfFiles, TheModelItsBuffersImagesAndProfilesResolvedBesideIt) {
  test::TempDir dir;
  const std::string model = (dir.path() / "lamp.gltf").string();
  test::write_file(model, R"({"asset": {"version": "2.0"},
    "buffers": [{"uri": "mesh.bin", "byteLength": 4}, {"uri": "data:application/octet-stream;base64,AAAA"},
                {"uri": "mesh.bin"}],
    "images": [{"uri": "tex%20ture.png"}],
    "extensions": {"EXT_lights_ies": {"lights": [{"uri": "profiles/led.ies"}, {"bufferView": 0}]}}})");
  auto files = gltf_files(model);
  ASSERT_TRUE(files.ok()) << files.error().message;
  const std::vector<std::string> expected{model, (dir.path() / "mesh.bin").string(),
                                          (dir.path() / "tex ture.png").string(),
                                          (dir.path() / "profiles/led.ies").string()};
  EXPECT_EQ(files.value(), expected);
}

std::string glb(const std::string& json, std::uint32_t claimed_json_length) {
  auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  std::string out = "glTF" + u32(2) + u32(0);
  out += u32(claimed_json_length) + "JSON" + json;
  return out;
}

TEST(GltfFiles, AGlbReadsItsJsonChunk) {
  test::TempDir dir;
  const std::string model = (dir.path() / "lamp.glb").string();
  const std::string json = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":4},{"uri":"extra.bin"}]})";
  test::write_file(model, glb(json, static_cast<std::uint32_t>(json.size())));
  auto files = gltf_files(model);
  ASSERT_TRUE(files.ok()) << files.error().message;
  EXPECT_EQ(files.value(), (std::vector<std::string>{model, (dir.path() / "extra.bin").string()}));
}

TEST(GltfFiles, TruncatedOrBrokenModelsAreErrorsNamingTheFile) {
  test::TempDir dir;
  const std::string model = (dir.path() / "half.glb").string();
  const std::string json = R"({"asset":{"version":"2.0"}})";
  test::write_file(model, glb(json, 4000));  // claims more JSON than the file holds
  auto files = gltf_files(model);
  ASSERT_FALSE(files.ok());
  EXPECT_EQ(files.error().where.file, model);
  EXPECT_NE(files.error().message.find("truncated"), std::string::npos);
  test::write_file(model, "glTF\x02");
  EXPECT_FALSE(gltf_files(model).ok());
  const std::string gltf = (dir.path() / "half.gltf").string();
  test::write_file(gltf, R"({"asset": {"vers)");
  EXPECT_FALSE(gltf_files(gltf).ok());
  EXPECT_FALSE(gltf_files((dir.path() / "missing.gltf").string()).ok());
}

}  // namespace
}  // namespace gonio::io
