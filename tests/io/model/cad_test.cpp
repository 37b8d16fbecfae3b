// CAD models (io/model/cad.h, step.h): files written by FreeCAD and by
// OpenCASCADE's DRAW harness (tests/cad/), read through the helper process,
// against the closed forms their scripts were built from.
#include "io/model/cad.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <utility>
#include <vector>
#include <algorithm>

#include "io/model/cad_model.h"
#include "io/model/model_check.h"
#include "io/support/content_hash.h"
#include "io/support/file_io.h"
#include "sim/affine.h"
#include "sim/bsdfs/library.h"
#include "sim/bsdfs/tabulated_bsdf.h"
#include "sim/scene.h"
#include "tests/io/model/cad_parts.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

constexpr double kFocal = 0.010;   // make_parts.py: F [m]
constexpr double kHole = 0.004;    // R_HOLE
constexpr double kAper = 0.030;    // R_APER
constexpr double kBall = 0.005;    // BALL_R

// Options with a cache the suite's processes share (ctest runs each test as
// a process of its own): a part meshed once is read from there after; the
// cache's own behaviour is CadCache's to test. The cache's key holds
// kCadReaderRevision but not the helper's code, so the folder is one per
// build of the helper (its bytes' hash): a changed io/model/step.cpp — a
// fix, or a mistake put in to see a test fail — must not be tested on the
// meshes the helper made before it.
CadLoadOptions cached() {
  static const std::string folder = [] {
    Result<std::string> helper = read_file(GONIO_CAD_HELPER_PATH, std::size_t{1} << 30);
    return std::string(GONIO_TEST_DATA_DIR "/cad-cache/helper-") +
           (helper.ok() ? content_hash_hex(*helper) : std::string("unread"));
  }();
  CadLoadOptions o;
  o.cache_dir = folder;
  return o;
}

Result<CadModel> tessellate(const fs::path& file, CadTessellation t = {}) {
  CadLoadOptions o = cached();
  o.tessellation = t;
  return tessellate_cad(file.string(), o);
}

// A sidecar beside a copy of `model` in `dir`; returns the copy's path.
fs::path with_sidecar(const TempDir& dir, const fs::path& model, const std::string& toml) {
  const fs::path copy = dir / model.filename().string();
  fs::copy_file(model, copy, fs::copy_options::overwrite_existing);
  test::write_file(dir / (model.stem().string() + ".gonio.toml"), toml);
  return copy;
}

const char* kLampSidecar = R"(
default_material = "black"

[materials.black]
kd = 0.05

[materials.mirror]
reflectance = 0.9
diffuse_reflectance = 0

[materials.pmma]
transmittance = 0.92
diffusion = 0
ior = 1.49

[[parts]]
match = "Reflector"
material = "mirror"

[[parts]]
match = "Lamp/Front*"
material = "pmma"

[[emitters]]
name = "LED"
at = "LED*"
position = [0, 0, 1]
flux_lm = 100
)";

TEST(CadStep, FreeCadAssemblyKeepsNamesPlacementsAndSharesTheRepeatedPart) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  Result<CadModel> m = tessellate(parts / "lamp.step");
  ASSERT_TRUE(m.ok()) << to_string(m.error());
  EXPECT_EQ(m->format, "STEP");
  ASSERT_EQ(m->parts.size(), 4u);    // housing, reflector, LED (once), lens
  ASSERT_EQ(m->placements.size(), 6u);
  std::set<std::string> paths;
  for (const CadPlacement& p : m->placements) paths.insert(p.path);
  EXPECT_EQ(paths, (std::set<std::string>{"Lamp/Housing", "Lamp/Reflector", "Lamp/LED1", "Lamp/LED2", "Lamp/LED3",
                                          "Lamp/FrontLens"}));
  // The three LEDs are one part: a reader that copied them would make three.
  std::set<std::uint32_t> led_parts;
  for (const CadPlacement& p : m->placements)
    if (p.path.find("LED") != std::string::npos) {
      led_parts.insert(p.part);
      EXPECT_EQ(m->parts[p.part].name, "LED");
    }
  EXPECT_EQ(led_parts.size(), 1u);
  // Placements in metres: LED1 at x = -3 mm, z = 0.5 mm, LED3 turned 180°.
  for (const CadPlacement& p : m->placements) {
    if (p.path == "Lamp/LED1") {
      EXPECT_NEAR(p.to_world.offset.x, -0.003, 1e-12);
      EXPECT_NEAR(p.to_world.offset.z, 0.0005, 1e-12);
    }
    if (p.path == "Lamp/LED3") {
      EXPECT_NEAR(p.to_world.m[0][0], -1.0, 1e-12);
      EXPECT_NEAR(p.to_world.offset.x, 0.003, 1e-12);
    }
  }
  // The housing is 80 mm square: the file's millimetres became metres.
  for (const CadPart& p : m->parts) {
    if (p.name == "Housing") {
      EXPECT_NEAR(p.size_m, std::sqrt(0.08 * 0.08 * 2 + 0.005 * 0.005), 1e-9);
    }
  }
}

TEST(CadStep, ReflectorVerticesLieOnTheParaboloidAndNormalsAreTheSurfaces) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  Result<CadModel> m = tessellate(parts / "reflector.step");
  ASSERT_TRUE(m.ok()) << to_string(m.error());
  ASSERT_EQ(m->parts.size(), 1u);
  const CadSurface& s = m->parts[0].surfaces.at(0);
  ASSERT_FALSE(s.normals.empty());
  double worst_z = 0.0, worst_normal = 0.0, rmin = 1.0, rmax = 0.0;
  for (std::size_t i = 0; i < s.positions.size(); ++i) {
    const Vec3 p = sim::to_double(s.positions[i]);
    const double r = std::hypot(p.x, p.y);
    rmin = std::min(rmin, r);
    rmax = std::max(rmax, r);
    // z = f − r²/(4f): a vertex off the surface is a wrong unit or frame.
    worst_z = std::max(worst_z, std::abs(p.z - (kFocal - r * r / (4 * kFocal))));
    // The surface normal (either side): ∇(z + r²/4f) = (x/2f, y/2f, 1).
    // The angle from the cross product: acos near 1 would read a float
    // normal's rounding (|n|² = 1 − 4e-8) as 2e-4 rad.
    const Vec3 exact = normalize(Vec3{p.x / (2 * kFocal), p.y / (2 * kFocal), 1.0});
    const Vec3 n = normalize(sim::to_double(s.normals[i]));
    worst_normal = std::max(worst_normal, std::atan2(length(cross(exact, n)), std::abs(dot(exact, n))));
  }
  EXPECT_LT(worst_z, 1e-7);                 // float rounding of millimetre-scale values
  EXPECT_NEAR(rmin, kHole, 1e-7);
  EXPECT_NEAR(rmax, kAper, 1e-7);
  EXPECT_LT(worst_normal, 1e-5);            // exact, not averaged facets (those are off by ~1°)
}

TEST(CadStep, FacetNormalsStayWithinTheAngularDeflectionAndTriangleCountsFollowIt) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  std::size_t previous = 0;
  for (double deg : {8.0, 4.0, 2.0}) {
    CadTessellation t;
    t.angular_deflection_deg = deg;
    t.chordal_relative = 0.5;  // leave the angle in charge
    Result<CadModel> m = tessellate(parts / "ball_lens.step", t);
    ASSERT_TRUE(m.ok()) << to_string(m.error());
    const CadSurface& s = m->parts[0].surfaces.at(0);
    // δ of a facet: its normal against the sphere's (radial) at its
    // vertices; 99 % of the area within the deflection (slivers along the
    // seam and at the poles tilt more, and catch next to no light).
    std::vector<std::pair<double, double>> deltas;
    double area = 0.0;
    for (std::size_t k = 0; k < s.indices.size(); k += 3) {
      const Vec3 a = sim::to_double(s.positions[s.indices[k]]), b = sim::to_double(s.positions[s.indices[k + 1]]),
                 c = sim::to_double(s.positions[s.indices[k + 2]]);
      const Vec3 n = cross(b - a, c - a);
      if (!(length(n) > 0.0)) continue;
      ASSERT_GT(dot(n, a + b + c), 0.0) << "a facet faces inwards: winding lost";
      double delta = 0.0;
      for (const Vec3& v : {a, b, c}) {
        const Vec3 r = normalize(v), f = normalize(n);
        delta = std::max(delta, std::atan2(length(cross(r, f)), dot(r, f)) * 180.0 / std::numbers::pi);
      }
      deltas.emplace_back(delta, length(n));
      area += length(n);
    }
    std::sort(deltas.begin(), deltas.end());
    double covered = 0.0, quantile = 0.0;
    for (const auto& [delta, a] : deltas) {
      covered += a;
      quantile = delta;
      if (covered >= 0.99 * area) break;
    }
    EXPECT_LT(quantile, deg * 1.02) << "at " << deg << "°";
    EXPECT_GT(quantile, deg / 4) << "at " << deg << "°: far finer than asked (wasted triangles)";
    EXPECT_GT(m->unique_triangle_count(), previous) << "a finer deflection must give more triangles";
    previous = m->unique_triangle_count();
  }
}

TEST(CadStep, BallLensMeshIsAClosedVolumeForTheModelChecks) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path model = with_sidecar(dir, parts / "ball_lens.step", R"(
[materials.glass]
transmittance = 0.92
diffusion = 0
ior = 1.5

[[parts]]
match = "BallLens"
material = "glass"

[[emitters]]
position = [0, 0, 7.5]
flux_lm = 1000
)");
  std::vector<Finding> findings;
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), &findings);
  ASSERT_TRUE(scene.ok()) << to_string(scene.error());
  ASSERT_EQ(scene->meshes.size(), 1u);
  EXPECT_GT(scene->materials[0].dielectric, 0.9);
  // Faces meet on shared edges at the same positions, so the checks weld
  // them into one closed, outward volume: no open-volume error.
  for (const Finding& f : check_model(*scene)) EXPECT_NE(f.severity, Severity::Error) << f.message;
  for (const sim::Vec3f& p : scene->meshes[0].positions) EXPECT_NEAR(length(sim::to_double(p)), kBall, 1e-8);
  // The emitter sits 7.5 mm above the centre, in metres.
  ASSERT_EQ(scene->emitters.size(), 1u);
  EXPECT_NEAR(scene->emitters[0].position.z, 0.0075, 1e-12);
  EXPECT_DOUBLE_EQ(scene->emitters[0].flux_lm, 1000.0);
}

TEST(CadStep, OpenRefractivePartIsRefusedByTheChecksNamingIt) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path model = with_sidecar(dir, parts / "open_lens.step", R"(
[materials.glass]
transmittance = 0.92
diffusion = 0

[[parts]]
match = "OpenLens"
material = "glass"

[[emitters]]
position = [0, 0, -10]
flux_lm = 1
)");
  std::vector<Finding> findings;
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), &findings);
  ASSERT_TRUE(scene.ok()) << to_string(scene.error());
  bool said = false;
  for (const Finding& f : findings) said |= f.code == "cad-open-shell" && f.message.find("OpenLens") != std::string::npos;
  EXPECT_TRUE(said) << "the reader must say which part does not close";
  bool refused = false;
  for (const Finding& f : check_model(*scene))
    refused |= f.severity == Severity::Error && f.code == "open-volume" && f.message.find("OpenLens") != std::string::npos;
  EXPECT_TRUE(refused);
}

TEST(CadStep, OpenCascadeFileInInchesWithColoursLayersAndItsOwnComponentNames) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  Result<CadModel> m = tessellate(parts / "colours_inch.step");
  ASSERT_TRUE(m.ok()) << to_string(m.error());
  EXPECT_EQ(m->file_unit, "INCH");
  const CadPart* block = nullptr;
  for (const CadPart& p : m->parts)
    if (p.name == "Block") block = &p;
  ASSERT_NE(block, nullptr);
  // 1 × 2 × 3 inches written as inches and read back as metres.
  EXPECT_NEAR(block->size_m, 0.0254 * std::sqrt(14.0), 1e-9);
  ASSERT_TRUE(block->colour.has_value());
  EXPECT_NEAR(block->colour->x, 1.0f, 1e-3f);
  EXPECT_NEAR(block->colour->y, 0.0f, 1e-3f);
  EXPECT_EQ(block->layers, std::vector<std::string>{"OPTICS"});
  // The x = 0 face is green: a surface of its own with its colour.
  ASSERT_EQ(block->surfaces.size(), 2u);
  int green = 0;
  for (const CadSurface& s : block->surfaces)
    if (s.colour && s.colour->y > 0.99f) {
      ++green;
      for (const sim::Vec3f& p : s.positions) EXPECT_NEAR(p.x, 0.0f, 1e-9f);
    }
  EXPECT_EQ(green, 1);
  // OpenCASCADE names components "=>[0:1:1:3]"; the product's name is used.
  std::set<std::string> paths;
  for (const CadPlacement& p : m->placements) paths.insert(p.path);
  EXPECT_EQ(paths, (std::set<std::string>{"Block", "ASSEMBLY/SOLID", "ASSEMBLY/SOLID[2]"}));
}

TEST(CadStep, IgesFilesFromFreeCadAndOpenCascadeAreRead) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  for (const char* name : {"pcx_lens.igs", "block.igs"}) {
    Result<CadModel> m = tessellate(parts / name);
    ASSERT_TRUE(m.ok()) << name << ": " << to_string(m.error());
    EXPECT_EQ(m->format, "IGES");
    EXPECT_GT(m->unique_triangle_count(), 0u);
  }
  Result<CadModel> block = tessellate(parts / "block.igs");
  ASSERT_TRUE(block.ok());
  EXPECT_NEAR(block->parts[0].size_m, 0.0254 * std::sqrt(14.0), 1e-9);
}

// Real files carry more than the optics: construction wires beside the
// solids (the Pro/E files of the CAx-IF round robin), and damage in
// entities no shape is made of (CAx-IF's dm1-oc-214.stp: a density
// REPRESENTATION listing itself among its items). Both are read, with a
// warning naming what was left out.
const Finding* finding(const CadModel& m, const std::string& code) {
  for (const Finding& f : m.findings)
    if (f.code == code) return &f;
  return nullptr;
}

TEST(CadStep, ConstructionWiresAreLeftOutWithAWarning) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  Result<CadModel> m = tessellate(parts / "with_wire.step");
  ASSERT_TRUE(m.ok()) << to_string(m.error());
  ASSERT_EQ(m->parts.size(), 1u);
  EXPECT_EQ(m->parts[0].name, "Block");
  ASSERT_EQ(m->placements.size(), 1u);
  const Finding* left = finding(*m, "cad-part-left-out");
  ASSERT_NE(left, nullptr);
  EXPECT_EQ(left->severity, Severity::Warning);
  EXPECT_NE(left->message.find("part 'Guide'"), std::string::npos) << left->message;
  EXPECT_NE(left->message.find("only wires, edges or points"), std::string::npos) << left->message;
}

TEST(CadStep, DamageOutsideTheShapesIsAWarningAndInsideThemAnError) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const std::string lamp = test::read_file(parts / "lamp.step");
  const std::size_t data_end = lamp.rfind("ENDSEC;");
  ASSERT_NE(data_end, std::string::npos);
  std::string damaged = lamp;
  damaged.insert(data_end, "#900001 = REPRESENTATION_CONTEXT('','');\n"
                           "#900002 = REPRESENTATION('density',(#900002),#900001);\n");
  const fs::path file = dir / "damaged_property.step";
  test::write_file(file, damaged);
  Result<CadModel> whole = tessellate(parts / "lamp.step");
  Result<CadModel> m = tessellate(file);
  ASSERT_TRUE(whole.ok());
  ASSERT_TRUE(m.ok()) << to_string(m.error());
  EXPECT_EQ(m->unique_triangle_count(), whole->unique_triangle_count());
  EXPECT_EQ(m->placements.size(), whole->placements.size());
  const Finding* cycle = finding(*m, "step-reference-cycle");
  ASSERT_NE(cycle, nullptr);
  EXPECT_NE(cycle->message.find("#900002"), std::string::npos) << cycle->message;
  const Finding* damage = finding(*m, "step-damaged-entity");
  ASSERT_NE(damage, nullptr);
  EXPECT_NE(damage->message.find("#900002"), std::string::npos) << damage->message;
  // The same damage in an entity shapes are made of is an error.
  std::string in_shape = lamp;
  in_shape.insert(data_end, "#900001 = REPRESENTATION_CONTEXT('','');\n"
                            "#900002 = SHAPE_REPRESENTATION('',(#900001),#900001);\n");
  const fs::path bad = dir / "damaged_shape.step";
  test::write_file(bad, in_shape);
  Result<CadModel> refused = tessellate(bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("damaged"), std::string::npos) << refused.error().message;
}

TEST(CadScene, SidecarRulesGiveMaterialsInstancesAndOneEmitterPerPlacement) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path model = with_sidecar(dir, parts / "lamp.step", kLampSidecar);
  std::vector<Finding> findings;
  CadLoadInfo info;
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), &findings, &info);
  ASSERT_TRUE(scene.ok()) << to_string(scene.error());
  auto material_of = [&](const std::string& name) -> const sim::Material* {
    for (const sim::Mesh& m : scene->meshes)
      if (m.name == name) return &scene->materials[m.material];
    return nullptr;
  };
  ASSERT_NE(material_of("Lamp/Reflector"), nullptr);
  EXPECT_DOUBLE_EQ(material_of("Lamp/Reflector")->mirror, 0.9);
  ASSERT_NE(material_of("Lamp/FrontLens"), nullptr);
  EXPECT_NEAR(material_of("Lamp/FrontLens")->dielectric, 0.92, 1e-12);
  EXPECT_DOUBLE_EQ(material_of("Lamp/Housing")->diffuse_reflect, 0.05);
  // The LED is one instanced mesh placed three times, named by path.
  ASSERT_EQ(scene->instances.size(), 3u);
  std::set<std::string> names;
  for (const sim::Instance& i : scene->instances) {
    names.insert(i.name);
    EXPECT_EQ(scene->meshes[i.mesh].name, "LED");
    EXPECT_TRUE(scene->meshes[i.mesh].instanced);
  }
  EXPECT_EQ(names, (std::set<std::string>{"Lamp/LED1", "Lamp/LED2", "Lamp/LED3"}));
  // One emitter per LED placement, 1 mm above each LED's origin (0.5 mm up).
  ASSERT_EQ(scene->emitters.size(), 3u);
  for (const sim::Emitter& e : scene->emitters) {
    EXPECT_NEAR(e.position.z, 0.0015, 1e-12);
    EXPECT_DOUBLE_EQ(e.flux_lm, 100.0);
  }
  // The default frame is CAD's Z-up: nadir −Z, C0 +X, C90 +Y.
  EXPECT_NEAR(scene->frame.up.z, 1.0, 1e-12);
  EXPECT_NEAR(scene->frame.c90.y, 1.0, 1e-12);
  EXPECT_EQ(info.placements, 6u);
  EXPECT_EQ(info.parts, 4u);
  EXPECT_EQ(info.placed_triangles, scene->placed_triangle_count());
}

TEST(CadScene, NoInstancingGivesTheSameGeometryFlat) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path model = with_sidecar(dir, parts / "lamp.step", kLampSidecar);
  CadLoadOptions flat = cached();
  flat.instancing = false;
  Result<sim::SceneDesc> a = load_cad(model.string(), cached(), nullptr);
  Result<sim::SceneDesc> b = load_cad(model.string(), flat, nullptr);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_TRUE(b->instances.empty());
  EXPECT_EQ(a->placed_triangle_count(), b->placed_triangle_count());
  EXPECT_LT(a->unique_triangle_count(), b->unique_triangle_count());
}

TEST(CadScene, PartsNoRuleCoversAreListedAllInOneError) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path model = with_sidecar(dir, parts / "lamp.step", R"(
[materials.mirror]
reflectance = 0.9

[[parts]]
match = "Reflector"
material = "mirror"

[[emitters]]
at = "LED1"
flux_lm = 1
)");
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), nullptr);
  ASSERT_FALSE(scene.ok());
  const std::string& m = scene.error().message;
  for (const char* part : {"Lamp/Housing", "Lamp/LED1", "Lamp/LED2", "Lamp/LED3", "Lamp/FrontLens"})
    EXPECT_NE(m.find(part), std::string::npos) << part << " missing from: " << m;
  EXPECT_EQ(m.find("Lamp/Reflector"), std::string::npos) << m;
  EXPECT_NE(m.find("5 part placement(s)"), std::string::npos) << m;
  EXPECT_EQ(scene.error().where.file, model.string());
}

TEST(CadScene, WithoutASidecarTheErrorNamesTheFileItLookedFor) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path copy = dir / "reflector.step";
  fs::copy_file(parts / "reflector.step", copy);
  Result<sim::SceneDesc> scene = load_cad(copy.string(), cached(), nullptr);
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().message.find("reflector.gonio.toml"), std::string::npos) << scene.error().message;
}

TEST(CadScene, RulesByColourAndLayer) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path model = with_sidecar(dir, parts / "colours_inch.step", R"(
length_unit = "mm"

[materials.green]
kd = 0.3
[materials.red]
kd = 0.6
[materials.chip]
kd = 0.1

[[parts]]
colour = "#00ff00"
material = "green"

[[parts]]
layer = "OPT*"
material = "red"

[[parts]]
match = "SOLID"
material = "chip"

[[emitters]]
position = [0, 0, 100]
flux_lm = 10
)");
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), nullptr);
  ASSERT_TRUE(scene.ok()) << to_string(scene.error());
  int green = 0, red = 0;
  for (const sim::Mesh& m : scene->meshes) {
    const double kd = scene->materials[m.material].diffuse_reflect;
    if (m.name.rfind("Block", 0) != 0) continue;
    green += kd == 0.3;
    red += kd == 0.6;
  }
  EXPECT_EQ(green, 1);  // the green face, before the layer rule
  EXPECT_EQ(red, 1);    // the rest of the block, by its layer
  // length_unit = "mm" overrides the file's inches for sidecar coordinates.
  EXPECT_NEAR(scene->emitters.at(0).position.z, 0.1, 1e-12);
}

TEST(CadScene, SidecarMaterialIsTheOneGltfExtrasGive) {
  // The same extras.gonio through the one reader and mapping: a sidecar
  // material that differed would mean two vocabularies.
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path model = with_sidecar(dir, parts / "ball_lens.step", R"(
[materials.opal]
transmittance = 0.6
diffusion = 0.7
reflectance = 0.3
ior = 1.49
spectral_transmittance = { wavelengths_nm = [400, 700], values = [0.5, 0.7] }

[[parts]]
match = "*"
material = "opal"

[[emitters]]
position = [0, 0, 20]
flux_lm = 5
spectrum = { blackbody_k = 3000 }
)");
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), nullptr);
  ASSERT_TRUE(scene.ok()) << to_string(scene.error());
  const sim::Material& m = scene->materials.at(0);
  EXPECT_DOUBLE_EQ(m.diffuse_transmit, 0.6 * 0.7);
  EXPECT_DOUBLE_EQ(m.dielectric, 0.6 * 0.3);
  EXPECT_DOUBLE_EQ(m.diffuse_reflect, 0.3);
  EXPECT_DOUBLE_EQ(m.ior, 1.49);
  EXPECT_EQ(m.spectral_transmittance.values, (std::vector<double>{0.5, 0.7}));
  EXPECT_FALSE(scene->emitters.at(0).spectrum.empty());
  EXPECT_TRUE(scene->spectral());
}

TEST(CadScene, SidecarTakesTheMeasuredMaterialsVocabularyAndNamesItsLine) {
  // Issue 31 asks for glTF's vocabulary in the sidecar, issue 32 widened it:
  // a preset, ABg, a measured BSDF file beside the sidecar. A reader that
  // knew only the older keys would call these materials empty ("says
  // neither how it scatters ...") or drop the table; a bad table must be an
  // error naming the sidecar's material and the CSV's line.
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  std::string csv = "theta_in,theta_out,phi_out,bsdf\n";
  for (double ti : {0.0, 60.0})
    for (double to = 0.0; to < 90.0; to += 15.0)
      for (double p : {0.0, 90.0, 180.0})
        csv += std::to_string(ti) + "," + std::to_string(to) + "," + std::to_string(p) + "," +
               std::to_string(0.4 / std::numbers::pi) + "\n";
  test::write_file(dir / "sheet.csv", csv);
  test::write_file(dir / "broken.csv", "theta_in,theta_out,phi_out,bsdf\n0,10,0,-1\n");
  const std::string rules = R"(
[materials.opal]
preset = "opal PC 3 mm"
[materials.blasted]
mirror = 0.4
abg = { A = 0.02, B = 0.01, g = 2.0 }
[materials.measured]
bsdf_file = "sheet.csv"
tabulated = 0.9

[[parts]]
match = "*"
material = "opal"

[[emitters]]
position = [0, 0, 20]
flux_lm = 5
)";
  const fs::path model = with_sidecar(dir, parts / "ball_lens.step", rules);
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), nullptr);
  ASSERT_TRUE(scene.ok()) << to_string(scene.error());
  const auto named = [&](const std::string& name) -> const sim::Material& {
    for (const sim::Material& m : scene->materials)
      if (m.name == name) return m;
    ADD_FAILURE() << "no material " << name;
    return scene->materials.at(0);
  };
  EXPECT_EQ(named("opal").scattering_per_m, sim::find_preset("opal PC 3 mm")->material.scattering_per_m);
  EXPECT_NEAR(named("blasted").abg_reflect.tis, 0.02 * std::numbers::pi * std::log(101.0), 1e-6);
  EXPECT_EQ(named("blasted").mirror, 0.4);
  ASSERT_TRUE(named("measured").table);
  EXPECT_EQ(named("measured").tabulated, 0.9);
  EXPECT_NEAR(named("measured").table->albedo(true, Vec3{0.0, 0.0, 1.0}), 0.4, 1e-6);

  std::string broken = rules;
  broken.replace(broken.find("sheet.csv"), 9, "broken.csv");
  TempDir dir2;
  fs::copy_file(dir / "broken.csv", dir2 / "broken.csv");
  const fs::path bad = with_sidecar(dir2, parts / "ball_lens.step", broken);
  Result<sim::SceneDesc> refused = load_cad(bad.string(), cached(), nullptr);
  ASSERT_FALSE(refused.ok());
  const std::string message = to_string(refused.error());
  EXPECT_NE(message.find("material 'measured'"), std::string::npos) << message;
  EXPECT_NE(message.find("broken.csv:2"), std::string::npos) << message;
}

TEST(CadScene, PointEmitterWithAProfileFollowsThePartAxes) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  fs::copy_file(test::source_dir() / "samples" / "curves" / "downlight.ies", dir / "led.ies");
  const fs::path model = with_sidecar(dir, parts / "lamp.step", std::string(R"(
default_material = "black"
[materials.black]
kd = 0.05

[[emitters]]
name = "LED"
at = "LED3"
profile = "led.ies"
nadir = [1, 0, 0]
c0 = [0, 0, 1]
)"));
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), nullptr);
  ASSERT_TRUE(scene.ok()) << to_string(scene.error());
  ASSERT_EQ(scene->emitters.size(), 1u);
  const sim::Emitter& e = scene->emitters[0];
  ASSERT_NE(e.profile, nullptr);
  // LED3 is turned 180° about Z: its +X is the world's −X.
  EXPECT_NEAR(e.frame.up.x, 1.0, 1e-12);
  EXPECT_NEAR(e.frame.c0.z, 1.0, 1e-12);
  EXPECT_GT(e.flux_lm, 0.0);
}

TEST(CadScene, SidecarProfileOutsideTheFolderIsRefused) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path model = with_sidecar(dir, parts / "ball_lens.step", R"(
default_material = "m"
[materials.m]
kd = 0.5
[[emitters]]
position = [0, 0, 20]
profile = "../../etc/passwd"
)");
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), nullptr);
  ASSERT_FALSE(scene.ok());
  EXPECT_NE(scene.error().message.find("outside"), std::string::npos) << scene.error().message;
}

// ---------------------------------------------------------------------------
// The mistakes a CAD user would see (issue 45): each test names the
// plausible mistake in the reader or the sidecar that makes it fail.

// FreeCAD's Placement(t, Rotation(axis, deg)): p ↦ R·p + t, right-handed,
// in millimetres; here in metres.
sim::Affine freecad_placement(const Vec3& t_mm, const Vec3& axis, double deg) {
  return sim::translation(t_mm * 1e-3) * sim::rotation(axis, deg * std::numbers::pi / 180.0);
}

const CadPlacement* placement_at(const CadModel& m, const std::string& path) {
  for (const CadPlacement& p : m.placements)
    if (p.path == path) return &p;
  return nullptr;
}

// Every vertex of a placement of make_parts.py's bar (10 × 2 × 1 mm from the
// origin) against where `expected` puts the bar: mapped back by its inverse
// (a rotation's is its transpose) each must lie in the bar, and each of the
// bar's eight corners must be a vertex. The placement's own split between
// the part's mesh and its location does not matter; only where the bar ends
// up in the world does.
void expect_bar_where(const CadModel& m, const std::string& path, const sim::Affine& expected) {
  SCOPED_TRACE(path);
  const CadPlacement* p = placement_at(m, path);
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(m.parts[p->part].name, "Bar");
  const Vec3 size{0.010, 0.002, 0.001};
  std::vector<Vec3> world;
  for (const CadSurface& s : m.parts[p->part].surfaces)
    for (const sim::Vec3f& v : s.positions) world.push_back(p->to_world.point(sim::to_double(v)));
  ASSERT_FALSE(world.empty());
  double outside = 0.0;
  for (const Vec3& w : world) {
    const Vec3 d = w - expected.offset;
    // Rᵀ·d: the columns of R dotted with d.
    const Vec3 local{expected.m[0][0] * d.x + expected.m[1][0] * d.y + expected.m[2][0] * d.z,
                     expected.m[0][1] * d.x + expected.m[1][1] * d.y + expected.m[2][1] * d.z,
                     expected.m[0][2] * d.x + expected.m[1][2] * d.y + expected.m[2][2] * d.z};
    outside = std::max({outside, -local.x, -local.y, -local.z, local.x - size.x, local.y - size.y, local.z - size.z});
  }
  EXPECT_LT(outside, 1e-8) << "a vertex lies outside where the bar should be [m]";
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 c = expected.point({corner & 1 ? size.x : 0.0, corner & 2 ? size.y : 0.0, corner & 4 ? size.z : 0.0});
    double nearest = 1.0;
    for (const Vec3& w : world) nearest = std::min(nearest, length(w - c));
    EXPECT_LT(nearest, 1e-8) << "no vertex at corner " << corner << " (" << c.x << ", " << c.y << ", " << c.z << ")";
  }
}

// The nearest world vertex of a placement to `point` [m].
double nearest_vertex(const CadModel& m, const CadPlacement& p, const Vec3& point) {
  double nearest = 1.0;
  for (const CadSurface& s : m.parts[p.part].surfaces)
    for (const sim::Vec3f& v : s.positions) nearest = std::min(nearest, length(p.to_world.point(sim::to_double(v)) - point));
  return nearest;
}

// Mistake: the placement's rotation read transposed (turned the other way).
// The lamp's LEDs are translated or turned by 180°, where a rotation is its
// own transpose; here the turns are 90° about X and Z and 30° about Y, none
// about a symmetry axis of the bar (it has none).
TEST(CadStep, TurnedPlacementsPutTheVerticesWhereTheRotationSays) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  Result<CadModel> m = tessellate(parts / "turned.step");
  ASSERT_TRUE(m.ok()) << to_string(m.error());
  ASSERT_EQ(m->parts.size(), 1u);  // one bar, placed four times
  ASSERT_EQ(m->placements.size(), 4u);
  expect_bar_where(*m, "Turned/BarX90", freecad_placement({20, 0, 0}, {1, 0, 0}, 90));
  expect_bar_where(*m, "Turned/BarY30", freecad_placement({0, 20, 0}, {0, 1, 0}, 30));
  expect_bar_where(*m, "Turned/BarZ90", freecad_placement({0, 0, 20}, {0, 0, 1}, 90));
  // The far corner (10, 2, 1) mm by hand: about X by 90°, (x, y, z) ↦
  // (x, −z, y); about Y by 30°, (x cos 30° + z sin 30°, y, −x sin 30° + z cos 30°);
  // about Z by 90°, (−y, x, z). Transposed, each would land elsewhere.
  const double c30 = std::cos(std::numbers::pi / 6), s30 = 0.5;
  const std::pair<const char*, Vec3> corners[] = {
      {"Turned/BarX90", Vec3{30, -1, 2}},
      {"Turned/BarY30", Vec3{10 * c30 + s30, 22, -10 * s30 + c30}},
      {"Turned/BarZ90", Vec3{-2, 10, 21}},
  };
  for (const auto& [path, corner_mm] : corners) {
    const CadPlacement* p = placement_at(*m, path);
    ASSERT_NE(p, nullptr) << path;
    EXPECT_LT(nearest_vertex(*m, *p, corner_mm * 1e-3), 1e-8) << path;
  }
}

// Mistake: a component's placement applied before its parent's instead of
// after (world = child · parent). Turned/Arm is turned 90° about Z and moved
// 40 mm along X; its component Tip is turned 90° about X and moved 10 mm
// along Y inside it.
TEST(CadStep, NestedAssemblyAppliesTheChildsPlacementInsideTheParents) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  Result<CadModel> m = tessellate(parts / "turned.step");
  ASSERT_TRUE(m.ok()) << to_string(m.error());
  const sim::Affine arm = freecad_placement({40, 0, 0}, {0, 0, 1}, 90);
  const sim::Affine tip = freecad_placement({0, 10, 0}, {1, 0, 0}, 90);
  expect_bar_where(*m, "Turned/Arm/Tip", arm * tip);
  // By hand: (10, 2, 1) → Tip's (10, −1, 2) + (0, 10, 0) = (10, 9, 2) →
  // Arm's (−9, 10, 2) + (40, 0, 0) = (31, 10, 2) mm. The other order would
  // put it at (38, 9, 10) mm.
  const CadPlacement* p = placement_at(*m, "Turned/Arm/Tip");
  ASSERT_NE(p, nullptr);
  EXPECT_LT(nearest_vertex(*m, *p, Vec3{31, 10, 2} * 1e-3), 1e-8);
  EXPECT_GT(nearest_vertex(*m, *p, Vec3{38, 9, 10} * 1e-3), 1e-3);
}

// Mistake: an emitter placed `at` a part moved with the part's origin but
// not turned with its axes (origin + position instead of the placement of
// position). BarZ90 is turned 90° about Z: its local X is the world's +Y.
// Tip (two levels down) is turned about X, then about Z: its local X is
// the world's +Y, its −Z the world's −X.
TEST(CadScene, EmitterAtATurnedPartTurnsWithThePartsAxes) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path model = with_sidecar(dir, parts / "turned.step", R"(
default_material = "black"
[materials.black]
kd = 0.05

[[emitters]]
name = "side"
at = "BarZ90"
position = [5, 0, 0]
flux_lm = 10

[[emitters]]
name = "tip"
at = "Tip"
position = [5, 0, 0.5]
flux_lm = 10
)");
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), nullptr);
  ASSERT_TRUE(scene.ok()) << to_string(scene.error());
  ASSERT_EQ(scene->emitters.size(), 2u);
  const sim::Emitter& side = scene->emitters[0];
  const sim::Emitter& tip = scene->emitters[1];
  ASSERT_EQ(side.name, "side");
  // (5, 0, 0) turned to (0, 5, 0), plus the part's origin (0, 0, 20) mm;
  // moved without turning it would be at (5, 0, 20) mm.
  EXPECT_NEAR(side.position.x, 0.0, 1e-12);
  EXPECT_NEAR(side.position.y, 0.005, 1e-12);
  EXPECT_NEAR(side.position.z, 0.020, 1e-12);
  // The default nadir (the part's −Z) and C0 (its +X) turn too.
  EXPECT_NEAR(side.frame.up.z, 1.0, 1e-12);
  EXPECT_NEAR(side.frame.c0.y, 1.0, 1e-12);
  // Tip: (5, 0, 0.5) → about X (5, −0.5, 0) + (0, 10, 0) → about Z
  // (−9.5, 5, 0) + (40, 0, 0) = (30.5, 5, 0) mm.
  ASSERT_EQ(tip.name, "tip");
  EXPECT_NEAR(tip.position.x, 0.0305, 1e-12);
  EXPECT_NEAR(tip.position.y, 0.005, 1e-12);
  EXPECT_NEAR(tip.position.z, 0.0, 1e-12);
  EXPECT_NEAR(tip.frame.up.x, 1.0, 1e-12);  // the zenith is −nadir: the part's +Z, the world's +X
  EXPECT_NEAR(tip.frame.c0.y, 1.0, 1e-12);
}

// Mistake: an emissive part's flux taken as L·A instead of π·L·A (a
// Lambertian surface of luminance L emits π·L per unit area). make_parts.py's
// panel is 10 × 10 mm, placed once (world geometry); the lamp's LED, a
// 2 × 2 × 1 mm box (16 mm²), is placed three times (an instanced mesh):
// the two ways the scene builder takes an emissive surface. (The area is
// the mesh's, of float vertices: to 1e-6.)
TEST(CadScene, EmissivePartsEmitPiTimesLuminanceTimesArea) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  constexpr double kL = 1.0e4;  // [cd/m²]
  TempDir dir;
  const fs::path panel = with_sidecar(dir, parts / "panel.step", R"(
[materials.panel]
luminance_cd_m2 = 1.0e4

[[parts]]
match = "Panel"
material = "panel"
)");
  Result<sim::SceneDesc> scene = load_cad(panel.string(), cached(), nullptr);
  ASSERT_TRUE(scene.ok()) << to_string(scene.error());
  ASSERT_EQ(scene->emitters.size(), 1u);
  EXPECT_EQ(scene->emitters[0].kind, sim::Emitter::Kind::Area);
  EXPECT_NEAR(scene->emitters[0].flux_lm, std::numbers::pi * kL * 1e-4, 1e-6 * std::numbers::pi * kL * 1e-4);

  const fs::path lamp = with_sidecar(dir, parts / "lamp.step", R"(
default_material = "black"
[materials.black]
kd = 0.05
[materials.led]
luminance_cd_m2 = 1.0e4

[[parts]]
match = "LED*"
material = "led"
)");
  Result<sim::SceneDesc> leds = load_cad(lamp.string(), cached(), nullptr);
  ASSERT_TRUE(leds.ok()) << to_string(leds.error());
  ASSERT_EQ(leds->emitters.size(), 3u);
  for (const sim::Emitter& e : leds->emitters) {
    EXPECT_EQ(e.kind, sim::Emitter::Kind::Area);
    EXPECT_NE(e.instance, sim::kNoInstance) << e.name << ": the LED is instanced";
    EXPECT_NEAR(e.flux_lm, std::numbers::pi * kL * 16e-6, 1e-6 * std::numbers::pi * kL * 16e-6) << e.name;
  }
}

// Mistake: the sidecar's coordinates read as millimetres whatever the
// model's unit. Without length_unit they are in the file's unit: the DRAW
// block is written in inches, so 4 is 4 in above the origin and 1 along
// the block's X is 1 in.
TEST(CadScene, SidecarCoordinatesAreInTheModelFilesUnitWithoutLengthUnit) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path model = with_sidecar(dir, parts / "colours_inch.step", R"(
default_material = "grey"
[materials.grey]
kd = 0.5

[[emitters]]
name = "above"
position = [0, 0, 4]
flux_lm = 1

[[emitters]]
name = "on the block"
at = "Block"
position = [1, 0, 0]
flux_lm = 1
)");
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), nullptr);
  ASSERT_TRUE(scene.ok()) << to_string(scene.error());
  ASSERT_EQ(scene->emitters.size(), 2u);
  EXPECT_NEAR(scene->emitters[0].position.z, 4 * 0.0254, 1e-12);
  EXPECT_NEAR(scene->emitters[1].position.x, 0.0254, 1e-12);
  EXPECT_NEAR(scene->emitters[1].position.z, 0.0, 1e-12);
}

// Mistake: a face OpenCASCADE reads REVERSED (STEP's ADVANCED_FACE with
// same_sense .F.) keeps the surface's own normal, which then points against
// its facets (whose winding is swapped), and the reader falls back to the
// facets' normals averaged at each vertex (measured: up to 1.7° off at the
// default δ = 2°). The reversed reflector's every vertex normal must be the
// paraboloid's to 1e-5 rad, on the facets' side, and opposite to the
// forward file's.
TEST(CadStep, ReversedFaceGetsTheSurfacesNormalsFlipped) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  for (const char* name : {"reflector.step", "reflector_reversed.step"}) {
    SCOPED_TRACE(name);
    const bool reversed = std::string(name) == "reflector_reversed.step";
    Result<CadModel> m = tessellate(parts / name);
    ASSERT_TRUE(m.ok()) << to_string(m.error());
    ASSERT_EQ(m->parts.size(), 1u);
    const CadSurface& s = m->parts[0].surfaces.at(0);
    ASSERT_EQ(s.normals.size(), s.positions.size());
    // Facet normals summed per vertex: the side the winding says.
    std::vector<Vec3> facets(s.positions.size());
    for (std::size_t k = 0; k + 2 < s.indices.size(); k += 3) {
      const Vec3 a = sim::to_double(s.positions[s.indices[k]]), b = sim::to_double(s.positions[s.indices[k + 1]]),
                 c = sim::to_double(s.positions[s.indices[k + 2]]);
      for (std::size_t j = 0; j < 3; ++j) facets[s.indices[k + j]] += cross(b - a, c - a);
    }
    double worst = 0.0;
    int against_facets = 0, towards_focus = 0;
    for (std::size_t i = 0; i < s.positions.size(); ++i) {
      const Vec3 p = sim::to_double(s.positions[i]);
      // ∇(z + r²/4f) = (x/2f, y/2f, 1): away from the focus's side of the
      // mirror, which the forward face's normal points to.
      const Vec3 away = normalize(Vec3{p.x / (2 * kFocal), p.y / (2 * kFocal), 1.0});
      const Vec3 exact = reversed ? away : away * -1.0;
      const Vec3 n = normalize(sim::to_double(s.normals[i]));
      worst = std::max(worst, std::atan2(length(cross(exact, n)), dot(exact, n)));
      against_facets += dot(n, facets[i]) < 0.0;
      towards_focus += dot(n, away) < 0.0;
    }
    EXPECT_LT(worst, 1e-5) << "[rad]: the surface's normal, on the facets' side";
    EXPECT_EQ(against_facets, 0);
    EXPECT_EQ(towards_focus, reversed ? 0 : static_cast<int>(s.positions.size()));
  }
}

// Glob case: sidecar patterns match names whatever their case (docs/cad.md,
// "The sidecar"): exporters change the case of names (Creo and IGES write
// them in capitals) and Windows CAD treats them case-blind. Mistake: a
// case-sensitive match, under which `led*` covers no part named LED and the
// emitter `at` it names nothing.
TEST(CadScene, PartPatternsMatchNamesWhateverTheirCase) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const fs::path model = with_sidecar(dir, parts / "lamp.step", R"(
default_material = "black"
[materials.black]
kd = 0.05
[materials.mirror]
reflectance = 0.9
diffuse_reflectance = 0

[[parts]]
match = "reflector"
material = "mirror"

[[parts]]
match = "lamp/front*"
material = "mirror"

[[emitters]]
name = "LED"
at = "LED1"
flux_lm = 1
)");
  // The rules: a case-sensitive match would leave the reflector and the
  // lens black, with only a warning (cad-rule-unused) to say so.
  std::vector<Finding> findings;
  Result<sim::SceneDesc> scene = load_cad(model.string(), cached(), &findings);
  ASSERT_TRUE(scene.ok()) << to_string(scene.error());
  for (const sim::Mesh& m : scene->meshes) {
    if (m.name == "Lamp/Reflector" || m.name == "Lamp/FrontLens") {
      EXPECT_DOUBLE_EQ(scene->materials[m.material].mirror, 0.9) << m.name;
    }
  }
  for (const Finding& f : findings) EXPECT_NE(f.code, "cad-rule-unused") << f.message;
  // An emitter `at` every LED: case-sensitive, an error ("names no part").
  const fs::path leds = with_sidecar(dir, parts / "lamp.step", R"(
default_material = "black"
[materials.black]
kd = 0.05

[[emitters]]
name = "LED"
at = "led*"
flux_lm = 1
)");
  Result<sim::SceneDesc> at_leds = load_cad(leds.string(), cached(), nullptr);
  if (at_leds.ok()) {
    EXPECT_EQ(at_leds->emitters.size(), 3u);  // LED1, LED2, LED3
  } else {
    ADD_FAILURE() << to_string(at_leds.error());
  }
  // Layers too: the DRAW block's layer is OPTICS.
  const fs::path block = with_sidecar(dir, parts / "colours_inch.step", R"(
default_material = "black"
[materials.black]
kd = 0.05
[materials.red]
kd = 0.6

[[parts]]
layer = "optics"
match = "block"
material = "red"

[[emitters]]
position = [0, 0, 10]
flux_lm = 1
)");
  Result<sim::SceneDesc> blocks = load_cad(block.string(), cached(), nullptr);
  ASSERT_TRUE(blocks.ok()) << to_string(blocks.error());
  int red = 0;
  for (const sim::Mesh& m : blocks->meshes) red += blocks->materials[m.material].diffuse_reflect == 0.6;
  EXPECT_GE(red, 1);
}

// ---------------------------------------------------------------------------
// Hostile and broken files: an error naming the file (and entity), never a
// crash of gonio.

std::string first_part_of(const fs::path& file, std::size_t bytes) {
  std::string text = test::read_file(file);
  return text.substr(0, std::min(bytes, text.size()));
}

TEST(CadHostile, BrokenFilesAreErrorsNamingFileAndEntity) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir dir;
  const std::string box = test::read_file(parts / "lamp.step");
  struct Case {
    const char* name;
    std::string bytes;
    const char* says;
  };
  std::string missing = box;
  // Point the first CLOSED_SHELL reference of the first solid at an entity
  // the file does not hold.
  const std::size_t brep = missing.find("MANIFOLD_SOLID_BREP('',#");
  ASSERT_NE(brep, std::string::npos);
  const std::size_t ref = brep + std::string("MANIFOLD_SOLID_BREP('',").size();
  const std::size_t end = missing.find(')', ref);
  const std::string target = missing.substr(ref, end - ref);
  missing.replace(ref, end - ref, "#999999");
  // The fuzzer's finding: a SEAM_CURVE (here a SURFACE_CURVE) whose basis
  // curve is itself made OpenCASCADE recurse until the stack ran out.
  std::string cycle = box;
  const std::size_t curve = cycle.find("= SURFACE_CURVE('',#");
  ASSERT_NE(curve, std::string::npos);
  const std::size_t hash = cycle.rfind('#', curve);
  const std::string self = cycle.substr(hash, cycle.find(' ', hash) - hash);
  const std::size_t basis = curve + std::string("= SURFACE_CURVE('',").size();
  cycle.replace(basis, cycle.find(',', basis) - basis, self);
  const std::string refers_to_itself = "entity " + self + " (line ";
  const Case cases[] = {
      {"empty.step", "", "empty file"},
      {"cycle.step", cycle, refers_to_itself.c_str()},
      {"truncated.step", first_part_of(parts / "lamp.step", 4000), "unexpected end of file"},
      {"missing.step", missing, "#999999"},
      {"garbage.step", "ISO-10303-21;\nthis is not STEP at all (((\n", "not a readable STEP file"},
      {"nodata.step", "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\nENDSEC;\nEND-ISO-10303-21;\n", "no"},
      {"binary.step", std::string("\0\x01\x02\xff\xfe", 5), "not a"},
      {"noiges.igs", "this is not IGES\n", "IGES"},
  };
  for (const Case& c : cases) {
    test::offer_fuzz_seed("step", c.bytes);
    const fs::path file = dir / c.name;
    test::write_file(file, c.bytes);
    Result<CadModel> m = tessellate(file);
    ASSERT_FALSE(m.ok()) << c.name;
    EXPECT_EQ(m.error().where.file, file.string()) << c.name;
    EXPECT_NE(m.error().message.find(c.says), std::string::npos) << c.name << ": " << m.error().message;
  }
  (void)target;
}

TEST(CadHostile, ACrashingOrHangingReaderIsAnErrorNotGoniosEnd) {
  TempDir dir;
  const fs::path crash = dir / "crash.sh", hang = dir / "hang.sh", model = dir / "m.step";
  test::write_file(crash, "#!/bin/sh\nkill -SEGV $$\n");
  test::write_file(hang, "#!/bin/sh\nexec sleep 60\n");
  test::write_file(model, "ISO-10303-21;\n");
  fs::permissions(crash, fs::perms::owner_all);
  fs::permissions(hang, fs::perms::owner_all);
  CadLoadOptions o;
  o.helper = crash.string();
  Result<CadModel> m = tessellate_cad(model.string(), o);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().message.find("crashed"), std::string::npos) << m.error().message;
  EXPECT_NE(m.error().message.find("SIGSEGV"), std::string::npos) << m.error().message;
  o.helper = hang.string();
  o.time_limit = std::chrono::seconds(1);
  m = tessellate_cad(model.string(), o);
  ASSERT_FALSE(m.ok());
  EXPECT_NE(m.error().message.find("within 1 s"), std::string::npos) << m.error().message;
}

TEST(CadCache, SecondReadComesFromTheCacheAndADamagedEntryIsReplaced) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  TempDir cache;
  CadLoadOptions o;
  o.cache_dir = cache.path().string();
  CadLoadInfo first, second, third;
  Result<CadModel> a = tessellate_cad((parts / "reflector.step").string(), o, &first);
  Result<CadModel> b = tessellate_cad((parts / "reflector.step").string(), o, &second);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_FALSE(first.from_cache);
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(serialize_cad_model(*a), serialize_cad_model(*b));
  // Damage the entry: it is read again from the file and rewritten.
  std::vector<fs::path> entries;
  for (const auto& e : fs::directory_iterator(cache.path())) entries.push_back(e.path());
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].filename().string().rfind("cad-", 0), 0u);
  test::write_file(entries[0], "GONIOCAD damaged");
  Result<CadModel> c = tessellate_cad((parts / "reflector.step").string(), o, &third);
  ASSERT_TRUE(c.ok());
  EXPECT_FALSE(third.from_cache);
  EXPECT_EQ(serialize_cad_model(*c), serialize_cad_model(*a));
  // Other settings, another entry.
  o.tessellation.angular_deflection_deg = 5.0;
  CadLoadInfo fourth;
  ASSERT_TRUE(tessellate_cad((parts / "reflector.step").string(), o, &fourth).ok());
  EXPECT_FALSE(fourth.from_cache);
  EXPECT_LT(fourth.unique_triangles, first.unique_triangles);
}

}  // namespace
}  // namespace gonio::io
