#include "io/photometric/gldf.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <numbers>
#include <string>

#include "io/photometric/ldt.h"
#include "io/photometric/photometric_file.h"
#include "io/support/xml.h"
#include "io/support/zip.h"
#include "photometry/flux.h"
#include "tests/support/photometry_fixtures.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

namespace fs = std::filesystem;
using photometry::Distribution;

constexpr double kDeg = std::numbers::pi / 180.0;

// parse_gldf, each archive also a seed for the GLDF fuzzer (scripts/fuzz.sh).
Result<GldfFile> parse(const std::string& archive, const std::string& name) {
  test::offer_fuzz_seed("gldf", archive);
  return parse_gldf(archive, name);
}

Distribution downlight() {
  Distribution d = test::sample_c(photometry::Symmetry::C0_C180, test::angles(0, 180, 15), test::angles(0, 180, 5),
                                  [](double c, double g) {
                                    return g < 90 ? 300.0 * std::cos(g * kDeg) * (1.0 + 0.1 * std::cos(c * kDeg))
                                                  : 0.0;
                                  });
  d.lamps = {photometry::LampSet{1, "LED", 1200.0, "3000", "80", 12.0}};
  d.keywords = {{"MANUFAC", "Gonio"}, {"LUMINAIRE", "Test downlight"}};
  return d;
}

// A unit cube lamp: 12 triangles, one point emitter 1 cm below its centre
// and one area emitter (its bottom face) in glTF's Y-up world.
sim::SceneDesc cube_scene() {
  sim::SceneDesc s;
  s.name = "cube";
  sim::Mesh box;
  for (int i = 0; i < 8; ++i)
    box.positions.push_back({(i & 1) ? 0.5f : -0.5f, (i & 2) ? 1.0f : 0.0f, (i & 4) ? 0.5f : -0.5f});
  box.indices = {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1,
                 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
  s.meshes.push_back(box);
  sim::Mesh die;
  die.positions = {{-0.1f, -0.01f, -0.2f}, {0.1f, -0.01f, -0.2f}, {0.1f, -0.01f, 0.2f}, {-0.1f, -0.01f, 0.2f}};
  die.indices = {0, 1, 2, 0, 2, 3};
  s.meshes.push_back(die);
  sim::Emitter area;
  area.kind = sim::Emitter::Kind::Area;
  area.mesh = 1;
  area.flux_lm = 100.0;
  s.emitters.push_back(area);
  return s;
}

// xmllint --schema on `xml` against the GLDF schema used in place.
void expect_valid_product_xml(const std::string& xml) {
  const fs::path schema = test::source_dir() / ".." / "shared" / "schemas" / "gldf-1.0.0-rc.3.xsd";
  const bool have_schema = fs::exists(schema);
  const test::ProcessResult probe = test::run_process({"/bin/sh", "-c", "command -v xmllint"});
  const bool have_xmllint = probe.exit_code == 0;
  if (!have_schema || !have_xmllint) {
    const std::string missing = !have_schema ? "the GLDF schema " + schema.string() : "xmllint (libxml2-utils)";
    GONIO_MISSING(missing + ": product.xml cannot be validated");
  }
  test::TempDir dir;
  test::write_file(dir / "product.xml", xml);
  std::string xmllint = probe.out;
  while (!xmllint.empty() && std::isspace(static_cast<unsigned char>(xmllint.back()))) xmllint.pop_back();
  const test::ProcessResult r =
      test::run_process({xmllint, "--noout", "--schema", schema.string(), (dir / "product.xml").string()});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("validates"), std::string::npos) << r.err;
}

TEST(Gldf, ProductXmlValidatesAgainstTheSchema) {
  GldfProduct p;
  p.name = "Test downlight";
  p.manufacturer = "Gonio & Co <tests>";
  p.description = "A downlight";
  p.photometries.push_back({"dl.ldt", "ldc/eulumdat", "ldt bytes", downlight()});
  p.photometries.push_back({"dl.ies", "ldc/ies", "ies bytes", downlight()});
  p.created_unix = 1764620000;
  SCOPED_TRACE("without geometry");
  expect_valid_product_xml(gldf_product_xml(p));
  p.geometry = l3d_from_scene(cube_scene());
  SCOPED_TRACE("with geometry");
  const std::string xml = gldf_product_xml(p);
  expect_valid_product_xml(xml);
  EXPECT_NE(xml.find("Gonio &amp; Co &lt;tests&gt;"), std::string::npos);
  EXPECT_NE(xml.find("<LightOutputRatio>"), std::string::npos);
  EXPECT_NE(xml.find("<EmitterObjectExternalName>lightEmittingObject</EmitterObjectExternalName>"),
            std::string::npos);
}

TEST(Gldf, LdtThroughGldfReadsBackExactly) {
  test::TempDir dir;
  const Distribution d = downlight();
  for (PhotometricFormat inner : {PhotometricFormat::Ldt, PhotometricFormat::Ies, PhotometricFormat::Tm33}) {
    SCOPED_TRACE(to_string(inner));
    PhotometricWriteOptions o;
    o.gldf_photometry = inner;
    o.gldf_created_unix = 1764620000;
    const fs::path path = dir / (std::string("dl-") + to_string(inner) + ".gldf");
    std::vector<Finding> w;
    ASSERT_TRUE(write_photometric_file(path.string(), d, o, &w).ok());
    auto direct = encode_photometric_file(d, inner, o, nullptr);
    ASSERT_TRUE(direct.ok());
    test::offer_fuzz_seed("gldf", test::read_file(path));
    auto back = read_photometric_file(path.string());
    ASSERT_TRUE(back.ok()) << to_string(back.error());
    EXPECT_EQ(back->format, inner);
    EXPECT_EQ(back->container, path.string());
    EXPECT_EQ(format_label(*back).rfind("GLDF (", 0), 0u) << format_label(*back);
    // The photometry inside is exactly what the format's own writer writes.
    auto entries = read_zip(test::read_file(path), path.string());
    ASSERT_TRUE(entries.ok());
    ASSERT_EQ(entries->size(), 2u);
    EXPECT_EQ((*entries)[0].name, "product.xml");
    EXPECT_EQ((*entries)[1].bytes, *direct);
    ASSERT_EQ(back->distribution.candela.size(), d.candela.size());
    for (std::size_t i = 0; i < d.candela.size(); ++i)  // LDT: 12 digits of cd/klm
      ASSERT_NEAR(back->distribution.candela[i], d.candela[i], 1e-11 * d.candela[i]) << i;
    const double fa = photometry::total_flux_lm(d), fb = photometry::total_flux_lm(back->distribution);
    EXPECT_NEAR(fb, fa, 1e-9 * fa);
    expect_valid_product_xml((*entries)[0].bytes);
  }
}

TEST(Gldf, L3dHoldsTheModelInTheLuminaireFrameAndTheEmitterWhereItIs) {
  const L3dGeometry g = l3d_from_scene(cube_scene());
  // glTF Y up -> L3D Z up: a vertex at world (0.5, 1, -0.5) is at X = C0 =
  // world +X, Y = C90 = world −Z, Z = world +Y.
  EXPECT_NE(g.obj.find("\nv 0.5 0.5 1\n"), std::string::npos) << g.obj.substr(0, 400);
  EXPECT_NE(g.obj.find("\nf 1 2 4\n"), std::string::npos);
  ASSERT_EQ(g.emitters.size(), 1u);
  const L3dEmitter& e = g.emitters[0];
  EXPECT_NEAR(e.position_m.x, 0.0, 1e-6);
  EXPECT_NEAR(e.position_m.y, 0.0, 1e-6);
  EXPECT_NEAR(e.position_m.z, -0.01, 1e-6);
  EXPECT_NEAR(e.size_x_m, 0.2, 1e-6);
  EXPECT_NEAR(e.size_y_m, 0.4, 1e-6);

  auto l3d = write_l3d(g, "test", 1764620000);
  ASSERT_TRUE(l3d.ok());
  auto entries = read_zip(*l3d, "x.l3d");
  ASSERT_TRUE(entries.ok());
  ASSERT_EQ(entries->size(), 2u);
  EXPECT_EQ((*entries)[0].name, "structure.xml");
  EXPECT_EQ((*entries)[1].name, "luminaire/luminaire.obj");
  auto structure = parse_xml((*entries)[0].bytes, "structure.xml");
  ASSERT_TRUE(structure.ok());
  EXPECT_EQ(structure->name, "Luminaire");
  const XmlElement* def = structure->child("GeometryDefinitions")->child("GeometryFileDefinition");
  EXPECT_EQ(*def->attribute("filename"), "luminaire.obj");
  EXPECT_EQ(*def->attribute("units"), "m");
  const XmlElement* leo =
      structure->child("Structure")->child("Geometry")->child("LightEmittingObjects")->child("LightEmittingObject");
  ASSERT_NE(leo, nullptr);
  EXPECT_EQ(*leo->child("Rectangle")->attribute("sizeY"), "0.4000000059604645");  // float vertices
}

// ---- L3D parts: instanced meshes written once, placed by position and angle

// An asymmetric tetrahedron, so that any wrong turn or mirror shows.
sim::Mesh tetra() {
  sim::Mesh m;
  m.positions = {{0.0f, 0.0f, 0.0f}, {0.05f, 0.0f, 0.0f}, {0.0f, 0.03f, 0.0f}, {0.0f, 0.0f, 0.02f}};
  m.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  m.instanced = true;
  return m;
}

// A triangle as placed in L3D's frame: its corners in order.
struct Placed {
  Vec3 p[3];
};

// Every triangle an .l3d archive places, read back from its bytes: each
// Geometry part's OBJ through its Position and its one-axis Rotation
// (right-handed, degrees).
std::vector<Placed> read_back_l3d(const std::string& archive) {
  std::vector<Placed> out;
  auto entries = read_zip(archive, "x.l3d");
  EXPECT_TRUE(entries.ok());
  if (!entries.ok()) return out;
  std::map<std::string, std::string> files;
  for (const ZipEntry& e : *entries) files[e.name] = e.bytes;
  auto structure = parse_xml(files["structure.xml"], "structure.xml");
  EXPECT_TRUE(structure.ok());
  if (!structure.ok()) return out;
  std::map<std::string, std::string> obj_of;  // geometry id → OBJ path
  for (const XmlElement& d : structure->child("GeometryDefinitions")->children)
    obj_of[*d.attribute("id")] = *d.attribute("id") + "/" + *d.attribute("filename");
  std::set<std::string> part_names;
  for (const XmlElement& part : structure->child("Structure")->children) {
    EXPECT_TRUE(part_names.insert(*part.attribute("partName")).second) << *part.attribute("partName");
    const auto vec = [&](const char* name) {
      const XmlElement* e = part.child(name);
      return Vec3{std::stod(*e->attribute("x")), std::stod(*e->attribute("y")), std::stod(*e->attribute("z"))};
    };
    const Vec3 position = vec("Position"), turn = vec("Rotation") * kDeg;
    EXPECT_LE((turn.x != 0.0) + (turn.y != 0.0) + (turn.z != 0.0), 1) << "two axes: the order would matter";
    const auto rotate = [&](Vec3 q) {
      if (turn.x != 0.0) return Vec3{q.x, std::cos(turn.x) * q.y - std::sin(turn.x) * q.z,
                                     std::sin(turn.x) * q.y + std::cos(turn.x) * q.z};
      if (turn.y != 0.0) return Vec3{std::cos(turn.y) * q.x + std::sin(turn.y) * q.z, q.y,
                                     -std::sin(turn.y) * q.x + std::cos(turn.y) * q.z};
      return Vec3{std::cos(turn.z) * q.x - std::sin(turn.z) * q.y, std::sin(turn.z) * q.x + std::cos(turn.z) * q.y,
                  q.z};
    };
    const std::string id = *part.child("GeometryReference")->attribute("geometryId");
    EXPECT_TRUE(obj_of.count(id)) << id;
    std::istringstream obj(files[obj_of[id]]);
    EXPECT_FALSE(obj.str().empty()) << obj_of[id];
    std::vector<Vec3> v;
    for (std::string line; std::getline(obj, line);) {
      std::istringstream in(line);
      std::string tag;
      in >> tag;
      if (tag == "v") {
        Vec3 q;
        in >> q.x >> q.y >> q.z;
        v.push_back(position + rotate(q));
      } else if (tag == "f") {
        std::size_t a, b, c;
        in >> a >> b >> c;
        out.push_back({{v.at(a - 1), v.at(b - 1), v.at(c - 1)}});
      }
    }
  }
  return out;
}

// The same triangles, each once, corners in the same cyclic order (so the
// same front side), within `tolerance` [m] (the flattened model's vertices
// are floats: ~10⁻⁸ m off at these sizes).
void expect_same_triangles(std::vector<Placed> got, const std::vector<Placed>& want, double tolerance) {
  ASSERT_EQ(got.size(), want.size());
  const auto close = [&](const Placed& a, const Placed& b, int shift) {
    for (int k = 0; k < 3; ++k)
      if (length(a.p[k] - b.p[(k + shift) % 3]) > tolerance) return false;
    return true;
  };
  for (const Placed& w : want) {
    bool found = false;
    for (std::size_t i = 0; i < got.size() && !found; ++i)
      for (int shift = 0; shift < 3 && !found; ++shift)
        if (close(w, got[i], shift)) {
          got.erase(got.begin() + static_cast<std::ptrdiff_t>(i));
          found = true;
        }
    EXPECT_TRUE(found) << "a triangle at " << w.p[0].x << " " << w.p[0].y << " " << w.p[0].z << " is missing";
  }
}

std::string l3d_bytes(const sim::SceneDesc& scene) {
  auto l3d = write_l3d(l3d_from_scene(scene), "test", 1764620000);
  EXPECT_TRUE(l3d.ok());
  return l3d.ok() ? *l3d : std::string();
}

TEST(Gldf, L3dWritesEachInstancedMeshOnceAndPlacesItsCopiesAsParts) {
  sim::SceneDesc scene = cube_scene();
  scene.meshes.push_back(tetra());
  const std::uint32_t t = static_cast<std::uint32_t>(scene.meshes.size() - 1);
  const Vec3 up{0, 1, 0}, c0{1, 0, 0};
  const auto place = [&](const sim::Affine& a) { scene.instances.push_back({t, a, "i"}); };
  place(sim::translation({0.3, 0.2, 0.1}));                                            // a part
  place(sim::translation({-0.3, 0.2, 0.1}) * sim::rotation(up, 30 * kDeg));           // about the zenith
  place(sim::translation({0, 1.2, 0}) * sim::rotation(c0, 45 * kDeg) * sim::scaling(2, 2, 2));  // about C0, x2
  place(sim::translation({0, 1.4, 0}) * sim::scaling(2, 2, 2));                         // the same scale
  place(sim::translation({0, -0.2, 0}) * sim::scaling(-1, 1, 1));                       // mirrored: body
  place(sim::translation({0, -0.4, 0}) * sim::scaling(1, 2, 1));                        // stretched: body
  place(sim::rotation({1, 1, 0}, 40 * kDeg));                                           // skew axis: body

  const L3dGeometry g = l3d_from_scene(scene);
  ASSERT_EQ(g.definitions.size(), 2u);  // the tetrahedron at scales 1 and 2
  ASSERT_EQ(g.parts.size(), 4u);
  EXPECT_NEAR(g.parts[1].rotation_deg.z, 30.0, 1e-9);
  EXPECT_NEAR(g.parts[2].rotation_deg.x, 45.0, 1e-9);
  EXPECT_EQ(g.parts[2].geometry_id, g.parts[3].geometry_id);
  EXPECT_NE(g.parts[0].geometry_id, g.parts[2].geometry_id);

  // Read back from the archive's bytes: the same triangles, same sides, as
  // the flattened model (the body of an all-flat L3D) places.
  const auto flat = read_back_l3d(l3d_bytes(sim::flattened(scene)));
  EXPECT_EQ(flat.size(), 12u + 2u + 7u * 4u);
  expect_same_triangles(read_back_l3d(l3d_bytes(scene)), flat, 1e-6);
}

TEST(Gldf, L3dOfAnArrayGrowsWithTheUniqueGeometryNotTheCopies) {
  const auto array = [](int copies) {
    sim::SceneDesc scene = cube_scene();
    scene.meshes.push_back(tetra());
    for (int i = 0; i < copies; ++i)
      scene.instances.push_back({2, sim::translation({0.01 * i, 1.1, 0.0}), "lens"});
    return scene;
  };
  const L3dGeometry two = l3d_from_scene(array(2)), many = l3d_from_scene(array(1000));
  ASSERT_EQ(many.definitions.size(), 1u);
  EXPECT_EQ(many.parts.size(), 1000u);
  EXPECT_EQ(many.obj, two.obj);
  EXPECT_EQ(many.definitions[0].obj, two.definitions[0].obj);
  expect_same_triangles(read_back_l3d(l3d_bytes(array(40))), read_back_l3d(l3d_bytes(sim::flattened(array(40)))),
                        1e-6);
}

TEST(Gldf, L3dBodyIsNeverEmptyWhenEveryMeshIsInstanced) {
  sim::SceneDesc scene;
  scene.name = "lenses";
  scene.materials.push_back({});
  scene.meshes.push_back(tetra());
  for (int i = 0; i < 3; ++i) scene.instances.push_back({0, sim::translation({0.1 * i, 0, 0}), "lens"});
  sim::Emitter e;
  e.position = {0, -0.1, 0};
  e.flux_lm = 1.0;
  scene.emitters.push_back(e);
  const L3dGeometry g = l3d_from_scene(scene);
  EXPECT_NE(g.obj.find("\nf "), std::string::npos) << "the body holds the first copy";
  EXPECT_EQ(g.parts.size(), 2u);
  ASSERT_EQ(g.emitters.size(), 1u);
  expect_same_triangles(read_back_l3d(l3d_bytes(scene)), read_back_l3d(l3d_bytes(sim::flattened(scene))), 1e-6);
}

std::string product(const std::string& file_element) {
  return "<?xml version=\"1.0\"?>\n<Root>\n<Header><Manufacturer>M</Manufacturer></Header>\n"
         "<GeneralDefinitions>\n<Files>\n" +
         file_element +
         "\n</Files>\n<Photometries>\n<Photometry id=\"p1\"><PhotometryFileReference fileId=\"f1\"/>"
         "</Photometry>\n</Photometries>\n</GeneralDefinitions>\n</Root>\n";
}

TEST(Gldf, BrokenContainersAreClearErrorsNamingTheArchiveAndLine) {
  const std::string ldt = *write_ldt(downlight(), {}, nullptr);
  const std::string good_file = "<File id=\"f1\" contentType=\"ldc/eulumdat\" type=\"localFileName\">a.ldt</File>";
  auto good = parse(*write_zip({{"product.xml", product(good_file)}, {"ldc/a.ldt", ldt}}, 0), "g.gldf");
  ASSERT_TRUE(good.ok()) << to_string(good.error());
  EXPECT_EQ(good->photometries.size(), 1u);
  EXPECT_EQ(good->manufacturer, "M");

  struct Case {
    const char* name;
    std::vector<ZipEntry> entries;
    const char* says;
    int line;
  };
  const std::vector<Case> cases = {
      {"missing file", {{"product.xml", product(good_file)}}, "refers to 'ldc/a.ldt', which the archive lacks", 6},
      {"no product.xml", {{"ldc/a.ldt", ldt}}, "no product.xml", 0},
      {"malformed", {{"product.xml", "<Root><Header></Root>"}, {"ldc/a.ldt", ldt}}, "malformed XML", 1},
      {"unknown id",
       {{"product.xml", product("<File id=\"f2\" contentType=\"ldc/eulumdat\" type=\"localFileName\">a.ldt</File>")}},
       "refers to file id 'f1'",
       9},
      {"escaping name",
       {{"product.xml", product("<File id=\"f1\" contentType=\"ldc/eulumdat\" type=\"localFileName\">../a.ldt</File>")}},
       "not a relative name inside the archive",
       6},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    auto r = parse(*write_zip(c.entries, 0), "bad.gldf");
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(c.says), std::string::npos) << r.error().message;
    EXPECT_EQ(r.error().where.line, c.line) << r.error().message;
    EXPECT_EQ(r.error().where.file.rfind("bad.gldf", 0), 0u) << r.error().where.file;
  }
}

}  // namespace
}  // namespace gonio::io
