// What a model is read from (model_files: the files gonio watch watches) and
// the CAD options' checks (check_model_input). No OpenCASCADE needed: only
// the sidecar is read.
#include "tools/run/model_input.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "io/model/cad.h"
#include "tests/support/test_support.h"

namespace gonio::cli {
namespace {

namespace fs = std::filesystem;

// A CAD model's files: the model, its sidecar, and the sidecar's profile and
// ray file resolved against the sidecar's folder (not the model's), each
// once. A watch that missed the sidecar would not rerun when a material is
// edited; one that resolved against the model's folder would watch nothing.
TEST(ModelFiles, ACadModelsSidecarAndItsProfilesAndRayFiles) {
  test::TempDir dir;
  fs::create_directories(dir / "optics");
  const std::string model = (dir / "lamp.step").string();
  const std::string sidecar = (dir / "optics" / "lamp.toml").string();
  test::write_file(sidecar, R"(
[[emitters]]
name = "a"
position = [0, 0, 0]
profile = "led.ies"

[[emitters]]
name = "b"
position = [1, 0, 0]
profile = "led.ies"

[[emitters]]
name = "c"
position = [2, 0, 0]
ray_file = "rays/cob.tm25ray"
)");
  ModelInputOptions options;
  options.parts_file = sidecar;
  EXPECT_EQ(model_files(model, options),
            (std::vector<std::string>{model, sidecar, (dir / "optics" / "led.ies").string(),
                                      (dir / "optics" / "rays" / "cob.tm25ray").string()}));
}

// Without --parts the sidecar beside the model is watched even before it
// exists (writing it then starts a run), and one that cannot be read adds
// nothing but itself.
TEST(ModelFiles, TheDefaultSidecarIsWatchedBeforeItExists) {
  test::TempDir dir;
  const std::string model = (dir / "Lamp.v2.STP").string();
  const std::string sidecar = (dir / "Lamp.v2.gonio.toml").string();
  EXPECT_EQ(model_files(model), (std::vector<std::string>{model, sidecar}));
  test::write_file(sidecar, "this is [not TOML");
  EXPECT_EQ(model_files(model), (std::vector<std::string>{model, sidecar}));
}

// A glTF model that cannot be read: just itself.
TEST(ModelFiles, AnUnreadableGltfModelIsJustItself) {
  test::TempDir dir;
  const std::string model = (dir / "lamp.glb").string();
  EXPECT_EQ(model_files(model), std::vector<std::string>{model});
}

// A .step model goes to the CAD reader, whichever way gonio was built: one
// without OpenCASCADE (GONIO_OCCT=OFF) refuses it saying so and naming the
// file; one with it reads it and names the file and what is wrong. A
// dispatch that sent it to the glTF reader would say "not glTF" instead.
TEST(LoadModel, AStepModelGoesToTheCadReaderOrIsRefusedByABuildWithoutIt) {
  test::TempDir dir;
  const std::string model = (dir / "lamp.step").string();
  test::write_file(model, "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\nENDSEC;\nEND-ISO-10303-21;\n");
  ModelLoad loaded = load_model(model);
  ASSERT_TRUE(loaded.error.has_value());
  EXPECT_FALSE(loaded.scene.has_value());
  const std::string message = to_string(*loaded.error);
  EXPECT_NE(message.find(model), std::string::npos) << message;
  EXPECT_EQ(message.find("glTF model"), std::string::npos) << message;
  if (io::cad_supported())
    EXPECT_NE(message.find("not a readable STEP file"), std::string::npos) << message;
  else
    EXPECT_NE(message.find("built without OpenCASCADE"), std::string::npos) << message;
}

TEST(CheckModelInput, CadOptionsNeedACadModelAndATessellationThatParses) {
  ModelInputOptions o;
  EXPECT_TRUE(check_model_input(o, {"a.glb"}).ok());
  o.tessellation = "1.5";
  EXPECT_TRUE(check_model_input(o, {"a.glb", "b.step"}).ok());  // bench: for the CAD one
  const Status gltf_only = check_model_input(o, {"a.glb", "b.gltf"});
  ASSERT_FALSE(gltf_only.ok());
  EXPECT_NE(gltf_only.error().message.find("--tessellation"), std::string::npos);
  o.tessellation.clear();
  o.parts_file = "x.toml";
  ASSERT_FALSE(check_model_input(o, {"a.glb"}).ok());
  EXPECT_NE(check_model_input(o, {"a.glb"}).error().message.find("--parts"), std::string::npos);
  EXPECT_TRUE(check_model_input(o, {"a.IGS"}).ok());
  o.tessellation = "0";
  EXPECT_FALSE(check_model_input(o, {"a.step"}).ok());
  o.tessellation = "2,0.01";
  EXPECT_TRUE(check_model_input(o, {"a.step"}).ok());
}

}  // namespace
}  // namespace gonio::cli
