// Lenses of revolution in design files (design/lens.h): closed solids whose
// vertices lie on the exact surfaces with exact outward normals, a TIR
// collimator's side as a B-spline, and the mistakes (surfaces that cross, an
// emitter in the glass, unknown keys) as errors naming the line.
#include "design/lens.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <string>

#include "design/design_export.h"
#include "design/design_file.h"
#include "design/design_scene.h"
#include "io/model/gltf.h"
#include "tests/support/rotation.h"
#include "tests/support/test_support.h"

namespace gonio::design {
namespace {

constexpr double kPi = std::numbers::pi;

// A negative meniscus below the source, thicker at its rim: inner sphere
// R = −40 mm (its centre above, toward the source), outer sphere R = 30 mm
// (R > 0: its centre toward −Z, below), vertex at z = −5 mm, 6 mm thick at
// the centre, ρ to 12 mm.
const char* kLens = R"(length_unit = "mm"

[materials.pmma]
dielectric = 1.0
ior = 1.491

[[emitters]]
name = "LED"
position = [0, 0, 0]
flux_lm = 1000

[[lenses]]
name = "lens"
material = "pmma"
vertex = -5
thickness = { value = 6, min = 4, max = 8 }
aperture = 12
inner = { profile = "conic", radius = -40, conic = 0 }
outer = { profile = "conic", radius = { value = 30, min = 20, max = 60 }, conic = 0 }
)";

// A cavity-less TIR collimator: flat inner face at z = −2 mm out to 3 mm,
// a parabolic side (a quadratic B-spline) out to the flat exit face, 15 mm
// wide at z = −20 mm. The quadratic's middle control point (10, −4) mm.
std::string tir_design() {
  const std::string text = kLens;
  return text.substr(0, text.find("[[lenses]]")) + R"([[lenses]]
name = "tir"
material = "pmma"
vertex = -2
thickness = 18
aperture = 3
inner = { profile = "conic" }
outer = { profile = "bspline", degree = 1, points = [[0, 0], [15, 0]] }
side = { profile = "bspline", degree = 2, points = [[10, -4]] }
)";
}

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

// The scene's meshes of one part (one per surface) as one mesh.
sim::Mesh part_mesh(const sim::SceneDesc& s, const std::string& name) {
  sim::Mesh out;
  out.name = name;
  for (const sim::Mesh& m : s.meshes) {
    if (m.name.rfind(name, 0) != 0) continue;  // "lens", "lens#1", … (a mesh per surface)
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    out.positions.insert(out.positions.end(), m.positions.begin(), m.positions.end());
    out.normals.insert(out.normals.end(), m.normals.begin(), m.normals.end());
    for (std::uint32_t i : m.indices) out.indices.push_back(base + i);
  }
  return out;
}

double angle(const Vec3& a, const Vec3& b) { return std::atan2(length(cross(a, b)), dot(a, b)); }

// Every directed edge of the triangles once and its reverse once: a closed,
// consistently wound surface (vertices matched by position).
struct Closure {
  std::size_t edges = 0, unmatched = 0, repeated = 0;
  double volume = 0.0;  // by the divergence theorem [m³]; > 0 for outward winding
};
Closure closure(const sim::Mesh& m) {
  using Key = std::array<float, 3>;
  auto key = [&](std::uint32_t i) { return Key{m.positions[i].x, m.positions[i].y, m.positions[i].z}; };
  std::map<std::pair<Key, Key>, int> directed;
  Closure c;
  for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const std::uint32_t v[3] = {m.indices[t], m.indices[t + 1], m.indices[t + 2]};
    for (int e = 0; e < 3; ++e) ++directed[{key(v[e]), key(v[(e + 1) % 3])}];
    const Vec3 a = sim::to_double(m.positions[v[0]]), b = sim::to_double(m.positions[v[1]]),
               cc = sim::to_double(m.positions[v[2]]);
    c.volume += dot(a, cross(b, cc)) / 6.0;
  }
  for (const auto& [edge, count] : directed) {
    ++c.edges;
    if (count > 1) ++c.repeated;
    const auto back = directed.find({edge.second, edge.first});
    if (back == directed.end() || back->second != count) ++c.unmatched;
  }
  return c;
}

TEST(Lens, MeniscusIsAClosedSolidOnItsExactSurfacesWithOutwardNormals) {
  Result<sim::SceneDesc> s = scene_of(kLens);
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  ASSERT_EQ(s->meshes.size(), 1u);  // one closed mesh: inner, side, outer
  const sim::Mesh m = part_mesh(*s, "lens");
  ASSERT_EQ(m.normals.size(), m.positions.size());
  // Inner: sphere of radius 40 mm centred at z = −5 + 40 mm; outer: radius
  // 30 mm centred at z = −11 − 30 mm; side: the cylinder ρ = 12 mm.
  const Vec3 ci{0, 0, 0.035}, co{0, 0, -0.041};
  const double zi_rim = 0.035 - std::sqrt(0.040 * 0.040 - 0.012 * 0.012);
  const double zo_rim = -0.041 + std::sqrt(0.030 * 0.030 - 0.012 * 0.012);
  std::size_t on_inner = 0, on_outer = 0, on_side = 0;
  double worst_p = 0.0, worst_n = 0.0;
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const Vec3 p = sim::to_double(m.positions[i]), n = sim::to_double(m.normals[i]);
    const double rho = std::hypot(p.x, p.y);
    const double di = std::abs(length(p - ci) - 0.040), d_o = std::abs(length(p - co) - 0.030);
    if (rho < 0.012 * (1 - 1e-5) && p.z > -0.008) {  // inner: outward is up, toward its centre above
      ++on_inner;
      worst_p = std::max(worst_p, di);
      worst_n = std::max(worst_n, angle(n, normalize(ci - p)));
    } else if (rho < 0.012 * (1 - 1e-5)) {  // outer: outward is down, toward its centre below
      ++on_outer;
      worst_p = std::max(worst_p, d_o);
      worst_n = std::max(worst_n, angle(n, normalize(co - p)));
    } else {
      EXPECT_NEAR(rho, 0.012, 1e-8);
      EXPECT_GE(p.z, zo_rim - 1e-8);
      EXPECT_LE(p.z, zi_rim + 1e-8);
      // Rim vertices carry the normal of their own surface; the side's are radial.
      if (p.z < zi_rim - 1e-7 && p.z > zo_rim + 1e-7) {
        ++on_side;
        worst_n = std::max(worst_n, angle(n, Vec3{p.x / rho, p.y / rho, 0}));
      }
    }
  }
  EXPECT_GT(on_inner, 100u);
  EXPECT_GT(on_outer, 100u);
  EXPECT_LT(worst_p, 1e-8);   // float positions of 4 cm
  EXPECT_LT(worst_n, 1e-6);   // exact normals, as floats
  (void)on_side;
  // Closed and wound outward: its volume is the lens's (two caps and a
  // cylinder), to the tessellation's error.
  const Closure c = closure(m);
  EXPECT_EQ(c.unmatched, 0u);
  EXPECT_EQ(c.repeated, 0u);
  auto cap = [](double R, double h) { return kPi * h * h * (3 * R - h) / 3.0; };
  const double hi = 0.040 - std::sqrt(0.040 * 0.040 - 0.012 * 0.012);  // the inner cap's height
  const double ho = 0.030 - std::sqrt(0.030 * 0.030 - 0.012 * 0.012);
  // The cylinder between the rims less the two caps of air: the inner
  // surface dips below its rim, the outer rises above its rim.
  const double exact = kPi * 0.012 * 0.012 * (zi_rim - zo_rim) - cap(0.030, ho) - cap(0.040, hi);
  EXPECT_NEAR(c.volume / exact, 1.0, 2e-3) << c.volume << " against " << exact;
}

TEST(Lens, ClosedAtEveryTessellation) {
  // Coarse deflections leave the azimuth count to the chordal deflection on
  // the widest circle, which differs per surface (the TIR collimator's inner
  // face is 3 mm wide, its exit 15 mm) unless the lens shares one.
  for (const auto& [text, name] : {std::pair{std::string(kLens), "lens"}, std::pair{tir_design(), "tir"}})
    for (double deg : {0.5, 5.0, 20.0, 45.0}) {
      Result<sim::SceneDesc> s = scene_of(text, deg);
      ASSERT_TRUE(s.ok()) << to_string(s.error());
      const Closure c = closure(part_mesh(*s, name));
      EXPECT_EQ(c.unmatched, 0u) << name << " " << deg;
      EXPECT_GT(c.volume, 0.0) << name << " " << deg;
    }
}

TEST(Lens, TheLibrarysClearPlasticIsTheLensesMaterial) {
  std::string text = kLens;
  const std::string glass = "dielectric = 1.0\nior = 1.491";
  text.replace(text.find(glass), glass.size(), "preset = \"clear PC\"");
  Result<sim::SceneDesc> s = scene_of(text);
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  const sim::Material& m = s->materials.at(s->meshes[0].material);
  EXPECT_EQ(m.dielectric, 1.0);
  EXPECT_EQ(m.ior, 1.585);
}

TEST(Lens, VariablesMoveTheSurfaces) {
  Result<Design> d = parse_design(kLens, "lamp.design.toml");
  ASSERT_TRUE(d.ok());
  ASSERT_NE(d->variable("lenses[0].thickness"), nullptr);
  ASSERT_TRUE(set_variable(*d, "lenses[0].thickness", 7.0).ok());
  std::vector<Finding> f;
  Result<sim::SceneDesc> s = design_scene(*d, options(2.0), &f);
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  float z_min = 1e9f;
  for (const sim::Vec3f& p : part_mesh(*s, "lens").positions) z_min = std::min(z_min, p.z);
  // The outer vertex at −5 − 7 mm, its rim 30 − √(30² − 12²) mm below it.
  EXPECT_NEAR(z_min, -0.012 - (0.030 - std::sqrt(0.030 * 0.030 - 0.012 * 0.012)), 1e-7);
}

TEST(Lens, TirCollimatorSideIsItsBSplineAndTheSolidIsClosed) {
  Result<sim::SceneDesc> s = scene_of(tir_design());
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  const sim::Mesh m = part_mesh(*s, "tir");
  const Closure c = closure(m);
  EXPECT_EQ(c.unmatched, 0u);
  EXPECT_GT(c.volume, 0.0);
  // Side vertices on the quadratic Bézier (3, −2), (10, −4), (15, −20) mm.
  std::size_t on_side = 0;
  double worst = 0.0;
  for (const sim::Vec3f& pf : m.positions) {
    const double rho = std::hypot(double(pf.x), double(pf.y)), z = pf.z;
    if (z > -0.0199999 && z < -0.0020001) {
      ++on_side;
      // Find t with ρ(t) = rho (monotone), then compare z.
      double lo = 0, hi = 1;
      for (int k = 0; k < 60; ++k) {
        const double t = 0.5 * (lo + hi);
        const double r = (1 - t) * (1 - t) * 3 + 2 * t * (1 - t) * 10 + t * t * 15;
        (r < rho * 1e3 ? lo : hi) = t;
      }
      const double t = 0.5 * (lo + hi);
      const double zt = (1 - t) * (1 - t) * -2 + 2 * t * (1 - t) * -4 + t * t * -20;
      worst = std::max(worst, std::abs(zt * 1e-3 - z));
    }
  }
  EXPECT_GT(on_side, 100u);
  EXPECT_LT(worst, 1e-7);
}

TEST(Lens, MistakesAreErrorsNamingTheLine) {
  struct Case {
    std::string from, to;
    int line;
    std::string says;
  };
  const std::vector<Case> cases = {
      {"aperture = 12", "aperture = 12\ncolour = 3", 18, "unknown key 'colour'"},
      {"conic = 0 }\nouter", "conic = 0, vertex = 2 }\nouter", 18, "unknown key 'vertex'"},
      {"material = \"pmma\"\nvertex", "material = \"glass\"\nvertex", 12, "material 'glass' is not defined"},
      // Thinner than zero: an outer sphere of R = −12.5 mm rises 9 mm to
      // z = −2 mm at the rim, above the inner one's −3.16 mm.
      {"radius = { value = 30, min = 20, max = 60 }", "radius = -12.5", 12, "thinner than zero near"},
      {"{ value = 6, min = 4, max = 8 }", "-20", 12, "thinner than zero on the axis"},
      {"vertex = -5\n", "", 17, "needs the lens's 'vertex'"},
      {"position = [0, 0, 0]", "position = [0, 0, -8]", 12, "lies inside the glass"},
      {"position = [0, 0, 0]", "position = [0, 0, -5]", 12, "a surface passes through the emitter"},
      {"outer = { profile = \"conic\", radius = { value = 30, min = 20, max = 60 }, conic = 0 }",
       "outer = { profile = \"polar\", theta_deg = [10, 40], r = [20, 20] }", 19, "theta_deg[0] must be 0"},
      {"outer = { profile = \"conic\", radius = { value = 30, min = 20, max = 60 }, conic = 0 }",
       "outer = { profile = \"bspline\", points = [[0, 1], [12, 0]] }", 19, "the first point must be the vertex"},
      {"outer = { profile = \"conic\", radius = { value = 30, min = 20, max = 60 }, conic = 0 }",
       "outer = { profile = \"nurbs\" }", 19, "profile 'nurbs' is not one a lens surface takes"},
      {"aperture = 12", "aperture = -1", 17, "'aperture' (the rims' ρ) must be > 0"},
  };
  for (const Case& c : cases) {
    std::string text = kLens;
    const std::size_t at = text.find(c.from);
    ASSERT_NE(at, std::string::npos) << c.from;
    text.replace(at, c.from.size(), c.to);
    Result<sim::SceneDesc> s = scene_of(text);
    ASSERT_FALSE(s.ok()) << c.to;
    EXPECT_EQ(s.error().where.file, "lamp.design.toml") << c.to;
    EXPECT_EQ(s.error().where.line, c.line) << c.to << ": " << to_string(s.error());
    EXPECT_NE(s.error().message.find(c.says), std::string::npos) << c.to << ": " << to_string(s.error());
  }
}

TEST(Lens, GltfHoldsTheLensAsTheDesignFileDoes) {
  test::TempDir dir;
  Result<Design> d = parse_design(kLens, (dir.path() / "lamp.design.toml").string());
  ASSERT_TRUE(d.ok());
  const std::string gltf = (dir.path() / "lamp.gltf").string();
  ASSERT_TRUE(write_design_gltf(*d, gltf, options(2.0).tessellation).ok());
  Result<sim::SceneDesc> from_design = scene_of(kLens);
  ASSERT_TRUE(from_design.ok());
  const std::string text = test::read_file(gltf);
  EXPECT_NE(text.find("\"lens\""), std::string::npos);
  EXPECT_NE(text.find("\"ior\""), std::string::npos);
  std::size_t triangles = 0;
  for (const sim::Mesh& m : from_design->meshes) triangles += m.indices.size() / 3;
  EXPECT_GT(triangles, 1000u);
}

// A placed lens (position, rotate_deg: about X, then Y, then Z about the
// origin, then moved) is the lens on the axis turned and moved: every vertex
// p' = R·p + t and normal n' = R·n, R = Rz·Ry·Rx, in the same order. Fails
// with the rotations composed the other way or the move before the turn.
TEST(Lens, APlacedLensIsTheAxialOneTurnedThenMoved) {
  Result<sim::SceneDesc> axial = scene_of(kLens);
  Result<sim::SceneDesc> placed = scene_of(std::string(kLens) + "position = [7, -3, 12]\nrotate_deg = [20, 30, 0]\n");
  ASSERT_TRUE(axial.ok() && placed.ok()) << (placed.ok() ? std::string() : to_string(placed.error()));
  const sim::Mesh a = part_mesh(*axial, "lens"), b = part_mesh(*placed, "lens");
  ASSERT_EQ(a.positions.size(), b.positions.size());
  ASSERT_EQ(a.indices, b.indices);
  const double cx = std::cos(20 * kPi / 180), sx = std::sin(20 * kPi / 180), cy = std::cos(30 * kPi / 180),
               sy = std::sin(30 * kPi / 180);
  auto turn = [&](const Vec3& v) {
    const Vec3 r1{v.x, cx * v.y - sx * v.z, sx * v.y + cx * v.z};  // about X
    return Vec3{cy * r1.x + sy * r1.z, r1.y, -sy * r1.x + cy * r1.z};  // then about Y
  };
  double worst = 0.0, worst_normal = 0.0;
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    const Vec3 expected = turn(sim::to_double(a.positions[i])) + Vec3{0.007, -0.003, 0.012};
    worst = std::max(worst, length(sim::to_double(b.positions[i]) - expected));
    worst_normal = std::max(worst_normal, angle(sim::to_double(b.normals[i]), turn(sim::to_double(a.normals[i]))));
  }
  EXPECT_LT(worst, 1e-8);
  EXPECT_LT(worst_normal, 1e-6);
  const Closure c = closure(b);
  EXPECT_EQ(c.unmatched, 0u);
  EXPECT_GT(c.volume, 0.0);
  // The emitter inside the moved glass (8 mm below the moved origin, in the
  // lens's own frame inside it) is found there; where the unmoved glass was, not.
  std::string inside = std::string(kLens) + "position = [0, 0, 30]\n";
  inside.replace(inside.find("position = [0, 0, 0]"), 20, "position = [0, 0, 22]");
  Result<sim::SceneDesc> bad = scene_of(inside);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("inside the glass"), std::string::npos) << to_string(bad.error());
  std::string outside = std::string(kLens) + "position = [0, 0, 30]\n";
  outside.replace(outside.find("position = [0, 0, 0]"), 20, "position = [0, 0, -8]");
  EXPECT_TRUE(scene_of(outside).ok());
  // Bad placements name their line (the appended key is line 20).
  for (const char* key : {"position = [1, 2]\n", "rotate_deg = [0, \"x\", 0]\n"}) {
    Result<sim::SceneDesc> s = scene_of(std::string(kLens) + key);
    ASSERT_FALSE(s.ok()) << key;
    EXPECT_EQ(s.error().where.line, 20) << to_string(s.error());
    EXPECT_NE(s.error().message.find("must be an array of three finite numbers"), std::string::npos) << to_string(s.error());
  }
}

// All three angles of rotate_deg non-zero: the placed lens is the axial one
// turned by R = Rz·Ry·Rx (about X, then Y, then Z, as docs/design.md says),
// the matrix built here from its entries, then moved. Fails with the turns
// composed in any other order.
TEST(Lens, APlacedLensTurnsAboutXThenYThenZ) {
  Result<sim::SceneDesc> axial = scene_of(kLens);
  Result<sim::SceneDesc> placed = scene_of(std::string(kLens) + "position = [7, -3, 12]\nrotate_deg = [20, 30, 45]\n");
  ASSERT_TRUE(axial.ok() && placed.ok()) << (placed.ok() ? std::string() : to_string(placed.error()));
  const sim::Mesh a = part_mesh(*axial, "lens"), b = part_mesh(*placed, "lens");
  ASSERT_EQ(a.positions.size(), b.positions.size());
  ASSERT_EQ(a.indices, b.indices);
  const test::Matrix3 r = test::rotation_xyz_deg(20, 30, 45);
  const auto turn = [&](const Vec3& v) { return test::apply(r, v); };
  double worst = 0.0, worst_normal = 0.0;
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    const Vec3 expected = turn(sim::to_double(a.positions[i])) + Vec3{0.007, -0.003, 0.012};
    worst = std::max(worst, length(sim::to_double(b.positions[i]) - expected));
    worst_normal = std::max(worst_normal, angle(sim::to_double(b.normals[i]), turn(sim::to_double(a.normals[i]))));
  }
  EXPECT_LT(worst, 1e-8);
  EXPECT_LT(worst_normal, 1e-6);
}

// The same lens written to glTF on the axis and read back as a fixed glTF
// part placed as a placed lens is: the same vertices, to float rounding.
TEST(Lens, APlacedLensIsTheFixedGltfPartPlacedTheSame) {
  test::TempDir dir;
  Result<Design> d = parse_design(kLens, (dir.path() / "axial.design.toml").string());
  ASSERT_TRUE(d.ok());
  ASSERT_TRUE(write_design_gltf(*d, (dir.path() / "lens.gltf").string(), options(2.0).tessellation).ok());
  const std::string place = "position = [7, -3, 12]\nrotate_deg = [20, 30, 45]\n";
  const std::string head = std::string(kLens).substr(0, std::string(kLens).find("[[lenses]]"));
  Result<Design> fixed = parse_design(head + "[[parts]]\nname = \"glass\"\nfile = \"lens.gltf\"\nmaterial = \"pmma\"\n" + place,
                                      (dir.path() / "fixed.design.toml").string());
  ASSERT_TRUE(fixed.ok()) << to_string(fixed.error());
  std::vector<Finding> findings;
  Result<sim::SceneDesc> a = design_scene(*fixed, options(2.0), &findings);
  Result<sim::SceneDesc> b = scene_of(std::string(kLens) + place);
  ASSERT_TRUE(a.ok() && b.ok()) << (a.ok() ? std::string() : to_string(a.error()));
  const sim::Mesh ma = part_mesh(*a, "glass/"), mb = part_mesh(*b, "lens");
  ASSERT_EQ(ma.positions.size(), mb.positions.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < ma.positions.size(); ++i) {
    double nearest = 1.0;  // in any order
    const Vec3 p = sim::to_double(mb.positions[i]);
    if (i < ma.positions.size()) nearest = length(sim::to_double(ma.positions[i]) - p);
    if (nearest > 1e-7)
      for (const sim::Vec3f& q : ma.positions) nearest = std::min(nearest, length(sim::to_double(q) - p));
    worst = std::max(worst, nearest);
  }
  EXPECT_LT(worst, 1e-7);
}

}  // namespace
}  // namespace gonio::design
