// The model checks' cache (io/model/model_check_cache.h) through check_model: an
// unchanged mesh is not checked again, an edited model only in the parts
// that changed, anything else in the cache folder is ignored, and the
// results do not depend on where they came from.
#include "io/model/model_check_cache.h"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "io/model/model_check.h"
#include "sim/shapes.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

// Three meshes: a clean glass sphere large enough for an entry of its own
// (kOwnEntryTriangles), an open glass box (open-volume) and a reflector with
// a degenerate triangle and two crossing triangles, which share one.
sim::SceneDesc scene_with_findings() {
  sim::SceneDesc s;
  s.name = "model.gltf";
  sim::Material glass;
  glass.name = "glass";
  glass.dielectric = 1.0;
  sim::Material paint;
  paint.name = "paint";
  paint.diffuse_reflect = 0.8;
  s.materials = {glass, paint};

  sim::Mesh sphere = sim::sphere(0.05, 64, 40);
  sphere.name = "sphere";
  sphere.material = 0;
  sim::Mesh box = sim::box(0.1, 0.1, 0.1);
  box.indices.resize(box.indices.size() - 6);
  box.name = "box";
  box.material = 0;
  sim::Mesh reflector;
  reflector.name = "reflector";
  reflector.material = 1;
  reflector.positions = {{0, 0, 0}, {2, 0, -1}, {2, 0, 1}, {2, -1, 0}, {2, 1, 0}, {1, 0, -0.5f}};
  reflector.indices = {0, 1, 2, 0, 3, 4, 0, 5, 1};  // crossing pair; 0-5-1 collinear
  s.meshes = {sphere, box, reflector};
  return s;
}

std::vector<std::string> texts(const std::vector<Finding>& findings) {
  std::vector<std::string> out;
  for (const Finding& f : findings)
    out.push_back(std::string(to_string(f.severity)) + " " + f.code + " " + f.message + " @" + f.where.file);
  return out;
}

std::vector<std::filesystem::path> files_in(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) out.push_back(e.path());
  return out;
}

// The file name of the entry holding these meshes.
std::string entry_of(const sim::SceneDesc& s, const std::vector<std::size_t>& meshes) {
  CheckGroup g;
  for (std::size_t i : meshes) {
    g.meshes.push_back(i);
    g.refractive.push_back(s.materials[s.meshes[i].material].dielectric > 0.0);
  }
  return cached_checks_name(check_group_key(s, g));
}

std::vector<std::string> names_in(const std::filesystem::path& dir) {
  std::vector<std::string> out;
  for (const auto& p : files_in(dir)) out.push_back(p.filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(ModelCheckCache, AnUnchangedModelIsNotCheckedAgain) {
  test::TempDir dir;
  ModelCheckOptions options;
  options.cache_dir = (dir / "cache").string();
  const sim::SceneDesc scene = scene_with_findings();
  const std::vector<Finding> uncached = check_model(scene);
  ASSERT_EQ(uncached.size(), 3u);  // open-volume, degenerate-triangle, self-intersection

  ModelCheckStats first, second;
  const std::vector<Finding> cold = check_model(scene, options, &first);
  EXPECT_EQ(first.meshes, 3u);
  EXPECT_EQ(first.meshes_from_cache, 0u);
  // The sphere's entry and the small meshes' one, no temporary file left behind.
  ASSERT_GE(scene.meshes[0].triangle_count(), kOwnEntryTriangles);
  ASSERT_LT(scene.meshes[1].triangle_count() + scene.meshes[2].triangle_count(), kOwnEntryTriangles);
  std::vector<std::string> expected_names = {entry_of(scene, {0}), entry_of(scene, {1, 2})};
  std::sort(expected_names.begin(), expected_names.end());
  EXPECT_EQ(names_in(dir / "cache"), expected_names);
  const std::vector<Finding> warm = check_model(scene, options, &second);
  EXPECT_EQ(second.meshes_from_cache, 3u);
  EXPECT_EQ(texts(cold), texts(uncached));
  EXPECT_EQ(texts(warm), texts(uncached));

  // The entry is what is read: an edited (well-formed) detail comes back.
  const std::filesystem::path box_entry = dir / "cache" / entry_of(scene, {1, 2});
  std::string bytes = test::read_file(box_entry);
  const std::string boundary = "boundary edges";
  const auto at = bytes.find(boundary);
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, boundary.size(), "BOUNDARY EDGES");
  test::write_file(box_entry, bytes);
  bool edited = false;
  for (const Finding& f : check_model(scene, options))
    edited = edited || f.message.find("BOUNDARY EDGES") != std::string::npos;
  EXPECT_TRUE(edited);

  // Names are not part of the key: a renamed mesh keeps its entry and is
  // named anew.
  sim::SceneDesc renamed = scene;
  renamed.meshes[1].name = "cover";
  ModelCheckStats third;
  const auto r = check_model(renamed, options, &third);
  EXPECT_EQ(third.meshes_from_cache, 3u);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_NE(r[0].message.find("mesh 'cover' (material 'glass')"), std::string::npos) << r[0].message;
}

TEST(ModelCheckCache, ChangedGeometryOrMaterialKindIsCheckedAgain) {
  test::TempDir dir;
  ModelCheckOptions options;
  options.cache_dir = dir.path().string();
  sim::SceneDesc scene = scene_with_findings();
  check_model(scene, options);

  // The large part moved: it is checked again, the small ones come from the
  // cache.
  sim::SceneDesc moved = scene;
  moved.meshes[0].positions[0].x += 1e-6f;
  ModelCheckStats a;
  EXPECT_EQ(texts(check_model(moved, options, &a)), texts(check_model(moved)));
  EXPECT_EQ(a.meshes_from_cache, 2u);

  // The box no longer refractive: its open volume is no longer an error. The
  // small meshes are checked again together; the sphere's entry stands.
  sim::SceneDesc painted = scene;
  painted.meshes[1].material = 1;
  ModelCheckStats b;
  const auto findings = check_model(painted, options, &b);
  EXPECT_EQ(b.meshes_from_cache, 1u);
  for (const Finding& f : findings) EXPECT_NE(f.code, "open-volume");
  EXPECT_EQ(texts(findings), texts(check_model(painted)));
  EXPECT_EQ(files_in(dir.path()).size(), 4u);
}

TEST(ModelCheckCache, ManySmallPartsShareOneEntry) {
  test::TempDir dir;
  ModelCheckOptions options;
  options.cache_dir = dir.path().string();
  sim::SceneDesc scene = scene_with_findings();
  scene.meshes.erase(scene.meshes.begin());  // no large part
  for (int k = 0; k < 300; ++k) {
    sim::Mesh part = sim::box(0.01, 0.01, 0.01);
    sim::transform(part, sim::translation({0.02 * k, 0.0, 0.0}));
    part.name = "screw";
    part.material = 1;
    scene.meshes.push_back(part);
  }
  ModelCheckStats cold, warm;
  const auto first = check_model(scene, options, &cold);
  EXPECT_EQ(files_in(dir.path()).size(), 1u);
  EXPECT_EQ(texts(check_model(scene, options, &warm)), texts(first));
  EXPECT_EQ(warm.meshes_from_cache, scene.meshes.size());
  EXPECT_EQ(texts(first), texts(check_model(scene)));
}

TEST(ModelCheckCache, ACorruptEntryIsIgnoredAndRewritten) {
  const sim::SceneDesc scene = scene_with_findings();
  const std::vector<std::string> expected = texts(check_model(scene));
  const std::string name = entry_of(scene, {1, 2});  // with the open glass box's error
  test::TempDir good_dir;
  ModelCheckOptions good;
  good.cache_dir = good_dir.path().string();
  check_model(scene, good);
  const std::string valid = test::read_file(good_dir / name);

  auto replace = [&](std::string s, const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) s.replace(at, from.size(), to);
    return s;
  };
  const std::vector<std::pair<std::string, std::string>> corrupt = {
      {"empty", ""},
      {"truncated", valid.substr(0, valid.size() / 2)},
      {"binary garbage", std::string("\x00\xff\x13\x37", 4)},
      {"not an object", "[1, 2, 3]\n"},
      {"another revision", replace(valid, "\"revision\":" + std::to_string(kModelCheckRevision), "\"revision\":999")},
      {"another format", replace(valid, "gonio mesh check", "something else")},
      {"wrong vertex count", replace(valid, "\"vertices\":", "\"vertices\":1")},
      {"unknown severity", replace(valid, "\"severity\":\"error\"", "\"severity\":\"fatal\"")},
      {"a count as text", replace(valid, "\"triangles\":", "\"triangles\":\"12\",\"x\":")},
      {"findings missing", replace(valid, "\"findings\":", "\"old\":")},
      {"another group's entry", test::read_file(good_dir / entry_of(scene, {0}))},
      {"a mesh missing", replace(valid, "\"meshes\":[", "\"meshes\":[],\"old\":[")},
  };
  for (const auto& [what, bytes] : corrupt) {
    test::TempDir dir;
    ModelCheckOptions options;
    options.cache_dir = dir.path().string();
    test::write_file(dir / name, bytes);
    ModelCheckStats stats;
    EXPECT_EQ(texts(check_model(scene, options, &stats)), expected) << what;
    EXPECT_EQ(stats.meshes_from_cache, 0u) << what;  // the sphere's entry is not there
    EXPECT_EQ(test::read_file(dir / name), valid) << what << ": the entry is rewritten";
  }
  // A folder in the entry's place, and a cache folder that is a file: the
  // checks run all the same.
  test::TempDir dir;
  std::filesystem::create_directories(dir / name);
  ModelCheckOptions options;
  options.cache_dir = dir.path().string();
  EXPECT_EQ(texts(check_model(scene, options)), expected);
  test::write_file(dir / "file", "x");
  options.cache_dir = (dir / "file").string();
  EXPECT_EQ(texts(check_model(scene, options)), expected);
}

}  // namespace
}  // namespace gonio::io
