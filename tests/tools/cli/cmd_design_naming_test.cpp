// A design file read as a model, as a user runs it: its outputs are named
// after the file without ".design.toml" (lamp.ies for lamp.design.toml, as
// `gonio design export` names its files), the TM-25 ray file's light source
// too, and report.json describes it in a "design_file" section of its own
// (its parts by kind, its variables' values, the meshes) rather than in
// "cad", which stays a STEP or IGES import's.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/photometric/tm25.h"
#include "tests/support/test_support.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

// A mirror dish about a point emitter; the dish's radius a variable.
const char* kLamp = R"(length_unit = "mm"
[materials.mirror]
ks = 1
mx = 0.1
my = 0.1
f0 = 1
[[emitters]]
name = "led"
position = [0, 0, 0]
flux_lm = 1000
[[reflectors]]
name = "dish"
material = "mirror"
profile = "conic"
radius = { value = 20, min = 10, max = 40 }
conic = -1
vertex = 10
aperture = [4, 30]
)";

TEST(DesignNaming, SimulateNamesTheOutputsAfterTheDesignWithoutItsSuffix) {
  test::TempDir dir;
  test::write_file(dir / "lamp.design.toml", kLamp);
  const fs::path out = dir / "out";
  test::ProcessResult r =
      gonio({"simulate", (dir / "lamp.design.toml").string(), "--out", out.string(), "--photons", "20000",
             "--iterations", "1", "--format", "ies,ldt,tm25", "--tm25-rays", "1000", "--no-cache"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const char* f : {"lamp.ies", "lamp.ldt", "lamp.tm25ray", "report.json"}) EXPECT_TRUE(fs::exists(out / f)) << f;
  for (const char* f : {"lamp.design.ies", "lamp.design.ldt", "lamp.design.tm25ray"})
    EXPECT_FALSE(fs::exists(out / f)) << f;
  Result<io::Tm25RaySet> rays = io::read_tm25_file((out / "lamp.tm25ray").string());
  ASSERT_TRUE(rays.ok()) << rays.error().message;
  EXPECT_EQ(rays->header.light_source, "lamp");

  // --name still wins.
  r = gonio({"simulate", (dir / "lamp.design.toml").string(), "--out", (dir / "named").string(), "--photons", "20000",
             "--iterations", "1", "--format", "ies", "--no-cache", "--name", "dish"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_TRUE(fs::exists(dir / "named" / "dish.ies"));
}

// gonio bench names each model's folder after the same stem: a design file
// and a glTF model of one name are refused before anything is read (with
// the design's old stem "lamp.design" they would not have been).
TEST(DesignNaming, BenchTakesTheSameStem) {
  test::TempDir dir;
  fs::create_directories(dir / "b");
  test::write_file(dir / "b" / "lamp.design.toml", kLamp);
  test::write_file(dir / "lamp.gltf", "");
  const test::ProcessResult r = gonio({"bench", (dir / "b" / "lamp.design.toml").string(),
                                       (dir / "lamp.gltf").string(), "--out", (dir / "o").string()});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("two models named 'lamp'"), std::string::npos) << r.err;
}

TEST(DesignNaming, ReportDescribesADesignFileInItsOwnSection) {
  test::TempDir dir;
  test::write_file(dir / "lamp.design.toml", kLamp);
  test::ProcessResult r = gonio({"simulate", (dir / "lamp.design.toml").string(), "--out", (dir / "out").string(),
                                 "--photons", "20000", "--iterations", "1", "--format", "ies", "--no-cache"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const nlohmann::json report = nlohmann::json::parse(test::read_file(dir / "out" / "report.json"));
  EXPECT_FALSE(report.contains("cad")) << "a design file is no CAD import";
  ASSERT_TRUE(report.contains("design_file")) << report.dump(2);
  const nlohmann::json& d = report.at("design_file");
  EXPECT_EQ(d.at("file"), (dir / "lamp.design.toml").string());
  EXPECT_EQ(d.at("length_unit"), "mm");
  EXPECT_EQ(d.at("kinds").at("reflectors"), 1);
  EXPECT_EQ(d.at("kinds").at("emitters"), 1);
  for (const char* k : {"lenses", "troughs", "covers", "parts"}) EXPECT_EQ(d.at("kinds").at(k), 0) << k;
  EXPECT_DOUBLE_EQ(d.at("variables").at("reflectors[0].radius").get<double>(), 20.0);
  EXPECT_EQ(d.at("variables").size(), 1u);
  EXPECT_EQ(d.at("parts"), 1);
  EXPECT_GT(d.at("triangles_unique").get<int>(), 1000);
  EXPECT_EQ(d.at("triangles_unique"), d.at("triangles_placed"));
  ASSERT_EQ(d.at("per_part").size(), 1u);
  EXPECT_EQ(d.at("per_part")[0].at("name"), "dish");
  EXPECT_EQ(d.at("per_part")[0].at("triangles"), d.at("triangles_unique"));
  EXPECT_TRUE(d.at("tessellation").at("exact_normals").is_boolean());
}

}  // namespace
}  // namespace gonio
