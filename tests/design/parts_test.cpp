// The design file's other part kinds (docs/design.md): extruded troughs,
// covers, fixed parts and faceted reflectors — on their exact surfaces,
// traced against closed forms, and their mistakes errors naming the line.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "design/design_file.h"
#include "design/design_export.h"
#include "design/design_scene.h"
#include "design/parts_export.h"
#include "design/trough.h"
#include "io/model/gltf.h"
#include "io/model/gltf_writer.h"
#include "io/model/step_export.h"
#include "io/support/file_io.h"
#include "sim/simulation.h"
#include "tests/support/rotation.h"
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

// Covers ---------------------------------------------------------------------

// The lamp of the cover tests: an isotropic point source at the origin and
// `cover` (a [[covers]] table's lines).
std::string cover_design(const std::string& cover) {
  return R"(length_unit = "mm"

[materials.clear]
dielectric = 1.0
ior = 1.5

[materials.opal]
preset = "opal PC 3 mm"

[materials.sheet]
diffuse_transmit = 0.6
kd = 0.3

[[emitters]]
name = "LED"
position = [0, 0, 0]
flux_lm = 1000

[[covers]]
name = "cover"
)" + cover;
}

// Signed volume of a closed mesh (divergence theorem): positive where its
// triangles wind counter-clockwise from outside.
double volume(const sim::Mesh& m) {
  double v = 0.0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const Vec3 a = sim::to_double(m.positions[m.indices[t]]), b = sim::to_double(m.positions[m.indices[t + 1]]),
               c = sim::to_double(m.positions[m.indices[t + 2]]);
    v += dot(a, cross(b, c)) / 6.0;
  }
  return v;
}

// Every edge (by its end points' positions) is shared by exactly two
// triangles that run along it in opposite directions: closed and
// consistently wound.
bool watertight(const sim::Mesh& m) {
  std::map<std::array<float, 6>, int> edges;  // directed edge → count
  for (std::size_t t = 0; t < m.indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const sim::Vec3f a = m.positions[m.indices[t + k]], b = m.positions[m.indices[t + (k + 1) % 3]];
      ++edges[{a.x, a.y, a.z, b.x, b.y, b.z}];
    }
  for (const auto& [e, n] : edges) {
    const auto back = edges.find({e[3], e[4], e[5], e[0], e[1], e[2]});
    if (n != 1 || back == edges.end() || back->second != 1) return false;
  }
  return true;
}

double cap_volume(double r, double h) { return kPi * h * h * (3 * r - h) / 3; }

TEST(DesignCover, ClearSolidsAreClosedWithTheirVolumes) {
  struct Case {
    std::string keys;
    double volume_mm3;
  };
  // The dome: base diameter 80 mm, sag 20 mm: R = 50 mm; 2 mm thick.
  const std::vector<Case> cases = {
      {"material = \"clear\"\nshape = \"plate\"\nsize = [100, 40]\nheight = -20\nthickness = 3\n", 100 * 40 * 3},
      {"material = \"clear\"\nshape = \"plate\"\ndiameter = 80\nheight = -20\nthickness = 3\n", kPi * 40 * 40 * 3},
      {"material = \"clear\"\nshape = \"dome\"\ndiameter = 80\nsag = 20\nheight = -30\nthickness = 2\n",
       cap_volume(50, 20) - cap_volume(48, 18)},
      {"material = \"clear\"\nshape = \"dome\"\ndiameter = 80\nsag = -20\nheight = -30\nthickness = 2\n",
       cap_volume(50, 20) - cap_volume(48, 18)},
      // The library's opal is a volume: 3 mm, the preset's thickness, without one given.
      {"material = \"opal\"\nshape = \"plate\"\nsize = [100, 40]\nheight = -20\n", 100 * 40 * 3},
  };
  for (const Case& c : cases) {
    Result<sim::SceneDesc> s = scene_of(cover_design(c.keys), 2.0);
    ASSERT_TRUE(s.ok()) << c.keys << to_string(s.error());
    ASSERT_EQ(s->meshes.size(), 1u);
    const sim::Mesh& m = s->meshes[0];
    EXPECT_TRUE(watertight(m)) << c.keys;
    // Chords inside the curved faces: the volume within 0.1 %.
    EXPECT_NEAR(volume(m) / (c.volume_mm3 * 1e-9), 1.0, 1e-3) << c.keys;
  }
  // The dome's two spheres about (0, 0, 0) (centre 30 mm above its base at −30 mm): |p| = 50 or 48 mm.
  Result<sim::SceneDesc> dome = scene_of(cover_design(cases[2].keys), 2.0);
  ASSERT_TRUE(dome.ok());
  for (std::size_t i = 0; i < dome->meshes[0].positions.size(); ++i) {
    const Vec3 p = sim::to_double(dome->meshes[0].positions[i]);
    const double r = length(p);
    if (std::abs(p.z + 0.030) < 1e-7) continue;  // the ring
    const bool outer = std::abs(r - 0.050) < 1e-7;
    ASSERT_TRUE(outer || std::abs(r - 0.048) < 1e-7) << r;
    // Out of the solid: away from the centre on the outer sphere, toward it on the inner.
    EXPECT_LT(angle(sim::to_double(dome->meshes[0].normals[i]), (outer ? 1.0 : -1.0) * normalize(p)), 1e-6);
  }
}

// A thin-sheet material makes one surface facing the luminaire.
TEST(DesignCover, ThinSheetIsOneSurfaceFacingTheLuminaire) {
  Result<sim::SceneDesc> s =
      scene_of(cover_design("material = \"sheet\"\nshape = \"plate\"\nsize = [100, 40]\nheight = -20\n"));
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  const sim::Mesh& m = s->meshes[0];
  EXPECT_NEAR(area(m), 0.1 * 0.04, 1e-9);
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_NEAR(m.positions[i].z, -0.020, 1e-8);
    EXPECT_EQ(m.normals[i].z, 1.0f);
  }
  s = scene_of(cover_design("material = \"sheet\"\nshape = \"dome\"\ndiameter = 80\nsag = 20\nheight = -30\n"));
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  for (std::size_t i = 0; i < s->meshes[0].positions.size(); ++i)  // toward the centre, the source
    EXPECT_LT(angle(sim::to_double(s->meshes[0].normals[i]), -normalize(sim::to_double(s->meshes[0].positions[i]))), 1e-6);
}

// The slab's transmittance: per polarisation (1 − R)/(1 + R) with R Fresnel's
// at one face (multiple reflections inside, no absorption), the mean of s and p.
double slab_transmittance(double theta, double n) {
  const double ci = std::cos(theta), st = std::sin(theta) / n, ct = std::sqrt(1 - st * st);
  const double rs = std::pow((ci - n * ct) / (ci + n * ct), 2), rp = std::pow((n * ci - ct) / (n * ci + ct), 2);
  return 0.5 * ((1 - rs) / (1 + rs) + (1 - rp) / (1 + rp));
}

// A clear plate (n = 1.5, 3 mm) 5 mm below an isotropic source, 2 m across:
// the flux leaving its lower face is ∫ ½ sin θ T(θ) dθ over the cone the
// disc subtends, T the slab's Fresnel transmittance.
TEST(DesignCover, ClearPlateTransmitsFresnelsFlux) {
  Result<sim::SceneDesc> s =
      scene_of(cover_design("material = \"clear\"\nshape = \"plate\"\ndiameter = 2000\nheight = -5\nthickness = 3\n"));
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  constexpr std::uint64_t kPhotons = 200'000;
  sim::Ledger ledger;
  const std::vector<sim::EscapedRay> rays = escapes(std::move(*s), kPhotons, &ledger);
  std::uint64_t through = 0;
  for (const sim::EscapedRay& r : rays)
    if (std::abs(r.origin.z + 0.008) < 1e-6 && r.direction.z < 0) ++through;
  const double theta_max = std::atan(1000.0 / 5.0);
  double expected = 0.0;
  constexpr int kSteps = 20000;
  for (int i = 0; i < kSteps; ++i) {
    const double th = (i + 0.5) * theta_max / kSteps;
    expected += 0.5 * std::sin(th) * slab_transmittance(th, 1.5) * theta_max / kSteps;
  }
  const double got = static_cast<double>(through) / kPhotons;
  const double sigma = std::sqrt(expected * (1 - expected) / kPhotons);
  std::printf("plate: traced %.5f, closed form %.5f (σ %.5f)\n", got, expected, sigma);
  EXPECT_NEAR(got, expected, 4 * sigma);
  // Nothing absorbed, nothing lost: every photon escapes.
  EXPECT_EQ(ledger.escaped.photons, kPhotons);
  EXPECT_NEAR(ledger.escaped.flux_lm, 1000.0, 1e-6);
}

// A clear dome (n = 1.5, 2 mm) about the source at its spheres' centre:
// every ray meets both faces at normal incidence, so what leaves the outer
// sphere radially is (1 − R₀)/(1 + R₀) = 0.923077 of what enters (R₀ = 0.04),
// and the books close with nothing absorbed or cut off.
TEST(DesignCover, ClearDomeAboutItsCentreConservesFluxAndTransmitsFresnels) {
  Result<sim::SceneDesc> s =
      scene_of(cover_design("material = \"clear\"\nshape = \"dome\"\ndiameter = 80\nsag = 20\nheight = -30\nthickness = 2\n"), 1.0);
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  constexpr std::uint64_t kPhotons = 200'000;
  sim::Ledger ledger;
  const std::vector<sim::EscapedRay> rays = escapes(std::move(*s), kPhotons, &ledger);
  EXPECT_TRUE(ledger.photons_close());
  EXPECT_EQ(ledger.escaped.photons, kPhotons);
  EXPECT_EQ(ledger.cutoff.photons, 0u);
  EXPECT_NEAR(ledger.escaped.flux_lm, 1000.0, 1e-6);
  // The cone that meets the inner sphere: α from the nadir below atan(ρ_in/30 mm), ρ_in = √(48² − 30²) mm.
  const double alpha_in = std::atan(std::sqrt(48.0 * 48 - 30 * 30) / 30);
  const double cone = 0.999 * alpha_in;  // off the ring's edge
  // Of the light that meets the inner sphere, the share that leaves the outer
  // one radially (through) against what comes back out of the inner one
  // toward the centre (back): light through the ring at the base leaves
  // bent and counts in neither.
  std::uint64_t through = 0, back = 0;
  for (const sim::EscapedRay& r : rays) {
    if (std::abs(length(r.origin) - 0.050) < 5e-4 && angle(r.direction, r.origin) < 1e-2 &&
        angle(r.direction, Vec3{0, 0, -1}) < cone)
      ++through;
    if (std::abs(length(r.origin) - 0.048) < 5e-4 && angle(r.direction, -1.0 * r.origin) < 1e-2 &&
        angle(r.direction, Vec3{0, 0, 1}) < cone)
      ++back;
  }
  const double expected = 0.96 / 1.04, n = static_cast<double>(through + back);
  EXPECT_NEAR(n / (kPhotons * (1 - std::cos(cone)) / 2), 1.0, 0.02);  // every photon of the cone, one way or the other
  const double got = static_cast<double>(through) / n;
  const double sigma = std::sqrt(expected * (1 - expected) / n);
  std::printf("dome: traced %.5f, closed form %.5f (σ %.5f)\n", got, expected, sigma);
  EXPECT_NEAR(got, expected, 4 * sigma);
}

TEST(DesignCover, MistakesAreErrorsNamingTheLine) {
  const std::string plate = "material = \"clear\"\nshape = \"plate\"\nsize = [100, 40]\nheight = -20\nthickness = 3\n";
  // [[covers]] is at line 19, its keys from 20 on (name 20, material 21, shape 22, size 23, height 24, thickness 25).
  struct Case {
    std::string from, to;
    int line;
    std::string says;
  };
  std::vector<Case> cases = {
      {"shape = \"plate\"", "shape = \"lens\"", 22, "shape 'lens' is not one Gonio knows (plate, dome)"},
      {"size = [100, 40]", "size = [100, -40]", 23, "'size' must be [x, y], two numbers > 0"},
      {"size = [100, 40]", "size = [100, 40]\ndiameter = 20", 23, "not both"},
      {"size = [100, 40]", "", 19, "give 'size' (a rectangle) or 'diameter' (a disc)"},
      {"thickness = 3", "thickness = 0", 25, "'thickness' must be a number > 0"},
      {"thickness = 3", "", 19, "is a volume (a dielectric or a medium): give the cover a 'thickness'"},
      {"material = \"clear\"", "material = \"sheet\"", 25, "is a thin sheet's (one surface)"},
      {"material = \"clear\"", "material = \"glass\"", 19, "material 'glass' is not defined"},
      {"height = -20", "heigth = -20", 24, "unknown key 'heigth'"},
      {"size = [100, 40]", "diameter = 80\nsag = 3", 24, "a plate has no 'sag'"},
      {"shape = \"plate\"\nsize = [100, 40]", "shape = \"dome\"\ndiameter = 80\nsag = 40", 24,
       "'sag' must be non-zero and smaller in size than the base's radius (40)"},
      {"shape = \"plate\"\nsize = [100, 40]", "shape = \"dome\"\ndiameter = 80\nsag = 2", 19,
       "thickness 3 mm is not less than its sag 2 mm"},
  };
  // The emitter at the origin inside the solid, or on the sheet.
  cases.push_back({"height = -20", "height = 1", 19, "the emitter 'LED' (line 14) lies inside the cover's solid"});
  cases.push_back({"material = \"clear\"\nshape = \"plate\"\nsize = [100, 40]\nheight = -20\nthickness = 3",
                   "material = \"sheet\"\nshape = \"plate\"\nsize = [100, 40]\nheight = 0", 19,
                   "the emitter 'LED' (line 14) lies on the cover"});
  cases.push_back({"shape = \"plate\"\nsize = [100, 40]\nheight = -20\nthickness = 3",
                   "shape = \"dome\"\ndiameter = 80\nsag = -20\nheight = -18.5\nthickness = 3", 19,
                   "lies inside the cover's solid"});
  for (const Case& c : cases) {
    Result<sim::SceneDesc> s = scene_of(edited(cover_design(plate), c.from, c.to));
    ASSERT_FALSE(s.ok()) << c.to;
    EXPECT_EQ(s.error().where.file, "lamp.design.toml") << c.to;
    EXPECT_EQ(s.error().where.line, c.line) << c.to << ": " << to_string(s.error());
    EXPECT_NE(s.error().message.find(c.says), std::string::npos) << c.to << ": " << to_string(s.error());
  }
}

// Facets ----------------------------------------------------------------------

// The paraboloid z = f − ρ²/4f (f = 10 mm) about the source at its focus, ρ 4 … 30 mm.
std::string faceted_dish(const std::string& facets) {
  return std::string(R"(length_unit = "mm"
[materials.mirror]
mirror = 1.0
[[emitters]]
name = "LED"
position = [0, 0, 0]
flux_lm = 1000
[[reflectors]]
name = "dish"
material = "mirror"
profile = "conic"
radius = 20
conic = -1
vertex = 10
aperture = [4, 30]
)") + (facets.empty() ? "" : "facets = " + facets + "\n");
}

TEST(DesignFacets, FlatFacetsHaveTheirCornersOnTheExactSurface) {
  Result<sim::SceneDesc> s = scene_of(faceted_dish("{ theta = 8, azimuth = 12, kind = \"flat\" }"));
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  const sim::Mesh& m = s->meshes[0];
  EXPECT_EQ(m.indices.size() / 3, 8u * 12u * 2u);
  for (const sim::Vec3f& v : m.positions) {
    const Vec3 p = sim::to_double(v);
    const double rho = std::hypot(p.x, p.y);
    EXPECT_NEAR(p.z, 0.010 - rho * rho / 0.040, 1e-8);
  }
  // Flat: each triangle's plane is its vertices' normal, facing the focus.
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    const Vec3 a = sim::to_double(m.positions[m.indices[t]]), b = sim::to_double(m.positions[m.indices[t + 1]]),
               c = sim::to_double(m.positions[m.indices[t + 2]]);
    const Vec3 n = normalize(cross(b - a, c - a));
    for (int k = 0; k < 3; ++k) ASSERT_LT(angle(n, sim::to_double(m.normals[m.indices[t + k]])), 1e-5);
    EXPECT_LT(dot(n, a), 0.0);
  }
}

TEST(DesignFacets, MistakesAreErrorsNamingTheLine) {
  // The facets' line is 16 (after the reflector's keys, from [[reflectors]] at line 8).
  for (const auto& [facets, says] : std::vector<std::pair<std::string, std::string>>{
           {"{ theta = -1 }", "'theta' must be 0 (smooth) or a whole number 1"},
           {"{ azimuth = 2 }", "'azimuth' must be 0 (smooth) or a whole number 3"},
           {"{ theta = 2.5 }", "'theta' must be 0"},
           {"{ theta = 8, kind = \"round\" }", "kind 'round' is not one Gonio makes (flat, curved)"},
           {"{ theta = 8, kind = \"curved\" }", "curved facets need 'radius_theta' or 'radius_azimuth'"},
           {"{ theta = 8, radius_theta = 50 }", "'radius_theta' bends curved facets: add kind = \"curved\""},
           {"{ azimuth = 8, kind = \"curved\", radius_theta = 50 }", "'radius_theta' without 'theta' facets"},
           {"{ theta = 8, kind = \"curved\", radius_theta = 0 }", "'radius_theta' must be a signed radius"},
           {"{ theta = 8, kind = \"curved\", radius_azimuth = 30 }", "'radius_azimuth' without 'azimuth' facets"},
           {"{ azimuth = 8, kind = \"curved\", radius_azimuth = \"x\" }", "'radius_azimuth' must be a signed radius"},
           {"{ theta = 8, tilt = 1 }", "unknown key 'tilt'"},
           {"{ kind = \"flat\" }", "give 'theta' or 'azimuth'"},
           {"8", "facets must be a table"}}) {
    Result<sim::SceneDesc> s = scene_of(faceted_dish(facets));
    ASSERT_FALSE(s.ok()) << facets;
    EXPECT_EQ(s.error().where.line, 16) << facets << ": " << to_string(s.error());
    EXPECT_NE(s.error().message.find("[[reflectors]] at line 8: facets"), std::string::npos) << to_string(s.error());
    EXPECT_NE(s.error().message.find(says), std::string::npos) << facets << ": " << to_string(s.error());
  }
}

// How far the reflected light of the dish strays from the axis: the 99th
// percentile of the reflected rays' angle from the nadir [deg].
double stray_p99(const std::string& facets) {
  Result<sim::SceneDesc> s = scene_of(faceted_dish(facets));
  EXPECT_TRUE(s.ok()) << to_string(s.error());
  if (!s.ok()) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> a;
  for (const sim::EscapedRay& r : escapes(std::move(*s), 40'000))
    if (length(r.origin) > 1e-9) a.push_back(angle(r.direction, Vec3{0, 0, -1}) * 180 / kPi);
  std::sort(a.begin(), a.end());
  return a.empty() ? std::numeric_limits<double>::quiet_NaN() : a[a.size() * 99 / 100];
}

// A smooth paraboloid collimates the focus's light; faceted along the
// profile, each flat facet turns it by up to its tangent's turn (at most
// 1.25 rad/N here, at ρ = 4 mm: d atan(ρ/2f) = 2f dρ/(4f² + ρ²), dρ = 26 mm/N);
// faceted around, the facets' tilt. Both converge to the smooth design.
TEST(DesignFacets, FacetedDishConvergesToTheSmoothOne) {
  const double smooth = stray_p99("");
  std::printf("smooth: %g deg\n", smooth);
  double last = INFINITY;
  for (int n : {8, 32, 128}) {
    const double p99 = stray_p99("{ theta = " + std::to_string(n) + " }");
    std::printf("theta %d: %g deg\n", n, p99);
    EXPECT_LT(p99, 1.25 / n * 180 / kPi) << n;
    EXPECT_LT(p99, last / 3) << n;  // ∝ 1/N: a quarter at each step
    last = p99;
  }
  last = INFINITY;
  for (int m : {16, 64, 256}) {
    const double p99 = stray_p99("{ azimuth = " + std::to_string(m) + " }");
    std::printf("azimuth %d: %g deg\n", m, p99);
    EXPECT_LT(p99, last / 3) << m;
    last = p99;
  }
  EXPECT_GT(last, smooth);
}

// Curved facets ---------------------------------------------------------------

// The dish's facet i of 6 along the profile (rows at ρ = 4 + 26·i/6 mm on
// z = 10 − ρ²/40 mm) bent into the arc of radius |R| through its ends, the
// centre on the focus's side for R > 0 (concave), away from it for R < 0:
// the centre (ρ, z) [m], from the closed form alone.
std::pair<double, double> dish_arc_centre(int i, double R) {
  auto row = [](int k) {
    const double r = 0.004 + 0.026 * k / 6.0;
    return std::pair{r, 0.010 - r * r / 0.040};
  };
  const auto [ar, az] = row(i);
  const auto [br, bz] = row(i + 1);
  const double c = std::hypot(br - ar, bz - az), mr = 0.5 * (ar + br), mz = 0.5 * (az + bz);
  double nr = (bz - az) / c, nz = -(br - ar) / c;
  if (nr * -mr + nz * -mz < 0) nr = -nr, nz = -nz;  // toward the focus
  const double w = std::sqrt(R * R - 0.25 * c * c), s = R > 0 ? 1.0 : -1.0;
  return {mr + s * w * nr, mz + s * w * nz};
}

// Curved along the profile: every vertex on its facet's arc (turned about
// the axis) and its normal the arc's, ±(centre − point)/|R|: across a facet
// the normal turns by 2·asin(c/2|R|), the facet's spread of the light.
TEST(DesignFacets, CurvedFacetsLieOnTheirArcsWithTheArcsNormals) {
  for (const double R : {0.040, -0.040}) {
    Result<sim::SceneDesc> s = scene_of(faceted_dish("{ theta = 6, kind = \"curved\", radius_theta = " +
                                                     std::to_string(R * 1e3) + " }"));
    ASSERT_TRUE(s.ok()) << to_string(s.error());
    const sim::Mesh& m = s->meshes[0];
    EXPECT_GT(m.indices.size() / 3, 6u * 2u * 8u);  // sub-rows along each arc
    double worst = 0.0, worst_normal = 0.0;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
      // The triangle's facet: the arc nearest its centroid (a row's vertex is on two).
      Vec3 centroid{0, 0, 0};
      for (int k = 0; k < 3; ++k) centroid += sim::to_double(m.positions[m.indices[t + k]]) * (1.0 / 3);
      const double crho = std::hypot(centroid.x, centroid.y);
      int band = 0;
      double nearest = 1.0;
      for (int i = 0; i < 6; ++i) {
        const auto [cr, cz] = dish_arc_centre(i, R);
        const double d = std::abs(std::hypot(crho - cr, centroid.z - cz) - std::abs(R));
        if (d < nearest && crho > 0.004 + 0.026 * i / 6.0 && crho < 0.004 + 0.026 * (i + 1) / 6.0) nearest = d, band = i;
      }
      const auto [cr, cz] = dish_arc_centre(band, R);
      for (int k = 0; k < 3; ++k) {
        const Vec3 p = sim::to_double(m.positions[m.indices[t + k]]), n = sim::to_double(m.normals[m.indices[t + k]]);
        const double rho = std::hypot(p.x, p.y), psi = std::atan2(p.y, p.x);
        worst = std::max(worst, std::abs(std::hypot(rho - cr, p.z - cz) - std::abs(R)));
        const double sgn = R > 0 ? 1.0 : -1.0, nr = sgn * (cr - rho) / std::abs(R), nz = sgn * (cz - p.z) / std::abs(R);
        worst_normal = std::max(worst_normal, angle(n, Vec3{nr * std::cos(psi), nr * std::sin(psi), nz}));
      }
    }
    std::printf("R %g mm: vertices within %g m of their arcs, normals within %g rad\n", R * 1e3, worst, worst_normal);
    EXPECT_LT(worst, 1e-8) << R;
    EXPECT_LT(worst_normal, 2e-6) << R;
  }
  // A radius below half a facet's chord: the radius's line (here the
  // facets table's, line 16; DesignFacets.RadiusTooSmallNamesItsOwnLine).
  Result<sim::SceneDesc> s = scene_of(faceted_dish("{ theta = 2, kind = \"curved\", radius_theta = 5 }"));
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().where.line, 16) << to_string(s.error());
  EXPECT_NE(s.error().message.find("smaller than half of facet 1's chord"), std::string::npos) << to_string(s.error());
}

// A radius too small for its facets is an error at the radius's own line,
// as every other facet error names the entry that is wrong: not the
// reflector's (line 8) nor the facets table's (line 16, a table of its own
// here), whether the radius comes first or last in the table.
TEST(DesignFacets, RadiusTooSmallNamesItsOwnLine) {
  for (const auto& [table, line, says] : std::vector<std::tuple<std::string, int, std::string>>{
           {"theta = 2\nkind = \"curved\"\nradius_theta = 5\n", 19, "radius_theta 5 mm is smaller than half of facet 1's chord"},
           {"radius_theta = 5\ntheta = 2\nkind = \"curved\"\n", 17, "radius_theta 5 mm is smaller than half of facet 1's chord"},
           {"azimuth = 8\nkind = \"curved\"\nradius_theta = 1e6\ntheta = 4\nradius_azimuth = -5\n", 21,
            "radius_azimuth -5 mm is smaller than half of the widest sector's chord"}}) {
    Result<sim::SceneDesc> s = scene_of(faceted_dish("") + "[reflectors.facets]\n" + table);
    ASSERT_FALSE(s.ok()) << table;
    const std::string shown = to_string(s.error());
    EXPECT_EQ(s.error().where.line, line) << shown;
    // The printed "FILE:LINE: message" reads the same line.
    const std::size_t colon = shown.find(".design.toml:");
    EXPECT_NE(colon, std::string::npos) << shown;
    if (colon != std::string::npos) {
      EXPECT_EQ(std::atoi(shown.c_str() + colon + std::string(".design.toml:").size()), line) << shown;
    }
    EXPECT_NE(shown.find("facets (line " + std::to_string(line) + "): " + says), std::string::npos) << shown;
    EXPECT_NE(shown.find("[[reflectors]] at line 8 (dish)"), std::string::npos) << shown;
    // The glTF and STEP exports name the same line, and write nothing.
    test::TempDir dir;
    Result<Design> d = parse_design(faceted_dish("") + "[reflectors.facets]\n" + table,
                                    (dir / "lamp.design.toml").string());
    ASSERT_TRUE(d.ok()) << to_string(d.error());
    Status gltf = write_design_gltf(*d, (dir / "lamp.gltf").string(), options(2.0).tessellation);
    ASSERT_FALSE(gltf.ok()) << table;
    EXPECT_EQ(gltf.error().where.line, line) << to_string(gltf.error());
    EXPECT_NE(gltf.error().message.find(says), std::string::npos) << to_string(gltf.error());
    EXPECT_FALSE(std::filesystem::exists(dir / "lamp.gltf"));
    Result<StepExportInfo> step = write_design_step(*d, (dir / "lamp.step").string());
    ASSERT_FALSE(step.ok()) << table;
    EXPECT_EQ(step.error().where.line, line) << to_string(step.error());
    EXPECT_NE(step.error().message.find(says), std::string::npos) << to_string(step.error());
    EXPECT_FALSE(std::filesystem::exists(dir / "lamp.step"));
  }
}

// A radius → ∞ is the flat facet: the same vertices and normals, one way or both.
TEST(DesignFacets, CurvedFacetsOfHugeRadiusAreTheFlatOnes) {
  for (const std::string counts : {"theta = 6", "azimuth = 12", "theta = 6, azimuth = 12"}) {
    std::string radii;
    if (counts.find("theta") != std::string::npos) radii += ", radius_theta = 1e9";
    if (counts.find("azimuth") != std::string::npos) radii += ", radius_azimuth = -1e9";
    Result<sim::SceneDesc> flat = scene_of(faceted_dish("{ " + counts + " }"));
    Result<sim::SceneDesc> curved = scene_of(faceted_dish("{ " + counts + ", kind = \"curved\"" + radii + " }"));
    ASSERT_TRUE(flat.ok() && curved.ok()) << counts;
    const sim::Mesh &a = flat->meshes[0], &b = curved->meshes[0];
    ASSERT_EQ(a.positions.size(), b.positions.size()) << counts;
    ASSERT_EQ(a.indices, b.indices) << counts;
    double worst = 0.0, worst_normal = 0.0;
    for (std::size_t v = 0; v < a.positions.size(); ++v) {
      worst = std::max(worst, length(sim::to_double(a.positions[v]) - sim::to_double(b.positions[v])));
      worst_normal = std::max(worst_normal, angle(sim::to_double(a.normals[v]), sim::to_double(b.normals[v])));
    }
    EXPECT_LT(worst, 1e-9) << counts;
    EXPECT_LT(worst_normal, 1e-5) << counts;
  }
}

// A flat mirror disc 20 mm below the source (ρ 2 … 40 mm), faceted along ρ
// into 4 rings curved with radius R: each ring's arc has its centre above
// its middle (R > 0), so at ρ the normal leans toward the ring's middle by
// asin((ρ − ρ_mid)/R), and each reflected ray leaves as the mirror image
// about that normal: the ring spreads a beam by ±2·asin(c/2R) (c = 9.5 mm).
// Traced, the normal each reflected ray implies, (out − in)/|out − in|, is
// the closed form's.
std::string curved_disc(const std::string& facets) {
  return std::string(R"(length_unit = "mm"
[materials.mirror]
mirror = 1.0
[[emitters]]
name = "LED"
position = [0, 0, 0]
flux_lm = 1000
[[reflectors]]
name = "disc"
material = "mirror"
profile = "conic"
radius = 0
vertex = -20
aperture = [2, 40]
)") + "facets = " + facets + "\n";
}

TEST(DesignFacets, CurvedRingsSpreadTheBeamAsTheirCurvatureSays) {
  for (const double R : {0.100, -0.100}) {
    Result<sim::SceneDesc> s = scene_of(curved_disc("{ theta = 4, kind = \"curved\", radius_theta = " +
                                                    std::to_string(R * 1e3) + " }"), 1.0);
    ASSERT_TRUE(s.ok()) << to_string(s.error());
    std::vector<double> off;
    double tilt_max = 0.0;
    for (const sim::EscapedRay& r : escapes(std::move(*s), 40'000)) {
      if (length(r.origin) < 1e-9) continue;
      const Vec3 p = r.origin, in = normalize(p), implied = normalize(r.direction - in);
      const double rho = std::hypot(p.x, p.y), psi = std::atan2(p.y, p.x);
      const int i = std::clamp(static_cast<int>((rho - 0.002) / 0.0095), 0, 3);
      const double mid = 0.002 + 0.0095 * (i + 0.5), half = 0.00475;
      const double zc = -0.020 + (R > 0 ? 1.0 : -1.0) * std::sqrt(R * R - half * half);
      const double sgn = R > 0 ? 1.0 : -1.0, nr = sgn * (mid - rho) / std::abs(R), nz = sgn * (zc - p.z) / std::abs(R);
      off.push_back(angle(implied, Vec3{nr * std::cos(psi), nr * std::sin(psi), nz}) * 180 / kPi);
      tilt_max = std::max(tilt_max, angle(implied, Vec3{0, 0, 1}) * 180 / kPi);
    }
    ASSERT_GT(off.size(), 10'000u);
    std::sort(off.begin(), off.end());
    const double closed = std::asin(0.00475 / std::abs(R)) * 180 / kPi;
    std::printf("R %g mm: implied normals off the closed form's by %g deg (median), %g deg (99 %%); largest tilt %g deg, closed form %g\n",
                R * 1e3, off[off.size() / 2], off[off.size() * 99 / 100], tilt_max, closed);
    EXPECT_LT(off[off.size() * 99 / 100], 0.01) << R;
    EXPECT_NEAR(tilt_max, closed, 0.02 * closed) << R;
  }
}

// Curved around (8 sectors, R = 100 mm) on the same disc: at (X, x) in a
// sector's frame (X along its mid-plane, x across, a = X·tan(π/8) the half
// chord) the surface is z = −20 mm − √(R² − x²) + √(R² − a²) and its normal
// ∝ (X·tan²(π/8)/√(R² − a²), −x/√(R² − x²), 1).
TEST(DesignFacets, CurvedSectorsLieOnTheirClosedForm) {
  const double R = 0.100, h = kPi / 8;
  Result<sim::SceneDesc> s = scene_of(curved_disc("{ azimuth = 8, kind = \"curved\", radius_azimuth = 100 }"));
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  const sim::Mesh& m = s->meshes[0];
  double worst = 0.0, worst_normal = 0.0, sag_max = 0.0;
  for (std::size_t t = 0; t < m.indices.size(); t += 3) {
    Vec3 centroid{0, 0, 0};
    for (int k = 0; k < 3; ++k) centroid += sim::to_double(m.positions[m.indices[t + k]]) * (1.0 / 3);
    double psi = std::atan2(centroid.y, centroid.x);
    if (psi < 0) psi += 2 * kPi;
    const double mid = (std::floor(psi / (2 * h)) + 0.5) * 2 * h;
    const Vec3 out{std::cos(mid), std::sin(mid), 0}, across{-std::sin(mid), std::cos(mid), 0};
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = sim::to_double(m.positions[m.indices[t + k]]), n = sim::to_double(m.normals[m.indices[t + k]]);
      const double X = dot(p, out), x = dot(p, across), a = X * std::tan(h);
      const double z = -0.020 - std::sqrt(R * R - x * x) + std::sqrt(R * R - a * a);
      worst = std::max(worst, std::abs(p.z - z));
      sag_max = std::max(sag_max, -0.020 - p.z);
      const Vec3 exact = normalize(
          out * (X * std::tan(h) * std::tan(h) / std::sqrt(R * R - a * a)) - across * (x / std::sqrt(R * R - x * x)) +
          Vec3{0, 0, 1});
      worst_normal = std::max(worst_normal, angle(n, exact));
    }
  }
  std::printf("sectors: within %g m, normals within %g rad, deepest %g mm\n", worst, worst_normal, sag_max * 1e3);
  EXPECT_LT(worst, 1e-8);
  EXPECT_LT(worst_normal, 2e-6);
  // The deepest vertex: near the widest chord's sagitta, R − √(R² − (40 mm·sin(π/8))²).
  const double a = 0.040 * std::sin(h);
  EXPECT_LE(sag_max, R - std::sqrt(R * R - a * a) + 1e-8);  // the sub-columns' vertices, at most there
  EXPECT_GT(sag_max, 0.95 * (R - std::sqrt(R * R - a * a)));
}

// Fixed parts -----------------------------------------------------------------

// A glTF part (Y up, metres, no light): a triangle named "board".
void write_board_gltf(const std::filesystem::path& path) {
  io::GltfWriter w;
  sim::Mesh m;
  m.positions = {{0.01f, 0.02f, 0.03f}, {0.02f, 0.02f, 0.03f}, {0.01f, 0.02f, 0.04f}};
  m.normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  m.indices = {0, 2, 1};
  const int material = w.material({{"name", "green"}});
  w.node({{"name", "board"}, {"mesh", w.mesh(m, material, "board")}});
  std::string bin;
  const std::string text = w.finish("housing.bin", bin);
  ASSERT_TRUE(io::write_file_atomic((path.parent_path() / "housing.bin").string(), bin).ok());
  ASSERT_TRUE(io::write_file_atomic(path.string(), text).ok());
}

const char* kHousing = R"(length_unit = "mm"

[materials.black]
reflectance = 0.05

[materials.mirror]
mirror = 0.9

[[emitters]]
name = "LED"
position = [0, 0, 0]
flux_lm = 1000

[[parts]]
name = "housing"
file = "housing.gltf"
position = [5, 6, 7]
rotate_deg = [0, 0, 90]
material = "black"
)";

Result<sim::SceneDesc> load_in(const test::TempDir& dir, const std::string& text) {
  const std::string path = (dir / "lamp.design.toml").string();
  EXPECT_TRUE(io::write_file_atomic(path, text).ok());
  std::vector<Finding> findings;
  return load_design(path, options(2.0), &findings);
}

// glTF (x, y, z) is the design's (x, −z, y) (Y up to Z up); turned 90° about
// Z, (x, y) → (−y, x); then moved by `position`.
TEST(DesignFixedPart, GltfPartLandsWherePositionAndRotationSay) {
  test::TempDir dir;
  write_board_gltf(dir / "housing.gltf");
  Result<sim::SceneDesc> s = load_in(dir, kHousing);
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  ASSERT_EQ(s->meshes.size(), 1u);
  const sim::Mesh& m = s->meshes[0];
  EXPECT_EQ(m.name.rfind("housing/", 0), 0u) << m.name;
  EXPECT_EQ(s->materials[m.material].name, "black");
  const std::vector<Vec3> expected = {{0.035, 0.016, 0.027}, {0.035, 0.026, 0.027}, {0.045, 0.016, 0.027}};
  ASSERT_EQ(m.positions.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {  // each where it should be (in any order)
    double nearest = 1.0;
    for (const sim::Vec3f& p : m.positions) nearest = std::min(nearest, length(sim::to_double(p) - expected[i]));
    EXPECT_LT(nearest, 1e-8) << i;
    EXPECT_LT(angle(sim::to_double(m.normals[i]), Vec3{0, 0, 1}), 1e-6) << i;
  }
  // Scaled by 2 about the file's origin, then turned and moved.
  s = load_in(dir, edited(kHousing, "material = \"black\"", "material = \"black\"\nscale = 2"));
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  double nearest = 1.0;
  for (const sim::Vec3f& p : s->meshes[0].positions)
    nearest = std::min(nearest, length(sim::to_double(p) - Vec3{0.065, 0.026, 0.047}));
  EXPECT_LT(nearest, 1e-8);
  // A sidecar rule in [[parts]] chooses among the file's meshes before the part's own material.
  s = load_in(dir, std::string(kHousing) + "\n[[parts]]\nmatch = \"housing/*board*\"\nmaterial = \"mirror\"\n");
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  EXPECT_EQ(s->materials[s->meshes[0].material].name, "mirror");
}

// rotate_deg = [a, b, c] is documented as "about X, then Y, then Z (the
// design's axes)": R = Rz(c)·Ry(b)·Rx(a), built here from the matrices'
// entries, independently of sim::rotation. All three angles non-zero, so
// that any other order (Rx·Ry·Rz, the angles swapped, the turns about the
// part's own axes) lands the triangle elsewhere; scaled about the file's
// origin first and moved by position last.
TEST(DesignFixedPart, ThreeAnglesTurnAboutXThenYThenZ) {
  test::TempDir dir;
  write_board_gltf(dir / "housing.gltf");
  const test::Matrix3 r = test::rotation_xyz_deg(20, 30, 45);
  Result<sim::SceneDesc> s = load_in(
      dir, edited(edited(kHousing, "rotate_deg = [0, 0, 90]", "rotate_deg = [20, 30, 45]"), "material = \"black\"",
                  "material = \"black\"\nscale = 2"));
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  ASSERT_EQ(s->meshes.size(), 1u);
  const sim::Mesh& m = s->meshes[0];
  ASSERT_EQ(m.positions.size(), 3u);
  // The board's corners and normal in the design's frame (glTF (x, y, z) is (x, −z, y)).
  const std::vector<Vec3> board = {{0.01, -0.03, 0.02}, {0.02, -0.03, 0.02}, {0.01, -0.04, 0.02}};
  const Vec3 normal = test::apply(r, Vec3{0, 0, 1});
  for (std::size_t i = 0; i < 3; ++i) {
    const Vec3 expected = test::apply(r, 2.0 * board[i]) + Vec3{0.005, 0.006, 0.007};
    double nearest = 1.0;  // in any order
    for (const sim::Vec3f& p : m.positions) nearest = std::min(nearest, length(sim::to_double(p) - expected));
    EXPECT_LT(nearest, 1e-8) << i;
    EXPECT_LT(angle(sim::to_double(m.normals[i]), normal), 1e-6) << i;
  }
  // The same through the transform itself, on the axes' unit vectors.
  FixedPart part;
  part.rotate_deg = {20, 30, 45};
  const sim::Affine t = fixed_part_transform(part);
  for (const Vec3& e : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}})
    EXPECT_LT(length(t.point(e) - test::apply(r, e)), 1e-12);
}

TEST(DesignFixedPart, MistakesAreErrorsNamingTheLine) {
  test::TempDir dir;
  write_board_gltf(dir / "housing.gltf");
  struct Case {
    std::string from, to;
    int line;
    std::string says;
  };
  // [[parts]] at line 14: name 15, file 16, position 17, rotate_deg 18, material 19.
  const std::vector<Case> cases = {
      {"housing.gltf", "missing.gltf", 16, "missing.gltf"},
      {"housing.gltf", "housing.obj", 16, "is not a model Gonio reads as a part"},
      {"housing.gltf", "../housing.gltf", 16, "../housing.gltf"},
      {"rotate_deg = [0, 0, 90]", "rotate_deg = [0, 90]", 18, "'rotate_deg' must be an array of three finite numbers"},
      {"material = \"black\"", "material = \"black\"\nscale = 0", 20, "'scale' must be a number > 0"},
      {"material = \"black\"", "material = \"chrome\"", 14, "material 'chrome' is not defined"},
      {"material = \"black\"", "colour = \"black\"", 19, "unknown key 'colour'"},
      {"name = \"housing\"\nfile", "name = \"LED\"\nfile", 14, ""},  // not taken: emitters are no parts
  };
  for (const Case& c : cases) {
    Result<sim::SceneDesc> s = load_in(dir, edited(kHousing, c.from, c.to));
    if (c.says.empty()) {
      EXPECT_TRUE(s.ok()) << c.to << ": " << to_string(s.error());
      continue;
    }
    ASSERT_FALSE(s.ok()) << c.to;
    EXPECT_EQ(s.error().where.file, (dir / "lamp.design.toml").string()) << c.to;
    EXPECT_EQ(s.error().where.line, c.line) << c.to << ": " << to_string(s.error());
    EXPECT_NE(s.error().message.find(c.says), std::string::npos) << c.to << ": " << to_string(s.error());
  }
  // gonio watch watches the part's file.
  const std::vector<std::string> files = design_files((dir / "lamp.design.toml").string());
  EXPECT_NE(std::find(files.begin(), files.end(), (dir / "housing.gltf").string()), files.end());
  // Surfaces no rule covers: the sidecar's error.
  Result<sim::SceneDesc> s = load_in(dir, edited(kHousing, "material = \"black\"\n", ""));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(to_string(s.error()).find("housing/"), std::string::npos) << to_string(s.error());
}

// A STEP part through the CAD reader: the paraboloid z = f − ρ²/4f (f = 10
// mm, ρ 4 … 30 mm) written as STEP by the design's own export, placed upside
// down (180° about X) 50 mm up: every vertex, taken back to the file's
// axes, lies on the paraboloid within the STEP's tolerance and the chordal
// deflection's float rounding.
TEST(DesignFixedPart, StepPartLandsWherePositionAndRotationSay) {
  if (!io::cad_supported()) GONIO_MISSING("a build with OpenCASCADE (GONIO_OCCT) for STEP parts");
  test::TempDir dir;
  const std::string dish = R"(length_unit = "mm"
[materials.mirror]
mirror = 1.0
[[emitters]]
name = "LED"
position = [0, 0, 0]
flux_lm = 1000
[[reflectors]]
name = "dish"
material = "mirror"
profile = "conic"
radius = 20
conic = -1
vertex = 10
aperture = [4, 30]
)";
  Result<Design> d = parse_design(dish, (dir / "dish.design.toml").string());
  ASSERT_TRUE(d.ok());
  Result<StepExportInfo> info = write_design_step(*d, (dir / "dish.step").string());
  ASSERT_TRUE(info.ok()) << to_string(info.error());
  const std::string text = edited(edited(kHousing, "housing.gltf", "dish.step"), "rotate_deg = [0, 0, 90]",
                                  "rotate_deg = [180, 0, 0]");
  Result<sim::SceneDesc> s = load_in(dir, edited(text, "position = [5, 6, 7]", "position = [0, 0, 50]"));
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  ASSERT_EQ(s->meshes.size(), 1u);
  EXPECT_EQ(s->meshes[0].name.rfind("housing/", 0), 0u) << s->meshes[0].name;
  double worst = 0.0;
  for (const sim::Vec3f& v : s->meshes[0].positions) {
    // Back: p = R·q + (0, 0, 50 mm), R = 180° about X: q = (x, −y, −(z − 50 mm)).
    const Vec3 p = sim::to_double(v);
    const Vec3 q{p.x, -p.y, -(p.z - 0.050)};
    const double rho = std::hypot(q.x, q.y);
    worst = std::max(worst, std::abs(q.z - (0.010 - rho * rho / 0.040)) / std::sqrt(1 + std::pow(rho / 0.020, 2)));
  }
  EXPECT_LT(worst, 3e-6);
}

// Fixed parts as STEP: a STEP part's own shapes placed by the helper (the
// paraboloid of the test above, turned 180° about X, scaled by 2, 50 mm
// up): read back, a part "housing/…" whose every vertex, taken back to the
// file's axes (q = R⁻¹(p − t)/2), lies on the paraboloid within 3 µm; a
// glTF part's triangle, placed as the simulation places it (the test of
// GltfPartLandsWherePositionAndRotationSay), a part "housing/board" with
// its corners there to 1 µm; the sidecar gives both the part's material.
TEST(DesignPartsExport, FixedPartsStepReadBackWherePlaced) {
  if (!io::cad_supported()) GONIO_MISSING("a build with OpenCASCADE (GONIO_OCCT) for STEP export");
  test::TempDir dir;
  Result<Design> d = parse_design(faceted_dish("").append(""), (dir / "dish.design.toml").string());
  ASSERT_TRUE(d.ok());
  ASSERT_TRUE(write_design_step(*d, (dir / "dish.step").string()).ok());
  const std::string step_part = edited(
      edited(edited(kHousing, "housing.gltf", "dish.step"), "rotate_deg = [0, 0, 90]", "rotate_deg = [180, 0, 0]\nscale = 2"),
      "position = [5, 6, 7]", "position = [0, 0, 50]");
  write_board_gltf(dir / "housing.gltf");
  for (const bool gltf : {false, true}) {
    const std::string stem = gltf ? "board" : "placed";
    d = parse_design(gltf ? std::string(kHousing) : step_part, (dir / (stem + ".design.toml")).string());
    ASSERT_TRUE(d.ok()) << to_string(d.error());
    Result<StepExportInfo> info = write_design_step(*d, (dir / (stem + ".step")).string());
    ASSERT_TRUE(info.ok()) << to_string(info.error());
    Result<io::CadModel> model = io::tessellate_cad((dir / (stem + ".step")).string(), options(1.0));
    ASSERT_TRUE(model.ok()) << to_string(model.error());
    ASSERT_EQ(model->placements.size(), 1u) << stem;
    const io::CadPlacement& pl = model->placements[0];
    EXPECT_NE(pl.path.find(gltf ? "housing/board" : "housing/dish"), std::string::npos) << pl.path;
    std::vector<Vec3> points;
    for (const io::CadSurface& surface : model->parts[pl.part].surfaces)
      for (const sim::Vec3f& v : surface.positions) points.push_back(pl.to_world.point(sim::to_double(v)));
    ASSERT_GE(points.size(), 3u);
    if (gltf) {
      const std::vector<Vec3> expected = {{0.035, 0.016, 0.027}, {0.035, 0.026, 0.027}, {0.045, 0.016, 0.027}};
      for (const Vec3& p : points) {
        double nearest = 1.0;
        for (const Vec3& e : expected) nearest = std::min(nearest, length(p - e));
        EXPECT_LT(nearest, 1e-6);
      }
      for (const Vec3& e : expected) {
        double nearest = 1.0;
        for (const Vec3& p : points) nearest = std::min(nearest, length(p - e));
        EXPECT_LT(nearest, 1e-6);
      }
    } else {
      double worst = 0.0, rho_max = 0.0;
      for (const Vec3& p : points) {
        const Vec3 q{p.x / 2, -p.y / 2, -(p.z - 0.050) / 2};
        const double rho = std::hypot(q.x, q.y);
        rho_max = std::max(rho_max, rho);
        worst = std::max(worst, std::abs(q.z - (0.010 - rho * rho / 0.040)) / std::sqrt(1 + std::pow(rho / 0.020, 2)));
      }
      std::printf("the placed STEP part: %zu vertices within %g m of the paraboloid (file's axes)\n", points.size(), worst);
      EXPECT_LT(worst, 3e-6);
      EXPECT_NEAR(rho_max, 0.030, 2e-6);  // scaled back: the rim where it was
    }
    Result<std::string> sidecar = io::read_file(info->sidecar, 1 << 20);
    ASSERT_TRUE(sidecar.ok());
    EXPECT_NE(sidecar->find("match = \"housing/*\""), std::string::npos) << *sidecar;
  }
}

// Placed lenses ---------------------------------------------------------------

// A plano-convex PMMA lens 5 mm below the source (flat inner face, outer
// sphere R = 15 mm, 4 mm thick, ρ to 8 mm), and the same design with the
// source and the lens both moved by Δ = (7, −3, 12) mm, or both turned
// upside down (the lens above the source, light going up).
std::string placed_lens(const std::string& emitter, const std::string& place) {
  return R"(length_unit = "mm"
[materials.pmma]
dielectric = 1.0
ior = 1.491
[[emitters]]
name = "LED"
)" + emitter + R"(
flux_lm = 1000
[[lenses]]
name = "lens"
material = "pmma"
vertex = -5
thickness = 4
aperture = 8
inner = { profile = "conic", radius = 0 }
outer = { profile = "conic", radius = 15 }
)" + place;
}

// The escaped light's directions, as sorted angles from `axis` [deg].
std::vector<double> escaped_angles(sim::SceneDesc scene, const Vec3& axis) {
  std::vector<double> a;
  for (const sim::EscapedRay& r : escapes(std::move(scene), 40'000)) a.push_back(angle(r.direction, axis) * 180 / kPi);
  std::sort(a.begin(), a.end());
  return a;
}

// Light's direction does not see a translation: the moved source and lens
// give the same distribution; turned upside down (rotate_deg = [180, 0, 0]
// and the source's nadir up), the same about +Z. Photon for photon where the
// tracer's random numbers follow the same paths: the percentiles agree to
// 10⁻³ degrees, while the unmoved lens with the moved source differs by
// degrees.
TEST(DesignLens, AMovedLensGivesTheMovedDistribution) {
  Result<sim::SceneDesc> here = scene_of(placed_lens("position = [0, 0, 0]", ""), 1.0);
  Result<sim::SceneDesc> moved = scene_of(placed_lens("position = [7, -3, 12]", "position = [7, -3, 12]\n"), 1.0);
  Result<sim::SceneDesc> up =
      scene_of(placed_lens("position = [0, 0, 0]\nnadir = [0, 0, 1]", "rotate_deg = [180, 0, 0]\n"), 1.0);
  Result<sim::SceneDesc> wrong = scene_of(placed_lens("position = [7, -3, 12]", ""), 1.0);
  ASSERT_TRUE(here.ok() && moved.ok() && up.ok() && wrong.ok())
      << (up.ok() ? std::string() : to_string(up.error())) << (moved.ok() ? std::string() : to_string(moved.error()));
  const std::vector<double> a = escaped_angles(std::move(*here), Vec3{0, 0, -1});
  const std::vector<double> b = escaped_angles(std::move(*moved), Vec3{0, 0, -1});
  const std::vector<double> c = escaped_angles(std::move(*up), Vec3{0, 0, 1});
  const std::vector<double> w = escaped_angles(std::move(*wrong), Vec3{0, 0, -1});
  ASSERT_FALSE(a.empty());
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), c.size());
  double worst_moved = 0.0, worst_up = 0.0, worst_wrong = 0.0;
  for (int q = 5; q <= 95; q += 5) {
    const std::size_t i = a.size() * static_cast<std::size_t>(q) / 100;
    worst_moved = std::max(worst_moved, std::abs(a[i] - b[i]));
    worst_up = std::max(worst_up, std::abs(a[i] - c[i]));
    worst_wrong = std::max(worst_wrong, std::abs(a[i] - w[std::min(i, w.size() - 1)]));
  }
  std::printf("percentiles 5…95 of the escaped angle: moved %g deg, upside down %g deg, source moved alone %g deg\n",
              worst_moved, worst_up, worst_wrong);
  EXPECT_LT(worst_moved, 1e-3);
  EXPECT_LT(worst_up, 1e-3);
  EXPECT_GT(worst_wrong, 1.0);
}

// A placed lens as STEP: the helper turns and moves the solid; read back, its
// vertices are the axial lens's STEP vertices turned and moved (each within
// 2 µm of the placed set's nearest).
TEST(DesignPartsExport, APlacedLensStepIsTheAxialOnePlaced) {
  if (!io::cad_supported()) GONIO_MISSING("a build with OpenCASCADE (GONIO_OCCT) for STEP export");
  test::TempDir dir;
  std::vector<Vec3> sets[2];
  for (int k = 0; k < 2; ++k) {
    Result<Design> d = parse_design(placed_lens("position = [0, 0, 0]", k ? "position = [0, 0, 40]\nrotate_deg = [180, 0, 0]\n" : ""),
                                    (dir / ("lens" + std::to_string(k) + ".design.toml")).string());
    ASSERT_TRUE(d.ok()) << to_string(d.error());
    const std::string step = (dir / ("lens" + std::to_string(k) + ".step")).string();
    Result<StepExportInfo> info = write_design_step(*d, step);
    ASSERT_TRUE(info.ok()) << to_string(info.error());
    Result<io::CadModel> model = io::tessellate_cad(step, options(2.0));
    ASSERT_TRUE(model.ok()) << to_string(model.error());
    ASSERT_EQ(model->placements.size(), 1u);
    const io::CadPlacement& pl = model->placements[0];
    for (const io::CadSurface& surface : model->parts[pl.part].surfaces)
      for (const sim::Vec3f& v : surface.positions) sets[k].push_back(pl.to_world.point(sim::to_double(v)));
  }
  ASSERT_FALSE(sets[0].empty());
  double worst = 0.0, z_min = 1.0;
  for (const Vec3& p : sets[1]) {
    const Vec3 back{p.x, -p.y, 0.040 - p.z};  // 180° about X, then 40 mm up: undone
    z_min = std::min(z_min, p.z);
    double nearest = 1.0;
    for (const Vec3& q : sets[0]) nearest = std::min(nearest, length(q - back));
    worst = std::max(worst, nearest);
  }
  EXPECT_LT(worst, 2e-6);
  EXPECT_NEAR(z_min, 0.045, 2e-6);  // the flat face, 5 mm below the axial source, now 45 mm up
}

// Export ----------------------------------------------------------------------

// The design's glTF holds its troughs, caps and covers as the simulation
// meshes them: read back by Gonio's glTF loader (Y up turned back to Z
// up), the same names, areas and materials.
TEST(DesignPartsExport, GltfHoldsTroughsAndCoversAsMeshed) {
  test::TempDir dir;
  const std::string text = edited(kTrough, "length = 400",
                                  "length = 400\ncaps = \"white\"\n[materials.white]\nreflectance = 0.8\n"
                                  "[materials.clear]\ndielectric = 1.0\nior = 1.5\n"
                                  "[[covers]]\nname = \"cover\"\nmaterial = \"clear\"\nshape = \"plate\"\n"
                                  "size = [100, 420]\nheight = -40\nthickness = 3\n");
  Result<Design> d = parse_design(text, (dir / "lamp.design.toml").string());
  ASSERT_TRUE(d.ok());
  Result<sim::SceneDesc> traced = design_scene(*d, options(2.0), nullptr);
  ASSERT_TRUE(traced.ok()) << to_string(traced.error());
  ASSERT_TRUE(write_design_gltf(*d, (dir / "lamp.gltf").string(), options(2.0).tessellation).ok());
  io::GltfLoadOptions o;
  o.require_emitters = false;
  Result<sim::SceneDesc> back = io::load_gltf((dir / "lamp.gltf").string(), nullptr, o);
  ASSERT_TRUE(back.ok()) << to_string(back.error());
  ASSERT_EQ(back->meshes.size(), traced->meshes.size());
  for (const sim::Mesh& t : traced->meshes) {
    const auto b = std::find_if(back->meshes.begin(), back->meshes.end(),
                                [&](const sim::Mesh& m) { return m.name.find(t.name) != std::string::npos; });
    ASSERT_NE(b, back->meshes.end()) << t.name;
    EXPECT_EQ(b->indices.size(), t.indices.size()) << t.name;
    EXPECT_NEAR(area(*b) / area(t), 1.0, 1e-6) << t.name;
    EXPECT_EQ(back->materials[b->material].name, traced->materials[t.material].name) << t.name;
    // Y up: the cover's upper face at the design's z = −40 mm is the glTF's y = −40 mm.
    if (t.name == "cover") {
      float top = -1.0f;
      for (const sim::Vec3f& p : b->positions) top = std::max(top, p.y);
      EXPECT_NEAR(top, -0.040f, 1e-7f);
    }
  }
}

// A lens beside another kind of part (here a cover): the glTF holds the lens
// once, as the simulation does (the other kinds' meshes come from the
// design's scene, which holds the lens too: it was written a second time,
// two overlapping lenses for whatever reads the glTF).
TEST(DesignPartsExport, GltfHoldsALensOnceBesideOtherParts) {
  test::TempDir dir;
  const std::string text = placed_lens("position = [0, 0, 0]", "") +
                           "[materials.white]\nreflectance = 0.8\n"
                           "[[covers]]\nname = \"plate\"\nmaterial = \"white\"\nshape = \"plate\"\n"
                           "diameter = 80\nheight = -30\n";
  Result<Design> d = parse_design(text, (dir / "lamp.design.toml").string());
  ASSERT_TRUE(d.ok()) << to_string(d.error());
  Result<sim::SceneDesc> traced = design_scene(*d, options(2.0), nullptr);
  ASSERT_TRUE(traced.ok()) << to_string(traced.error());
  ASSERT_TRUE(write_design_gltf(*d, (dir / "lamp.gltf").string(), options(2.0).tessellation).ok());
  io::GltfLoadOptions o;
  o.require_emitters = false;
  Result<sim::SceneDesc> back = io::load_gltf((dir / "lamp.gltf").string(), nullptr, o);
  ASSERT_TRUE(back.ok()) << to_string(back.error());
  const sim::SceneDesc flat = sim::flattened(*back);
  std::size_t lenses = 0;
  for (const sim::Mesh& m : flat.meshes) lenses += m.name.find("lens") != std::string::npos ? 1 : 0;
  EXPECT_EQ(lenses, 1u);
  EXPECT_EQ(flat.meshes.size(), sim::flattened(*traced).meshes.size());
}

// The design's own sidecar rules ([[parts]] without `file`) come before its
// parts' rules in the simulation (the first rule that matches wins), so a
// rule may give a reflector another material. The STEP's sidecar keeps
// them, in that order, with or without fixed parts: the STEP traces as the
// design does (they were dropped without a fixed part, and put after the
// parts' rules with one).
TEST(DesignPartsExport, StepSidecarKeepsTheDesignsRulesFirst) {
  if (!io::cad_supported()) GONIO_MISSING("a build with OpenCASCADE (GONIO_OCCT) for STEP export");
  test::TempDir dir;
  const std::string text = faceted_dish("") +
                           "[materials.black]\nreflectance = 0.05\n[[parts]]\nmatch = \"dish*\"\nmaterial = \"black\"\n";
  Result<sim::SceneDesc> traced = scene_of(text);
  ASSERT_TRUE(traced.ok()) << to_string(traced.error());
  ASSERT_EQ(traced->meshes.size(), 1u);
  EXPECT_EQ(traced->materials[traced->meshes[0].material].name, "black");  // the design's rule wins
  Result<Design> d = parse_design(text, (dir / "lamp.design.toml").string());
  ASSERT_TRUE(d.ok()) << to_string(d.error());
  Result<StepExportInfo> info = write_design_step(*d, (dir / "lamp.step").string());
  ASSERT_TRUE(info.ok()) << to_string(info.error());
  Result<io::PartsFile> sidecar = io::read_parts_file(info->sidecar);
  ASSERT_TRUE(sidecar.ok()) << to_string(sidecar.error());
  const auto first = std::find_if(sidecar->rules.begin(), sidecar->rules.end(),
                                  [](const io::PartsRule& r) { return io::glob_match(r.match, "dish"); });
  ASSERT_NE(first, sidecar->rules.end());
  EXPECT_EQ(first->material, "black") << "the STEP's sidecar gives the dish another material than the design";
}

// Facets the STEP export cannot write in reasonable time and memory (each a
// face OpenCASCADE sews; --theta and --azimuth allow 100 000 each, 10¹⁰
// faces): more than the faces a part may have (the fixed parts' bound) is an
// error naming the reflector's line before anything is built or sent to the
// helper, flat or curved. Within the bound, the part is made.
TEST(DesignPartsExport, TooManyFacetsForTheStepAreAnErrorNamingTheLine) {
  for (const std::string& facets : {std::string("{ theta = 150, azimuth = 150, kind = \"flat\" }"),
                                   std::string("{ theta = 150, azimuth = 150, kind = \"curved\", radius_theta = 500 }"),
                                   std::string("{ theta = 6000 }")}) {
    Result<Design> d = parse_design(faceted_dish(facets), "lamp.design.toml");
    ASSERT_TRUE(d.ok()) << to_string(d.error());
    Result<DesignParts> parts = read_design_parts(resolved_document(*d), d->path);
    ASSERT_TRUE(parts.ok()) << to_string(parts.error());
    const Reflector& r = parts->reflectors.at(0);
    Result<ProfileCurve> curve = ProfileCurve::make(r.profile);
    ASSERT_TRUE(curve.ok());
    Result<io::StepRevolvedPart> part = faceted_step_part(r, *curve);
    ASSERT_FALSE(part.ok()) << facets << ": " << part->faces.size() << " faces, " << part->patches.size() / 2
                            << " patches";
    EXPECT_NE(part.error().message.find("more than the " + std::to_string(kMaxStepPartFaces)), std::string::npos)
        << part.error().message;
    if (io::cad_supported()) {
      const Result<StepExportInfo> info = write_design_step(*d, "never-written.step");
      ASSERT_FALSE(info.ok());
      EXPECT_NE(to_string(info.error()).find("lamp.design.toml:8: [[reflectors]] at line 8 (dish): "), std::string::npos)
          << to_string(info.error());
    }
  }
  Result<Design> d = parse_design(faceted_dish("{ theta = 100, azimuth = 200, kind = \"flat\" }"), "lamp.design.toml");
  ASSERT_TRUE(d.ok());
  Result<DesignParts> parts = read_design_parts(resolved_document(*d), d->path);
  ASSERT_TRUE(parts.ok());
  Result<ProfileCurve> curve = ProfileCurve::make(parts->reflectors.at(0).profile);
  ASSERT_TRUE(curve.ok());
  Result<io::StepRevolvedPart> part = faceted_step_part(parts->reflectors.at(0), *curve);
  ASSERT_TRUE(part.ok()) << part.error().message;
  EXPECT_EQ(part->faces.size(), 20000u);
}

// A trough's caps as STEP: the part "NAME caps", a plane face at each end
// (y = ±200 mm), closing the cross-section between the two halves
// (z ≤ f − x²/4f, z ≥ the rim's −30 mm), with the caps' material in the sidecar.
TEST(DesignPartsExport, TroughCapsStepReadBackAsPlaneFacesAtTheEnds) {
  if (!io::cad_supported()) GONIO_MISSING("a build with OpenCASCADE (GONIO_OCCT) for STEP export");
  test::TempDir dir;
  for (const bool slot : {false, true}) {
    std::string text = edited(kTrough, "length = 400", "length = 400\ncaps = \"white\"\n[materials.white]\nreflectance = 0.8\n");
    if (slot) text = edited(text, "aperture = [0, 40]", "aperture = [5, 40]");
    Result<Design> d = parse_design(text, (dir / "lamp.design.toml").string());
    ASSERT_TRUE(d.ok());
    Result<StepExportInfo> info = write_design_step(*d, (dir / "caps.step").string());
    ASSERT_TRUE(info.ok()) << to_string(info.error());
    EXPECT_EQ(info->parts, slot ? 3u : 2u);
    Result<io::CadModel> model = io::tessellate_cad((dir / "caps.step").string(), options(1.0));
    ASSERT_TRUE(model.ok()) << to_string(model.error());
    ASSERT_EQ(model->placements.size(), slot ? 3u : 2u);
    const auto caps = std::find_if(model->placements.begin(), model->placements.end(),
                                   [](const io::CadPlacement& p) { return p.path.find("trough caps") != std::string::npos; });
    ASSERT_NE(caps, model->placements.end());
    EXPECT_EQ(model->parts[caps->part].faces, 2u);
    double off_plane = 0.0, x_max = -1.0, z_min = 1.0, z_max = -1.0, outside = 0.0;
    std::size_t low = 0, high = 0;
    for (const io::CadSurface& surface : model->parts[caps->part].surfaces)
      for (const sim::Vec3f& v : surface.positions) {
        const Vec3 p = caps->to_world.point(sim::to_double(v));
        off_plane = std::max(off_plane, std::abs(std::abs(p.y) - 0.200));
        (p.y < 0 ? low : high) += 1;
        x_max = std::max(x_max, std::abs(p.x));
        z_min = std::min(z_min, p.z);
        z_max = std::max(z_max, p.z);
        outside = std::max({outside, p.z - (0.010 - p.x * p.x / 0.040), -0.030 - p.z});
      }
    EXPECT_LT(off_plane, 2e-6) << slot;
    EXPECT_GT(low, 3u);
    EXPECT_GT(high, 3u);
    EXPECT_NEAR(x_max, 0.040, 2e-6);
    EXPECT_NEAR(z_min, -0.030, 2e-6);
    EXPECT_NEAR(z_max, slot ? 0.010 - 0.005 * 0.005 / 0.040 : 0.010, 2e-6) << slot;
    EXPECT_LT(outside, 2e-6) << slot;
    Result<std::string> sidecar = io::read_file(info->sidecar, 1 << 20);
    ASSERT_TRUE(sidecar.ok());
    EXPECT_NE(sidecar->find("match = \"trough caps\"\nmaterial = \"white\""), std::string::npos) << *sidecar;
  }
}

// A dish faceted both ways as STEP: one part named "dish" of 6 × 12 plane
// faces, every vertex within 2 µm of its facet's plane through four corners
// on the exact paraboloid z = 10 − ρ²/40 mm (rows at ρ = 4 + 26·i/6 mm,
// sectors of 30°).
TEST(DesignPartsExport, FlatFacetsStepReadBackOnTheirPlanes) {
  if (!io::cad_supported()) GONIO_MISSING("a build with OpenCASCADE (GONIO_OCCT) for STEP export");
  test::TempDir dir;
  Result<Design> d = parse_design(faceted_dish("{ theta = 6, azimuth = 12, kind = \"flat\" }"),
                                  (dir / "lamp.design.toml").string());
  ASSERT_TRUE(d.ok());
  Result<StepExportInfo> info = write_design_step(*d, (dir / "facets.step").string());
  ASSERT_TRUE(info.ok()) << to_string(info.error());
  EXPECT_EQ(info->parts, 1u);
  Result<io::CadModel> model = io::tessellate_cad((dir / "facets.step").string(), options(1.0));
  ASSERT_TRUE(model.ok()) << to_string(model.error());
  ASSERT_EQ(model->placements.size(), 1u);
  const io::CadPlacement& pl = model->placements[0];
  EXPECT_NE(pl.path.find("dish"), std::string::npos) << pl.path;
  EXPECT_EQ(model->parts[pl.part].faces, 72u);
  const double step = 2.0 * kPi / 12.0;
  auto corner = [&](int i, double psi) {
    const double rho = 0.004 + 0.026 * i / 6.0;
    return Vec3{rho * std::cos(psi), rho * std::sin(psi), 0.010 - rho * rho / 0.040};
  };
  double worst = 0.0, rho_min = 1.0, rho_max = -1.0;
  std::size_t vertices = 0;
  for (const io::CadSurface& surface : model->parts[pl.part].surfaces)
    for (const sim::Vec3f& v : surface.positions) {
      const Vec3 p = pl.to_world.point(sim::to_double(v));
      double psi = std::atan2(p.y, p.x);
      if (psi < 0) psi += 2.0 * kPi;
      const int sector = static_cast<int>(psi / step);
      const double rho = std::hypot(p.x, p.y);
      rho_min = std::min(rho_min, rho);
      rho_max = std::max(rho_max, rho);
      double best = 1.0;
      for (int j = sector - 1; j <= sector + 1; ++j)
        for (int i = 0; i < 6; ++i) {
          const Vec3 a = corner(i, step * j), b = corner(i, step * (j + 1)), c = corner(i + 1, step * j);
          if (p.z > a.z + 2e-6 || p.z < c.z - 2e-6) continue;  // not this band
          best = std::min(best, std::abs(dot(p - a, normalize(cross(b - a, c - a)))));
        }
      worst = std::max(worst, best);
      ++vertices;
    }
  EXPECT_GE(vertices, 4u * 72u / 4u);
  EXPECT_LT(worst, 2e-6);
  EXPECT_NEAR(rho_max, 0.030, 2e-6);
  EXPECT_NEAR(rho_min, 0.004, 2e-6);  // the inner row
  Result<std::string> sidecar = io::read_file(info->sidecar, 1 << 20);
  ASSERT_TRUE(sidecar.ok());
  EXPECT_NE(sidecar->find("match = \"dish\""), std::string::npos) << *sidecar;

}

// Facets one way only and curved facets as STEP: one part of B-spline
// patches (one per facet; smooth around, four quarter turns per band), read
// back by gonio's CAD reader with every vertex within 2 µm of the exact
// faceted surface's closed form: cone bands through the rows (θ flat), the
// arcs of DesignFacets.CurvedFacetsLieOnTheirArcsWithTheArcsNormals (θ
// curved), the ruled sectors (azimuth flat: at X along the sector's
// mid-plane the paraboloid's z at ρ = X / cos(π/12)), the disc's curved
// sectors (DesignFacets.CurvedSectorsLieOnTheirClosedForm).
TEST(DesignPartsExport, OneWayAndCurvedFacetsStepReadBackOnTheirSurfaces) {
  if (!io::cad_supported()) GONIO_MISSING("a build with OpenCASCADE (GONIO_OCCT) for STEP export");
  test::TempDir dir;
  struct Case {
    std::string text;
    std::size_t faces;
    std::function<double(const Vec3&)> off;  // distance from the exact surface [m]
  };
  auto row = [](int k) {
    const double r = 0.004 + 0.026 * k / 6.0;
    return std::pair{r, 0.010 - r * r / 0.040};
  };
  auto to_segment = [](double pr, double pz, std::pair<double, double> a, std::pair<double, double> b) {
    const double dr = b.first - a.first, dz = b.second - a.second;
    const double t = std::clamp(((pr - a.first) * dr + (pz - a.second) * dz) / (dr * dr + dz * dz), 0.0, 1.0);
    return std::hypot(pr - a.first - t * dr, pz - a.second - t * dz);
  };
  const double h12 = kPi / 12, h8 = kPi / 8;
  const std::vector<Case> cases = {
      {faceted_dish("{ theta = 6 }"), 24,
       [&](const Vec3& p) {
         double best = 1.0;
         for (int i = 0; i < 6; ++i) best = std::min(best, to_segment(std::hypot(p.x, p.y), p.z, row(i), row(i + 1)));
         return best;
       }},
      {faceted_dish("{ theta = 6, kind = \"curved\", radius_theta = 40 }"), 24,
       [&](const Vec3& p) {
         double best = 1.0;
         const double rho = std::hypot(p.x, p.y);
         for (int i = 0; i < 6; ++i) {
           if (rho < row(i).first - 2e-6 || rho > row(i + 1).first + 2e-6) continue;
           const auto [cr, cz] = dish_arc_centre(i, 0.040);
           best = std::min(best, std::abs(std::hypot(rho - cr, p.z - cz) - 0.040));
         }
         return best;
       }},
      {faceted_dish("{ azimuth = 12 }"), 12,
       [&](const Vec3& p) {
         double psi = std::atan2(p.y, p.x);
         if (psi < 0) psi += 2 * kPi;
         const double mid = (std::floor(psi / (2 * h12)) + 0.5) * 2 * h12;
         const double rho = (p.x * std::cos(mid) + p.y * std::sin(mid)) / std::cos(h12);
         return std::abs(p.z - (0.010 - rho * rho / 0.040));
       }},
      {curved_disc("{ azimuth = 8, kind = \"curved\", radius_azimuth = 100 }"), 8,
       [&](const Vec3& p) {
         double psi = std::atan2(p.y, p.x);
         if (psi < 0) psi += 2 * kPi;
         const double mid = (std::floor(psi / (2 * h8)) + 0.5) * 2 * h8, R = 0.100;
         const double X = p.x * std::cos(mid) + p.y * std::sin(mid), x = -p.x * std::sin(mid) + p.y * std::cos(mid);
         const double a = X * std::tan(h8);
         return std::abs(p.z - (-0.020 - std::sqrt(R * R - x * x) + std::sqrt(R * R - a * a)));
       }},
  };
  int k = 0;
  for (const Case& c : cases) {
    const std::string stem = "facets" + std::to_string(k++);
    Result<Design> d = parse_design(c.text, (dir / (stem + ".design.toml")).string());
    ASSERT_TRUE(d.ok()) << to_string(d.error());
    Result<StepExportInfo> info = write_design_step(*d, (dir / (stem + ".step")).string());
    ASSERT_TRUE(info.ok()) << to_string(info.error());
    EXPECT_EQ(info->parts, 1u);
    Result<io::CadModel> model = io::tessellate_cad((dir / (stem + ".step")).string(), options(1.0));
    ASSERT_TRUE(model.ok()) << to_string(model.error());
    ASSERT_EQ(model->placements.size(), 1u);
    const io::CadPlacement& pl = model->placements[0];
    EXPECT_EQ(model->parts[pl.part].faces, c.faces) << stem;
    double worst = 0.0;
    std::size_t vertices = 0;
    for (const io::CadSurface& surface : model->parts[pl.part].surfaces)
      for (const sim::Vec3f& v : surface.positions) {
        worst = std::max(worst, c.off(pl.to_world.point(sim::to_double(v))));
        ++vertices;
      }
    std::printf("%s: %zu vertices, within %g m of the exact facets; the helper's fit within %g mm\n", stem.c_str(),
                vertices, worst, info->max_deviation_mm);
    EXPECT_GT(vertices, 100u) << stem;
    EXPECT_LT(worst, 2e-6) << stem;
  }
  // A radius too small for a facet: the radius's line (the facets table's,
  // 16, here; DesignFacets.RadiusTooSmallNamesItsOwnLine), nothing written.
  Result<Design> d = parse_design(faceted_dish("{ theta = 2, kind = \"curved\", radius_theta = 5 }"),
                                  (dir / "small.design.toml").string());
  ASSERT_TRUE(d.ok());
  Result<StepExportInfo> info = write_design_step(*d, (dir / "small.step").string());
  ASSERT_FALSE(info.ok());
  EXPECT_EQ(info.error().where.line, 16) << to_string(info.error());
  EXPECT_FALSE(std::filesystem::exists(dir / "small.step"));
}

// A trough as STEP (the helper's B-spline profile extruded along Y): read
// back by gonio's CAD reader, one part named as the design names it, every
// vertex within 1.5 µm of the exact parabolic cylinder and spanning its
// x and y; the sidecar beside it gives it its material.
// The helper's request carries an extruded part: its length, and x of either sign.
TEST(DesignPartsExport, ExtrudedPartsInTheStepRequest) {
  io::StepExport r;
  r.product = "lamp";
  io::StepRevolvedPart p;
  p.name = "trough";
  p.rho = {-1.5, 0.0, 1.5};
  p.z = {0.0, 1.0, 0.0};
  p.extrude_mm = 400;
  r.parts.push_back(p);
  Result<io::StepExport> back = io::parse_step_export(io::serialize_step_export(r), "request");
  ASSERT_TRUE(back.ok()) << to_string(back.error());
  EXPECT_EQ(back->parts[0].extrude_mm, 400.0);
  EXPECT_EQ(back->parts[0].rho, p.rho);
  r.parts[0].extrude_mm = 0.0;  // turned about Z, x < 0 is a profile across the axis
  EXPECT_FALSE(io::parse_step_export(io::serialize_step_export(r), "request").ok());
  std::string bad = io::serialize_step_export(back.value());
  bad.replace(bad.find("extrude 400"), 11, "extrude -4");
  EXPECT_FALSE(io::parse_step_export(bad, "request").ok());
}

TEST(DesignPartsExport, TroughStepReadsBackOnTheExactCylinder) {
  if (!io::cad_supported()) GONIO_MISSING("a build with OpenCASCADE (GONIO_OCCT) for STEP export");
  test::TempDir dir;
  Result<Design> d = parse_design(kTrough, (dir / "lamp.design.toml").string());
  ASSERT_TRUE(d.ok());
  Result<StepExportInfo> info = write_design_step(*d, (dir / "trough.step").string());
  ASSERT_TRUE(info.ok()) << to_string(info.error());
  EXPECT_EQ(info->parts, 1u);
  EXPECT_LT(info->max_deviation_mm, 1e-3);
  io::CadLoadOptions o;
  o.tessellation.angular_deflection_deg = 1.0;
  Result<io::CadModel> model = io::tessellate_cad((dir / "trough.step").string(), o);
  ASSERT_TRUE(model.ok()) << to_string(model.error());
  ASSERT_EQ(model->placements.size(), 1u);
  const io::CadPlacement& pl = model->placements[0];
  EXPECT_NE(pl.path.find("trough"), std::string::npos) << pl.path;
  double worst = 0.0, x_min = 1, x_max = -1, y_min = 1, y_max = -1;
  for (const io::CadSurface& surface : model->parts[pl.part].surfaces)
    for (const sim::Vec3f& v : surface.positions) {
      const Vec3 p = pl.to_world.point(sim::to_double(v));
      // Distance from z = f − x²/4f along its normal (first order).
      worst = std::max(worst, std::abs(p.z - (0.010 - p.x * p.x / 0.040)) / std::sqrt(1 + std::pow(p.x / 0.020, 2)));
      x_min = std::min(x_min, p.x);
      x_max = std::max(x_max, p.x);
      y_min = std::min(y_min, p.y);
      y_max = std::max(y_max, p.y);
    }
  EXPECT_LT(worst, 1.5e-6);
  EXPECT_NEAR(x_min, -0.040, 2e-6);
  EXPECT_NEAR(x_max, 0.040, 2e-6);
  EXPECT_NEAR(y_min, -0.200, 2e-6);
  EXPECT_NEAR(y_max, 0.200, 2e-6);
  Result<std::string> sidecar = io::read_file(info->sidecar, 1 << 20);
  ASSERT_TRUE(sidecar.ok());
  EXPECT_NE(sidecar->find("match = \"trough\""), std::string::npos) << *sidecar;
  EXPECT_EQ(sidecar->find("troughs"), std::string::npos) << *sidecar;

  // With a slot along the vertex (x from 5 mm), the two halves are two parts.
  Result<Design> slot = parse_design(edited(kTrough, "aperture = [0, 40]", "aperture = [5, 40]"),
                                     (dir / "slot.design.toml").string());
  ASSERT_TRUE(slot.ok());
  info = write_design_step(*slot, (dir / "slot.step").string());
  ASSERT_TRUE(info.ok()) << to_string(info.error());
  EXPECT_EQ(info->parts, 2u);
  model = io::tessellate_cad((dir / "slot.step").string(), o);
  ASSERT_TRUE(model.ok()) << to_string(model.error());
  ASSERT_EQ(model->placements.size(), 2u);
  for (const io::CadPlacement& half : model->placements) {
    const bool mirrored = half.path.find("trough mirrored") != std::string::npos;
    EXPECT_TRUE(mirrored || half.path.find("trough") != std::string::npos) << half.path;
    for (const io::CadSurface& surface : model->parts[half.part].surfaces)
      for (const sim::Vec3f& v : surface.positions) {
        const Vec3 p = half.to_world.point(sim::to_double(v));
        EXPECT_GE((mirrored ? -1 : 1) * p.x, 0.005 - 2e-6);
        EXPECT_LT(std::abs(p.z - (0.010 - p.x * p.x / 0.040)), 3e-6);
      }
  }
}

// The kinds' numbers are variables as a reflector's are: set, the scene follows.
TEST(DesignTrough, LengthAndCoverHeightAreVariables) {
  const std::string text = edited(edited(cover_design("material = \"clear\"\nshape = \"plate\"\nsize = [100, 40]\n"
                                                      "height = { value = -20, min = -50, max = -10 }\nthickness = 3\n"),
                                         "[[covers]]", std::string(kTrough).substr(std::string(kTrough).find("[[troughs]]")) +
                                                           "\n[materials.mirror]\nmirror = 1.0\n\n[[covers]]"),
                                  "length = 400", "length = { value = 400, min = 100, max = 800, name = \"L\" }");
  Result<Design> d = parse_design(text, "lamp.design.toml");
  ASSERT_TRUE(d.ok()) << to_string(d.error());
  ASSERT_NE(d->variable("L"), nullptr);
  ASSERT_NE(d->variable("covers[0].height"), nullptr);
  ASSERT_TRUE(set_variable(*d, "L", 600).ok());
  ASSERT_TRUE(set_variable(*d, "covers[0].height", -30).ok());
  EXPECT_FALSE(set_variable(*d, "L", 900).ok());  // outside its bounds
  std::vector<Finding> findings;
  Result<sim::SceneDesc> s = design_scene(*d, options(2.0), &findings);
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  float y_max = -1.0f, z_top = -1.0f;
  for (const sim::Mesh& m : s->meshes)
    for (const sim::Vec3f& p : m.positions) {
      if (m.name == "trough") y_max = std::max(y_max, p.y);
      if (m.name == "cover") z_top = std::max(z_top, p.z);
    }
  EXPECT_NEAR(y_max, 0.3f, 1e-7f);
  EXPECT_NEAR(z_top, -0.030f, 1e-7f);
}

// Covers as STEP (OpenCASCADE's primitives): read back by gonio's CAD
// reader, named as the design names them, every vertex on its exact surfaces.
TEST(DesignPartsExport, CoverStepReadsBackOnItsExactSurfaces) {
  if (!io::cad_supported()) GONIO_MISSING("a build with OpenCASCADE (GONIO_OCCT) for STEP export");
  test::TempDir dir;
  const std::string text = cover_design("material = \"clear\"\nshape = \"plate\"\nsize = [100, 40]\nheight = -20\nthickness = 3\n") +
                           "\n[[covers]]\nname = \"dome\"\nmaterial = \"clear\"\nshape = \"dome\"\ndiameter = 80\nsag = 20\n"
                           "height = -30\nthickness = 2\n"
                           "\n[[covers]]\nname = \"up\"\nmaterial = \"sheet\"\nshape = \"dome\"\ndiameter = 80\nsag = -20\n"
                           "height = 30\n"
                           "\n[[covers]]\nname = \"disc\"\nmaterial = \"sheet\"\nshape = \"plate\"\ndiameter = 80\nheight = -60\n";
  Result<Design> d = parse_design(text, (dir / "covers.design.toml").string());
  ASSERT_TRUE(d.ok()) << to_string(d.error());
  Result<StepExportInfo> info = write_design_step(*d, (dir / "covers.step").string());
  ASSERT_TRUE(info.ok()) << to_string(info.error());
  EXPECT_EQ(info->parts, 4u);
  io::CadLoadOptions o;
  o.tessellation.angular_deflection_deg = 2.0;
  Result<io::CadModel> model = io::tessellate_cad((dir / "covers.step").string(), o);
  ASSERT_TRUE(model.ok()) << to_string(model.error());
  ASSERT_EQ(model->placements.size(), 4u);
  std::map<std::string, std::size_t> vertices;
  for (const io::CadPlacement& pl : model->placements) {
    std::string name;
    for (const char* n : {"cover", "dome", "up", "disc"})
      if (pl.path.size() >= std::strlen(n) && pl.path.compare(pl.path.size() - std::strlen(n), std::strlen(n), n) == 0)
        name = n;
    ASSERT_FALSE(name.empty()) << pl.path;
    // The clear ones closed solids, the sheets none.
    EXPECT_EQ(model->parts[pl.part].solids, name == "cover" || name == "dome" ? 1u : 0u) << name;
    for (const io::CadSurface& surface : model->parts[pl.part].surfaces)
      for (const sim::Vec3f& v : surface.positions) {
        const Vec3 p = pl.to_world.point(sim::to_double(v));
        ++vertices[name];
        const double r = length(p);
        if (name == "cover") {
          EXPECT_LE(std::abs(p.x), 0.050 + 1e-8);
          EXPECT_LE(std::abs(p.y), 0.020 + 1e-8);
          EXPECT_TRUE(std::abs(p.z + 0.020) < 1e-8 || std::abs(p.z + 0.023) < 1e-8 ||
                      (std::abs(std::abs(p.x) - 0.050) < 1e-8 || std::abs(std::abs(p.y) - 0.020) < 1e-8))
              << p.x << " " << p.y << " " << p.z;
        } else if (name == "dome") {  // spheres of 50 and 48 mm about the origin, the ring at z = −30 mm
          EXPECT_TRUE(std::abs(r - 0.050) < 2e-6 || std::abs(r - 0.048) < 2e-6 || std::abs(p.z + 0.030) < 1e-8) << r;
          EXPECT_LE(p.z, -0.030 + 1e-8);
        } else if (name == "up") {  // bulging up: the sphere of 50 mm about (0, 0, 0), z from 30 to 50 mm
          EXPECT_NEAR(r, 0.050, 2e-6);
          EXPECT_GE(p.z, 0.030 - 1e-8);
        } else {
          EXPECT_NEAR(p.z, -0.060, 1e-8);
          EXPECT_LE(std::hypot(p.x, p.y), 0.040 + 1e-8);
        }
      }
  }
  EXPECT_EQ(vertices.size(), 4u);
}

// A polar table of one radius is a circular cylinder about the Y axis: every
// vertex at that distance from the axis, its normal toward it.
TEST(DesignTrough, PolarProfileIsAboutTheYAxis) {
  const std::string text = edited(kTrough, "profile = \"conic\"\nradius = 20\nconic = -1\nvertex = 10\naperture = [0, 40]",
                                  "profile = \"polar\"\ntheta_deg = [0, 45, 90]\nr = [25, 25, 25]");
  Result<sim::SceneDesc> s = scene_of(text);
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  const sim::Mesh& m = s->meshes[0];
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const Vec3 p = sim::to_double(m.positions[i]);
    EXPECT_NEAR(std::hypot(p.x, p.z), 0.025, 1e-8);
    EXPECT_LE(p.z, 1e-8);
    EXPECT_LT(angle(sim::to_double(m.normals[i]), normalize(Vec3{-p.x, 0.0, -p.z})), 1e-6);
  }
}

}  // namespace
}  // namespace gonio::design
