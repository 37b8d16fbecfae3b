// STEP export of design files (design/design_export.h, write_design_step):
// each reflector written by the helper gonio-cad as a face of revolution
// whose meridian is a B-spline within the stated tolerance of the exact
// profile, named by its part's name, with a sidecar that makes the STEP a
// luminaire. Read back by gonio's own CAD reader (every vertex on the exact
// surface, the names, the materials) and by FreeCAD (the names, and the
// paraboloid's area against its closed form).
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>

#include "design/design_export.h"
#include "design/design_file.h"
#include "design/design_scene.h"
#include "design/lens.h"
#include "design/revolved.h"
#include "io/model/cad.h"
#include "io/model/parts_file.h"
#include "io/model/step_export.h"
#include "io/support/process.h"
#include "tests/support/test_support.h"

#ifndef GONIO_TEST_DATA_DIR
#error "GONIO_TEST_DATA_DIR must name the build's test-data folder"
#endif

namespace gonio::design {
namespace {

constexpr double kPi = std::numbers::pi;
namespace fs = std::filesystem;

// Three profiles of the three kinds; the dish is the paraboloid z = 10 − ρ²/40
// mm over ρ 4…30 mm.
const char* kDesign = R"(length_unit = "mm"

[materials.mirror]
mirror = 0.9

[materials.white]
reflectance = 0.8

[[emitters]]
name = "LED"
position = [0, 0, 0]
profile = "led.ies"

[[reflectors]]
name = "Outer dish"
material = "mirror"
profile = "conic"
radius = { value = 20, min = 10, max = 40 }
conic = -1
vertex = 10
aperture = [4, 30]

[[reflectors]]
name = "polar"
material = "white"
profile = "polar"
theta_deg = [100, 120, 140, 160, 180]
r = [40, 38, 37, 36, 35]

[[reflectors]]
name = "spline"
material = "mirror"
profile = "bspline"
points = [[0, 60], [20, 58], [40, 50], [50, 30]]
)";

// The paraboloid's area, (2πR²/3)·[(1 + ρ²/R²)^(3/2)] from ρ₀ to ρ₁ [mm²].
double dish_area_mm2() {
  const double R = 20.0;
  auto F = [&](double rho) { return 2.0 * kPi * R * R / 3.0 * std::pow(1.0 + rho * rho / (R * R), 1.5); };
  return F(30.0) - F(4.0);
}

struct Written {
  Design design;
  DesignParts parts;
  StepExportInfo info;
};

Written write_step(const fs::path& dir) {
  test::write_file(dir / "lamp.design.toml", kDesign);
  test::write_file(dir / "led.ies", "not read by the export\n");
  Result<Design> d = read_design_file((dir / "lamp.design.toml").string());
  EXPECT_TRUE(d.ok()) << (d.ok() ? "" : to_string(d.error()));
  Result<DesignParts> parts = read_design_parts(resolved_document(*d), d->path);
  EXPECT_TRUE(parts.ok());
  fs::create_directories(dir / "cad");
  Result<StepExportInfo> info = write_design_step(*d, (dir / "cad" / "lamp.step").string());
  EXPECT_TRUE(info.ok()) << (info.ok() ? "" : to_string(info.error()));
  return {*d, *parts, info.ok() ? *info : StepExportInfo{}};
}

TEST(DesignStep, PartsReadBackOnTheExactSurfacesWithTheirNames) {
  test::TempDir dir;
  const Written w = write_step(dir.path());
  ASSERT_EQ(w.info.parts, 3u);
  EXPECT_LE(w.info.max_deviation_mm, kStepToleranceMm);
  EXPECT_EQ(w.info.sidecar, (dir / "cad" / "lamp.gonio.toml").string());

  io::CadLoadOptions o;
  o.tessellation.angular_deflection_deg = 2.0;
  Result<io::CadModel> model = io::tessellate_cad((dir / "cad" / "lamp.step").string(), o);
  ASSERT_TRUE(model.ok()) << to_string(model.error());
  ASSERT_EQ(model->parts.size(), 3u);
  for (const Reflector& r : w.parts.reflectors) {
    const auto part = std::find_if(model->parts.begin(), model->parts.end(),
                                   [&](const io::CadPart& p) { return p.name == r.name; });
    ASSERT_NE(part, model->parts.end()) << r.name;
    EXPECT_EQ(part->faces, 1u) << r.name;
    Result<ProfileCurve> curve = ProfileCurve::make(r.profile);
    ASSERT_TRUE(curve.ok());
    // Every vertex on the exact surface (within the B-spline's tolerance and
    // the samples' spacing) and the profile's whole span covered.
    double worst = 0.0, z_lo = 1e9, z_hi = -1e9, rho_lo = 1e9, rho_hi = -1e9;
    std::size_t vertices = 0;
    for (const io::CadSurface& s : part->surfaces)
      for (std::size_t i = 0; i < s.positions.size(); ++i) {
        const sim::Vec3f& p = s.positions[i];
        const double rho = std::hypot(double(p.x), double(p.y)), z = p.z;
        // distance_to_profile walks the whole curve: every 7th vertex.
        if (i % 7 == 0) worst = std::max(worst, distance_to_profile(*curve, rho, z));
        z_lo = std::min(z_lo, z), z_hi = std::max(z_hi, z);
        rho_lo = std::min(rho_lo, rho), rho_hi = std::max(rho_hi, rho);
        ++vertices;
      }
    EXPECT_GT(vertices, 100u) << r.name;
    // 1 µm of the B-spline, and the float of the vertices (60 mm · 2⁻²⁴ ≈ 4 nm).
    EXPECT_LT(worst, 1.5e-6) << r.name;
    double e_rho_lo = 1e9, e_rho_hi = -1e9, e_z_lo = 1e9, e_z_hi = -1e9;
    for (int i = 0; i <= 1000; ++i) {
      double rho = 0, z = 0, dr = 0, dz = 0;
      curve->eval(curve->t0() + (curve->t1() - curve->t0()) * i / 1000.0, rho, z, dr, dz);
      e_rho_lo = std::min(e_rho_lo, rho), e_rho_hi = std::max(e_rho_hi, rho);
      e_z_lo = std::min(e_z_lo, z), e_z_hi = std::max(e_z_hi, z);
    }
    EXPECT_NEAR(rho_hi, e_rho_hi, 2e-6) << r.name;
    EXPECT_NEAR(rho_lo, e_rho_lo, 2e-6) << r.name;
    EXPECT_NEAR(z_hi, e_z_hi, 2e-6) << r.name;
    EXPECT_NEAR(z_lo, e_z_lo, 2e-6) << r.name;
  }

  // The sidecar: a rule per part with its material, the emitter's profile
  // found from the STEP's folder, so that the STEP loads as a luminaire.
  Result<io::PartsFile> sidecar = io::read_parts_file(w.info.sidecar);
  ASSERT_TRUE(sidecar.ok()) << to_string(sidecar.error());
  ASSERT_EQ(sidecar->rules.size(), 3u);
  ASSERT_EQ(sidecar->emitters.size(), 1u);
  EXPECT_EQ(sidecar->emitters[0].profile, "led.ies");
  EXPECT_EQ(test::read_file(dir / "cad" / "led.ies"), "not read by the export\n");
  std::map<std::string, std::string> material_of;
  for (const io::PartsRule& rule : sidecar->rules) material_of[rule.match] = rule.material;
  EXPECT_EQ(material_of["Outer dish"], "mirror");
  EXPECT_EQ(material_of["polar"], "white");
  EXPECT_EQ(material_of["spline"], "mirror");
}

// The request gonio hands the helper: a round trip, and malformed ones refused.
TEST(DesignStep, TheHelpersRequestRoundTripsAndRefusesMalformedText) {
  io::StepExport r;
  r.product = "lamp";
  r.tolerance_mm = 2.5e-4;
  r.parts.push_back({"a dish", {0.0, 1.0 / 3.0, 30.0}, {10.0, 9.5, -12.5}, {}});
  r.parts.push_back({"b", {4.0, 5.0}, {1.0, 2.0}, {}});
  r.parts.push_back({"lens", {0.0, 5.0, 5.0, 0.0}, {-1.0, -1.0, -3.0, -3.0}, {0, 1, 2}});  // a disc
  Result<io::StepExport> back = io::parse_step_export(io::serialize_step_export(r), "request");
  ASSERT_TRUE(back.ok()) << to_string(back.error());
  EXPECT_EQ(back->product, "lamp");
  EXPECT_EQ(back->tolerance_mm, 2.5e-4);
  ASSERT_EQ(back->parts.size(), 3u);
  EXPECT_EQ(back->parts[0].name, "a dish");
  EXPECT_TRUE(back->parts[0].curves.empty());
  EXPECT_EQ(back->parts[2].curves, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(back->parts[0].rho, r.parts[0].rho);  // 17 digits: exact
  EXPECT_EQ(back->parts[0].z, r.parts[0].z);
  const std::string good = io::serialize_step_export(r);
  for (const std::string& bad :
       {std::string(), std::string("gonio-step-export 2\n"), good.substr(0, good.size() - 6),
        good + "trailing\n",
        std::string("gonio-step-export 1\nproduct p\ntolerance 1\nparts 1\npart a\npoints 2\n-1 2\n2 3\n"),
        std::string("gonio-step-export 1\nproduct p\ntolerance 0\nparts 1\n"),
        std::string("gonio-step-export 1\nproduct p\ntolerance 1\nparts 1\npart a\npoints 2\n1 nan\n2 3\n"),
        std::string("gonio-step-export 1\nproduct p\ntolerance 1\nparts 1\npart a\npoints 1\n1 2\n"),
        std::string("gonio-step-export 1\nproduct p\ntolerance 1\nparts 1\npart a\ncurves 2 0 0\npoints 2\n1 2\n2 3\n"),
        std::string("gonio-step-export 1\nproduct p\ntolerance 1\nparts 1\npart a\ncurves 2 0 1\npoints 2\n1 2\n2 3\n"),
        std::string("gonio-step-export 1\nproduct p\ntolerance 1\nparts 1\npart a\ncurves 1 1\npoints 2\n1 2\n2 3\n")}) {
    Result<io::StepExport> parsed = io::parse_step_export(bad, "request");
    EXPECT_FALSE(parsed.ok()) << bad;
  }
}

TEST(DesignStep, ADesignWithoutPartsOrWithABadToleranceIsAnError) {
  test::TempDir dir;
  Result<Design> empty = parse_design("length_unit = \"mm\"\n", (dir / "e.design.toml").string());
  ASSERT_TRUE(empty.ok());
  Result<StepExportInfo> r = write_design_step(*empty, (dir / "e.step").string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("no parts"), std::string::npos) << r.error().message;
  EXPECT_FALSE(fs::exists(dir / "e.step"));
  Result<Design> d = parse_design(kDesign, (dir / "lamp.design.toml").string());
  ASSERT_TRUE(d.ok());
  r = write_design_step(*d, (dir / "lamp.step").string(), 0.0);
  ASSERT_FALSE(r.ok());
  EXPECT_FALSE(fs::exists(dir / "lamp.step"));
}

// What FreeCAD made of a STEP file (tests/design/read_step.py): per object
// with a shape its type, area and faces, by label.
struct FreeCadObject {
  std::string type;
  double area_mm2 = 0.0;
  int faces = 0;
};
struct FreeCadListing {
  bool missing = false;  // no freecadcmd: `text` says why
  std::string text;      // the listing, or FreeCAD's output where it wrote none
  std::map<std::string, FreeCadObject> found;
};
FreeCadListing freecad_listing(const fs::path& step, const fs::path& dir) {
  FreeCadListing out;
  const fs::path py = test::source_dir() / "tests" / "design" / "read_step.py";
  const fs::path listing = dir / "parts.txt";
  // FreeCAD runs one at a time (its user folder is shared): the CAD tests' lock.
  const fs::path lock_dir = fs::path(GONIO_TEST_DATA_DIR) / "cad";
  fs::create_directories(lock_dir);
  const int lock = ::open((lock_dir / ".lock").c_str(), O_CREAT | O_RDWR, 0644);
  if (lock >= 0) ::flock(lock, LOCK_EX);
  test::ScopedEnv in("GONIO_STEP_IN", step.c_str());
  test::ScopedEnv env_out("GONIO_STEP_OUT", listing.c_str());
  Result<io::ProcessOutput> fc = io::run_program({"freecadcmd", py.string()}, std::chrono::seconds(300),
                                                 std::size_t{1} << 20, "install Debian's freecad (scripts/setup.sh)");
  if (lock >= 0) ::close(lock);
  if (!fc.ok()) {
    out.missing = true;
    out.text = fc.error().message;
    return out;
  }
  if (!fs::exists(listing)) {
    out.text = fc->out + fc->err;
    return out;
  }
  out.text = test::read_file(listing);
  std::istringstream lines(out.text);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string label, type, area, faces;
    if (!(std::getline(fields, label, '\t') && std::getline(fields, type, '\t') && std::getline(fields, area, '\t') &&
          std::getline(fields, faces, '\t')))
      continue;
    out.found[label] = {type, std::stod(area), std::stoi(faces)};
  }
  return out;
}

TEST(DesignStep, FreeCadFindsThePartsByName) {
  test::TempDir dir;
  const Written w = write_step(dir.path());
  FreeCadListing fc = freecad_listing(dir / "cad" / "lamp.step", dir.path());
  if (fc.missing) GONIO_MISSING("FreeCAD's freecadcmd on PATH: " + fc.text);
  std::map<std::string, FreeCadObject>& found = fc.found;
  ASSERT_EQ(found.size(), 4u) << fc.text;
  // The assembly, named by the file, holds the three parts.
  ASSERT_TRUE(found.count("lamp")) << fc.text;
  EXPECT_EQ(found["lamp"].type, "App::Part");
  EXPECT_EQ(found["lamp"].faces, 3);
  for (const char* name : {"Outer dish", "polar", "spline"}) {
    ASSERT_TRUE(found.count(name)) << name << "\n" << fc.text;
    EXPECT_EQ(found[name].type, "Part::Feature") << name;
    EXPECT_EQ(found[name].faces, 1) << name;
  }
  // The paraboloid's area as FreeCAD integrates it on the B-spline surface.
  EXPECT_NEAR(found["Outer dish"].area_mm2 / dish_area_mm2(), 1.0, 1e-5);  // measured 1.1e-6
}

// Lenses as solids: the meniscus of tests/design/lens_test.cpp (spheres of
// R −40 and 30 mm, 6 mm thick, ρ to 12 mm) and a TIR collimator whose side
// is a quadratic B-spline.
const char* kLenses = R"(length_unit = "mm"

[materials.pmma]
dielectric = 1.0
ior = 1.491

[[emitters]]
name = "LED"
position = [0, 0, 0]
profile = "led.ies"

[[lenses]]
name = "lens"
material = "pmma"
vertex = -5
thickness = 6
aperture = 12
inner = { profile = "conic", radius = -40 }
outer = { profile = "conic", radius = 30 }

[[lenses]]
name = "tir"
material = "pmma"
vertex = -30
thickness = 18
aperture = 3
inner = { profile = "conic" }
outer = { profile = "bspline", degree = 1, points = [[0, 0], [15, 0]] }
side = { profile = "bspline", degree = 2, points = [[10, -32]] }
)";

// The meniscus's area: two spherical caps and the cylinder between the rims [mm²].
double meniscus_area_mm2() {
  const double hi = 40.0 - std::sqrt(40.0 * 40.0 - 144.0), ho = 30.0 - std::sqrt(30.0 * 30.0 - 144.0);
  const double zi_rim = -5.0 + hi, zo_rim = -11.0 - ho;
  return 2 * kPi * 40.0 * hi + 2 * kPi * 30.0 * ho + 2 * kPi * 12.0 * (zi_rim - zo_rim);
}

double distance_to_polygon(const std::vector<std::pair<double, double>>& poly, double rho, double z) {
  double best = INFINITY;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& a = poly[i];
    const auto& b = poly[(i + 1) % poly.size()];
    const double ex = b.first - a.first, ez = b.second - a.second, len2 = ex * ex + ez * ez;
    const double u = len2 > 0 ? std::clamp(((rho - a.first) * ex + (z - a.second) * ez) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, std::hypot(rho - a.first - u * ex, z - a.second - u * ez));
  }
  return best;
}

TEST(DesignStep, LensesAreSolidsOnTheirExactSurfaces) {
  test::TempDir dir;
  test::write_file(dir / "lenses.design.toml", kLenses);
  test::write_file(dir / "led.ies", "not read by the export\n");
  Result<Design> d = read_design_file((dir / "lenses.design.toml").string());
  ASSERT_TRUE(d.ok()) << to_string(d.error());
  Result<DesignParts> parts = read_design_parts(resolved_document(*d), d->path);
  ASSERT_TRUE(parts.ok()) << to_string(parts.error());
  Result<StepExportInfo> info = write_design_step(*d, (dir / "cad" / "lenses.step").string());
  ASSERT_TRUE(info.ok()) << to_string(info.error());
  EXPECT_EQ(info->parts, 2u);
  EXPECT_LE(info->max_deviation_mm, kStepToleranceMm);
  io::CadLoadOptions o;
  o.tessellation.angular_deflection_deg = 2.0;
  Result<io::CadModel> model = io::tessellate_cad((dir / "cad" / "lenses.step").string(), o);
  ASSERT_TRUE(model.ok()) << to_string(model.error());
  for (const Lens& lens : parts->lenses) {
    const auto part = std::find_if(model->parts.begin(), model->parts.end(),
                                   [&](const io::CadPart& p) { return p.name == lens.name; });
    ASSERT_NE(part, model->parts.end()) << lens.name;
    EXPECT_EQ(part->solids, 1u) << lens.name;
    EXPECT_EQ(part->faces, 3u) << lens.name;
    const std::vector<std::pair<double, double>> poly = lens_meridian(lens, 4096);
    double worst = 0.0;
    std::size_t vertices = 0;
    for (const io::CadSurface& s : part->surfaces)
      for (std::size_t i = 0; i < s.positions.size(); i += 5, ++vertices) {
        const sim::Vec3f& p = s.positions[i];
        worst = std::max(worst, distance_to_polygon(poly, std::hypot(double(p.x), double(p.y)), p.z));
      }
    EXPECT_GT(vertices, 100u) << lens.name;
    EXPECT_LT(worst, 2e-6) << lens.name;  // within the B-spline's 1 µm and the floats'
  }
  // The sidecar gives each lens its material.
  const std::string sidecar = test::read_file(dir / "cad" / "lenses.gonio.toml");
  EXPECT_NE(sidecar.find("match = \"tir\""), std::string::npos) << sidecar;
  EXPECT_EQ(sidecar.find("[[lenses]]"), std::string::npos) << sidecar;

  // FreeCAD finds the solids by name; the meniscus's area is the closed form's.
  FreeCadListing fc = freecad_listing(dir / "cad" / "lenses.step", dir.path());
  if (fc.missing) GONIO_MISSING("FreeCAD's freecadcmd on PATH: " + fc.text);
  std::map<std::string, FreeCadObject>& found = fc.found;
  for (const char* name : {"lens", "tir"}) {
    ASSERT_TRUE(found.count(name)) << name << "\n" << fc.text;
    EXPECT_EQ(found[name].type, "Part::Feature") << name;
  }
  std::printf("meniscus area: FreeCAD %.9g mm², closed form %.9g mm²\n", found["lens"].area_mm2, meniscus_area_mm2());
  EXPECT_NEAR(found["lens"].area_mm2 / meniscus_area_mm2(), 1.0, 1e-5);
}

// A trough (design/trough.h) as STEP: FreeCAD finds the part by its name, one
// face, of the parabolic cylinder's area 400 mm × 20 mm × (2√5 + asinh 2)
// (f = 10 mm, x over ±40 mm); measured 4·10⁻⁵ above it (docs/design.md).
TEST(DesignStep, FreeCadFindsTheTroughByName) {
  test::TempDir dir;
  Result<Design> d = parse_design(R"(length_unit = "mm"
[materials.mirror]
mirror = 1.0
[[emitters]]
name = "LED"
position = [0, 0, 0]
flux_lm = 1000
[[troughs]]
name = "Linear trough"
material = "mirror"
profile = "conic"
radius = 20
conic = -1
vertex = 10
aperture = [0, 40]
length = 400
)",
                                  (dir / "trough.design.toml").string());
  ASSERT_TRUE(d.ok());
  Result<StepExportInfo> info = write_design_step(*d, (dir / "trough.step").string());
  ASSERT_TRUE(info.ok()) << to_string(info.error());
  FreeCadListing fc = freecad_listing(dir / "trough.step", dir.path());
  if (fc.missing) GONIO_MISSING("FreeCAD's freecadcmd on PATH: " + fc.text);
  ASSERT_TRUE(fc.found.count("Linear trough")) << fc.text;
  const FreeCadObject& t = fc.found["Linear trough"];
  EXPECT_EQ(t.type, "Part::Feature");
  EXPECT_EQ(t.faces, 1);
  EXPECT_NEAR(t.area_mm2 / (400.0 * 20.0 * (2 * std::sqrt(5.0) + std::asinh(2.0))), 1.0, 1e-4);
}

// The request's B-spline patches and placed files (curved facets, fixed
// parts) round-trip to 17 digits; malformed ones are refused.
TEST(DesignStep, PatchesAndPlacedFilesRoundTripInTheRequest) {
  io::StepExport r;
  r.product = "lamp";
  io::StepRevolvedPart patches;
  patches.name = "dish";
  patches.patches = {2, 3};
  for (int i = 0; i < 6; ++i) patches.patch_points.insert(patches.patch_points.end(), {i / 3.0, 1.0 + i, -2.5 * i});
  r.parts.push_back(patches);
  io::StepRevolvedPart file;
  file.name = "housing";
  file.file = "/tmp/some where/housing.step";
  file.place = {0, -1, 0, 5, 2, 0, 0, 1.0 / 3.0, 0, 0, 2, -7};
  r.parts.push_back(file);
  const std::string text = io::serialize_step_export(r);
  Result<io::StepExport> back = io::parse_step_export(text, "request");
  ASSERT_TRUE(back.ok()) << to_string(back.error());
  ASSERT_EQ(back->parts.size(), 2u);
  EXPECT_EQ(back->parts[0].patches, patches.patches);
  EXPECT_EQ(back->parts[0].patch_points, patches.patch_points);
  EXPECT_EQ(back->parts[1].file, file.file);
  EXPECT_EQ(back->parts[1].place, file.place);
  const std::string head = "gonio-step-export 1\nproduct p\ntolerance 1\nparts 1\npart a\n";
  for (const std::string& bad : {head + "patches 1\n1 2 0 0 0 1 1 1\npoints 0\n",           // a row of one
                                 head + "patches 1\n2 2 0 0 0 1 1 1\npoints 0\n",           // too few numbers
                                 head + "patches 1\n2 2 0 0 0 1 1 1 2 2 2 3 3 nan\npoints 0\n",
                                 head + "patches 1\n2 2 0 0 0 1 1 1 2 2 2 3 3 3\npoints 2\n1 2\n2 3\n",
                                 head + "file x.step\nplace 1 0 0 0 0 1 0 0 0 0 1\npoints 0\n",  // 11 numbers
                                 head + "file x.step\npoints 0\n", head + "file \nplace 1 0 0 0 0 1 0 0 0 0 1 0\npoints 0\n"}) {
    EXPECT_FALSE(io::parse_step_export(bad, "request").ok()) << bad;
  }
}

// FreeCAD opens a design's STEP with curved facets, a placed STEP part and a
// placed glTF part and finds them by name: "dish", 6 × 12 curved facets (one
// B-spline face each), "lid/first", the placed file's product, and
// "shell/dish/…", the glTF's mesh as plane faces (1596 triangles: its area
// 0.27 % below the paraboloid's, the polyhedron inscribed in it).
TEST(DesignStep, FreeCadFindsCurvedFacetsAndFixedPartsByName) {
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
  Result<Design> first = parse_design(dish, (dir / "first.design.toml").string());
  ASSERT_TRUE(first.ok());
  Result<StepExportInfo> info = write_design_step(*first, (dir / "first.step").string());
  if (!info.ok() && !io::cad_supported()) GONIO_MISSING("a build with OpenCASCADE (GONIO_OCCT) for STEP export");
  ASSERT_TRUE(info.ok()) << to_string(info.error());
  // The same dish as glTF (coarse: 10°), a fixed glTF part "shell".
  io::CadTessellation coarse;
  coarse.angular_deflection_deg = 10.0;
  ASSERT_TRUE(write_design_gltf(*first, (dir / "first.gltf").string(), coarse).ok());
  Result<Design> d = parse_design(dish + "facets = { theta = 6, azimuth = 12, kind = \"curved\", radius_theta = 40, "
                                         "radius_azimuth = 100 }\n[[parts]]\nname = \"lid\"\nfile = \"first.step\"\n"
                                         "position = [0, 0, 40]\nrotate_deg = [180, 0, 0]\nmaterial = \"mirror\"\n"
                                         "[[parts]]\nname = \"shell\"\nfile = \"first.gltf\"\nposition = [0, 0, -40]\n",
                                  (dir / "lamp.design.toml").string());
  ASSERT_TRUE(d.ok()) << to_string(d.error());
  info = write_design_step(*d, (dir / "lamp.step").string());
  ASSERT_TRUE(info.ok()) << to_string(info.error());
  FreeCadListing fc = freecad_listing(dir / "lamp.step", dir.path());
  if (fc.missing) GONIO_MISSING("FreeCAD's freecadcmd on PATH: " + fc.text);
  ASSERT_TRUE(fc.found.count("dish")) << fc.text;
  EXPECT_EQ(fc.found["dish"].faces, 72) << fc.text;
  ASSERT_TRUE(fc.found.count("lid/first")) << fc.text;
  EXPECT_GE(fc.found["lid/first"].faces, 1) << fc.text;
  // The placed paraboloid keeps its area (a rigid placement): (2π·R²/3)·[(1 + ρ²/R²)^(3/2)] over ρ 4 … 30 mm, R = 20 mm.
  const double area = 2 * std::acos(-1.0) * 400.0 / 3.0 * (std::pow(1 + 900.0 / 400, 1.5) - std::pow(1 + 16.0 / 400, 1.5));
  EXPECT_NEAR(fc.found["lid/first"].area_mm2 / area, 1.0, 1e-5) << fc.text;
  // The glTF part: its triangles as plane faces, one part named as placed; a
  // polyhedron inscribed in the paraboloid, its area a little below the surface's.
  // (The simulation names the glTF loader's mesh "dish/dish/0": "shell/" and that.)
  const auto shell = std::find_if(fc.found.begin(), fc.found.end(),
                                  [](const auto& f) { return f.first.rfind("shell/dish", 0) == 0; });
  ASSERT_NE(shell, fc.found.end()) << fc.text;
  EXPECT_GT(shell->second.faces, 100) << fc.text;
  EXPECT_NEAR(shell->second.area_mm2 / area, 1.0, 0.02) << fc.text;
  EXPECT_LT(shell->second.area_mm2, area) << fc.text;
}

}  // namespace
}  // namespace gonio::design
