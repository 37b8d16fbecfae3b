// Tests of the glTF loader against models written here with nlohmann::json,
// independently of tinygltf.
#include "io/model/gltf.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <numbers>

#include "io/model/gltf_lights.h"
#include "io/photometric/ies.h"
#include "io/photometric/ldt.h"
#include "io/photometric/tm25.h"
#include "photometry/colour.h"
#include "photometry/flux.h"
#include "photometry/reflectance.h"
#include "sim/bsdfs/library.h"
#include "sim/bsdfs/tabulated_bsdf.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

using nlohmann::json;
constexpr double kPi = std::numbers::pi;

// A glTF document under construction with one binary buffer.
class Doc {
 public:
  enum class Form { ExternalBin, DataUri, Glb };

  json j;
  std::string bin;

  Doc() {
    j["asset"] = {{"version", "2.0"}, {"generator", "gonio tests"}};
    j["scene"] = 0;
    j["scenes"] = json::array({json{{"nodes", json::array()}}});
    j["nodes"] = json::array();
    j["meshes"] = json::array();
    j["accessors"] = json::array();
    j["bufferViews"] = json::array();
  }

  int view(const void* data, std::size_t bytes) {
    while (bin.size() % 4) bin.push_back('\0');
    const std::size_t offset = bin.size();
    bin.append(static_cast<const char*>(data), bytes);
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    return static_cast<int>(j["bufferViews"].size() - 1);
  }

  int accessor(int view_index, int component_type, std::size_t count, const char* type) {
    j["accessors"].push_back({{"bufferView", view_index},
                              {"componentType", component_type},
                              {"count", count},
                              {"type", type}});
    return static_cast<int>(j["accessors"].size() - 1);
  }

  int vec3(const std::vector<float>& xyz) {
    return accessor(view(xyz.data(), xyz.size() * 4), 5126, xyz.size() / 3, "VEC3");
  }
  int vec4(const std::vector<float>& xyzw) {
    return accessor(view(xyzw.data(), xyzw.size() * 4), 5126, xyzw.size() / 4, "VEC4");
  }
  int indices(const std::vector<std::uint32_t>& idx) {
    return accessor(view(idx.data(), idx.size() * 4), 5125, idx.size(), "SCALAR");
  }
  int indices16(const std::vector<std::uint16_t>& idx) {
    return accessor(view(idx.data(), idx.size() * 2), 5123, idx.size(), "SCALAR");
  }

  // A mesh with one primitive; returns the mesh index.
  int mesh(const std::vector<float>& positions, const std::vector<std::uint32_t>& idx,
           int material = -1, int mode = 4, const std::string& name = "",
           const std::vector<float>& normals = {}) {
    json prim = {{"attributes", {{"POSITION", vec3(positions)}}}, {"mode", mode}};
    if (!idx.empty()) prim["indices"] = indices(idx);
    if (material >= 0) prim["material"] = material;
    if (!normals.empty()) prim["attributes"]["NORMAL"] = vec3(normals);
    json m = {{"primitives", json::array({prim})}};
    if (!name.empty()) m["name"] = name;
    j["meshes"].push_back(m);
    return static_cast<int>(j["meshes"].size() - 1);
  }

  int node(json n, bool root = true) {
    j["nodes"].push_back(std::move(n));
    const int i = static_cast<int>(j["nodes"].size() - 1);
    if (root) j["scenes"][0]["nodes"].push_back(i);
    return i;
  }

  int material(json m) {
    if (!j.contains("materials")) j["materials"] = json::array();
    j["materials"].push_back(std::move(m));
    return static_cast<int>(j["materials"].size() - 1);
  }

  void use(const std::string& extension) {
    if (!j.contains("extensionsUsed")) j["extensionsUsed"] = json::array();
    for (const auto& e : j["extensionsUsed"])
      if (e == extension) return;
    j["extensionsUsed"].push_back(extension);
  }

  int khr_light(json l) {
    use("KHR_lights_punctual");
    j["extensions"]["KHR_lights_punctual"]["lights"].push_back(std::move(l));
    return static_cast<int>(j["extensions"]["KHR_lights_punctual"]["lights"].size() - 1);
  }

  // A node with an isotropic KHR point light of intensity I at p.
  int point_light(double intensity, std::array<double, 3> p = {0, 0, 0}) {
    const int l = khr_light({{"type", "point"}, {"intensity", intensity}});
    return node({{"name", "lamp"},
                 {"translation", {p[0], p[1], p[2]}},
                 {"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}});
  }

  std::string write(const test::TempDir& dir, const std::string& stem,
                    Form form = Form::ExternalBin) const {
    json doc = j;
    std::string data = bin;
    while (data.size() % 4) data.push_back('\0');
    if (!data.empty()) {
      json buffer = {{"byteLength", bin.size()}};
      if (form == Form::ExternalBin) {
        buffer["uri"] = stem + ".bin";
        test::write_file(dir / (stem + ".bin"), bin);
      } else if (form == Form::DataUri) {
        buffer["uri"] = "data:application/octet-stream;base64," + base64(bin);
      }
      doc["buffers"] = json::array({buffer});
    }
    if (doc["accessors"].empty()) doc.erase("accessors");
    if (doc["bufferViews"].empty()) doc.erase("bufferViews");
    if (doc["meshes"].empty()) doc.erase("meshes");
    if (form != Form::Glb) {
      const std::string path = (dir / (stem + ".gltf")).string();
      test::write_file(path, doc.dump(2));
      return path;
    }
    const std::string path = (dir / (stem + ".glb")).string();
    test::write_file(path, glb(doc.dump(), data.empty() ? std::string() : data));
    return path;
  }

  static std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
      const auto n = static_cast<std::uint32_t>(static_cast<unsigned char>(in[i]) << 16 |
                                                static_cast<unsigned char>(in[i + 1]) << 8 |
                                                static_cast<unsigned char>(in[i + 2]));
      for (int k = 3; k >= 0; --k) out.push_back(t[(n >> (6 * k)) & 63]);
    }
    if (i + 1 == in.size()) {
      const auto n = static_cast<std::uint32_t>(static_cast<unsigned char>(in[i]) << 16);
      out += {t[(n >> 18) & 63], t[(n >> 12) & 63], '=', '='};
    } else if (i + 2 == in.size()) {
      const auto n = static_cast<std::uint32_t>(static_cast<unsigned char>(in[i]) << 16 |
                                                static_cast<unsigned char>(in[i + 1]) << 8);
      out += {t[(n >> 18) & 63], t[(n >> 12) & 63], t[(n >> 6) & 63], '='};
    }
    return out;
  }

  static std::string glb(std::string json_text, std::string data) {
    while (json_text.size() % 4) json_text.push_back(' ');
    auto u32 = [](std::uint32_t v) {
      std::string s(4, '\0');
      for (int k = 0; k < 4; ++k) s[static_cast<std::size_t>(k)] = static_cast<char>((v >> (8 * k)) & 0xFF);
      return s;
    };
    std::string body = u32(static_cast<std::uint32_t>(json_text.size())) + "JSON" + json_text;
    if (!data.empty()) body += u32(static_cast<std::uint32_t>(data.size())) + std::string("BIN\0", 4) + data;
    return "glTF" + u32(2) + u32(static_cast<std::uint32_t>(12 + body.size())) + body;
  }
};

const std::vector<float> kQuad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};  // in z = 0, facing +Z
const std::vector<std::uint32_t> kQuadIdx = {0, 1, 2, 0, 2, 3};

bool has_code(const std::vector<Finding>& findings, const std::string& code) {
  for (const Finding& f : findings)
    if (f.code == code) return true;
  return false;
}

// The models the tests load are seeds for tests/fuzz/gltf_fuzzer.cpp.
void offer_seed(const std::string& path) {
  if (std::filesystem::is_regular_file(path)) test::offer_fuzz_seed("gltf", test::read_file(path));
}

sim::SceneDesc load_ok(const std::string& path, std::vector<Finding>* findings = nullptr) {
  offer_seed(path);
  Result<sim::SceneDesc> r = load_gltf(path, findings);
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : to_string(r.error()));
  return r.ok() ? std::move(r).value() : sim::SceneDesc{};
}

// The error's text, and a check that it names the file.
std::string load_error(const std::string& path) {
  offer_seed(path);
  Result<sim::SceneDesc> r = load_gltf(path, nullptr);
  EXPECT_FALSE(r.ok()) << path;
  if (r.ok()) return "";
  EXPECT_EQ(r.error().where.file, path);
  return r.error().message;
}

#define EXPECT_CONTAINS(haystack, needle) \
  EXPECT_NE(std::string(haystack).find(needle), std::string::npos) << (haystack)

Vec3 pos(const sim::Mesh& m, std::size_t i) {
  return {m.positions[i].x, m.positions[i].y, m.positions[i].z};
}

Vec3 face_normal(const sim::Mesh& m, std::size_t t) {
  const Vec3 a = pos(m, m.indices[3 * t]), b = pos(m, m.indices[3 * t + 1]),
             c = pos(m, m.indices[3 * t + 2]);
  return normalize(cross(b - a, c - a));
}

void expect_near(const Vec3& a, const Vec3& b, double tol = 1e-5) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

// --- containers ------------------------------------------------------------

TEST(Gltf, SameSceneFromExternalBinDataUriAndGlb) {
  test::TempDir dir;
  Doc d;
  d.node({{"name", "plate"}, {"mesh", d.mesh(kQuad, kQuadIdx, -1, 4, "quad")}});
  d.point_light(100.0, {0, 1, 0});
  for (Doc::Form form : {Doc::Form::ExternalBin, Doc::Form::DataUri, Doc::Form::Glb}) {
    std::vector<Finding> findings;
    const sim::SceneDesc s = load_ok(d.write(dir, "m" + std::to_string(static_cast<int>(form)), form),
                                     &findings);
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].positions.size(), 4u);
    EXPECT_EQ(s.meshes[0].indices, kQuadIdx);
    expect_near(pos(s.meshes[0], 2), {1, 1, 0});
    EXPECT_EQ(s.meshes[0].name, "plate/quad/0");
    ASSERT_EQ(s.emitters.size(), 1u);
    EXPECT_EQ(s.emitters[0].kind, sim::Emitter::Kind::Point);
    EXPECT_EQ(s.emitters[0].profile, nullptr);
    EXPECT_NEAR(s.emitters[0].flux_lm, 4 * kPi * 100.0, 1e-9);
    expect_near(s.emitters[0].position, {0, 1, 0});
    EXPECT_TRUE(has_code(findings, "default-material"));  // the quad has no material
    ASSERT_EQ(s.materials.size(), 1u);
  }
}

// --- geometry --------------------------------------------------------------

TEST(Gltf, ChildTransformsComposeWithTheParents) {
  test::TempDir dir;
  const double h = std::sqrt(0.5);
  for (bool as_matrix : {false, true}) {
    Doc d;
    const int m = d.mesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 1, 2}, -1, 4, "tri");
    const int child = d.node({{"name", "child"},
                              {"mesh", m},
                              {"translation", {1, 0, 0}},
                              {"scale", {1, 1, 3}}},
                             false);
    json parent = {{"name", "parent"}, {"children", {child}}};
    if (as_matrix) {
      // T(1,2,3) · R_y(90°) · S(2): columns of the linear part are
      // R(2e_x) = (0,0,−2), R(2e_y) = (0,2,0), R(2e_z) = (2,0,0).
      parent["matrix"] = {0, 0, -2, 0, 0, 2, 0, 0, 2, 0, 0, 0, 1, 2, 3, 1};
    } else {
      parent["translation"] = {1, 2, 3};
      parent["rotation"] = {0, h, 0, h};  // 90° about +Y
      parent["scale"] = {2, 2, 2};
    }
    d.node(parent);
    d.point_light(1.0);
    const sim::SceneDesc s = load_ok(d.write(dir, as_matrix ? "matrix" : "trs"));
    ASSERT_EQ(s.meshes.size(), 1u);
    // p → child (scale, translate) → parent scale 2 → R_y(90°): (x, y, z) ↦ (z, y, −x)
    // → translate (1, 2, 3).
    auto expected = [](Vec3 p) {
      p = Vec3{p.x, p.y, 3 * p.z} + Vec3{1, 0, 0};
      p = 2.0 * p;
      p = Vec3{p.z, p.y, -p.x};
      return p + Vec3{1, 2, 3};
    };
    expect_near(pos(s.meshes[0], 0), expected({0, 0, 0}));
    expect_near(pos(s.meshes[0], 1), expected({1, 0, 0}));
    expect_near(pos(s.meshes[0], 2), expected({0, 1, 0}));
    EXPECT_EQ(s.meshes[0].name, "child/tri/0");
  }
}

TEST(Gltf, MirroringTransformsKeepFrontFacesFront) {
  test::TempDir dir;
  Doc d;
  const std::vector<float> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const int m = d.mesh(kQuad, kQuadIdx, -1, 4, "quad", normals);
  d.node({{"mesh", m}, {"scale", {-1, 1, 1}}});
  d.node({{"mesh", m}, {"scale", {1, 1, -2}}});
  d.point_light(1.0);
  const std::string path = d.write(dir, "mirror");
  // The mesh is placed twice: one instanced mesh, two instances; flattened
  // (by the loader, or from the instanced scene) two world meshes.
  const sim::SceneDesc instanced = load_ok(path);
  ASSERT_EQ(instanced.meshes.size(), 1u);
  EXPECT_TRUE(instanced.meshes[0].instanced);
  ASSERT_EQ(instanced.instances.size(), 2u);
  EXPECT_LT(instanced.instances[0].to_world.determinant(), 0.0);
  Result<sim::SceneDesc> flat_load = load_gltf(path, nullptr, {.instancing = false});
  ASSERT_TRUE(flat_load.ok());
  for (const sim::SceneDesc& s : {sim::flattened(instanced), flat_load.value()}) {
    ASSERT_EQ(s.meshes.size(), 2u);
    EXPECT_TRUE(s.instances.empty());
    for (const sim::Mesh& mesh : s.meshes) {
      EXPECT_FALSE(mesh.instanced);
      ASSERT_EQ(mesh.normals.size(), 4u);
      for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const Vec3 shading{mesh.normals[0].x, mesh.normals[0].y, mesh.normals[0].z};
        EXPECT_NEAR(dot(face_normal(mesh, t), shading), 1.0, 1e-6);
      }
    }
    // x-mirror keeps the normal +Z; z-mirror turns it to −Z.
    EXPECT_NEAR(s.meshes[0].normals[0].z, 1.0f, 1e-6f);
    EXPECT_NEAR(s.meshes[1].normals[0].z, -1.0f, 1e-6f);
    EXPECT_EQ(s.meshes[0].name, "node-0/quad/0");
    EXPECT_EQ(s.meshes[1].name, "node-1/quad/0");
  }
}

TEST(Gltf, StripsAndFansBecomeConsistentlyWoundTriangles) {
  test::TempDir dir;
  Doc d;
  // A zigzag strip in z = 0 whose triangles all face +Z.
  const std::vector<float> strip = {0, 1, 0, 0, 0, 0, 1, 1, 0, 1, 0, 0, 2, 1, 0, 2, 0, 0};
  d.node({{"mesh", d.mesh(strip, {0, 1, 2, 3, 4, 5}, -1, 5, "strip")}});
  // Two strips of two triangles stitched into one by repeating 3 and 4.
  const std::vector<float> two = {0, 1, 0, 0, 0, 0, 1, 1, 0, 1, 0, 0,
                                  3, 1, 0, 3, 0, 0, 4, 1, 0, 4, 0, 0};
  d.node({{"mesh", d.mesh(two, {0, 1, 2, 3, 3, 4, 4, 5, 6, 7}, -1, 5, "stitched")}});
  // A fan around the origin, counter-clockwise seen from +Z, without indices.
  const std::vector<float> fan = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 1, 0};
  d.node({{"mesh", d.mesh(fan, {}, -1, 6, "fan")}});
  d.point_light(1.0);
  const sim::SceneDesc s = load_ok(d.write(dir, "strips"));
  ASSERT_EQ(s.meshes.size(), 3u);
  EXPECT_EQ(s.meshes[0].triangle_count(), 4u);
  EXPECT_EQ(s.meshes[1].triangle_count(), 4u);  // the four stitching triangles are dropped
  EXPECT_EQ(s.meshes[2].triangle_count(), 3u);
  auto area = [](const sim::Mesh& m) {
    double a = 0.0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
      a += 0.5 * length(cross(pos(m, m.indices[3 * t + 1]) - pos(m, m.indices[3 * t]),
                              pos(m, m.indices[3 * t + 2]) - pos(m, m.indices[3 * t])));
    return a;
  };
  EXPECT_NEAR(area(s.meshes[0]), 2.0, 1e-6);
  EXPECT_NEAR(area(s.meshes[1]), 2.0, 1e-6);
  EXPECT_NEAR(area(s.meshes[2]), 1.5, 1e-6);
  for (const sim::Mesh& m : s.meshes)
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
      EXPECT_NEAR(face_normal(m, t).z, 1.0, 1e-6) << m.name << " triangle " << t;
}

TEST(Gltf, PrimitivesSharingAVertexAccessorKeepOnlyTheirVertices) {
  test::TempDir dir;
  Doc d;
  std::vector<float> grid;  // 1000 vertices in a row
  for (int i = 0; i < 1000; ++i) grid.insert(grid.end(), {float(i), float(i % 2), 0.0f});
  const int m = d.mesh(grid, {10, 11, 12});
  json second = d.j["meshes"][m]["primitives"][0];
  second["indices"] = d.indices({500, 502, 501});
  d.j["meshes"][m]["primitives"].push_back(second);
  d.node({{"mesh", m}});
  d.point_light(1.0);
  const sim::SceneDesc s = load_ok(d.write(dir, "shared"));
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].positions.size(), 3u);
  EXPECT_EQ(s.meshes[1].positions.size(), 3u);
  EXPECT_EQ(s.meshes[1].indices, (std::vector<std::uint32_t>{0, 1, 2}));
  expect_near(pos(s.meshes[1], 1), {502, 0, 0});
  expect_near(pos(s.meshes[1], 2), {501, 1, 0});
}

// CAD exporters interleave vertex attributes (one bufferView, byteStride)
// and offset accessors into shared views; the loader reads them in place.
TEST(Gltf, InterleavedAndOffsetAccessorsReadAsPackedOnes) {
  test::TempDir dir;
  const std::vector<float> normals = {0, 0, 1, 0, 0.6f, 0.8f, 0, 0, 1, 0.6f, 0, 0.8f};
  Doc packed;
  packed.node({{"mesh", packed.mesh(kQuad, kQuadIdx, -1, 4, "", normals)}});
  packed.point_light(1.0);
  const sim::SceneDesc a = load_ok(packed.write(dir, "packed"));

  Doc d;
  std::vector<float> interleaved;  // position, normal, one float of padding: 28 bytes a vertex
  for (std::size_t v = 0; v < 4; ++v) {
    interleaved.insert(interleaved.end(), kQuad.begin() + 3 * v, kQuad.begin() + 3 * v + 3);
    interleaved.insert(interleaved.end(), normals.begin() + 3 * v, normals.begin() + 3 * v + 3);
    interleaved.push_back(-7.0f);
  }
  const int vv = d.view(interleaved.data(), interleaved.size() * 4);
  d.j["bufferViews"][vv]["byteStride"] = 28;
  const int pa = d.accessor(vv, 5126, 4, "VEC3");
  const int na = d.accessor(vv, 5126, 4, "VEC3");
  d.j["accessors"][na]["byteOffset"] = 12;
  std::vector<std::uint16_t> idx = {9, 9};  // two indices of another primitive first
  for (std::uint32_t i : kQuadIdx) idx.push_back(static_cast<std::uint16_t>(i));
  const int ia = d.accessor(d.view(idx.data(), idx.size() * 2), 5123, kQuadIdx.size(), "SCALAR");
  d.j["accessors"][ia]["byteOffset"] = 4;
  d.j["meshes"].push_back(
      {{"primitives", json::array({{{"attributes", {{"POSITION", pa}, {"NORMAL", na}}}, {"indices", ia}}})}});
  d.node({{"mesh", 0}});
  d.point_light(1.0);
  const sim::SceneDesc b = load_ok(d.write(dir, "interleaved"));

  ASSERT_EQ(a.meshes.size(), 1u);
  ASSERT_EQ(b.meshes.size(), 1u);
  EXPECT_EQ(b.meshes[0].indices, a.meshes[0].indices);
  ASSERT_EQ(b.meshes[0].positions.size(), 4u);
  ASSERT_EQ(b.meshes[0].normals.size(), 4u);
  for (std::size_t v = 0; v < 4; ++v) {
    expect_near(pos(b.meshes[0], v), pos(a.meshes[0], v), 0.0);
    const sim::Vec3f na_ = a.meshes[0].normals[v], nb = b.meshes[0].normals[v];
    expect_near({nb.x, nb.y, nb.z}, {na_.x, na_.y, na_.z}, 0.0);
  }
  EXPECT_NEAR(b.meshes[0].normals[1].y, 0.6f, 1e-6);

  // A stride that would read the last element past the view is refused.
  d.j["bufferViews"][vv]["byteStride"] = 32;
  EXPECT_CONTAINS(load_error(d.write(dir, "overlong")), "do not fit in bufferView");
}

TEST(Gltf, PointsAndLinesAreErrorsNamingNodeMeshAndPrimitive) {
  test::TempDir dir;
  for (int mode : {0, 1, 2, 3}) {
    Doc d;
    d.node({{"name", "wire"}, {"mesh", d.mesh(kQuad, {0, 1, 2, 3}, -1, mode, "cable")}});
    d.point_light(1.0);
    const std::string message = load_error(d.write(dir, "lines" + std::to_string(mode)));
    EXPECT_CONTAINS(message, "node 'wire'");
    EXPECT_CONTAINS(message, "mesh 'cable'");
    EXPECT_CONTAINS(message, "primitive 0");
    EXPECT_CONTAINS(message, "only triangles");
  }
}

TEST(Gltf, SparseAccessorsAreApplied) {
  test::TempDir dir;
  Doc d;
  const int m = d.mesh({0, 0, 0, 5, 5, 5, 0, 1, 0}, {0, 1, 2});
  const std::vector<std::uint16_t> which = {1};
  const std::vector<float> value = {1, 0, 0};
  const int iv = d.view(which.data(), 2);
  const int vv = d.view(value.data(), 12);
  const int pos_accessor = d.j["meshes"][m]["primitives"][0]["attributes"]["POSITION"];
  d.j["accessors"][pos_accessor]["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", iv}, {"componentType", 5123}}},
      {"values", {{"bufferView", vv}}}};
  d.node({{"mesh", m}});
  d.point_light(1.0);
  const sim::SceneDesc s = load_ok(d.write(dir, "sparse"));
  expect_near(pos(s.meshes[0], 1), {1, 0, 0});
}

TEST(Gltf, UnitScaleAndModelFrameComeFromExtras) {
  test::TempDir dir;
  Doc d;
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx)}, {"translation", {0, 0, 100}}});
  d.point_light(1.0, {0, 0, 50});
  d.j["asset"]["extras"] = {
      {"gonio", {{"unit_m", 0.001}, {"frame", {{"up", {0, 0, 2}}, {"c0", {1, 0, 0.5}}}}}}};
  const sim::SceneDesc s = load_ok(d.write(dir, "mm"));
  expect_near(pos(s.meshes[0], 2), {0.001, 0.001, 0.1});
  expect_near(s.emitters[0].position, {0, 0, 0.05});
  expect_near(s.frame.up, {0, 0, 1}, 1e-12);
  expect_near(s.frame.c0, {1, 0, 0}, 1e-12);
  expect_near(s.frame.c90, {0, 1, 0}, 1e-12);  // up × c0

  // Scene extras win over asset extras; default frame otherwise.
  d.j["scenes"][0]["extras"] = {{"gonio", {{"frame", {{"up", {1, 0, 0}}, {"c0", {0, 1, 0}}}}}}};
  const sim::SceneDesc t = load_ok(d.write(dir, "scene-frame"));
  expect_near(t.frame.up, {1, 0, 0}, 1e-12);
  expect_near(pos(t.meshes[0], 2), {1, 1, 100});  // asset extras (unit_m) not read

  Doc plain;
  plain.point_light(1.0);
  const sim::SceneDesc u = load_ok(plain.write(dir, "plain"));
  expect_near(u.frame.up, {0, 1, 0}, 0);
  expect_near(u.frame.c0, {1, 0, 0}, 0);
  expect_near(u.frame.c90, {0, 0, -1}, 0);

  d.j["scenes"][0]["extras"] = {{"gonio", {{"frame", {{"up", {0, 1, 0}}, {"c0", {0, -3, 0}}}}}}};
  EXPECT_CONTAINS(load_error(d.write(dir, "parallel")), "parallel");
  d.j["scenes"][0]["extras"] = {{"gonio", {{"unit_m", -1}}}};
  EXPECT_CONTAINS(load_error(d.write(dir, "negative-unit")), "unit_m");
}

TEST(Gltf, TheDefaultSceneChoosesTheNodesElseEveryRootIsLoaded) {
  test::TempDir dir;
  Doc d;
  const int m = d.mesh(kQuad, kQuadIdx);
  d.node({{"name", "in-scene"}, {"mesh", m}});
  d.point_light(1.0);
  d.j["nodes"].push_back({{"name", "elsewhere"}, {"mesh", m}});  // root of no scene
  d.j["scenes"].push_back({{"nodes", {2}}});
  const sim::SceneDesc s = load_ok(d.write(dir, "scene0"));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].name, "in-scene/mesh-0/0");

  d.j.erase("scene");
  std::vector<Finding> findings;
  const sim::SceneDesc all = load_ok(d.write(dir, "roots"), &findings);
  // Both roots place the mesh: one instanced mesh, placed twice.
  EXPECT_EQ(all.meshes.size(), 1u);
  EXPECT_EQ(all.instances.size(), 2u);
  EXPECT_EQ(all.placed_triangle_count(), 2 * all.unique_triangle_count());
  EXPECT_TRUE(has_code(findings, "no-default-scene"));

  d.j["scene"] = 7;
  EXPECT_CONTAINS(load_error(d.write(dir, "scene7")), "default scene 7 does not exist");
}

// Images only texture a model: undecodable or missing ones must not stop a
// load (tinygltf would decode them with stb_image).
TEST(Gltf, ImagesAreNeitherDecodedNorRequired) {
  test::TempDir dir;
  Doc d;
  test::write_file(dir / "broken.png", "\x89PNG but not really");
  const std::string junk = "not an image at all";
  const int view = d.view(junk.data(), junk.size());
  d.j["images"] = {{{"uri", "broken.png"}}, {{"uri", "missing.jpg"}},
                   {{"bufferView", view}, {"mimeType", "image/png"}}};
  d.j["textures"] = {{{"source", 0}}};
  const int mat = d.material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx, mat)}});
  d.point_light(1.0);
  std::vector<Finding> findings;
  load_ok(d.write(dir, "images"), &findings);
  EXPECT_TRUE(has_code(findings, "textures-ignored"));
}

// tinygltf 2.7 refuses a spot light without its "spot" object (the extension
// would default the cones); the error must still name the file and say why.
TEST(Gltf, ASpotLightWithoutItsSpotObjectIsAClearError) {
  test::TempDir dir;
  Doc d;
  const int l = d.khr_light({{"type", "spot"}});
  d.node({{"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}});
  EXPECT_CONTAINS(load_error(d.write(dir, "bare-spot")), "Spot light description not found");
}

// --- hostile input ---------------------------------------------------------

TEST(Gltf, BadGeometryIsAnErrorNamingThePart) {
  test::TempDir dir;
  {
    Doc d;
    d.node({{"name", "n"}, {"mesh", d.mesh(kQuad, {0, 1, 7})}});
    d.point_light(1.0);
    const std::string e = load_error(d.write(dir, "index"));
    EXPECT_CONTAINS(e, "index 7");
    EXPECT_CONTAINS(e, "out of range");
    EXPECT_CONTAINS(e, "node 'n'");
  }
  {
    Doc d;
    std::vector<float> p = kQuad;
    p[4] = std::numeric_limits<float>::quiet_NaN();
    d.node({{"mesh", d.mesh(p, kQuadIdx)}});
    d.point_light(1.0);
    const std::string e = load_error(d.write(dir, "nan"));
    EXPECT_CONTAINS(e, "POSITION");
    EXPECT_CONTAINS(e, "element 1 is not finite");
  }
  {
    Doc d;
    const int m = d.mesh(kQuad, kQuadIdx);
    d.j["accessors"][0]["count"] = 1000000000;  // 10⁹ positions in a 48-byte view
    d.node({{"mesh", m}});
    d.point_light(1.0);
    const std::string e = load_error(d.write(dir, "absurd"));
    EXPECT_CONTAINS(e, "1000000000 elements");
    EXPECT_CONTAINS(e, "do not fit");
  }
  {
    Doc d;
    const int m = d.mesh(kQuad, kQuadIdx);
    d.j["accessors"][0].erase("bufferView");
    d.j["accessors"][0]["count"] = 2000000000;  // not backed by any data
    d.node({{"mesh", m}});
    d.point_light(1.0);
    EXPECT_CONTAINS(load_error(d.write(dir, "unbacked")), "absurd");
  }
  {
    Doc d;
    const int m = d.mesh(kQuad, kQuadIdx);
    d.j["bufferViews"][0]["byteLength"] = 4096;
    d.node({{"mesh", m}});
    d.point_light(1.0);
    EXPECT_CONTAINS(load_error(d.write(dir, "view")), "past the end of buffer");
  }
  {
    Doc d;
    const int m = d.mesh(kQuad, {0, 1, 2, 3});
    d.node({{"mesh", m}});
    d.point_light(1.0);
    EXPECT_CONTAINS(load_error(d.write(dir, "whole")), "whole triangles");
  }
  {
    Doc d;
    d.node({{"mesh", 3}});
    d.point_light(1.0);
    EXPECT_CONTAINS(load_error(d.write(dir, "nomesh")), "mesh 3 does not exist");
  }
  {
    Doc d;
    d.node({{"mesh", d.mesh(kQuad, kQuadIdx)}, {"scale", {1.0, 1e300, 1e300}}});
    d.point_light(1.0);
    EXPECT_CONTAINS(load_error(d.write(dir, "huge")), "not finite in world space");
  }
  {
    Doc d;
    d.node({{"name", "bad"}, {"translation", {1, 2}}});
    d.point_light(1.0);
    EXPECT_CONTAINS(load_error(d.write(dir, "trs")), "'translation' has 2 numbers");
  }
}

TEST(Gltf, NodeGraphCyclesAndBadChildrenAreErrors) {
  test::TempDir dir;
  Doc d;
  d.point_light(1.0);
  d.j["nodes"].push_back({{"name", "a"}, {"children", {2}}});
  d.j["nodes"].push_back({{"name", "b"}, {"children", {1}}});
  d.j["scenes"][0]["nodes"].push_back(1);
  EXPECT_CONTAINS(load_error(d.write(dir, "cycle")), "reached twice");
  d.j["nodes"][2]["children"] = {42};
  EXPECT_CONTAINS(load_error(d.write(dir, "child")), "child index 42 out of range");
}

TEST(Gltf, UnreadableFilesAreErrorsNamingTheFile) {
  test::TempDir dir;
  EXPECT_CONTAINS(load_error((dir / "missing.gltf").string()), "cannot open");
  EXPECT_FALSE(load_gltf(dir.path().string(), nullptr).ok());
  test::write_file(dir / "empty.gltf", "");
  EXPECT_CONTAINS(load_error((dir / "empty.gltf").string()), "empty");
  test::write_file(dir / "junk.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [ }");
  EXPECT_CONTAINS(load_error((dir / "junk.gltf").string()), "not a readable glTF");
  std::string noise;
  for (int i = 0; i < 4096; ++i) noise.push_back(static_cast<char>((i * 7919) & 0xFF));
  test::write_file(dir / "noise.glb", noise);
  load_error((dir / "noise.glb").string());
}

TEST(Gltf, MissingBuffersAreErrorsNamingTheBuffer) {
  test::TempDir dir;
  Doc d;
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx)}});
  d.point_light(1.0);
  const std::string path = d.write(dir, "lost");
  std::filesystem::remove(dir / "lost.bin");
  EXPECT_CONTAINS(load_error(path), "lost.bin");

  // A data URI shorter than the buffer's byteLength.
  json doc = d.j;
  doc["buffers"] = json::array({{{"byteLength", 100}, {"uri", "data:application/octet-stream;base64,AAAA"}}});
  test::write_file(dir / "short.gltf", doc.dump());
  load_error((dir / "short.gltf").string());
}

TEST(Gltf, TruncatedGlbIsAnErrorAtEveryLength) {
  test::TempDir dir;
  Doc d;
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx)}});
  d.point_light(1.0);
  const std::string full = test::read_file(d.write(dir, "whole", Doc::Form::Glb));
  ASSERT_TRUE(load_gltf((dir / "whole.glb").string(), nullptr).ok());
  for (std::size_t n = 0; n < full.size(); n += (n < 64 ? 1 : 7)) {
    const std::string path = (dir / "cut.glb").string();
    test::write_file(path, full.substr(0, n));
    Result<sim::SceneDesc> r = load_gltf(path, nullptr);
    EXPECT_FALSE(r.ok()) << "length " << n;
  }
  test::write_file(dir / "cut.glb", full.substr(0, full.size() - 8));
  EXPECT_CONTAINS(load_error((dir / "cut.glb").string()), "truncated .glb");

  // A BIN chunk that claims more bytes than the container holds.
  std::string liar = full;
  const std::uint32_t json_len = static_cast<unsigned char>(liar[12]) |
                                 static_cast<unsigned char>(liar[13]) << 8;
  const std::size_t bin_header = 20 + json_len;
  liar[bin_header] = static_cast<char>(static_cast<unsigned char>(liar[bin_header]) + 8);
  test::write_file(dir / "liar.glb", liar);
  EXPECT_CONTAINS(load_error((dir / "liar.glb").string()), "declares");
}

// Random corruption of a valid model, text and binary: every load ends in a
// scene or an error, never a crash (the suite also runs under the sanitizers).
TEST(Gltf, CorruptedModelsNeverCrash) {
  test::TempDir dir;
  Doc d;
  const int mat = d.material({{"emissiveFactor", {1, 1, 1}}, {"doubleSided", true}});
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx, mat, 4, "q", {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1})},
          {"rotation", {0, 0.6, 0, 0.8}},
          {"children", {1}}});
  d.j["nodes"].push_back({{"mesh", 0}, {"scale", {2, 2, 2}}});
  d.point_light(5.0);
  const std::string glb = test::read_file(d.write(dir, "base", Doc::Form::Glb));
  const std::string text = test::read_file(d.write(dir, "text", Doc::Form::DataUri));
  std::uint32_t state = 12345;
  auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return state >> 8;
  };
  int loaded = 0, failed = 0;
  for (int round = 0; round < 400; ++round) {
    const bool binary = round % 2 == 0;
    std::string bytes = binary ? glb : text;
    const int edits = 1 + static_cast<int>(next() % 4);
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = next() % bytes.size();
      if (binary) {
        bytes[at] = static_cast<char>(next() & 0xFF);
      } else {
        // Digits for digits keeps the JSON valid more often and reaches
        // counts, offsets and indices.
        const char c = bytes[at];
        bytes[at] = (c >= '0' && c <= '9') ? static_cast<char>('0' + next() % 10)
                                           : static_cast<char>(next() & 0x7F);
      }
    }
    const std::string path = (dir / (binary ? "fuzz.glb" : "fuzz.gltf")).string();
    test::write_file(path, bytes);
    Result<sim::SceneDesc> r = load_gltf(path, nullptr);
    if (r.ok()) {
      ++loaded;
      for (const sim::Mesh& m : r->meshes)
        for (std::uint32_t i : m.indices) ASSERT_LT(i, m.positions.size());
    } else {
      ++failed;
      EXPECT_EQ(r.error().where.file, path);
      EXPECT_FALSE(r.error().message.empty());
    }
  }
  EXPECT_GT(failed, 0);
  EXPECT_GT(loaded, 0);
}

TEST(Gltf, UnsupportedRequiredGeometryExtensionsAreErrors) {
  test::TempDir dir;
  Doc d;
  d.point_light(1.0);
  d.j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  d.use("KHR_draco_mesh_compression");
  EXPECT_CONTAINS(load_error(d.write(dir, "draco")), "KHR_draco_mesh_compression");
}

TEST(Gltf, AModelWithoutEmittersIsAnError) {
  test::TempDir dir;
  Doc d;
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx)}});
  EXPECT_CONTAINS(load_error(d.write(dir, "dark")), "no emitter");
  const int l = d.khr_light({{"type", "point"}, {"intensity", 0.0}});
  d.node({{"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}});
  EXPECT_CONTAINS(load_error(d.write(dir, "zero")), "no emitter");
}

// --- KHR_lights_punctual ---------------------------------------------------

TEST(Gltf, SpotLightsPointDownTheirNodesMinusZWithTheSpecsFalloff) {
  test::TempDir dir;
  Doc d;
  const double inner = 0.2, outer = 0.5, I = 2000.0;
  const int l = d.khr_light({{"type", "spot"},
                             {"name", "spot"},
                             {"intensity", I},
                             {"color", {1.0, 0.5, 0.2}},
                             {"spot", {{"innerConeAngle", inner}, {"outerConeAngle", outer}}}});
  const double s = std::sin(-kPi / 4), c = std::cos(-kPi / 4);
  // −90° about X turns the node's −Z onto world −Y.
  d.node({{"rotation", {s, 0, 0, c}}, {"translation", {0, 3, 0}},
          {"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}});
  const int dl = d.khr_light({{"type", "directional"}});
  d.node({{"extensions", {{"KHR_lights_punctual", {{"light", dl}}}}}});
  std::vector<Finding> findings;
  const sim::SceneDesc scene = load_ok(d.write(dir, "spot"), &findings);
  ASSERT_EQ(scene.emitters.size(), 1u);
  const sim::Emitter& e = scene.emitters[0];
  EXPECT_EQ(e.name, "spot");
  EXPECT_NEAR(e.flux_lm, khr_spot_flux_lm(I, inner, outer), 1e-9);
  EXPECT_NEAR(e.flux_lm, 2 * kPi * I * ((1 - std::cos(inner)) + (std::cos(inner) - std::cos(outer)) / 3),
              1e-9);
  expect_near(e.position, {0, 3, 0}, 1e-12);
  const Vec3 axis = e.frame.to_world(photometry::direction_from_c_gamma(0, 0));
  expect_near(axis, {0, -1, 0}, 1e-12);
  ASSERT_NE(e.profile, nullptr);
  const photometry::Distribution x = photometry::expand_symmetry(*e.profile);
  EXPECT_DOUBLE_EQ(photometry::interpolate(x, 0, 0), I);
  EXPECT_NEAR(photometry::interpolate(x, 0, 0.35 * 180 / kPi), I * khr_spot_falloff(0.35, inner, outer),
              1e-3 * I);
  EXPECT_EQ(photometry::interpolate(x, 0, 40.0), 0.0);
  EXPECT_TRUE(has_code(findings, "directional-light-ignored"));
  EXPECT_TRUE(has_code(findings, "light-color-ignored"));
}

TEST(Gltf, BadLightsAreErrorsNamingTheLight) {
  test::TempDir dir;
  auto with_light = [&](json light, const std::string& stem) {
    Doc d;
    const int l = d.khr_light(std::move(light));
    d.node({{"name", "holder"}, {"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}});
    return load_error(d.write(dir, stem));
  };
  EXPECT_CONTAINS(with_light({{"type", "point"}, {"intensity", -1}}, "neg"), "negative");
  EXPECT_CONTAINS(with_light({{"type", "area"}}, "type"), "unknown light type 'area'");
  EXPECT_CONTAINS(with_light({{"type", "spot"}, {"spot", {{"outerConeAngle", 2.0}}}}, "cone"),
                  "outerConeAngle");
  const std::string e = with_light({{"type", "point"}, {"intensity", "bright"}}, "str");
  EXPECT_CONTAINS(e, "node 'holder'");
  Doc d;
  d.node({{"extensions", {{"KHR_lights_punctual", {{"light", 5}}}}}});
  d.point_light(1.0);
  EXPECT_CONTAINS(load_error(d.write(dir, "idx")), "light 5 does not exist");
}

// Fuzz finding (glTF harness, this session): an accessor of no elements
// and no bufferView made the loader memset a null pointer (undefined
// behaviour that UBSan reported). It is a primitive without triangles.
TEST(Gltf, FuzzFoundAnEmptyAccessorWithoutBufferViewIsAnEmptyPrimitive) {
  test::TempDir dir;
  Doc d;
  d.j["accessors"].push_back({{"componentType", 5126}, {"count", 0}, {"type", "VEC3"}});
  const int empty = static_cast<int>(d.j["accessors"].size() - 1);
  d.j["meshes"].push_back({{"primitives", json::array({json{{"attributes", {{"POSITION", empty}}}}})}});
  d.node({{"mesh", 0}});
  d.point_light(1.0);
  std::vector<Finding> findings;
  const sim::SceneDesc s = load_ok(d.write(dir, "empty-accessor"), &findings);
  EXPECT_TRUE(s.meshes.empty());
  EXPECT_TRUE(has_code(findings, "empty-primitive"));
}

// --- instancing --------------------------------------------------------------

// A point transformed by an instance, for comparisons.
Vec3 placed_point(const sim::Instance& i, const Vec3& p) { return i.to_world.point(p); }

TEST(Gltf, AMeshPlacedByManyNodesIsStoredOnceAndInstanced) {
  test::TempDir dir;
  Doc d;
  const int shared = d.mesh(kQuad, kQuadIdx, -1, 4, "lens");
  const int single = d.mesh(kQuad, kQuadIdx, -1, 4, "plate");
  d.node({{"name", "a"}, {"mesh", shared}, {"translation", {1, 0, 0}}});
  const int child = d.node({{"name", "b"}, {"mesh", shared}, {"scale", {2, 2, 2}}}, false);
  d.node({{"name", "parent"}, {"translation", {0, 5, 0}}, {"children", {child}}});
  d.node({{"name", "c"}, {"mesh", single}});
  d.point_light(1.0);
  d.j["scenes"][0]["extras"] = {{"gonio", {{"unit_m", 0.001}}}};
  const std::string path = d.write(dir, "shared");
  const sim::SceneDesc s = load_ok(path);
  ASSERT_EQ(s.meshes.size(), 2u);
  // The shared mesh: once, in its own frame (glTF units), instanced.
  EXPECT_EQ(s.meshes[0].name, "lens/0");
  EXPECT_TRUE(s.meshes[0].instanced);
  EXPECT_EQ(s.meshes[0].positions[1].x, 1.0f);
  // The mesh placed once: world geometry in metres.
  EXPECT_EQ(s.meshes[1].name, "c/plate/0");
  EXPECT_FALSE(s.meshes[1].instanced);
  EXPECT_EQ(s.meshes[1].positions[1].x, 0.001f);
  ASSERT_EQ(s.instances.size(), 2u);
  EXPECT_EQ(s.instances[0].name, "a");
  EXPECT_EQ(s.instances[1].name, "b");
  // World transforms with the unit and the parent's: (1,0,0) in the mesh
  // goes to (2,0,0) mm under node a, to 2·(1,0,0) + (0,5,0) mm under b.
  expect_near(placed_point(s.instances[0], {1, 0, 0}), {0.002, 0, 0}, 1e-15);
  expect_near(placed_point(s.instances[1], {1, 0, 0}), {0.002, 0.005, 0}, 1e-15);
  EXPECT_EQ(s.unique_triangle_count(), 4u);
  EXPECT_EQ(s.placed_triangle_count(), 6u);

  // Without instancing: the same world geometry, one mesh per placement.
  Result<sim::SceneDesc> flat = load_gltf(path, nullptr, {.instancing = false});
  ASSERT_TRUE(flat.ok());
  ASSERT_EQ(flat->meshes.size(), 3u);
  const sim::SceneDesc f = sim::flattened(s);
  ASSERT_EQ(f.meshes.size(), 3u);
  for (std::size_t m = 0; m < 3; ++m) {
    EXPECT_EQ(flat->meshes[m].name, f.meshes[m].name);
    EXPECT_EQ(flat->meshes[m].indices, f.meshes[m].indices);
    for (std::size_t v = 0; v < f.meshes[m].positions.size(); ++v)
      expect_near(pos(flat->meshes[m], static_cast<std::uint32_t>(v)), pos(f.meshes[m], static_cast<std::uint32_t>(v)), 1e-12);
  }
  EXPECT_EQ(f.meshes[0].name, "a/lens/0");
  EXPECT_EQ(f.meshes[1].name, "b/lens/0");
  EXPECT_EQ(f.meshes[2].name, "c/plate/0");
}

TEST(Gltf, ExtMeshGpuInstancingPlacesOneCopyPerElement) {
  test::TempDir dir;
  Doc d;
  d.use("EXT_mesh_gpu_instancing");
  const int m = d.mesh(kQuad, kQuadIdx, -1, 4, "led");
  const std::vector<float> t = {0, 0, 0, 10, 0, 0, 0, 10, 0};
  const float h = static_cast<float>(std::sqrt(0.5));
  const std::vector<float> r = {0, 0, 0, 1, 0, 0, h, h, 0, 0, 0, 1};  // none, 90° about z, none
  const std::vector<float> sc = {1, 1, 1, 1, 1, 1, -1, 1, 1};         // the third mirrored
  d.node({{"name", "board"},
          {"mesh", m},
          {"translation", {0, 0, 5}},
          {"extensions",
           {{"EXT_mesh_gpu_instancing",
             {{"attributes", {{"TRANSLATION", d.vec3(t)}, {"ROTATION", d.vec4(r)}, {"SCALE", d.vec3(sc)}}}}}}}});
  d.point_light(1.0);
  const sim::SceneDesc s = load_ok(d.write(dir, "gpu", Doc::Form::Glb));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(s.meshes[0].instanced);
  ASSERT_EQ(s.instances.size(), 3u);  // and none for the node itself
  EXPECT_EQ(s.instances[2].name, "board[2]");
  expect_near(placed_point(s.instances[0], {1, 0, 0}), {1, 0, 5}, 1e-12);
  expect_near(placed_point(s.instances[1], {1, 0, 0}), {10, 1, 5}, 1e-6);
  expect_near(placed_point(s.instances[2], {1, 0, 0}), {-1, 10, 5}, 1e-12);
  EXPECT_LT(s.instances[2].to_world.determinant(), 0.0);

  // Counts that disagree, no transform attribute, a non-float accessor.
  Doc bad = d;
  bad.j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"] =
      bad.vec3({1, 1, 1});
  EXPECT_CONTAINS(load_error(bad.write(dir, "counts")), "SCALE has 1 elements");
  bad = d;
  bad.j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = {{"_ID", 0}};
  EXPECT_CONTAINS(load_error(bad.write(dir, "none")), "none of TRANSLATION, ROTATION and SCALE");
  bad = d;
  bad.j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["ROTATION"] =
      bad.indices({1, 2, 3, 4});
  EXPECT_CONTAINS(load_error(bad.write(dir, "int")), "ROTATION");
  bad = d;
  bad.j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"] = 99;
  EXPECT_CONTAINS(load_error(bad.write(dir, "missing")), "accessor 99 does not exist");
}

TEST(Gltf, AnInstancedEmissiveMeshEmitsFromEveryCopy) {
  test::TempDir dir;
  Doc d;
  const int led = d.material({{"name", "led"}, {"emissiveFactor", {1, 1, 1}}});
  const int m = d.mesh(kQuad, kQuadIdx, led, 4, "die");
  d.node({{"name", "one"}, {"mesh", m}});
  d.node({{"name", "big"}, {"mesh", m}, {"scale", {2, 3, 1}}});
  d.point_light(1.0);
  const sim::SceneDesc s = load_ok(d.write(dir, "dies"));
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.instances.size(), 2u);
  ASSERT_EQ(s.emitters.size(), 3u);  // two dies and the lamp
  EXPECT_EQ(s.emitters[0].mesh, 0u);
  EXPECT_EQ(s.emitters[0].instance, 0u);
  EXPECT_EQ(s.emitters[1].instance, 1u);
  EXPECT_EQ(s.emitters[1].name, "big/die/0");
  // π·L·A with each copy's own area (L = 1 cd/m² for white emissiveFactor).
  EXPECT_NEAR(s.emitters[0].flux_lm, kPi * 1.0, 1e-9);
  EXPECT_NEAR(s.emitters[1].flux_lm, kPi * 6.0, 1e-9);
  // Flattened, each emitter is on its own world mesh.
  const sim::SceneDesc f = sim::flattened(s);
  EXPECT_EQ(f.emitters[1].mesh, 1u);
  EXPECT_EQ(f.emitters[1].instance, sim::kNoInstance);
  EXPECT_EQ(f.meshes[1].name, "big/die/0");
}

// --- emissive surfaces -----------------------------------------------------

TEST(Gltf, EmissiveMaterialsAreLambertianAreaEmittersWithPiLA) {
  test::TempDir dir;
  Doc d;
  d.use("KHR_materials_emissive_strength");
  const int one_sided = d.material({{"name", "led"},
                                    {"emissiveFactor", {1, 1, 1}},
                                    {"extensions",
                                     {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1000.0}}}}}});
  const int two_sided = d.material({{"name", "panel"}, {"emissiveFactor", {0, 1, 0}}, {"doubleSided", true}});
  const int by_extras = d.material({{"name", "tagged"},
                                    {"extras", {{"gonio", {{"luminance_cd_m2", 5000.0}}}}}});
  // 1 × 1 quads; the first scaled to 2 × 3.
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx, one_sided)}, {"scale", {2, 3, 1}}});
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx, two_sided)}});
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx, by_extras)}});
  const sim::SceneDesc s = load_ok(d.write(dir, "emissive"));
  ASSERT_EQ(s.emitters.size(), 3u);
  EXPECT_EQ(s.emitters[0].kind, sim::Emitter::Kind::Area);
  EXPECT_EQ(s.emitters[0].mesh, 0u);
  EXPECT_FALSE(s.emitters[0].two_sided);
  EXPECT_NEAR(s.emitters[0].flux_lm, kPi * 1000.0 * 6.0, 1e-6);
  EXPECT_EQ(s.emitters[1].mesh, 1u);
  EXPECT_TRUE(s.emitters[1].two_sided);
  EXPECT_NEAR(s.emitters[1].flux_lm, 2 * kPi * 0.7152 * 1.0, 1e-9);
  EXPECT_NEAR(s.emitters[2].flux_lm, kPi * 5000.0, 1e-6);
}

TEST(Gltf, NodeFluxIsSplitOverEmissivePrimitivesByPiLA) {
  test::TempDir dir;
  Doc d;
  const int bright = d.material({{"emissiveFactor", {1, 1, 1}}});
  const int dim = d.material({{"emissiveFactor", {0.5, 0.5, 0.5}}});
  const int m = d.mesh(kQuad, kQuadIdx, bright);
  json second = d.j["meshes"][m]["primitives"][0];
  second["material"] = dim;
  d.j["meshes"][m]["primitives"].push_back(second);
  json extras = json::object();
  extras["gonio"]["flux_lm"] = 900.0;
  extras["other_tool"] = 1;  // not Gonio's: left alone
  d.node({{"mesh", m}, {"extras", extras}});
  const sim::SceneDesc s = load_ok(d.write(dir, "split"));
  ASSERT_EQ(s.emitters.size(), 2u);
  EXPECT_NEAR(s.emitters[0].flux_lm, 600.0, 1e-9);
  EXPECT_NEAR(s.emitters[1].flux_lm, 300.0, 1e-9);
  EXPECT_NEAR(s.total_flux_lm(), 900.0, 1e-9);
}

// Issue 34, case 4: a ray set (TM-25) on a node that rotates, scales and
// moves it. A flat set in the file's z = 0 (millimetres) must start where
// the node's whole transform puts it: T + R·S·p with R 90° about +X, S
// (2, 3, 4), T (0.1, 0.2, 0.3) m — (10, 20, 0) mm lands at (0.12, 0.2,
// 0.36) m; taking the translation alone would leave it at (0.11, 0.22,
// 0.3). Directions take the linear part, normalised: +z of the file (S: 4z,
// R: −4y) points along −Y.
TEST(Gltf, RaySetsStartWhereTheNodesRotationScaleAndTranslationPutThem) {
  test::TempDir dir;
  // x y z [mm], kx ky kz, Tri_Y [lm]
  std::vector<float> rays = {10.0f, 20.0f, 0.0f, 0.0f, 0.0f, 1.0f, 1.0f,  //
                             -30.0f, 5.0f, 0.0f, 0.6f, 0.0f, 0.8f, 2.0f};
  ASSERT_TRUE(write_tm25_file((dir / "flat.tm25ray").string(), make_luminous_ray_set(rays)).ok());
  Doc d;
  const double h = std::sqrt(0.5);
  json node = {{"name", "led"},
               {"rotation", {h, 0.0, 0.0, h}},
               {"scale", {2.0, 3.0, 4.0}},
               {"translation", {0.1, 0.2, 0.3}}};
  node["extras"]["gonio"]["ray_file"] = "flat.tm25ray";
  d.node(node);
  const sim::SceneDesc s = load_ok(d.write(dir, "turned"));
  ASSERT_EQ(s.emitters.size(), 1u);
  const sim::Emitter& e = s.emitters[0];
  ASSERT_EQ(e.kind, sim::Emitter::Kind::RaySet);
  ASSERT_NE(e.rays, nullptr);
  ASSERT_EQ(e.rays->size(), 2u);
  expect_near(sim::to_double(e.rays->position_m[0]), {0.12, 0.2, 0.36}, 1e-6);
  expect_near(sim::to_double(e.rays->position_m[1]), {0.04, 0.2, 0.315}, 1e-6);
  expect_near(sim::to_double(e.rays->direction[0]), {0.0, -1.0, 0.0}, 1e-6);
  const double n = std::hypot(1.2, 3.2);
  expect_near(sim::to_double(e.rays->direction[1]), {1.2 / n, -3.2 / n, 0.0}, 1e-6);
  EXPECT_NEAR(e.flux_lm, 3.0, 1e-6);
  expect_near(e.position, {0.1, 0.2, 0.3}, 1e-12);
}

// --- extras ----------------------------------------------------------------

TEST(Gltf, FluxExtrasOnNodeWinOverLightWhichWinsOverIntensity) {
  test::TempDir dir;
  Doc d;
  const int plain = d.khr_light({{"type", "point"}, {"intensity", 10.0}});
  const int tagged = d.khr_light(
      {{"type", "point"}, {"intensity", 10.0}, {"extras", {{"gonio", {{"flux_lm", 1200.0}}}}}});
  d.node({{"extensions", {{"KHR_lights_punctual", {{"light", plain}}}}}});
  d.node({{"extensions", {{"KHR_lights_punctual", {{"light", tagged}}}}}});
  d.node({{"extensions", {{"KHR_lights_punctual", {{"light", tagged}}}}},
          {"extras", {{"gonio", {{"flux_lm", 345.0}, {"flux_lumens", 1}}}}}});
  std::vector<Finding> findings;
  const sim::SceneDesc s = load_ok(d.write(dir, "flux"), &findings);
  ASSERT_EQ(s.emitters.size(), 3u);
  EXPECT_NEAR(s.emitters[0].flux_lm, 40 * kPi, 1e-9);
  EXPECT_EQ(s.emitters[1].flux_lm, 1200.0);
  EXPECT_EQ(s.emitters[2].flux_lm, 345.0);
  EXPECT_TRUE(has_code(findings, "unknown-extras-key"));  // flux_lumens: a typo is reported

  d.j["nodes"][2]["extras"]["gonio"] = {{"flux_lm", "lots"}};
  EXPECT_CONTAINS(load_error(d.write(dir, "flux-string")), "'flux_lm' must be a number");
  d.j["nodes"][2]["extras"]["gonio"] = {{"flux_lm", -3}};
  EXPECT_CONTAINS(load_error(d.write(dir, "flux-negative")), "negative");
}

TEST(Gltf, NodeFluxOnANodeWithTwoKindsOfEmitterIsAmbiguous) {
  test::TempDir dir;
  Doc d;
  const int glow = d.material({{"emissiveFactor", {1, 1, 1}}});
  const int l = d.khr_light({{"type", "point"}});
  d.node({{"name", "both"},
          {"mesh", d.mesh(kQuad, kQuadIdx, glow)},
          {"extensions", {{"KHR_lights_punctual", {{"light", l}}}}},
          {"extras", {{"gonio", {{"flux_lm", 100}}}}}});
  EXPECT_CONTAINS(load_error(d.write(dir, "ambiguous")), "ambiguous");
}

// --- materials -------------------------------------------------------------

TEST(Gltf, MaterialsAndTheirExtensionsReachTheScene) {
  test::TempDir dir;
  Doc d;
  for (const char* e : {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume",
                        "KHR_materials_diffuse_transmission", "KHR_materials_clearcoat"})
    d.use(e);
  const int alu = d.material({{"name", "aluminium"},
                              {"pbrMetallicRoughness",
                               {{"baseColorFactor", {0.92, 0.92, 0.92, 1}},
                                {"metallicFactor", 1.0},
                                {"roughnessFactor", 0.02}}}});
  const int pmma = d.material(
      {{"name", "pmma"},
       {"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
       {"extensions",
        {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
         {"KHR_materials_ior", {{"ior", 1.49}}},
         {"KHR_materials_volume", {{"thicknessFactor", 0.01}, {"attenuationDistance", 2.0},
                                   {"attenuationColor", {0.95, 0.95, 0.95}}}}}}});
  const int opal = d.material(
      {{"name", "opal"},
       {"extras", {{"gonio", {{"reflectance", 0.4}, {"diffuse_reflectance", 0.3},
                              {"transmittance", 0.6}}}}}});
  const int coat = d.material({{"name", "lacquer"},
                               {"extensions", {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1}}}}}});
  for (int m : {alu, pmma, opal, coat}) d.node({{"mesh", d.mesh(kQuad, kQuadIdx, m)}});
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx, alu)}});  // shared material: one scene material
  d.point_light(1.0);
  std::vector<Finding> findings;
  const sim::SceneDesc s = load_ok(d.write(dir, "materials"), &findings);
  ASSERT_EQ(s.materials.size(), 4u);
  ASSERT_EQ(s.meshes.size(), 5u);
  EXPECT_EQ(s.meshes[4].material, s.meshes[0].material);
  const sim::Material& a = s.materials[s.meshes[0].material];
  EXPECT_EQ(a.name, "aluminium");
  EXPECT_NEAR(a.mirror, 0.92, 1e-12);
  const sim::Material& p = s.materials[s.meshes[1].material];
  EXPECT_NEAR(p.dielectric, 1.0, 1e-12);
  EXPECT_NEAR(p.ior, 1.49, 1e-12);
  EXPECT_NEAR(p.attenuation_per_m, -std::log(0.95) / 2.0, 1e-12);
  const sim::Material& o = s.materials[s.meshes[2].material];
  EXPECT_NEAR(o.diffuse_transmit, 0.6, 1e-12);
  EXPECT_NEAR(o.diffuse_reflect, 0.3, 1e-12);
  EXPECT_NEAR(o.mirror, 0.1, 1e-12);
  EXPECT_TRUE(has_code(findings, "unsupported-material-extension"));

  d.j["materials"][opal]["extras"]["gonio"]["transmittance"] = 0.9;
  const std::string e = load_error(d.write(dir, "bad-opal"));
  EXPECT_CONTAINS(e, "material 'opal'");
  EXPECT_CONTAINS(e, "exceeds 1");
}

// --- EXT_lights_ies --------------------------------------------------------

// An isotropic 100 cd profile written by hand in LM-63-2002 (independent of
// Gonio's IES writer): Φ = 4π · 100 lm.
const char* kIsotropicIes =
    "IESNA:LM-63-2002\r\n"
    "[TEST] GLTF-TEST\r\n"
    "[MANUFAC] gonio tests\r\n"
    "TILT=NONE\r\n"
    "1 1000 1 3 1 1 2 0 0 0\r\n"
    "1 1 10\r\n"
    "0 90 180\r\n"
    "0\r\n"
    "100 100 100\r\n";

void add_ies_lights(Doc& d, json lights) {
  d.use("EXT_lights_ies");
  d.j["extensions"]["EXT_lights_ies"]["lights"] = std::move(lights);
}

int ies_node(Doc& d, int light, json instance = json::object(), json node = json::object()) {
  instance["light"] = light;
  node["extensions"]["EXT_lights_ies"] = instance;
  return d.node(node);
}

TEST(Gltf, IesProfilesByUriCarryTheirIntegratedFluxTimesTheMultiplier) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "profiles");
  test::write_file(dir / "profiles" / "iso lamp.ies", kIsotropicIes);
  Doc d;
  add_ies_lights(d, {{{"name", "iso"}, {"uri", "profiles/iso%20lamp.ies"}}});
  ies_node(d, 0, {{"multiplier", 2.0}, {"color", {1.0, 0.9, 0.8}}});
  ies_node(d, 0);
  std::vector<Finding> findings;
  const sim::SceneDesc s = load_ok(d.write(dir, "iso"), &findings);
  ASSERT_EQ(s.emitters.size(), 2u);
  EXPECT_EQ(s.emitters[0].name, "iso");
  EXPECT_NEAR(s.emitters[0].flux_lm, 2 * 4 * kPi * 100.0, 1e-9 * 2513.0);
  EXPECT_NEAR(s.emitters[1].flux_lm, 4 * kPi * 100.0, 1e-9 * 1257.0);
  ASSERT_NE(s.emitters[0].profile, nullptr);
  EXPECT_EQ(s.emitters[0].profile, s.emitters[1].profile);  // read once, shared
  EXPECT_EQ(s.emitters[0].profile->candela, (std::vector<double>{100, 100, 100}));
  EXPECT_TRUE(has_code(findings, "light-color-ignored"));
}

TEST(Gltf, IesFluxExtrasOnTheProfileScaleWithTheMultiplierOnTheNodeTheyAreFinal) {
  test::TempDir dir;
  test::write_file(dir / "iso.ies", kIsotropicIes);
  Doc d;
  add_ies_lights(d, {{{"uri", "iso.ies"}, {"extras", {{"gonio", {{"flux_lm", 800.0}}}}}}});
  ies_node(d, 0, {{"multiplier", 0.5}});
  ies_node(d, 0, {{"multiplier", 0.5}}, {{"extras", {{"gonio", {{"flux_lm", 123.0}}}}}});
  const sim::SceneDesc s = load_ok(d.write(dir, "extras"));
  ASSERT_EQ(s.emitters.size(), 2u);
  EXPECT_EQ(s.emitters[0].flux_lm, 400.0);
  EXPECT_EQ(s.emitters[1].flux_lm, 123.0);
}

TEST(Gltf, IesProfilesFromBufferViewsAndDataUris) {
  test::TempDir dir;
  Doc d;
  const std::string ies = kIsotropicIes;
  const int view = d.view(ies.data(), ies.size());
  add_ies_lights(d, {{{"bufferView", view}, {"mimeType", "application/x-ies-lm-63"}},
                     {{"uri", "data:application/x-ies-lm-63;base64," + Doc::base64(ies)}}});
  ies_node(d, 0);
  ies_node(d, 1);
  for (Doc::Form form : {Doc::Form::ExternalBin, Doc::Form::Glb}) {
    const sim::SceneDesc s = load_ok(d.write(dir, "embedded", form));
    ASSERT_EQ(s.emitters.size(), 2u);
    for (const sim::Emitter& e : s.emitters) EXPECT_NEAR(e.flux_lm, 4 * kPi * 100.0, 1e-6);
  }
}

// An asymmetric profile for the orientation test: a narrow peak at
// (C 60°, γ 30°) over a weak isotropic floor, every C-plane stored.
photometry::Distribution peaked_profile(double peak_c_deg, double peak_gamma_deg) {
  photometry::Distribution p;
  p.type = photometry::PhotometricType::C;
  p.symmetry = photometry::Symmetry::None;
  for (int c = 0; c <= 360; c += 5) p.horizontal_deg.push_back(c);
  for (int g = 0; g <= 180; g += 2) p.vertical_deg.push_back(g);
  const Vec3 peak = photometry::direction_from_c_gamma(peak_c_deg * kPi / 180, peak_gamma_deg * kPi / 180);
  for (double c : p.horizontal_deg)
    for (double g : p.vertical_deg) {
      const Vec3 dir = photometry::direction_from_c_gamma(c * kPi / 180, g * kPi / 180);
      const double angle = std::acos(std::clamp(dot(dir, peak), -1.0, 1.0));
      p.candela.push_back(10.0 + 1000.0 * std::exp(-angle * angle / (2 * 0.1 * 0.1)));
    }
  p.absolute = true;
  p.lamps = {photometry::LampSet{}};
  p.set_keyword("TEST", "ORIENTATION");
  p.set_keyword("TESTLAB", "gonio tests");
  p.set_keyword("MANUFAC", "gonio tests");
  p.set_keyword("ISSUEDATE", "2024-01-01");
  return p;
}

// 3×3 rotation matrix of a unit quaternion (x, y, z, w), row-major.
std::array<Vec3, 3> quaternion_rows(double x, double y, double z, double w) {
  return {Vec3{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
          Vec3{2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
          Vec3{2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
}
Vec3 rotate(const std::array<Vec3, 3>& r, const Vec3& v) { return {dot(r[0], v), dot(r[1], v), dot(r[2], v)}; }

// The extension's mapping end to end: (0°, 0°) along the node's −Z, the
// X/Z plane the vertical photometric plane of C0 (+X), C90 on +Y; the node's
// rotation (here a parent's and a child's, with scale) turns it all. The
// profile's peak must come out where that puts it in world space.
TEST(Gltf, IesOrientationFollowsTheExtensionThroughNodeRotations) {
  test::TempDir dir;
  const double pc = 60.0, pg = 30.0;
  const photometry::Distribution profile = peaked_profile(pc, pg);
  ASSERT_TRUE(photometry::validate(profile).ok());
  io::IesWriteOptions options;
  test::write_file(dir / "peak.ies", io::write_ies(profile, options, nullptr));

  Doc d;
  add_ies_lights(d, {{{"uri", "peak.ies"}}});
  // Parent: 40° about (1, 2, 3); child: 75° about +Y, scaled non-uniformly.
  const Vec3 axis = normalize(Vec3{1, 2, 3});
  const double a = 40 * kPi / 180, b = 75 * kPi / 180;
  const double qp[4] = {axis.x * std::sin(a / 2), axis.y * std::sin(a / 2), axis.z * std::sin(a / 2),
                        std::cos(a / 2)};
  const double qc[4] = {0, std::sin(b / 2), 0, std::cos(b / 2)};
  const int child = d.node({{"name", "led"},
                            {"rotation", {qc[0], qc[1], qc[2], qc[3]}},
                            {"scale", {3, 0.5, 2}},
                            {"translation", {0.1, 0, 0}},
                            {"extensions", {{"EXT_lights_ies", {{"light", 0}}}}}},
                           false);
  d.node({{"rotation", {qp[0], qp[1], qp[2], qp[3]}}, {"children", {child}}});
  const sim::SceneDesc s = load_ok(d.write(dir, "oriented"));
  ASSERT_EQ(s.emitters.size(), 1u);
  const sim::Emitter& e = s.emitters[0];
  EXPECT_NEAR(e.flux_lm, photometry::total_flux_lm(profile), 1e-3 * e.flux_lm);

  // Where the extension puts the peak: node-local (sin γ cos C, sin γ sin C,
  // −cos γ) in (X, Y, Z), then the child's and the parent's rotations.
  const auto rp = quaternion_rows(qp[0], qp[1], qp[2], qp[3]);
  const auto rc = quaternion_rows(qc[0], qc[1], qc[2], qc[3]);
  auto world_of = [&](double c_deg, double g_deg) {
    const double c = c_deg * kPi / 180, g = g_deg * kPi / 180;
    return rotate(rp, rotate(rc, Vec3{std::sin(g) * std::cos(c), std::sin(g) * std::sin(c), -std::cos(g)}));
  };
  for (auto [c, g] : {std::pair{0.0, 0.0}, std::pair{0.0, 90.0}, std::pair{90.0, 90.0},
                      std::pair{pc, pg}, std::pair{200.0, 120.0}})
    expect_near(e.frame.to_world(photometry::direction_from_c_gamma(c * kPi / 180, g * kPi / 180)),
                world_of(c, g), 1e-12);

  // The brightest world direction, searched over the sphere through the
  // emitter's frame and profile, is the extension's peak.
  const photometry::Distribution x = photometry::expand_symmetry(*e.profile);
  Vec3 best;
  double best_i = -1;
  for (int i = 0; i < 400; ++i)
    for (int j = 0; j < 800; ++j) {
      const double theta = kPi * (i + 0.5) / 400, phi = 2 * kPi * j / 800;
      const Vec3 w{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
      const photometry::CGamma cg = photometry::c_gamma_from_direction(e.frame.to_local(w));
      const double v = photometry::interpolate(x, cg.c_rad * 180 / kPi, cg.gamma_rad * 180 / kPi);
      if (v > best_i) {
        best_i = v;
        best = w;
      }
    }
  EXPECT_GT(dot(best, world_of(pc, pg)), std::cos(1.0 * kPi / 180));
}

TEST(Gltf, EulumdatProfilesByUriAndDataUri) {
  test::TempDir dir;
  photometry::Distribution iso;
  iso.type = photometry::PhotometricType::C;
  iso.symmetry = photometry::Symmetry::Rotational;
  iso.horizontal_deg = {0};
  for (int g = 0; g <= 180; g += 5) iso.vertical_deg.push_back(g);
  iso.candela.assign(iso.vertical_deg.size(), 50.0);
  iso.lamps = {photometry::LampSet{}};
  iso.lamps[0].flux_lm = 4 * kPi * 50.0;
  Result<std::string> ldt = io::write_ldt(iso, {}, nullptr);
  ASSERT_TRUE(ldt.ok()) << to_string(ldt.error());
  test::write_file(dir / "iso.LDT", *ldt);
  Doc d;
  add_ies_lights(d, {{{"uri", "iso.LDT"}},
                     {{"uri", "data:application/x-eulumdat;base64," + Doc::base64(*ldt)}}});
  ies_node(d, 0);
  ies_node(d, 1);
  const sim::SceneDesc s = load_ok(d.write(dir, "ldt"));
  ASSERT_EQ(s.emitters.size(), 2u);
  for (const sim::Emitter& e : s.emitters) {
    EXPECT_NEAR(e.flux_lm, 4 * kPi * 50.0, 1e-6 * e.flux_lm);
    EXPECT_NEAR(photometry::interpolate(photometry::expand_symmetry(*e.profile), 0, 77), 50.0, 1e-9);
  }
}

TEST(Gltf, BrokenIesProfilesAreErrorsNamingLightFileAndLine) {
  test::TempDir dir;
  std::string broken = kIsotropicIes;
  broken.replace(broken.find("100 100 100"), 11, "100 oops 100");
  test::write_file(dir / "broken.ies", broken);
  Doc d;
  add_ies_lights(d, {{{"name", "bad"}, {"uri", "broken.ies"}}});
  ies_node(d, 0);
  const std::string e = load_error(d.write(dir, "broken"));
  EXPECT_CONTAINS(e, "EXT_lights_ies light 'bad'");
  EXPECT_CONTAINS(e, "broken.ies:9");
}

TEST(Gltf, IesLightsWithMissingProfilesAreErrorsNamingLightAndFile) {
  test::TempDir dir;
  Doc d;
  d.use("EXT_lights_ies");
  d.j["extensions"]["EXT_lights_ies"]["lights"] = {{{"name", "led"}, {"uri", "profiles/led%20a.ies"}}};
  d.node({{"name", "holder"}, {"extensions", {{"EXT_lights_ies", {{"light", 0}}}}}});
  const std::string e = load_error(d.write(dir, "ies"));
  EXPECT_CONTAINS(e, "EXT_lights_ies light 'led'");
  EXPECT_CONTAINS(e, "profiles/led%20a.ies");
  EXPECT_CONTAINS(e, "led a.ies");  // the decoded path that was tried

  d.j["extensions"]["EXT_lights_ies"]["lights"] = {{{"bufferView", 0}, {"mimeType", "image/png"}}};
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx)}});
  EXPECT_CONTAINS(load_error(d.write(dir, "mime")), "mimeType 'image/png'");

  d.j["extensions"]["EXT_lights_ies"]["lights"] = {{{"name", "x"}}};
  EXPECT_CONTAINS(load_error(d.write(dir, "neither")), "needs a 'uri' or a 'bufferView'");

  d.j["extensions"]["EXT_lights_ies"]["lights"] = {{{"uri", "a.ies"}}};
  d.j["nodes"][0]["extensions"]["EXT_lights_ies"]["multiplier"] = -2;
  EXPECT_CONTAINS(load_error(d.write(dir, "mult")), "multiplier");
}


// --- paths from a model ----------------------------------------------------
// A model's uris name files beside it. One that leaves the model's folder
// (an absolute path, a '..' climbing out, a symbolic link leading out) is
// refused, naming the model and the uri, unless allow_outside_paths.

namespace fs = std::filesystem;

struct OutsideCase {
  std::string uri;
  fs::path file;     // where the named file really is
  const char* says;  // why it is refused; null: inside, loads
};

// Rewrites one uri of a written model: buffers[0], images[0] or the first
// EXT_lights_ies light.
void set_uri(const std::string& model, const std::string& what, const std::string& uri) {
  json j = json::parse(test::read_file(model));
  if (what == "buffer") j["buffers"][0]["uri"] = uri;
  if (what == "image") j["images"][0]["uri"] = uri;
  if (what == "profile") j["extensions"]["EXT_lights_ies"]["lights"][0]["uri"] = uri;
  test::write_file(model, j.dump());
}

// The folders of these tests: ROOT/model/ holds the model, ROOT/outside/
// what it must not reach, ROOT/model/out-link a symbolic link to
// ROOT/outside, ROOT/model/in-link one to ROOT/model/sub.
struct Folders {
  test::TempDir root;
  fs::path model = root / "model", outside = root / "outside", sub = root / "model" / "sub";
  Folders() {
    fs::create_directories(sub);
    fs::create_directories(outside);
    fs::create_directory_symlink(outside, model / "out-link");
    fs::create_directory_symlink(sub, model / "in-link");
  }
  // The same file name in each place, with the same bytes.
  std::vector<OutsideCase> cases(const std::string& name) const {
    return {{"../outside/" + name, outside / name, "climbs out with '..'"},
            {(outside / name).string(), outside / name, "is an absolute path"},
            {(model / name).string(), model / name, "is an absolute path"},
            {"out-link/" + name, outside / name, "resolves through a symbolic link"},
            {"sub/../../outside/" + name, outside / name, "climbs out with '..'"},
            {"sub/../" + name, model / name, nullptr},
            {"in-link/" + name, sub / name, nullptr},
            {name, model / name, nullptr}};
  }
};

void expect_refused_unless_allowed(const std::string& model, const OutsideCase& c, const std::string& what) {
  SCOPED_TRACE(what + " uri " + c.uri);
  Result<sim::SceneDesc> r = load_gltf(model, nullptr);
  if (c.says) {
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().where.file, model);
    EXPECT_CONTAINS(r.error().message, "'" + c.uri + "'");
    EXPECT_CONTAINS(r.error().message, c.says);
    EXPECT_CONTAINS(r.error().message, "outside the model's folder");
    EXPECT_CONTAINS(r.error().message, "--allow-outside-paths");
  } else {
    EXPECT_TRUE(r.ok()) << to_string(r.error());
  }
  GltfLoadOptions allow;
  allow.allow_outside_paths = true;
  Result<sim::SceneDesc> allowed = load_gltf(model, nullptr, allow);
  EXPECT_TRUE(allowed.ok()) << to_string(allowed.error());
}

TEST(GltfPaths, BufferUrisLeavingTheModelsFolderAreRefused) {
  const Folders f;
  Doc d;
  d.mesh(kQuad, kQuadIdx);
  d.point_light(100.0);
  test::TempDir scratch;
  const std::string written = d.write(scratch, "lamp");  // writes lamp.bin beside it
  const std::string bin = test::read_file(scratch / "lamp.bin");
  const std::string model = (f.model / "lamp.gltf").string();
  for (const OutsideCase& c : f.cases("lamp.bin")) {
    fs::copy_file(written, model, fs::copy_options::overwrite_existing);
    set_uri(model, "buffer", c.uri);
    for (const fs::path& p : {f.outside / "lamp.bin", f.model / "lamp.bin", f.sub / "lamp.bin"}) fs::remove(p);
    test::write_file(c.file, bin);
    expect_refused_unless_allowed(model, c, "buffer");
  }
  // Nothing of the kind in a .glb's own buffer or a data URI.
  EXPECT_TRUE(load_gltf(d.write(f.root, "embedded", Doc::Form::Glb), nullptr).ok());
  EXPECT_TRUE(load_gltf(d.write(f.root, "inline", Doc::Form::DataUri), nullptr).ok());
}

TEST(GltfPaths, ImageUrisLeavingTheModelsFolderAreRefused) {
  const Folders f;
  Doc d;
  d.point_light(100.0);
  d.j["images"] = json::array({json{{"uri", "tex.png"}}});
  test::TempDir scratch;
  const std::string written = d.write(scratch, "lamp");
  const std::string model = (f.model / "lamp.gltf").string();
  for (const OutsideCase& c : f.cases("tex.png")) {
    fs::copy_file(written, model, fs::copy_options::overwrite_existing);
    set_uri(model, "image", c.uri);
    test::write_file(c.file, "not decoded");
    expect_refused_unless_allowed(model, c, "image");
  }
}

TEST(GltfPaths, ProfileUrisAndTheirTiltFilesLeavingTheModelsFolderAreRefused) {
  const Folders f;
  Doc d;
  add_ies_lights(d, {{{"name", "lamp"}, {"uri", "p.ies"}}});
  ies_node(d, 0);
  test::TempDir scratch;
  const std::string written = d.write(scratch, "lamp");
  const std::string model = (f.model / "lamp.gltf").string();
  for (const OutsideCase& c : f.cases("p.ies")) {
    fs::copy_file(written, model, fs::copy_options::overwrite_existing);
    set_uri(model, "profile", c.uri);
    test::write_file(c.file, kIsotropicIes);
    expect_refused_unless_allowed(model, c, "profile");
  }
  // A profile inside whose TILT=<file> leaves the folder.
  std::string tilted = kIsotropicIes;
  const std::string tilt = "1\r\n3\r\n0 45 90\r\n1 1 1\r\n";
  for (const OutsideCase& c : f.cases("tilt.dat")) {
    std::string ies = tilted;
    ies.replace(ies.find("TILT=NONE"), 9, "TILT=" + c.uri);
    fs::copy_file(written, model, fs::copy_options::overwrite_existing);
    set_uri(model, "profile", "p.ies");
    test::write_file(f.model / "p.ies", ies);
    test::write_file(c.file, tilt);
    SCOPED_TRACE("TILT=" + c.uri);
    expect_refused_unless_allowed(model, c, "TILT file");
  }
}

}  // namespace
}  // namespace gonio::io

namespace gonio::io {
namespace {

// extras.gonio spectra (issue 24): a light's and an emissive material's
// spectrum in each form, material spectra and dispersion; bad input is an
// error naming the file, the part and the key.
TEST(GltfSpectral, SpectraOnLightsAndMaterialsReachTheScene) {
  test::TempDir dir;
  Doc d;
  const int l = d.khr_light({{"type", "point"},
                             {"intensity", 10.0},
                             {"extras", {{"gonio", {{"spectrum", {{"blackbody_k", 2700.0}}}}}}}});
  d.node({{"name", "lamp"}, {"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}});
  const json table = {{"wavelengths_nm", {400.0, 550.0, 700.0}}, {"values", {0.2, 0.5, 0.9}}};
  const int glass = d.material({{"name", "glass"},
                                {"extras", {{"gonio", {{"dielectric", 0.9},
                                                       {"ior", 1.6},
                                                       {"abbe_number", 35.0},
                                                       {"spectral_transmittance", table}}}}}});
  const int paint = d.material({{"name", "paint"},
                                {"extras", {{"gonio", {{"kd", 0.5},
                                                       {"spectral_reflectance", table},
                                                       {"ior_nm", {{"wavelengths_nm", {400.0, 700.0}},
                                                                   {"values", {1.53, 1.51}}}}}}}}});
  const json over = {{"over_gamma",
                      {{{"gamma_deg", 0.0}, {"blackbody_k", 6500.0}},
                       {{"gamma_deg", 70.0}, {"wavelengths_nm", {450.0, 580.0}}, {"values", {0.3, 1.0}}}}}};
  const int led = d.material({{"name", "led"},
                              {"extras", {{"gonio", {{"luminance_cd_m2", 1000.0}, {"spectrum", over}}}}}});
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx, glass)}});
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx, paint)}});
  d.node({{"mesh", d.mesh(kQuad, kQuadIdx, led)}});
  const sim::SceneDesc s = load_ok(d.write(dir, "spectral"));
  ASSERT_EQ(s.emitters.size(), 2u);
  EXPECT_TRUE(s.spectral());
  const sim::Emitter& point = s.emitters[0].kind == sim::Emitter::Kind::Point ? s.emitters[0] : s.emitters[1];
  const sim::Emitter& area = s.emitters[0].kind == sim::Emitter::Kind::Area ? s.emitters[0] : s.emitters[1];
  ASSERT_EQ(point.spectrum.over_gamma.size(), 1u);
  EXPECT_NEAR(photometry::cct_duv(photometry::tristimulus(point.spectrum.over_gamma[0].spectrum)).cct_k, 2700.0, 0.5);
  ASSERT_EQ(area.spectrum.over_gamma.size(), 2u);
  EXPECT_EQ(area.spectrum.over_gamma[1].gamma_deg, 70.0);
  EXPECT_EQ(area.spectrum.over_gamma[1].spectrum.values, (std::vector<double>{0.3, 1.0}));
  ASSERT_EQ(s.materials.size(), 3u);
  EXPECT_EQ(s.materials[0].abbe_number, 35.0);
  EXPECT_EQ(s.materials[0].spectral_transmittance.values, (std::vector<double>{0.2, 0.5, 0.9}));
  EXPECT_EQ(s.materials[1].spectral_reflectance.wavelengths_nm, (std::vector<double>{400.0, 550.0, 700.0}));
  EXPECT_EQ(s.materials[1].ior_nm.values, (std::vector<double>{1.53, 1.51}));

  // Without any of it the scene is grey.
  Doc grey;
  grey.point_light(1.0);
  EXPECT_FALSE(load_ok(grey.write(dir, "grey")).spectral());
}

// In a spectral scene a coloured base colour becomes a Jakob–Hanika
// reflectance spectrum with the luminous reflectance the grey mapping gave;
// grey colours and grey scenes stay as they were.
TEST(GltfSpectral, BaseColoursBecomeSmoothSpectraInSpectralScenes) {
  test::TempDir dir;
  const auto doc = [](bool spectral) {
    Doc d;
    json light = {{"type", "point"}, {"intensity", 1.0}};
    if (spectral) light["extras"] = {{"gonio", {{"spectrum", {{"blackbody_k", 4000.0}}}}}};
    const int l = d.khr_light(light);
    d.node({{"name", "lamp"}, {"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}});
    const int red = d.material({{"name", "red"},
                                {"pbrMetallicRoughness", {{"baseColorFactor", {0.7, 0.1, 0.05, 1.0}},
                                                          {"metallicFactor", 0.0}}}});
    const int grey = d.material({{"name", "grey"},
                                 {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1.0}},
                                                           {"metallicFactor", 0.0}}}});
    d.node({{"mesh", d.mesh(kQuad, kQuadIdx, red)}});
    d.node({{"mesh", d.mesh(kQuad, kQuadIdx, grey)}});
    return d;
  };
  const sim::SceneDesc s = load_ok(doc(true).write(dir, "spectral"));
  ASSERT_EQ(s.materials.size(), 2u);
  const sim::Material& red = s.materials[0];
  ASSERT_FALSE(red.spectral_reflectance.empty());
  EXPECT_GT(red.spectral_reflectance.at(650.0), 5.0 * red.spectral_reflectance.at(450.0));
  const double reflect = red.diffuse_reflect + red.mirror + red.glossy;
  EXPECT_NEAR(photometry::tristimulus_under_d65(red.spectral_reflectance).Y, reflect, 1e-3);
  EXPECT_TRUE(s.materials[1].spectral_reflectance.empty());
  const sim::SceneDesc g = load_ok(doc(false).write(dir, "grey"));
  EXPECT_TRUE(g.materials[0].spectral_reflectance.empty());
  EXPECT_FALSE(g.spectral());
}

TEST(GltfSpectral, BadSpectraAreErrorsNamingFilePartAndKey) {
  test::TempDir dir;
  auto light_error = [&](json spectrum, const std::string& stem) {
    Doc d;
    const int l = d.khr_light({{"type", "point"}, {"intensity", 1.0},
                               {"extras", {{"gonio", {{"spectrum", std::move(spectrum)}}}}}});
    d.node({{"name", "lamp"}, {"extensions", {{"KHR_lights_punctual", {{"light", l}}}}}});
    return load_error(d.write(dir, stem));
  };
  auto material_error = [&](json gonio, const std::string& stem) {
    Doc d;
    d.point_light(1.0);
    const int m = d.material({{"name", "skin"}, {"extras", {{"gonio", std::move(gonio)}}}});
    d.node({{"mesh", d.mesh(kQuad, kQuadIdx, m)}});
    return load_error(d.write(dir, stem));
  };
  const std::string e = light_error({{"wavelengths_nm", {500.0, 400.0}}, {"values", {1.0, 1.0}}}, "order");
  EXPECT_CONTAINS(e, "node 'lamp'");
  EXPECT_CONTAINS(e, "extras.gonio.spectrum: wavelength 1 (400 nm) does not increase");
  EXPECT_CONTAINS(light_error({{"blackbody_k", -5.0}}, "bb"), "extras.gonio.spectrum.blackbody_k = -5 must lie in");
  EXPECT_CONTAINS(light_error({{"values", {1.0, 1.0}}}, "nowl"), "'wavelengths_nm' is missing (or give blackbody_k)");
  EXPECT_CONTAINS(light_error({{"wavelengths_nm", {400.0, "x"}}, {"values", {1.0, 1.0}}}, "str"),
                  "extras.gonio.spectrum.wavelengths_nm[1] is not a number");
  EXPECT_CONTAINS(light_error({{"over_gamma", {{{"gamma_deg", 10.0}, {"blackbody_k", 3000.0}},
                                               {{"gamma_deg", 5.0}, {"blackbody_k", 3000.0}}}}},
                              "gamma"),
                  "spectrum at entry 1: gamma_deg 5 does not increase");
  EXPECT_CONTAINS(light_error({{"over_gamma", {{{"blackbody_k", 3000.0}}}}}, "nogamma"),
                  "extras.gonio.spectrum.over_gamma[0]: 'gamma_deg' is missing");
  const std::string m = material_error(
      {{"kd", 0.5}, {"spectral_reflectance", {{"wavelengths_nm", {400.0, 700.0}}, {"values", {0.5, 1.5}}}}},
      "refl");
  EXPECT_CONTAINS(m, "material 'skin'");
  EXPECT_CONTAINS(m, "extras.gonio.spectral_reflectance: value 1 (1.5) exceeds 1");
  EXPECT_CONTAINS(material_error({{"ior_nm", {{"wavelengths_nm", {400.0, 700.0}}, {"values", {1.5, 0.9}}}}}, "ior"),
                  "extras.gonio.ior_nm: value 1 (0.9) must be >= 1");
  EXPECT_CONTAINS(material_error({{"abbe_number", -3.0}}, "abbe"), "extras.gonio.abbe_number must be > 0");
}

}  // namespace
}  // namespace gonio::io

namespace gonio::io {
namespace {

// Measured materials in extras.gonio (io/model/material_extras.h): a preset
// by name, ABg from TracePro's A, a measured BSDF beside the model,
// incidence tables; and the errors that name the key.
TEST(GltfMaterials, PresetAbgBsdfFileAndIncidenceTablesAreRead) {
  test::TempDir dir;
  // A CSV goniometer table beside the model: Lambertian reflection 0.4.
  std::string csv = "theta_in,theta_out,phi_out,bsdf\n";
  for (double ti : {0.0, 60.0})
    for (double to = 0.0; to < 90.0; to += 15.0)
      for (double p : {0.0, 90.0, 180.0}) csv += std::to_string(ti) + "," + std::to_string(to) + "," + std::to_string(p) + "," + std::to_string(0.4 / 3.14159265358979) + "\n";
  test::write_file(dir / "sheet.csv", csv);
  Doc d;
  d.point_light(1.0);
  const int opal = d.material({{"name", "opal"}, {"extras", {{"gonio", {{"preset", "opal PC 3 mm"}}}}}});
  const int blast = d.material(
      {{"name", "blasted"},
       {"extras", {{"gonio", {{"mirror", 0.4}, {"abg", {{"A", 0.02}, {"B", 0.01}, {"g", 2.0}}}}}}}});
  const int measured = d.material(
      {{"name", "measured"}, {"extras", {{"gonio", {{"bsdf_file", "sheet.csv"}, {"tabulated", 0.9}}}}}});
  const int paint = d.material(
      {{"name", "paint"},
       {"extras",
        {{"gonio", {{"kd", 0.8}, {"reflectance_over_angle", {{"angles_deg", {0.0, 60.0, 85.0}}, {"values", {0.8, 0.7, 0.4}}}},
                    {"glossy_compensation", false}}}}}});
  for (int m : {opal, blast, measured, paint}) d.node({{"mesh", d.mesh(kQuad, kQuadIdx, m)}});
  const sim::SceneDesc s = load_ok(d.write(dir, "measured"));
  ASSERT_EQ(s.materials.size(), 4u);
  const sim::Material& o = s.materials[0];
  EXPECT_EQ(o.name, "opal");
  EXPECT_EQ(o.scattering_per_m, sim::find_preset("opal PC 3 mm")->material.scattering_per_m);
  EXPECT_EQ(o.dielectric, 1.0);
  // TIS = A · π ln((B + 1)/B) for g = 2.
  EXPECT_NEAR(s.materials[1].abg_reflect.tis, 0.02 * 3.14159265358979 * std::log(101.0), 1e-6);
  EXPECT_EQ(s.materials[1].mirror, 0.4);
  ASSERT_TRUE(s.materials[2].table);
  EXPECT_EQ(s.materials[2].tabulated, 0.9);
  EXPECT_NEAR(s.materials[2].table->albedo(true, Vec3{0.0, 0.0, 1.0}), 0.4, 1e-6);
  const sim::Material& p = s.materials[3];
  EXPECT_FALSE(p.glossy_compensation);
  EXPECT_NEAR(p.diffuse_reflect * p.over_incidence[0].at(std::cos(60.0 * 3.14159265358979 / 180.0)), 0.7, 1e-12);
  EXPECT_TRUE(p.over_incidence[1].empty());
}

// A volume preset's sheet form (issue 43): the part as one sheet of
// triangles scattering by the tabulated BSDF of the preset's sheet, which
// gives back the preset's datasheet transmittance at normal incidence;
// "walk" is the preset as it is.
TEST(GltfMaterials, VolumeFormSheetIsThePresetsTabulatedSheet) {
  test::TempDir dir;
  Doc d;
  d.point_light(1.0);
  const int sheet = d.material(
      {{"name", "shade"}, {"extras", {{"gonio", {{"preset", "opal PMMA 3 mm"}, {"volume_form", "sheet"}}}}}});
  const int walk = d.material(
      {{"name", "shell"}, {"extras", {{"gonio", {{"preset", "opal PMMA 3 mm"}, {"volume_form", "walk"}}}}}});
  for (int m : {sheet, walk}) d.node({{"mesh", d.mesh(kQuad, kQuadIdx, m)}});
  const sim::SceneDesc s = load_ok(d.write(dir, "sheetform"));
  ASSERT_EQ(s.materials.size(), 2u);
  const sim::MaterialPreset& opal = *sim::find_preset("opal PMMA 3 mm");
  const sim::Material& a = s.materials[0];
  EXPECT_EQ(a.name, "shade");
  ASSERT_TRUE(a.table);
  EXPECT_EQ(a.tabulated, 1.0);
  EXPECT_EQ(a.scattering_per_m, 0.0);
  EXPECT_EQ(a.dielectric, 0.0);
  const double albedo = a.table->albedo(true, Vec3{0.0, 0.0, 1.0});
  const double reflect = a.table->front.rows[0].reflect_albedo;
  EXPECT_NEAR(albedo - reflect, opal.transmittance, 0.01);  // T 0.60 at 3 mm
  EXPECT_GT(reflect, 0.2);
  EXPECT_LT(albedo, 1.0);  // it absorbs a little (μa 2.89 /m)
  const sim::Material& b = s.materials[1];
  EXPECT_EQ(b.name, "shell");
  EXPECT_FALSE(b.table);
  EXPECT_EQ(b.scattering_per_m, opal.material.scattering_per_m);
}

TEST(GltfMaterials, BadMeasuredMaterialsAreErrorsNamingTheKey) {
  test::TempDir dir;
  test::write_file(dir / "broken.csv", "theta_in,theta_out,phi_out,bsdf\n0,10,0,-1\n");
  auto material_error = [&](json gonio, const std::string& stem) {
    Doc d;
    d.point_light(1.0);
    const int m = d.material({{"name", "skin"}, {"extras", {{"gonio", std::move(gonio)}}}});
    d.node({{"mesh", d.mesh(kQuad, kQuadIdx, m)}});
    return load_error(d.write(dir, stem));
  };
  EXPECT_CONTAINS(material_error({{"preset", "opal glass"}}, "nopreset"), "preset 'opal glass' is not in the library");
  EXPECT_CONTAINS(material_error({{"preset", "black"}, {"kd", 0.5}}, "mixed"), "preset stands alone");
  EXPECT_CONTAINS(material_error({{"preset", "black"}, {"volume_form", "sheet"}}, "sheetblack"),
                  "volume_form \"sheet\" needs a volume preset");
  EXPECT_CONTAINS(material_error({{"kd", 0.5}, {"volume_form", "sheet"}}, "sheetnone"),
                  "volume_form \"sheet\" needs a volume preset");
  EXPECT_CONTAINS(material_error({{"preset", "opal PC 3 mm"}, {"volume_form", "thin"}}, "sheetthin"),
                  "'volume_form' must be \"walk\" or \"sheet\"");
  EXPECT_CONTAINS(material_error({{"abg", {{"B", 0.01}, {"g", 2.0}}}}, "notis"), "give either tis or A");
  EXPECT_CONTAINS(material_error({{"abg", {{"tis", 0.5}, {"B", 0.0}, {"g", 2.0}}}}, "b0"), "extras.gonio.abg.B = 0");
  EXPECT_CONTAINS(material_error({{"abg", {{"A", 50.0}, {"B", 0.01}, {"g", 2.0}}}}, "bigA"), "(A · I0) must lie in 0..1");
  // A broken or missing BSDF file: the error names that file (and line),
  // its message the material that refers to it.
  auto file_error = [&](const std::string& file, const std::string& stem) {
    Doc d;
    d.point_light(1.0);
    const int m = d.material({{"name", "skin"}, {"extras", {{"gonio", {{"bsdf_file", file}}}}}});
    d.node({{"mesh", d.mesh(kQuad, kQuadIdx, m)}});
    Result<sim::SceneDesc> r = load_gltf(d.write(dir, stem), nullptr);
    EXPECT_FALSE(r.ok()) << file;
    return r.ok() ? std::string() : to_string(r.error());
  };
  EXPECT_CONTAINS(file_error("missing.xml", "missing"), "missing.xml: material 'skin' (#0): extras.gonio.bsdf_file");
  EXPECT_CONTAINS(file_error("broken.csv", "broken"), "broken.csv:2: material 'skin' (#0): extras.gonio.bsdf_file: bsdf -1");
  EXPECT_CONTAINS(material_error({{"bsdf_file", "../outside.csv"}}, "outside"), "outside the model's folder");
  EXPECT_CONTAINS(material_error({{"tabulated", 0.5}}, "notable"), "'tabulated' weighs a bsdf_file");
  EXPECT_CONTAINS(material_error({{"kd", 0.5}, {"reflectance_over_angle", {{"angles_deg", {0.0, 95.0}}, {"values", {0.5, 0.5}}}}}, "angle"),
                  "reflectance_over_angle.angles_deg must increase within 0..90");
  EXPECT_CONTAINS(material_error({{"kd", 0.5}, {"lobe_over_angle", {{"shiny", {{"angles_deg", {0.0}}, {"values", {1.0}}}}}}}, "lobe"),
                  "lobe_over_angle.shiny is not a lobe");
  EXPECT_CONTAINS(material_error({{"kd", 0.9}, {"lobe_over_angle", {{"diffuse_reflect", {{"angles_deg", {0.0, 80.0}}, {"values", {1.0, 1.5}}}}}}}, "over1"),
                  "scatter 1.35, more than 1");
  EXPECT_CONTAINS(material_error({{"dielectric", 1.0}, {"scattering_g", 1.0}}, "g1"), "extras.gonio.scattering_g = 1");
  EXPECT_CONTAINS(material_error({{"glossy_compensation", 1}}, "comp"), "'glossy_compensation' must be true or false");
}

}  // namespace
}  // namespace gonio::io
