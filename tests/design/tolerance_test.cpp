// Tolerance files and the tolerance analysis' parts (design/tolerance_spec.h,
// design/tolerance.h): parsing with lines in the errors, what a model must
// have, perturbations against closed forms, the Latin hypercube's strata,
// the truncated normal's quantiles, --spec limits, the noise floor.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "design/tolerance.h"
#include "design/tolerance_spec.h"
#include "sim/scene.h"

namespace gonio::design {
namespace {

sim::SceneDesc small_scene() {
  sim::SceneDesc s;
  sim::Emitter led;
  led.name = "LED";
  led.flux_lm = 100.0;
  led.position = {0.0, 0.01, 0.0};
  s.emitters.push_back(led);
  sim::Emitter panel;
  panel.name = "panel";
  panel.kind = sim::Emitter::Kind::Area;
  panel.flux_lm = 50.0;
  s.emitters.push_back(panel);
  sim::Material alu;
  alu.name = "alu";
  alu.glossy = 0.9;
  alu.glossy_mx = alu.glossy_my = 0.09;
  s.materials.push_back(alu);
  sim::Material opal;
  opal.name = "opal";
  opal.diffuse_transmit = 0.6;
  opal.diffuse_reflect = 0.3;
  s.materials.push_back(opal);
  return s;
}

ToleranceSpec parse_ok(const std::string& text) {
  Result<ToleranceSpec> s = parse_tolerances(text, "t.toml");
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : to_string(s.error()));
  return s.ok() ? s.value() : ToleranceSpec{};
}

std::string error_of(const std::string& text) {
  Result<ToleranceSpec> s = parse_tolerances(text, "t.toml");
  return s.ok() ? std::string("(parsed)") : to_string(s.error());
}

TEST(ToleranceSpec, ParsesEveryLawWithItsLine) {
  const ToleranceSpec s = parse_ok(
      "[emitter.LED]\n"
      "x = { normal = 0.05, truncate = 2 }\n"
      "tilt_y = { uniform = 1.0 }\n"
      "flux = { values = [-5, 0, 7.5] }\n"
      "[material.alu]\n"
      "roughness = { uniform = 20 }\n");
  ASSERT_EQ(s.tolerances.size(), 4u);
  // toml++ keeps keys sorted: flux, tilt_y, x; then the material.
  EXPECT_EQ(s.tolerances[0].label(), "LED.flux");
  EXPECT_EQ(s.tolerances[0].line, 4);
  EXPECT_EQ(s.tolerances[0].law.low(), -5.0);
  EXPECT_EQ(s.tolerances[0].law.high(), 7.5);
  EXPECT_EQ(s.tolerances[2].label(), "LED.x");
  EXPECT_EQ(s.tolerances[2].line, 2);
  EXPECT_DOUBLE_EQ(s.tolerances[2].law.high(), 0.1);  // ±2σ
  EXPECT_STREQ(s.tolerances[2].unit(), "mm");
  EXPECT_STREQ(s.tolerances[1].unit(), "deg");
  EXPECT_EQ(s.tolerances[3].label(), "alu.roughness");
  EXPECT_EQ(s.tolerances[3].line, 6);
}

TEST(ToleranceSpec, MistakesNameTheLine) {
  for (const auto& [text, says] : std::vector<std::pair<std::string, std::string>>{
           {"[emitter.LED]\nx = 0.1\n", "t.toml:2: emitter.LED.x: write a law as a table"},
           {"[emitter.LED]\n\nwobble = { uniform = 1 }\n", "t.toml:3: unknown emitter value 'wobble'"},
           {"[material.alu]\nx = { uniform = 1 }\n", "t.toml:2: unknown material value 'x'"},
           {"[lamp.LED]\nx = { uniform = 1 }\n", "t.toml:1: unknown section 'lamp'"},
           {"[emitter.LED]\nx = { uniform = 1, normal = 2 }\n", "t.toml:2: emitter.LED.x: give exactly one of"},
           {"[emitter.LED]\nx = { }\n", "t.toml:2: emitter.LED.x: give exactly one of"},
           {"[emitter.LED]\nx = { normal = -1 }\n", "t.toml:2: emitter.LED.x.normal: σ must be ≥ 0"},
           {"[emitter.LED]\nx = { uniform = 1, truncate = 2 }\n", "t.toml:2: emitter.LED.x: truncate goes with normal"},
           {"[emitter.LED]\nx = { normal = 1, truncate = 0 }\n", "t.toml:2: emitter.LED.x.truncate must lie in"},
           {"[emitter.LED]\nx = { values = [] }\n", "t.toml:2: emitter.LED.x.values must be a non-empty array"},
           {"[emitter.LED]\nx = { values = [1, \"a\"] }\n", "t.toml:2: emitter.LED.x.values must be a finite"},
           {"[emitter.LED]\nx = { uniform = nan }\n", "t.toml:2: emitter.LED.x.uniform must be a finite"},
           {"[emitter.LED]\nflux = { uniform = 100 }\n", "t.toml:2: emitter.LED.flux: a change of −100 %"},
           {"[emitter.LED]\nx = { sigma = 1 }\n", "t.toml:2: emitter.LED.x: unknown key 'sigma'"},
           {"[emitter]\nLED = 3\n", "t.toml:2: [emitter.LED] must be a table"},
           {"", "t.toml: no tolerances"},
           {"[emitter.LED\n", "t.toml:1"},
       }) {
    const std::string e = error_of(text);
    EXPECT_EQ(e.rfind(says, 0), 0u) << "input:\n" << text << "error: " << e;
  }
}

TEST(ToleranceSpec, WhatTheModelLacksIsNamed) {
  const sim::SceneDesc scene = small_scene();
  for (const auto& [text, says] : std::vector<std::pair<std::string, std::string>>{
           {"[emitter.LEDs]\nx = { uniform = 1 }\n", "t.toml:2: the model has no emitter 'LEDs' (it has 'LED', 'panel')"},
           {"[material.alu]\nscattering = { uniform = 1 }\n", "t.toml:2: alu.scattering: the material does not scatter in volume"},
           {"[material.steel]\nroughness = { uniform = 1 }\n", "t.toml:2: the model has no material 'steel' (it has 'alu', 'opal')"},
           {"[material.alu]\ntransmittance = { uniform = 1 }\n", "t.toml:2: alu.transmittance: the material transmits nothing"},
           {"[material.opal]\nroughness = { uniform = 1 }\n", "t.toml:2: opal.roughness: the material has no glossy lobe"},
           {"[material.alu]\nreflectance = { uniform = 12 }\n", "t.toml:2: alu.reflectance at +12 % would make the material's lobes sum to 1.008 > 1"},
       }) {
    const ToleranceSpec s = parse_ok(text);
    const Status st = check_tolerances(s, scene);
    ASSERT_FALSE(st.ok()) << text;
    EXPECT_EQ(to_string(st.error()).rfind(says, 0), 0u) << to_string(st.error());
  }
  // The panel's flux may vary: flux applies to any emitter.
  EXPECT_TRUE(check_tolerances(parse_ok("[emitter.panel]\nflux = { uniform = 5 }\n"), scene).ok());
}

TEST(ToleranceSpec, ZeroLeavesTheSceneBitForBit) {
  const ToleranceSpec s = parse_ok(
      "[emitter.LED]\nx = { uniform = 1 }\ntilt_x = { uniform = 1 }\nflux = { uniform = 1 }\n"
      "[material.alu]\nreflectance = { uniform = 1 }\nroughness = { uniform = 1 }\n");
  sim::SceneDesc a = small_scene();
  ASSERT_TRUE(check_tolerances(s, a).ok());
  apply_tolerances(s, std::vector<double>(s.tolerances.size(), 0.0), a);
  const sim::SceneDesc b = small_scene();
  const sim::Emitter &ea = a.emitters[0], &eb = b.emitters[0];
  EXPECT_EQ(std::memcmp(&ea.position, &eb.position, sizeof(Vec3)), 0);
  EXPECT_EQ(std::memcmp(&ea.frame, &eb.frame, sizeof(photometry::PhotometricFrame)), 0);
  EXPECT_EQ(ea.flux_lm, eb.flux_lm);
  EXPECT_EQ(a.materials[0].glossy, b.materials[0].glossy);
  EXPECT_EQ(a.materials[0].glossy_mx, b.materials[0].glossy_mx);
}

TEST(ToleranceSpec, PerturbationsAgainstClosedForms) {
  const ToleranceSpec s = parse_ok(
      "[emitter.LED]\ny = { uniform = 1 }\ntilt_x = { uniform = 1 }\nflux = { uniform = 1 }\n"
      "[material.alu]\nreflectance = { uniform = 1 }\nroughness = { uniform = 1 }\n"
      "[material.opal]\ntransmittance = { uniform = 1 }\n");
  // Order: LED.flux, LED.tilt_x, LED.y, alu.reflectance, alu.roughness, opal.transmittance.
  sim::SceneDesc scene = small_scene();
  ASSERT_TRUE(check_tolerances(s, scene).ok());
  apply_tolerances(s, std::vector<double>{-10.0, 30.0, 0.25, -5.0, 20.0, 10.0}, scene);
  const sim::Emitter& e = scene.emitters[0];
  EXPECT_DOUBLE_EQ(e.flux_lm, 90.0);
  // y runs along C90, which is world −Z in Gonio's default frame: 0.25 mm.
  EXPECT_DOUBLE_EQ(e.position.z, -0.25e-3);
  EXPECT_DOUBLE_EQ(e.position.y, 0.01);
  // Tilted 30° about C0 (+X): the nadir (−up) turns from −Y by 30° towards…
  // a right-handed turn about +X takes −Y to (0, −cos 30°, −sin 30°).
  const Vec3 nadir = -1.0 * e.frame.up;
  EXPECT_NEAR(nadir.x, 0.0, 1e-15);
  EXPECT_NEAR(nadir.y, -std::cos(std::numbers::pi / 6), 1e-15);
  EXPECT_NEAR(nadir.z, -std::sin(std::numbers::pi / 6), 1e-15);
  EXPECT_NEAR(dot(e.frame.c0, e.frame.up), 0.0, 1e-15);  // still orthonormal
  EXPECT_DOUBLE_EQ(scene.materials[0].glossy, 0.9 * 0.95);
  EXPECT_DOUBLE_EQ(scene.materials[0].glossy_mx, 0.09 * 1.2);
  EXPECT_DOUBLE_EQ(scene.materials[0].glossy_my, 0.09 * 1.2);
  EXPECT_DOUBLE_EQ(scene.materials[1].diffuse_transmit, 0.6 * 1.1);
  EXPECT_DOUBLE_EQ(scene.materials[1].diffuse_reflect, 0.3);  // reflectance untouched
  // The area emitter kept its flux.
  EXPECT_EQ(scene.emitters[1].flux_lm, 50.0);
}

// A spectral reflectance replaces the lobes' total at each wavelength
// (sim/tracer/spectral.h): a reflectance tolerance scales it with the lobes
// (scaling the lobes alone would change nothing), and its largest value
// bounds the tolerance: 0.8 · 1.3 > 1 is an error, 0.8 · 1.25 = 1 is not;
// largest_scale lets ±10 % be scaled by (1 − 0.8 − 0.1)/(0.8 · 0.1) = 1.25
// with a 0.1 transmission beside it.
TEST(ToleranceSpec, SpectralReflectanceScalesWithTheLobesAndBoundsThem) {
  sim::SceneDesc scene = small_scene();
  sim::Material& red = scene.materials[1];  // opal: diffuse 0.3 reflect, 0.6 transmit
  red.diffuse_transmit = 0.1;
  red.spectral_reflectance = {{400.0, 600.0, 700.0}, {0.1, 0.8, 0.4}};
  const Status over = check_tolerances(parse_ok("[material.opal]\nreflectance = { uniform = 30 }\n"), scene);
  ASSERT_FALSE(over.ok());
  EXPECT_EQ(to_string(over.error()).rfind("t.toml:2: opal.reflectance at +30 % would make the material's lobes sum to 1.14 > 1", 0), 0u)
      << to_string(over.error());
  const ToleranceSpec s = parse_ok("[material.opal]\nreflectance = { uniform = 10 }\n");
  ASSERT_TRUE(check_tolerances(s, scene).ok());
  EXPECT_NEAR(largest_scale(s.tolerances[0], scene), (1.0 - 0.8 - 0.1) / (0.8 * 0.1), 1e-12);
  apply_tolerances(s, std::vector<double>{-10.0}, scene);
  EXPECT_DOUBLE_EQ(scene.materials[1].diffuse_reflect, 0.3 * 0.9);
  EXPECT_DOUBLE_EQ(scene.materials[1].spectral_reflectance.values[1], 0.8 * 0.9);
  EXPECT_DOUBLE_EQ(scene.materials[1].spectral_reflectance.values[2], 0.4 * 0.9);
  EXPECT_EQ(scene.materials[1].diffuse_transmit, 0.1);
}

// A part: every mesh of that name moved along, or turned about, the
// luminaire's axes through the centre of their bounding box.
TEST(ToleranceSpec, PartsMoveAndTurnAboutTheirCentre) {
  sim::SceneDesc scene = small_scene();
  sim::Mesh lens;
  lens.name = "lens";
  lens.positions = {{0.0f, 0.0f, 0.0f}, {0.02f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.02f}};
  lens.indices = {0, 1, 2};
  lens.normals = {{0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
  scene.meshes.push_back(lens);
  sim::Mesh copy = lens;
  copy.instanced = true;
  copy.name = "screw";
  scene.meshes.push_back(copy);
  const ToleranceSpec s = parse_ok("[part.lens]\nx = { uniform = 1 }\ntilt_y = { uniform = 1 }\n");
  ASSERT_TRUE(check_tolerances(s, scene).ok());
  // Spec order: lens.tilt_y, then lens.x.
  apply_tolerances(s, std::vector<double>{90.0, 0.5}, scene);
  const sim::Mesh& m = scene.meshes[0];
  // A right-handed quarter turn about C90 (world −Z) through the box's
  // centre (0.01, 0, 0.01) maps (x, y) about it to (y, −x); then +0.5 mm
  // along C0 (+X).
  const auto near = [](const sim::Vec3f& p, double x, double y, double z) {
    EXPECT_NEAR(p.x, x, 1e-7);
    EXPECT_NEAR(p.y, y, 1e-7);
    EXPECT_NEAR(p.z, z, 1e-7);
  };
  near(m.positions[0], 0.0105, 0.01, 0.0);
  near(m.positions[1], 0.0105, -0.01, 0.0);
  near(m.positions[2], 0.0105, 0.01, 0.02);
  near(m.normals[0], 1.0, 0.0, 0.0);
  near(scene.meshes[1].positions[1], 0.02, 0.0, 0.0);  // another part stays
  const ToleranceSpec bad = parse_ok("[part.screw]\nx = { uniform = 1 }\n");
  EXPECT_NE(to_string(check_tolerances(bad, scene).error()).find("instanced mesh"), std::string::npos);
  const ToleranceSpec none = parse_ok("[part.len]\nz = { uniform = 1 }\n");
  EXPECT_EQ(to_string(check_tolerances(none, scene).error()), "t.toml:2: the model has no part 'len' (it has 'lens', 'screw')");
}

// Instanced parts (docs/tolerance.md, "Instanced parts"): an instanced mesh
// with two copies moved by a tolerance must place its vertices where the
// same scene with its copies un-instanced (sim::flattened, world meshes
// "NODE/lens/0") puts them under the same moves. The mesh's name moves each
// copy about its own centre by the one value drawn; a node's name moves
// that copy; a path above several copies moves them as one body.
sim::SceneDesc two_copies(const std::string& a, const std::string& b) {
  sim::SceneDesc scene = small_scene();
  sim::Mesh lens;
  lens.name = "lens/0";
  lens.instanced = true;
  lens.positions = {{0.0f, 0.0f, 0.0f}, {0.02f, 0.0f, 0.0f}, {0.0f, 0.01f, 0.02f}};
  lens.normals = {{0.0f, 1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.894427f, -0.447214f}};
  lens.indices = {0, 1, 2};
  scene.meshes.push_back(lens);
  sim::Mesh holder;
  holder.name = "holder/holder/0";
  holder.positions = {{-0.1f, -0.01f, -0.1f}, {0.1f, -0.01f, -0.1f}, {0.0f, -0.01f, 0.1f}};
  holder.indices = {0, 1, 2};
  scene.meshes.push_back(holder);
  scene.instances.push_back({0, sim::translation({0.05, 0.0, 0.0}), a});
  scene.instances.push_back({0, sim::translation({-0.05, 0.002, 0.01}) * sim::rotation({0.0, 1.0, 0.0}, 0.5), b});
  return scene;
}

void expect_same_vertices(const sim::SceneDesc& a, const sim::SceneDesc& b, const std::string& what) {
  ASSERT_EQ(a.meshes.size(), b.meshes.size()) << what;
  for (std::size_t m = 0; m < a.meshes.size(); ++m) {
    EXPECT_EQ(a.meshes[m].name, b.meshes[m].name) << what;
    for (std::size_t i = 0; i < a.meshes[m].positions.size(); ++i) {
      EXPECT_NEAR(a.meshes[m].positions[i].x, b.meshes[m].positions[i].x, 2e-8) << what << " " << a.meshes[m].name;
      EXPECT_NEAR(a.meshes[m].positions[i].y, b.meshes[m].positions[i].y, 2e-8) << what << " " << a.meshes[m].name;
      EXPECT_NEAR(a.meshes[m].positions[i].z, b.meshes[m].positions[i].z, 2e-8) << what << " " << a.meshes[m].name;
    }
    for (std::size_t i = 0; i < a.meshes[m].normals.size(); ++i) {
      EXPECT_NEAR(a.meshes[m].normals[i].x, b.meshes[m].normals[i].x, 1e-6) << what << " " << a.meshes[m].name;
      EXPECT_NEAR(a.meshes[m].normals[i].z, b.meshes[m].normals[i].z, 1e-6) << what << " " << a.meshes[m].name;
    }
  }
}

TEST(ToleranceSpec, InstancedPartsMoveLikeTheirUninstancedCopies) {
  struct Case {
    std::string a, b, instanced, flat, what;
  };
  const std::string moves = "tilt_x = { uniform = 7 }\ntilt_y = { uniform = 5 }\ny = { uniform = 2 }\n";
  const std::vector<Case> cases = {
      // The mesh's name: both copies, each about its own centre, one value.
      {"lensA", "lensB", "[part.lens]\n" + moves, "[part.lensA]\n" + moves + "[part.lensB]\n" + moves, "mesh"},
      // One copy's node.
      {"lensA", "lensB", "[part.lensB]\n" + moves, "[part.lensB]\n" + moves, "node"},
      // A CAD path above both copies: one body about their common centre.
      {"array/lensA", "array/lensB", "[part.array]\n" + moves, "[part.array]\n" + moves, "path"},
      // The copies of one EXT_mesh_gpu_instancing node, "row[0]" and "row[1]": one body.
      {"row[0]", "row[1]", "[part.row]\n" + moves, "[part.\"row[0]\"]\n" + moves + "[part.\"row[1]\"]\n" + moves,
       "gpu copies, each by its own name"}};
  for (const Case& c : cases) {
    if (c.what.rfind("gpu", 0) == 0) continue;  // below: one body, not two
    sim::SceneDesc instanced = two_copies(c.a, c.b);
    sim::SceneDesc flat = sim::flattened(instanced);
    const ToleranceSpec si = parse_ok(c.instanced), sf = parse_ok(c.flat);
    ASSERT_TRUE(check_tolerances(si, instanced).ok()) << c.what;
    ASSERT_TRUE(check_tolerances(sf, flat).ok()) << c.what;
    std::vector<double> vi, vf;
    for (std::size_t i = 0; i < si.tolerances.size(); ++i) vi.push_back(1.5 + static_cast<double>(i));
    for (std::size_t i = 0; i < sf.tolerances.size(); ++i) vf.push_back(1.5 + static_cast<double>(i % si.tolerances.size()));
    apply_tolerances(si, vi, instanced);
    apply_tolerances(sf, vf, flat);
    expect_same_vertices(sim::flattened(instanced), flat, c.what);
  }
  // The copies of a gpu-instanced node named by the node: one body.
  sim::SceneDesc row = two_copies("row[0]", "row[1]");
  sim::SceneDesc row_flat = sim::flattened(two_copies("row/0", "row/1"));
  const ToleranceSpec sr = parse_ok("[part.row]\n" + moves);
  ASSERT_TRUE(check_tolerances(sr, row).ok());
  apply_tolerances(sr, std::vector<double>{1.5, 2.5, 3.5}, row);
  apply_tolerances(sr, std::vector<double>{1.5, 2.5, 3.5}, row_flat);
  sim::SceneDesc row_moved = sim::flattened(row);
  for (sim::Mesh& m : row_moved.meshes) m.name = m.name == "row[0]/lens/0" ? "row/0/lens/0" : m.name == "row[1]/lens/0" ? "row/1/lens/0" : m.name;
  expect_same_vertices(row_moved, row_flat, "gpu copies by the node");
  // Untouched: the other copy and the holder (the node case).
  sim::SceneDesc one = two_copies("lensA", "lensB");
  const sim::SceneDesc before = sim::flattened(one);
  apply_tolerances(parse_ok("[part.lensB]\n" + moves), std::vector<double>{1.5, 2.5, 3.5}, one);
  const sim::SceneDesc after = sim::flattened(one);
  const auto same = [](const sim::Mesh& x, const sim::Mesh& y) {
    for (std::size_t i = 0; i < x.positions.size(); ++i)
      if (std::memcmp(&x.positions[i], &y.positions[i], sizeof x.positions[i]) != 0) return false;
    return x.positions.size() == y.positions.size();
  };
  // Flattened: lensA, lensB (the instanced mesh's place, in instance order), the holder.
  EXPECT_TRUE(same(after.meshes[0], before.meshes[0]));   // lensA
  EXPECT_FALSE(same(after.meshes[1], before.meshes[1]));  // lensB
  EXPECT_TRUE(same(after.meshes[2], before.meshes[2]));   // the holder
  // A form error on an instanced part is refused, naming it.
  EXPECT_NE(to_string(check_tolerances(parse_ok("[part.lens]\nform = { modes = 1, rms_um = 3 }\n"), one).error())
                .find("form errors shape world meshes only"),
            std::string::npos);
}

// independent = true: each copy of the instanced mesh draws its own value —
// one tolerance per copy, named by its placed name, which moves that copy
// alone: the scene equals the un-instanced one with each copy's node given
// its own value.
TEST(ToleranceSpec, IndependentCopiesDrawTheirOwnValues) {
  sim::SceneDesc instanced = two_copies("lensA", "lensB");
  sim::SceneDesc flat = sim::flattened(instanced);
  ToleranceSpec si = parse_ok("[part.lens]\nindependent = true\ntilt_x = { uniform = 7 }\ny = { normal = 1 }\n");
  ASSERT_EQ(si.tolerances.size(), 2u);
  EXPECT_TRUE(si.tolerances[0].independent);
  ASSERT_TRUE(expand_independent_copies(si, instanced).ok());
  ASSERT_EQ(si.tolerances.size(), 4u);
  EXPECT_EQ(si.tolerances[0].label(), "lensA/lens/0.tilt_x");
  EXPECT_EQ(si.tolerances[1].label(), "lensB/lens/0.tilt_x");
  EXPECT_EQ(si.tolerances[3].label(), "lensB/lens/0.y");
  EXPECT_EQ(si.tolerances[3].line, 4);
  EXPECT_EQ(si.tolerances[3].law.sigma, 1.0);
  ASSERT_TRUE(check_tolerances(si, instanced).ok());
  const ToleranceSpec sf = parse_ok("[part.lensA]\ntilt_x = { uniform = 7 }\ny = { normal = 1 }\n"
                                    "[part.lensB]\ntilt_x = { uniform = 7 }\ny = { normal = 1 }\n");
  ASSERT_TRUE(check_tolerances(sf, flat).ok());
  // Spec order: A.tilt_x, B.tilt_x, A.y, B.y; the flat file's: A.tilt_x, A.y, B.tilt_x, B.y.
  apply_tolerances(si, std::vector<double>{4.0, -6.0, 0.7, -1.9}, instanced);
  apply_tolerances(sf, std::vector<double>{4.0, 0.7, -6.0, -1.9}, flat);
  expect_same_vertices(sim::flattened(instanced), flat, "independent copies");
  // Not a mesh's copies, or not a boolean: errors naming the line.
  ToleranceSpec node = parse_ok("[part.lensA]\nindependent = true\nx = { uniform = 1 }\n");
  EXPECT_EQ(to_string(expand_independent_copies(node, instanced).error()),
            "t.toml:3: lensA.x: independent = true needs the name of an instanced mesh (its copies draw their own "
            "values); 'lensA' is not one");
  EXPECT_EQ(error_of("[part.lens]\nindependent = 1\nx = { uniform = 1 }\n"),
            "t.toml:2: part.lens.independent must be true or false");
}

// independent = true where two copies share their placed name (glTF nodes
// of the same name): one tolerance per copy could not tell them apart —
// each would move both copies and report.json's values would keep one of
// the two labels — so it is an error naming the line and the name.
TEST(ToleranceSpec, IndependentCopiesOfTheSameNameAreAnError) {
  const sim::SceneDesc instanced = two_copies("lensA", "lensA");
  ToleranceSpec s = parse_ok("[part.lens]\nindependent = true\ntilt_x = { uniform = 7 }\n");
  const Status expanded = expand_independent_copies(s, instanced);
  ASSERT_FALSE(expanded.ok()) << s.tolerances.size() << " tolerances";
  EXPECT_EQ(to_string(expanded.error()),
            "t.toml:3: lens.tilt_x: independent = true: two copies of 'lens' are placed as 'lensA/lens/0' (the same "
            "node name): give their nodes distinct names");
}

// A profile's form error: `form = { modes = K, rms_um = S }` is K Legendre
// modes of the sag, each N(0, S/√K). On a flat annulus (normal up, ρ from
// 10 to 30 mm on 201 equally spaced rings) mode 2 at 5 µm displaces every
// vertex along the up axis by 5 µm·√5·P₂(t) exactly, its RMS over the
// rings is 5 µm (orthonormal modes: to the rings' quadrature), and each
// normal turns by the slope, atan(δ′(ρ)), away from the axis where the sag
// rises outwards.
TEST(ToleranceSpec, FormErrorsAreLegendreModesOfTheSag) {
  for (double t : {-1.0, -0.3, 0.0, 0.45, 1.0}) {
    EXPECT_NEAR(legendre(3, t)[0], 0.5 * (5 * t * t * t - 3 * t), 1e-14);
    EXPECT_NEAR(legendre(3, t)[1], 0.5 * (15 * t * t - 3), 1e-13);
    EXPECT_NEAR(legendre(2, t)[1], 3 * t, 1e-14);
  }
  const ToleranceSpec s = parse_ok("[part.dish]\nform = { modes = 3, rms_um = 6 }\nz = { uniform = 1 }\n");
  ASSERT_EQ(s.tolerances.size(), 4u);
  EXPECT_EQ(s.tolerances[0].label(), "dish.form1");
  EXPECT_EQ(s.tolerances[2].label(), "dish.form3");
  EXPECT_EQ(std::string(s.tolerances[1].unit()), "µm");
  EXPECT_DOUBLE_EQ(s.tolerances[1].law.sigma, 6.0 / std::sqrt(3.0));
  EXPECT_EQ(s.tolerances[1].line, 2);
  EXPECT_EQ(error_of("[part.dish]\n\nform = { modes = 0, rms_um = 5 }\n"),
            "t.toml:3: part.dish.form.modes must be a whole number from 1 to 8");
  EXPECT_EQ(error_of("[part.dish]\nform = { modes = 2 }\n"), "t.toml:2: part.dish.form: give both modes and rms_um");
  EXPECT_EQ(error_of("[part.dish]\nform = { modes = 2, rms = 3 }\n"),
            "t.toml:2: part.dish.form: unknown key 'rms' (modes, rms_um)");

  sim::SceneDesc scene = small_scene();
  sim::Mesh dish;
  dish.name = "dish";
  constexpr int kRings = 201;
  for (int i = 0; i < kRings; ++i) {
    const double rho = 0.01 + 0.02 * i / (kRings - 1.0);
    for (int j = 0; j < 4; ++j) {
      const double phi = 0.3 + j * std::numbers::pi / 2.0;
      dish.positions.push_back(sim::to_float(Vec3{rho * std::cos(phi), 0.0, rho * std::sin(phi)}));
      dish.normals.push_back({0.0f, 1.0f, 0.0f});
    }
  }
  for (std::uint32_t k = 0; k + 2 < dish.positions.size(); k += 3) dish.indices.insert(dish.indices.end(), {k, k + 1, k + 2});
  const sim::Mesh before = dish;
  scene.meshes.push_back(dish);
  const ToleranceSpec mode2 = parse_ok("[part.dish]\nform = { modes = 2, rms_um = 5 }\n");
  ASSERT_TRUE(check_tolerances(mode2, scene).ok());
  apply_tolerances(mode2, std::vector<double>{0.0, 5.0}, scene);  // form1 0, form2 5 µm
  // The up axis of the default frame is +Y; the box's centre is on the axis.
  const Vec3 up = scene.frame.up;
  double ss = 0.0;
  const double a = 5e-6 * std::sqrt(5.0);
  for (std::size_t i = 0; i < before.positions.size(); ++i) {
    const Vec3 p0 = sim::to_double(before.positions[i]), p1 = sim::to_double(scene.meshes.back().positions[i]);
    const Vec3 r = p0 - dot(p0, up) * up;
    const double rho = length(r), t = (rho - 0.01) / 0.01 - 1.0;
    const double want = a * 0.5 * (3.0 * t * t - 1.0);
    EXPECT_NEAR(dot(p1 - p0, up), want, 2e-9) << "ρ = " << rho;
    ss += dot(p1 - p0, up) * dot(p1 - p0, up);
    // Slope δ′ = a·3t·dt/dρ; the normal leans away from the axis by atan(δ′).
    const double slope = a * 3.0 * t / 0.01;
    const Vec3 n = sim::to_double(scene.meshes.back().normals[i]);
    EXPECT_NEAR(dot(n, (1.0 / rho) * r), -slope / std::sqrt(1.0 + slope * slope), 1e-6) << "ρ = " << rho;
    EXPECT_NEAR(length(n), 1.0, 1e-6);
  }
  EXPECT_NEAR(std::sqrt(ss / static_cast<double>(before.positions.size())), 5e-6, 0.02 * 5e-6);
  // A zero amplitude leaves the mesh as it was, bit for bit.
  sim::SceneDesc again = small_scene();
  again.meshes.push_back(before);
  apply_tolerances(mode2, std::vector<double>{0.0, 0.0}, again);
  EXPECT_EQ(0, std::memcmp(again.meshes.back().positions.data(), before.positions.data(),
                           before.positions.size() * sizeof(sim::Vec3f)));
}

TEST(ToleranceLaw, QuantilesFollowTheLaws) {
  ToleranceLaw n;
  n.kind = ToleranceLaw::Kind::Normal;
  n.sigma = 2.0;
  n.truncate = 10.0;  // as good as untruncated
  EXPECT_NEAR(n.quantile(0.5), 0.0, 1e-12);
  // Φ(1) = 0.841344746…: one σ.
  EXPECT_NEAR(n.quantile(0.8413447460685429), 2.0, 1e-9);
  EXPECT_NEAR(n.quantile(1.0 - 0.8413447460685429), -2.0, 1e-9);
  n.truncate = 1.0;  // truncated at ±σ: the ends are the limits
  EXPECT_NEAR(n.quantile(0.0), -2.0, 1e-12);
  EXPECT_NEAR(n.quantile(1.0), 2.0, 1e-12);
  ToleranceLaw u;
  u.half_width = 0.5;
  EXPECT_DOUBLE_EQ(u.quantile(0.25), -0.25);
  ToleranceLaw v;
  v.kind = ToleranceLaw::Kind::Values;
  v.values = {3.0, 1.0, 2.0};
  EXPECT_EQ(v.quantile(0.0), 3.0);
  EXPECT_EQ(v.quantile(0.5), 1.0);
  EXPECT_EQ(v.quantile(0.99), 2.0);
  EXPECT_EQ(v.low(), 1.0);
  EXPECT_EQ(v.high(), 3.0);
}

TEST(LatinHypercube, OnePointPerStratumInEveryDimension) {
  const std::size_t n = 37, dims = 5;
  const auto u = latin_hypercube(n, dims, 7);
  ASSERT_EQ(u.size(), n);
  for (std::size_t d = 0; d < dims; ++d) {
    std::set<std::size_t> strata;
    for (const auto& p : u) {
      ASSERT_GE(p[d], 0.0);
      ASSERT_LT(p[d], 1.0);
      strata.insert(static_cast<std::size_t>(p[d] * n));
    }
    EXPECT_EQ(strata.size(), n) << "dimension " << d;
  }
  EXPECT_EQ(latin_hypercube(n, dims, 7), u);  // seeded
  EXPECT_NE(latin_hypercube(n, dims, 8), u);
  // Dimensions are shuffled independently: not the same order.
  std::size_t same = 0;
  for (const auto& p : u) same += static_cast<std::size_t>(p[0] * n) == static_cast<std::size_t>(p[1] * n);
  EXPECT_LT(same, n);
}

// The Latin hypercube through a law's quantile: one draw in each of N
// equally likely strata, so the draws' empirical distribution function is
// within 1/N of the law's everywhere (Kolmogorov–Smirnov D ≤ 1/N, a bound
// by construction, not a tolerance). A quantile that forgot the
// truncation's renormalisation breaks it.
TEST(LatinHypercube, DrawsFollowATruncatedNormalWithinOneOverN) {
  ToleranceLaw law;
  law.kind = ToleranceLaw::Kind::Normal;
  law.sigma = 0.05;
  law.truncate = 2.0;
  const std::size_t n = 200;
  const auto u = latin_hypercube(n, 1, 3);
  std::vector<double> x;
  for (const auto& p : u) x.push_back(law.quantile(p[0]));
  std::sort(x.begin(), x.end());
  const auto phi = [](double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); };
  const auto cdf = [&](double v) { return (phi(v / 0.05) - phi(-2.0)) / (phi(2.0) - phi(-2.0)); };
  double d = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double f = cdf(x[i]);
    d = std::max({d, std::abs(f - static_cast<double>(i) / n), std::abs(f - static_cast<double>(i + 1) / n)});
  }
  EXPECT_LE(d, 1.0 / n + 1e-9);
  EXPECT_GE(x.front(), -0.1);
  EXPECT_LE(x.back(), 0.1);
}

TEST(SpecLimits, Parse) {
  const auto l = parse_spec("beam_c0=24..28,flux=900..,rms=..1.5");
  ASSERT_TRUE(l.ok()) << l.error().message;
  ASSERT_EQ(l->size(), 3u);
  EXPECT_EQ((*l)[0].figure, kBeamC0);
  EXPECT_TRUE((*l)[0].holds(24.0));
  EXPECT_FALSE((*l)[0].holds(28.01));
  EXPECT_TRUE((*l)[1].holds(1e9));
  EXPECT_FALSE((*l)[2].holds(1.6));
  EXPECT_EQ((*l)[0].text(), "beam_c0=24..28");
  EXPECT_EQ((*l)[1].text(), "flux=900..");
  for (const auto& [text, says] : std::vector<std::pair<std::string, std::string>>{
           {"beam=24..28", "unknown figure"}, {"beam_c0=24", "FIGURE=LO..HI"}, {"beam_c0=..", "at least one"},
           {"beam_c0=28..24", "above the high"}, {"beam_c0=a..28", "not a number"}, {"", "FIGURE=LO..HI"}}) {
    const auto r = parse_spec(text);
    ASSERT_FALSE(r.ok()) << text;
    EXPECT_NE(r.error().message.find(says), std::string::npos) << r.error().message;
  }
}

TEST(SpecLimits, InverseSensitivityIsLinear) {
  SpecLimit l;
  l.figure = kBeamC0;
  l.lo = 24.0;
  l.hi = 28.0;
  // Nominal 26: +0.5° at the high limit reaches 28 at 4× the tolerance,
  // −0.25° at the low limit reaches 24 at 8×: 4.
  EXPECT_DOUBLE_EQ(allowed_scale(26.0, -0.25, 0.5, l), 4.0);
  EXPECT_DOUBLE_EQ(allowed_scale(27.0, -2.0, 0.1, l), 1.5);  // the low side binds
  EXPECT_TRUE(std::isinf(allowed_scale(26.0, 0.0, 0.0, l)));
  EXPECT_EQ(allowed_scale(29.0, 0.1, 0.1, l), 0.0);  // out already
  SpecLimit open;
  open.figure = kFlux;
  open.lo = 900.0;
  EXPECT_TRUE(std::isinf(allowed_scale(950.0, 10.0, 20.0, open)));  // no upper limit to reach
  EXPECT_DOUBLE_EQ(allowed_scale(950.0, -10.0, 20.0, open), 5.0);
}

// The nearest rank: of n finite values sorted ascending, the one at rank
// max(1, ⌈P·n/100⌉); NaN left out, ties by index.
TEST(Percentiles, NearestRank) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> v = {5.0, 1.0, nan, 4.0, 2.0, 3.0};  // 5 finite
  EXPECT_EQ(nearest_rank(v, 0.0), 1u);     // rank 1: 1.0
  EXPECT_EQ(nearest_rank(v, 20.0), 1u);    // ⌈1⌉ = 1
  EXPECT_EQ(nearest_rank(v, 20.5), 4u);    // ⌈1.025⌉ = 2: 2.0
  EXPECT_EQ(nearest_rank(v, 50.0), 5u);    // ⌈2.5⌉ = 3: 3.0
  EXPECT_EQ(nearest_rank(v, 100.0), 0u);   // 5.0
  EXPECT_FALSE(nearest_rank({nan, nan}, 50.0).has_value());
  EXPECT_FALSE(nearest_rank({}, 50.0).has_value());
  // Ties: the earlier index first.
  EXPECT_EQ(nearest_rank({2.0, 1.0, 1.0, 3.0}, 25.0), 1u);
  EXPECT_EQ(nearest_rank({2.0, 1.0, 1.0, 3.0}, 50.0), 2u);
  // 95 % of 20: rank 19 exactly (not 20 from 0.95 · 20 rounding up).
  std::vector<double> twenty(20);
  for (std::size_t i = 0; i < twenty.size(); ++i) twenty[i] = static_cast<double>(i);
  EXPECT_EQ(nearest_rank(twenty, 95.0), 18u);
  EXPECT_EQ(nearest_rank(twenty, 5.0), 0u);
  EXPECT_EQ(nearest_rank(twenty, 5.01), 1u);
}

TEST(Percentiles, ParseNamesTheItem) {
  Result<std::vector<PercentileChoice>> c = parse_percentiles("5,95,beam_c0:50,cct:2.5");
  ASSERT_TRUE(c.ok()) << to_string(c.error());
  ASSERT_EQ(c->size(), 4u);
  EXPECT_EQ((*c)[0].figure, kRms);
  EXPECT_EQ((*c)[1].percent, 95.0);
  EXPECT_EQ((*c)[2].figure, kBeamC0);
  EXPECT_EQ((*c)[2].stem(), "p50_beam_c0");
  EXPECT_EQ((*c)[3].stem(), "p2.5_cct");
  EXPECT_EQ((*c)[0].stem(), "p5_rms");
  for (const auto& [text, says] : std::vector<std::pair<std::string, std::string>>{
           {"101", "--percentile '101': write P or FIGURE:P with P from 0 to 100"},
           {"5,-1", "--percentile '-1': write P or FIGURE:P"},
           {"5,", "--percentile '': write P"},
           {"beam:50", "--percentile 'beam:50': unknown figure (peak_cd, "},
           {"beam_c0:x", "--percentile 'beam_c0:x': write P"}}) {
    Result<std::vector<PercentileChoice>> bad = parse_percentiles(text);
    ASSERT_FALSE(bad.ok()) << text;
    EXPECT_EQ(bad.error().message.rfind(says, 0), 0u) << bad.error().message;
  }
}

TEST(NoiseFloor, StandardDeviationAndRmsMean) {
  FigureValues nominal{}, a{}, b{};
  nominal[kFlux] = 10.0;
  a[kFlux] = 12.0;
  b[kFlux] = 14.0;
  a[kRms] = 0.2;
  b[kRms] = 0.4;
  const FigureValues noise = noise_floor(nominal, {a, b});
  EXPECT_DOUBLE_EQ(noise[kFlux], 2.0);  // sample σ of 10, 12, 14
  EXPECT_DOUBLE_EQ(noise[kRms], 0.3);
  EXPECT_TRUE(below_noise(3.9, 2.0));
  EXPECT_FALSE(below_noise(4.1, 2.0));
  EXPECT_FALSE(below_noise(1.0, std::nan("")));  // no floor: ranked
  EXPECT_TRUE(std::isnan(noise_floor(nominal, {})[kFlux]));
}

TEST(Histogram, CountsEveryValue) {
  const Histogram h = histogram({0.0, 0.1, 0.5, 0.99, 1.0, std::nan("")}, 4);
  ASSERT_EQ(h.edges.size(), 5u);
  EXPECT_EQ(h.counts, (std::vector<std::size_t>{2, 0, 1, 2}));
}

}  // namespace
}  // namespace gonio::design
