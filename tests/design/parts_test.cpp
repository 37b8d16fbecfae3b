// The design file's other part kinds (docs/design.md): extruded troughs,
// covers, fixed parts and faceted reflectors — on their exact surfaces,
// traced against closed forms, and their mistakes errors naming the line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "design/design_file.h"
#include "design/design_scene.h"
#include "design/trough.h"
#include "sim/simulation.h"
#include "tests/support/test_support.h"

namespace gonio::design {
namespace {

constexpr double kPi = std::numbers::pi;

io::CadLoadOptions options(double deg) {
  io::CadLoadOptions o;
  o.tessellation.angular_deflection_deg = deg;
  return o;
}

Result<sim::SceneDesc> scene_of(const std::string& text, double deg = 2.0) {
  Result<Design> d = parse_design(text, "lamp.design.toml");
  if (!d.ok()) return d.error();
  std::vector<Finding> findings;
  return design_scene(*d, options(deg), &findings);
}

// Traces `scene` and keeps every escaped photon.
std::vector<sim::EscapedRay> escapes(sim::SceneDesc scene, std::uint64_t photons, sim::Ledger* ledger = nullptr) {
  sim::SimulationSettings s;
  s.photons_per_iteration = photons;
  s.iterations = 1;
  s.threads = 2;
  s.capture_escaped_photons = photons;
  Result<sim::Simulation> sim = sim::Simulation::create(std::move(scene), s);
  EXPECT_TRUE(sim.ok()) << (sim.ok() ? std::string() : to_string(sim.error()));
  if (!sim.ok()) return {};
  sim->run_iteration();
  if (ledger) *ledger = sim->ledger();
  return sim->escaped_rays();
}

// A parabolic trough, z = f − x²/4f (f = 10 mm), its focal line on the Y
// axis through the emitter, 400 mm long, x over ±40 mm.
const char* kTrough = R"(length_unit = "mm"

[materials.mirror]
mirror = 1.0

[[emitters]]
name = "LED"
position = [0, 0, 0]
flux_lm = 1000

[[troughs]]
name = "trough"
material = "mirror"
profile = "conic"
radius = 20
conic = -1
vertex = 10
aperture = [0, 40]
length = 400
)";

double angle(const Vec3& a, const Vec3& b) { return std::atan2(length(cross(a, b)), dot(a, b)); }

TEST(DesignTrough, VerticesAndNormalsAreOnTheExactParabolicCylinder) {
  Result<sim::SceneDesc> s = scene_of(kTrough);
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  ASSERT_EQ(s->meshes.size(), 1u);
  const sim::Mesh& m = s->meshes[0];
  EXPECT_EQ(m.name, "trough");
  ASSERT_EQ(m.normals.size(), m.positions.size());
  const double f = 0.010;
  double worst_z = 0.0, worst_n = 0.0, x_min = 1, x_max = -1, y_min = 1, y_max = -1;
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const Vec3 p = sim::to_double(m.positions[i]);
    worst_z = std::max(worst_z, std::abs(p.z - (f - p.x * p.x / (4 * f))));
    // The normal facing the focal line: −(x/2f, 0, 1)/|·|.
    worst_n = std::max(worst_n, angle(sim::to_double(m.normals[i]), normalize(Vec3{-p.x / (2 * f), 0.0, -1.0})));
    x_min = std::min(x_min, p.x);
    x_max = std::max(x_max, p.x);
    y_min = std::min(y_min, p.y);
    y_max = std::max(y_max, p.y);
  }
  EXPECT_LT(worst_z, 1e-8);
  EXPECT_LT(worst_n, 1e-6);
  EXPECT_NEAR(x_min, -0.040, 1e-8);  // float positions
  EXPECT_NEAR(x_max, 0.040, 1e-8);  // float positions
  EXPECT_NEAR(y_min, -0.200, 1e-8);  // float positions
  EXPECT_NEAR(y_max, 0.200, 1e-8);  // float positions
  // Every triangle wound counter-clockwise seen from its normals' side.
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const Vec3 a = sim::to_double(m.positions[m.indices[t]]), b = sim::to_double(m.positions[m.indices[t + 1]]),
               c = sim::to_double(m.positions[m.indices[t + 2]]);
    ASSERT_GT(dot(cross(b - a, c - a), sim::to_double(m.normals[m.indices[t]])), 0.0);
  }
}

// The angle of a direction in the cross-section (XZ) from the nadir, and along the trough (YZ).
double across(const Vec3& d) { return std::atan2(d.x, -d.z); }
double along(const Vec3& d) { return std::atan2(d.y, -d.z); }

// Closed form: every ray from the focal line of a parabola leaves it
// parallel to the axis after one reflection, so the reflected light of a
// parabolic trough has no x component — collimated in the cross-section
// (the C0–C180 plane), spread along the trough (C90–C270) as the source
// spreads it. The width left across is the tessellation's.
TEST(DesignTrough, ParabolicTroughCollimatesAcrossAndSpreadsAlong) {
  std::vector<double> widths;
  for (const double deg : {2.0, 0.5}) {
    Result<sim::SceneDesc> s = scene_of(kTrough, deg);
    ASSERT_TRUE(s.ok()) << to_string(s.error());
    const std::vector<sim::EscapedRay> rays = escapes(std::move(*s), 100'000);
    ASSERT_EQ(rays.size(), 100'000u);  // a mirror of reflectance 1: nothing is lost
    std::vector<double> a;
    double along_max = 0.0;
    for (const sim::EscapedRay& r : rays) {
      if (length(r.origin) < 1e-9) continue;  // straight from the source
      a.push_back(std::abs(across(r.direction)));
      along_max = std::max(along_max, std::abs(along(r.direction)));
    }
    // Half of the light goes up into the trough (more: its rim is 30 mm below the source).
    ASSERT_GT(a.size(), 50'000u);
    std::sort(a.begin(), a.end());
    const double p99 = a[a.size() * 99 / 100] * 180 / kPi;
    widths.push_back(p99);
    std::printf("δ %g: p99 %g deg, %zu reflected\n", deg, p99, a.size());
    EXPECT_LT(p99, deg / 50) << "δ = " << deg << "°";
    EXPECT_GT(along_max * 180 / kPi, 80.0);  // along the trough: no collimation
  }
  EXPECT_LT(widths[1], widths[0]);  // a finer tessellation, a narrower beam across
}

std::string edited(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

double area(const sim::Mesh& m) {
  double a = 0.0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const Vec3 p = sim::to_double(m.positions[m.indices[t]]), q = sim::to_double(m.positions[m.indices[t + 1]]),
               r = sim::to_double(m.positions[m.indices[t + 2]]);
    a += 0.5 * length(cross(q - p, r - p));
  }
  return a;
}

// The caps close the cross-section between the two halves: each the area
// between the parabola and its rim's line, ∫(f − x²/4f + 30 mm) dx over
// ±40 mm = 3200 − 1066.67 mm².
TEST(DesignTrough, CapsCloseTheCrossSection) {
  const std::string text = edited(kTrough, "length = 400", "length = 400\ncaps = \"white\"\n[materials.white]\nreflectance = 0.8");
  Result<sim::SceneDesc> s = scene_of(text);
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  ASSERT_EQ(s->meshes.size(), 2u);
  const sim::Mesh& caps = s->meshes[1];
  EXPECT_EQ(caps.name, "trough caps");
  const double expected = 2 * (3200.0 - 2.0 * 40 * 40 * 40 / 3 / 40) * 1e-6;
  EXPECT_NEAR(area(caps) / expected, 1.0, 1e-3);
  for (std::size_t i = 0; i < caps.positions.size(); ++i) {
    const Vec3 p = sim::to_double(caps.positions[i]);
    EXPECT_NEAR(std::abs(p.y), 0.2, 1e-8);
    EXPECT_LT(angle(sim::to_double(caps.normals[i]), Vec3{0.0, p.y < 0 ? 1.0 : -1.0, 0.0}), 1e-9);  // into the trough
  }
}

TEST(DesignTrough, MistakesAreErrorsNamingTheLine) {
  struct Case {
    std::string from, to;
    int line;
    std::string says;
  };
  const std::vector<Case> cases = {
      {"length = 400", "length = -4", 19, "[[troughs]] at line 11: 'length' must be a number > 0"},
      {"length = 400", "lenght = 400", 19, "[[troughs]] at line 11: unknown key 'lenght'"},
      {"length = 400", "length = 400\ncaps = \"white\"", 20, "material 'white' is not defined"},
      {"length = 400", "length = 400\ncaps = 3", 20, "'caps' must be the name"},
      {"length = 400", "length = 400\nsymmetric = 1", 20, "'symmetric' must be true or false"},
      {"profile = \"conic\"", "profile = \"nurbs\"", 14, "profile 'nurbs' is not one Gonio knows"},
      {"material = \"mirror\"\nprofile", "material = \"chrome\"\nprofile", 11, "material 'chrome' is not defined"},
      // z = 10 mm − x²/40 mm passes through (x, z) = (−20, 0) mm, here 150 mm along the trough.
      {"position = [0, 0, 0]", "position = [-20, 150, 0]", 11, "passes through the emitter 'LED'"},
      {"conic = -1", "conic = 1", 14, "is not defined out to ρ = 40 mm"},
  };
  for (const Case& c : cases) {
    Result<sim::SceneDesc> s = scene_of(edited(kTrough, c.from, c.to));
    ASSERT_FALSE(s.ok()) << c.to;
    EXPECT_EQ(s.error().where.file, "lamp.design.toml") << c.to;
    EXPECT_EQ(s.error().where.line, c.line) << c.to << ": " << to_string(s.error());
    EXPECT_NE(s.error().message.find(c.says), std::string::npos) << c.to << ": " << to_string(s.error());
  }
  // Beyond the trough's end the same point is no mistake.
  EXPECT_TRUE(scene_of(edited(kTrough, "position = [0, 0, 0]", "position = [-20, 250, 0]")).ok());
  // A name taken by a reflector.
  const std::string both = std::string(kTrough) +
                           "\n[[reflectors]]\nname = \"trough\"\nmaterial = \"mirror\"\nprofile = \"conic\"\n"
                           "radius = 20\nconic = -1\nvertex = 50\naperture = [4, 30]\n";
  Result<sim::SceneDesc> s = scene_of(both);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().where.line, 11) << to_string(s.error());
  EXPECT_NE(s.error().message.find("is taken by the part at line 21"), std::string::npos) << to_string(s.error());
}

}  // namespace
}  // namespace gonio::design
