// gonio simulate, run as a user would, on a small glTF model written here.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "io/exr.h"
#include "sim/shapes.h"
#include "tests/support/test_support.h"

namespace gonio {
namespace {

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

std::string base64(const std::string& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += table[v >> 18];
    out += table[(v >> 12) & 63];
    out += table[(v >> 6) & 63];
    out += table[v & 63];
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    out += table[v >> 18];
    out += table[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == bytes.size()) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8);
    out += table[v >> 18];
    out += table[(v >> 12) & 63];
    out += table[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

// A white box shade 0.2 m wide, open at the bottom, with a 1000 lm point
// light inside: written with nlohmann::json and a data-URI buffer.
std::string shade_model() {
  sim::Mesh box = sim::box(0.2, 0.2, 0.2);
  // Drop the two triangles of the −Y face (the box's quads come in the
  // order +X, −X, +Y, −Y, +Z, −Z): light leaves downwards.
  box.indices.erase(box.indices.begin() + 18, box.indices.begin() + 24);
  std::string bin;
  bin.append(reinterpret_cast<const char*>(box.positions.data()), box.positions.size() * sizeof(sim::Vec3f));
  const std::size_t positions_bytes = bin.size();
  bin.append(reinterpret_cast<const char*>(box.indices.data()), box.indices.size() * sizeof(std::uint32_t));
  using nlohmann::json;
  json g;
  g["asset"] = {{"version", "2.0"}};
  g["extensionsUsed"] = json::array({"KHR_lights_punctual"});

  json light = {{"type", "point"}, {"intensity", 1000.0 / (4.0 * 3.141592653589793)}};
  g["extensions"]["KHR_lights_punctual"]["lights"] = json::array({light});
  g["scene"] = 0;
  g["scenes"] = json::array({json{{"nodes", json::array({0, 1})}}});

  json shade_node = {{"name", "shade"}, {"mesh", 0}};
  json lamp_node = {{"name", "lamp"}};
  lamp_node["extensions"]["KHR_lights_punctual"]["light"] = 0;
  g["nodes"] = json::array({shade_node, lamp_node});

  json primitive = {{"indices", 1}, {"material", 0}};
  primitive["attributes"]["POSITION"] = 0;
  json mesh = {{"name", "shade"}, {"primitives", json::array({primitive})}};
  g["meshes"] = json::array({mesh});

  json material = {{"name", "white"}};
  material["pbrMetallicRoughness"] = {{"baseColorFactor", json::array({0.8, 0.8, 0.8, 1.0})},
                                      {"metallicFactor", 0.0},
                                      {"roughnessFactor", 1.0}};
  g["materials"] = json::array({material});

  json buffer = {{"byteLength", bin.size()},
                 {"uri", "data:application/octet-stream;base64," + base64(bin)}};
  g["buffers"] = json::array({buffer});
  json view0 = {{"buffer", 0}, {"byteOffset", 0}, {"byteLength", positions_bytes}, {"target", 34962}};
  json view1 = {{"buffer", 0},
                {"byteOffset", positions_bytes},
                {"byteLength", bin.size() - positions_bytes},
                {"target", 34963}};
  g["bufferViews"] = json::array({view0, view1});
  json positions = {{"bufferView", 0}, {"componentType", 5126}, {"count", box.positions.size()},
                    {"type", "VEC3"}};
  positions["min"] = json::array({-0.1, -0.1, -0.1});
  positions["max"] = json::array({0.1, 0.1, 0.1});
  json indices = {{"bufferView", 1}, {"componentType", 5125}, {"count", box.indices.size()},
                  {"type", "SCALAR"}};
  g["accessors"] = json::array({positions, indices});
  return g.dump();
}

TEST(Simulate, WritesTheFarFieldAndAReportThatCloses) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations", "3",
                  "--face-size", "16"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("iteration"), std::string::npos);  // no progress unless stderr is a terminal
  EXPECT_NE(r.out.find("60000 photons in 3 iterations"), std::string::npos) << r.out;

  const auto report = nlohmann::json::parse(test::read_file(out / "report.json"));
  EXPECT_EQ(report["photons_emitted"], 60000);
  EXPECT_EQ(report["photons_emitted"].get<std::uint64_t>(),
            report["photons_escaped"].get<std::uint64_t>() + report["photons_absorbed"].get<std::uint64_t>() +
                report["photons_cutoff"].get<std::uint64_t>());
  EXPECT_NEAR(report["emitted_lm"].get<double>(), 1000.0, 1e-9);
  EXPECT_TRUE(report["ledger"]["photons_close"].get<bool>());
  EXPECT_GT(report["photons_per_s"].get<double>(), 0.0);
  EXPECT_EQ(report["settings"]["face_size"], 16);
  EXPECT_EQ(report["program"]["name"], "gonio");

  auto image = io::read_exr((out / "farfield.exr").string());
  ASSERT_TRUE(image.ok()) << image.error().message;
  auto field = io::far_field_from_image(*image, "farfield.exr");
  ASSERT_TRUE(field.ok());
  EXPECT_EQ(field->total_photons(), report["photons_escaped"].get<std::uint64_t>());
  EXPECT_NEAR(field->total_flux_lm(), report["escaped_lm"].get<double>(), 1e-4 * 1000.0);
  // The box is open at the bottom only: more light goes down than up.
  double down = 0.0, up = 0.0;
  for (std::size_t t = 0; t < field->texel_count(); ++t) {
    const Vec3 d = field->grid().texel_direction(t);
    (d.y < 0 ? down : up) += field->flux_lm(t);
  }
  EXPECT_GT(down, 0.9 * field->total_flux_lm());
}

TEST(Simulate, SameSeedSameBytesWithOneOrTwoThreads) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  for (const char* t : {"1", "2"}) {
    auto r = gonio({"simulate", model.string(), "--out", (dir / t).string(), "--photons", "30000", "--iterations", "2",
                    "--threads", t, "--seed", "42", "--face-size", "16"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  EXPECT_EQ(test::read_file(dir / "1" / "farfield.exr"), test::read_file(dir / "2" / "farfield.exr"));
  auto a = nlohmann::json::parse(test::read_file(dir / "1" / "report.json"));
  auto b = nlohmann::json::parse(test::read_file(dir / "2" / "report.json"));
  EXPECT_EQ(a["meshes"], b["meshes"]);
  EXPECT_EQ(a["escaped_lm"], b["escaped_lm"]);
}

TEST(Simulate, BadInputsAndUsage) {
  test::TempDir dir;
  auto r = gonio({"simulate", (dir / "missing.gltf").string(), "--out", (dir / "o").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("gonio: "), std::string::npos);
  EXPECT_NE(r.err.find("missing.gltf"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "o" / "report.json"));

  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  EXPECT_EQ(gonio({"simulate", model.string()}).exit_code, 2);  // no --out
  EXPECT_EQ(gonio({"simulate", model.string(), "--out", "x", "--photons", "0"}).exit_code, 2);
  EXPECT_EQ(gonio({"simulate", model.string(), "--out", "x", "--threads", "-1"}).exit_code, 2);
  EXPECT_EQ(gonio({"simulate", model.string(), "--out", "x", "--bogus"}).exit_code, 2);

  test::write_file(dir / "broken.gltf", "{ not json");
  r = gonio({"simulate", (dir / "broken.gltf").string(), "--out", (dir / "o").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("broken.gltf"), std::string::npos);

  // An output directory that cannot be created.
  test::write_file(dir / "file", "x");
  r = gonio({"simulate", model.string(), "--out", (dir / "file" / "sub").string(), "--photons", "1000",
             "--iterations", "1"});
  EXPECT_EQ(r.exit_code, 1);
}

TEST(Simulate, PreviewFilesFollowEveryIteration) {
  test::TempDir dir;
  const auto model = dir / "shade.gltf";
  test::write_file(model, shade_model());
  const auto out = dir / "out";
  // Without filtering the preview is the raw far field, texel for texel.
  auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations", "2",
                  "--face-size", "16", "--preview", "--filter", "none"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto raw = io::read_exr((out / "farfield.exr").string());
  const auto preview = io::read_exr((out / "preview.exr").string());
  ASSERT_TRUE(raw.ok() && preview.ok());
  ASSERT_NE(raw->find_float("Y"), nullptr);
  ASSERT_NE(preview->find_float("Y"), nullptr);
  EXPECT_EQ(raw->find_float("Y")->values, preview->find_float("Y")->values);
  EXPECT_EQ(test::read_file(out / "preview.png").substr(1, 3), "PNG");
  const auto report = nlohmann::json::parse(test::read_file(out / "report.json"));
  EXPECT_NEAR(report["preview"]["flux_lm"].get<double>(), report["escaped_lm"].get<double>(),
              1e-6 * report["escaped_lm"].get<double>());

  // The default filter smooths but keeps the flux within a few percent.
  r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations", "1",
             "--face-size", "16", "--preview"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto filtered = nlohmann::json::parse(test::read_file(out / "report.json"));
  EXPECT_NEAR(filtered["preview"]["flux_lm"].get<double>(), filtered["escaped_lm"].get<double>(),
              0.05 * filtered["escaped_lm"].get<double>());

  EXPECT_EQ(gonio({"simulate", model.string(), "--out", out.string(), "--preview", "--adaptive", "--no-adaptive"})
                .exit_code,
            2);
  EXPECT_EQ(gonio({"simulate", model.string(), "--out", out.string(), "--preview", "--filter", "box"}).exit_code, 2);
}

TEST(Simulate, HelpNamesEveryOption) {
  auto r = gonio({"simulate", "--help"});
  EXPECT_EQ(r.exit_code, 0);
  for (const char* o : {"--photons", "--iterations", "--seed", "--threads", "--max-bounces", "--face-size", "--out"})
    EXPECT_NE(r.out.find(o), std::string::npos) << o;
}

}  // namespace
}  // namespace gonio
