// gonio simulate, watch and bench on CAD models (STEP with a TOML sidecar,
// io/model/cad.h), run as a user would, on the parts FreeCAD writes at test
// time (tests/cad/make_parts.py).
//
// The reflector is an ideal paraboloid (focal length 10 mm, lamp hole r = 4 mm,
// aperture r = 30 mm) with its focus at the file's origin, opening towards
// −Z, which is the nadir (γ = 0) of CAD's default frame. An isotropic point
// source of Φ at the focus gives, in closed form:
//   - γ < 67.38° (inside the aperture's cone, atan(30/12.5)): the direct
//     light only, I = Φ/4π;
//   - 67.38° < γ < 157.38° (the mirror as seen from the focus): nothing;
//   - γ > 157.38° (through the lamp hole, atan(4/9.6) from the zenith): Φ/4π;
//   - the mirror's share of the sphere, (cos 22.62° − cos 112.62°)/2 = 0.654,
//     leaves about the axis: a beam at γ = 0.
// The mirror is a smooth glossy lobe (Beckmann roughness 0.1, f0 = 1, whose
// albedo is 1 − 3·10⁻⁵ at these incidences, sim/bsdfs/material.h), so that the beam
// is about ten degrees wide: an ideal mirror's would be a delta, which no
// C-γ grid carries (the energy check says so, rightly: the IES file's flux
// would miss the escaped flux by 13 %, by 1 % at roughness 0.05). Its tail
// adds under 0.3 % to the direct light beyond γ = 35° (facets tilted 17.5°:
// exp(−tan²17.5°/0.1²) = 5·10⁻⁵ of the beam's peak density), and next to
// nothing is absorbed: the escaped flux is Φ.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/photometric/photometric_file.h"
#include "tests/io/model/cad_parts.h"
#include "tests/support/test_support.h"

extern char** environ;

namespace gonio {
namespace {

namespace fs = std::filesystem;

constexpr double kFlux = 1000.0;                                // the sidecar's flux_lm
constexpr double kDirect = kFlux / (4.0 * std::numbers::pi);   // Φ/4π [cd]

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

nlohmann::json read_json(const fs::path& file) { return nlohmann::json::parse(test::read_file(file)); }

std::string reflector_sidecar(double flux_lm) {
  return R"(
[materials.mirror]
ks = 1
mx = 0.1
my = 0.1
f0 = 1

[[parts]]
match = "Reflector"
material = "mirror"

[[emitters]]
name = "lamp"
position = [0, 0, 0]          # the paraboloid's focus, in the file's millimetres
flux_lm = )" + std::to_string(flux_lm) + "\n";
}

// A copy of the FreeCAD reflector with its sidecar beside it, in `dir`.
fs::path reflector_with_sidecar(const fs::path& parts, const fs::path& dir, double flux_lm = kFlux) {
  const fs::path model = dir / "reflector.step";
  fs::copy_file(parts / "reflector.step", model, fs::copy_options::overwrite_existing);
  test::write_file(dir / "reflector.gonio.toml", reflector_sidecar(flux_lm));
  return model;
}

// The IES file's intensity averaged over its C planes and over γ in [lo, hi].
double mean_intensity(const fs::path& ies, double lo_deg, double hi_deg) {
  Result<io::PhotometricFile> f = io::read_photometric_file(ies.string());
  EXPECT_TRUE(f.ok()) << to_string(f.error());
  if (!f.ok()) return std::nan("");
  const photometry::Distribution& d = f->distribution;
  double sum = 0.0;
  int n = 0;
  for (std::size_t h = 0; h < d.horizontal_count(); ++h)
    for (std::size_t v = 0; v < d.vertical_count(); ++v)
      if (d.vertical_deg[v] >= lo_deg && d.vertical_deg[v] <= hi_deg) {
        sum += d.at(h, v);
        ++n;
      }
  return n ? sum / n : std::nan("");
}

// The whole run: files written, report.json's cad section, the energy checks,
// and the far field's closed form. A mistake in the frame (Y-up as glTF),
// the unit (metres read as millimetres moves the source off the focus), the
// sidecar's material or the exact normals shows in the intensities.
TEST(SimulateCad, FreeCadReflectorWithItsSidecarEndToEnd) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  test::TempDir dir;
  const fs::path model = reflector_with_sidecar(parts, dir.path());
  const fs::path out = dir / "out";
  const auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "200000", "--iterations",
                        "2", "--cache", (dir / "cache").string(), "--threads", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"reflector.ies", "reflector.ldt", "farfield.exr", "farfield-latlong.exr", "reflector.svg",
                        "report.json"})
    EXPECT_TRUE(fs::is_regular_file(out / f)) << f;

  const auto report = read_json(out / "report.json");
  ASSERT_TRUE(report.contains("cad")) << report.dump(2);
  const auto& cad = report["cad"];
  EXPECT_EQ(cad["format"], "STEP");
  EXPECT_EQ(cad["parts_file"], (dir / "reflector.gonio.toml").string());
  EXPECT_EQ(cad["parts"], 1);
  EXPECT_EQ(cad["placements"], 1);
  EXPECT_DOUBLE_EQ(cad["tessellation"]["angular_deflection_deg"].get<double>(), 2.0);  // 0.8 × the 2.5° step
  EXPECT_TRUE(cad["tessellation"]["exact_normals"].get<bool>());
  EXPECT_TRUE(cad["tessellation"]["chordal_mm"].is_null());
  EXPECT_FALSE(cad["from_cache"].get<bool>());
  EXPECT_EQ(cad["triangles_unique"], report["setup"]["triangles_unique"]);
  ASSERT_EQ(cad["per_part"].size(), 1u);
  EXPECT_EQ(cad["per_part"][0]["name"], "Reflector");
  EXPECT_EQ(cad["per_part"][0]["triangles"], cad["triangles_unique"]);
  // The part's size is its bounding box's diagonal: 60 × 60 × 22.1 mm.
  EXPECT_NEAR(cad["per_part"][0]["size_mm"].get<double>(), std::sqrt(60.0 * 60 + 60 * 60 + 22.1 * 22.1), 0.5);
  EXPECT_TRUE(report["energy"]["passed"].get<bool>()) << report["energy"].dump();
  EXPECT_NEAR(report["escaped_lm"].get<double>(), kFlux, 1e-3 * kFlux);  // a (nearly) lossless mirror

  const fs::path ies = out / "reflector.ies";
  EXPECT_NEAR(mean_intensity(ies, 35.0, 62.5), kDirect, 0.03 * kDirect);
  EXPECT_LT(mean_intensity(ies, 72.5, 152.5), 0.01 * kDirect);
  EXPECT_NEAR(mean_intensity(ies, 162.5, 180.0), kDirect, 0.05 * kDirect);
  EXPECT_GT(mean_intensity(ies, 0.0, 0.0), 20.0 * kDirect);  // the beam
}

// --tessellation overrides what the grid asks for; a γ step of 5° asks for
// 4°, the same settings as --tessellation 4, so that run finds the mesh in
// the cache. report.json says which, with the triangle counts.
TEST(SimulateCad, TessellationFollowsTheGridOrTheOptionAndIsCached) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  test::TempDir dir;
  const fs::path model = reflector_with_sidecar(parts, dir.path());
  auto run = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"simulate", model.string(), "--out", (dir / name).string(), "--photons",
                                     "20000", "--iterations", "1", "--format", "ies", "--cache",
                                     (dir / "cache").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = gonio(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return read_json(dir / name / "report.json")["cad"];
  };
  const auto fine = run("default", {});
  const auto coarse = run("option", {"--tessellation", "4"});
  // (A 5° grid carries this ten-degree beam's flux to 1.2 %, not the default 0.5 %.)
  const auto grid = run("grid", {"--gamma-step", "5", "--flux-tolerance", "0.02"});
  EXPECT_DOUBLE_EQ(fine["tessellation"]["angular_deflection_deg"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(coarse["tessellation"]["angular_deflection_deg"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(grid["tessellation"]["angular_deflection_deg"].get<double>(), 4.0);
  EXPECT_FALSE(fine["from_cache"].get<bool>());
  EXPECT_FALSE(coarse["from_cache"].get<bool>());
  EXPECT_TRUE(grid["from_cache"].get<bool>());
  // Halving the angle about quadruples the facets (docs/cad.md: 3 065 at 4°,
  // 12 290 at 2°).
  const double ratio = fine["triangles_unique"].get<double>() / coarse["triangles_unique"].get<double>();
  EXPECT_GT(ratio, 2.5);
  EXPECT_LT(ratio, 6.0);
  EXPECT_EQ(grid["triangles_unique"], coarse["triangles_unique"]);

  const auto chordal = run("chordal", {"--tessellation", "4,0.05"});
  EXPECT_DOUBLE_EQ(chordal["tessellation"]["chordal_mm"].get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(chordal["per_part"][0]["chordal_deflection_mm"].get<double>(), 0.05);
}

// Parts no rule covers: one error listing every placement, exit 1, no
// output folder.
TEST(SimulateCad, PartsWithoutAMaterialAreListedAllAndNothingIsWritten) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  test::TempDir dir;
  const fs::path model = dir / "lamp.step";
  fs::copy_file(parts / "lamp.step", model);
  const fs::path sidecar = dir / "optics.toml";  // given with --parts
  test::write_file(sidecar, R"(
[materials.mirror]
reflectance = 0.9

[[parts]]
match = "Reflector"
material = "mirror"

[[emitters]]
at = "LED1"
flux_lm = 100
)");
  const fs::path out = dir / "out";
  const auto r = gonio({"simulate", model.string(), "--parts", sidecar.string(), "--out", out.string(),
                        "--photons", "1000", "--iterations", "1", "--cache", (dir / "cache").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  for (const char* part : {"Lamp/Housing", "Lamp/LED1", "Lamp/LED2", "Lamp/LED3", "Lamp/FrontLens"})
    EXPECT_NE(r.err.find(part), std::string::npos) << part << " missing from: " << r.err;
  EXPECT_EQ(r.err.find("Lamp/Reflector"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("5 part placement(s) have no material"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(model.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(sidecar.string()), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
}

// A STEP file cut short: an error naming the file and where OpenCASCADE's
// parser stopped, exit 1, nothing written, the input untouched.
TEST(SimulateCad, TruncatedStepIsAnErrorNamingTheFileAndNothingIsWritten) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  test::TempDir dir;
  const std::string whole = test::read_file(parts / "reflector.step");
  const std::string cut = whole.substr(0, whole.size() / 2);
  const fs::path model = dir / "reflector.step";
  test::write_file(model, cut);
  test::write_file(dir / "reflector.gonio.toml", reflector_sidecar(kFlux));
  const fs::path out = dir / "out";
  const auto r = gonio({"simulate", model.string(), "--out", out.string(), "--cache", (dir / "cache").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(model.string() + ":"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("unexpected end of file"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(test::read_file(model), cut);
  EXPECT_FALSE(fs::exists(dir / "cache") && !fs::is_empty(dir / "cache"));  // nothing cached either
}

// A sidecar with a mistake: an error naming the sidecar and the line
// (toml++'s for syntax, the reader's for an unknown key), exit 1, nothing
// written. A message that named the model only, or lost the line, would
// leave the user hunting; one that fell back to a default would hide it.
TEST(SimulateCad, BadSidecarIsAnErrorNamingItsFileAndLine) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  test::TempDir dir;
  const fs::path model = reflector_with_sidecar(parts, dir.path());
  const fs::path sidecar = dir / "reflector.gonio.toml";
  struct Case {
    const char* what;
    std::string text;
    std::string where;  // "FILE:LINE" expected in the message
    const char* says;
  };
  const std::vector<Case> cases = {
      {"syntax", "[materials.mirror]\nks = 1\nmx = = 0.1\n", sidecar.string() + ":3", ""},
      {"unknown key", "[materials.mirror]\nks = 1\n\n[[parts]]\nmatch = \"Reflector\"\nmaterial = \"mirror\"\nshiny = true\n",
       sidecar.string() + ":7", "unknown key 'shiny'"},
      {"undefined material", "[[parts]]\nmatch = \"Reflector\"\nmaterial = \"chrome\"\n", sidecar.string() + ":1: ",
       "chrome' is not defined"},
  };
  for (const Case& c : cases) {
    test::write_file(sidecar, c.text);
    const fs::path out = dir / "out";
    const auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "1000", "--iterations",
                          "1", "--cache", (dir / "cache").string()});
    EXPECT_EQ(r.exit_code, 1) << c.what << ": " << r.err;
    EXPECT_NE(r.err.find(c.where), std::string::npos) << c.what << ": " << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.what << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.what;
    EXPECT_EQ(test::read_file(sidecar), c.text) << c.what;  // inputs untouched
  }
  // No sidecar at all: the error names the one it looked for.
  fs::remove(sidecar);
  const auto r = gonio({"simulate", model.string(), "--out", (dir / "out").string(), "--cache",
                        (dir / "cache").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(sidecar.string()), std::string::npos) << r.err;
  // --parts naming a file that is not there: the same, for that file.
  const auto given = gonio({"simulate", model.string(), "--parts", (dir / "optics.toml").string(), "--out",
                            (dir / "out").string(), "--cache", (dir / "cache").string()});
  EXPECT_EQ(given.exit_code, 1) << given.err;
  EXPECT_NE(given.err.find((dir / "optics.toml").string()), std::string::npos) << given.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// IGES through the command line (written by FreeCAD and by OpenCASCADE's
// DRAW): report.json says IGES, and a sidecar's default_material covers
// whatever the file calls its parts. An isotropic source of Φ inside a
// black box absorbs (nearly) everything: what escapes is what the box
// reflects, ks 0, kd 0.05, a closed form only in the limit; asserted as
// less than a tenth.
TEST(SimulateCad, IgesModelsAreSimulatedWithTheirSidecar) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  test::TempDir dir;
  for (const char* name : {"pcx_lens", "block"}) {
    const fs::path model = dir / (std::string(name) + ".igs");
    fs::copy_file(parts / (std::string(name) + ".igs"), model);
    test::write_file(dir / (std::string(name) + ".gonio.toml"), R"(
default_material = "black"

[materials.black]
kd = 0.05

[[emitters]]
name = "lamp"
position = [0, 0, -1000]      # far below the part, in the file's unit
flux_lm = 100
)");
    const fs::path out = dir / name;
    const auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "20000", "--iterations",
                          "1", "--format", "ies", "--cache", (dir / "cache").string()});
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    const auto report = read_json(out / "report.json");
    EXPECT_EQ(report["cad"]["format"], "IGES") << name;
    EXPECT_GE(report["cad"]["parts"].get<int>(), 1) << name;
    EXPECT_GT(report["cad"]["triangles_unique"].get<int>(), 0) << name;
    // The part hides a little of the sphere: most of the flux escapes.
    EXPECT_GT(report["escaped_lm"].get<double>(), 90.0) << name;
    EXPECT_LE(report["escaped_lm"].get<double>(), 100.0 + 1e-6) << name;
  }
}

// An emissive part, as a user runs it (issue 45). Mistake: Φ = L·A instead
// of π·L·A for a sidecar material with luminance_cd_m2. make_parts.py's
// panel is a 10 × 10 mm square in z = 0 facing +Z (the zenith, γ = 180°, of
// CAD's default frame); at L = 10⁴ cd/m² it emits Φ = π·L·A = π lm, the
// ledger's emitted flux to rounding, and its far field is Lambertian,
// I(γ) = L·A·|cos γ| = 1 cd·|cos γ| above it and nothing below. The peak is
// fitted to every bin above the panel (I₀ = Σ I·c·w / Σ c²·w, c = |cos γ|,
// w = sin γ), and the zenith's own bin (the cap γ > 178.75°, 4.8·10⁻⁴ of the
// photons: ±3 % at 2²¹) is checked loosely.
TEST(SimulateCad, EmissivePanelEmitsPiLuminanceAreaAndPeaksAtLuminanceArea) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  test::TempDir dir;
  const fs::path model = dir / "panel.step";
  fs::copy_file(parts / "panel.step", model);
  test::write_file(dir / "panel.gonio.toml", R"(
[materials.panel]
luminance_cd_m2 = 1.0e4

[[parts]]
match = "Panel"
material = "panel"
)");
  const double peak = 1.0e4 * 1.0e-4;  // L·A [cd]
  const fs::path out = dir / "out";
  const auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "2097152", "--iterations",
                        "1", "--format", "ies", "--cache", (dir / "cache").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_json(out / "report.json");
  // (The area is the mesh's, of float vertices: to 1e-6.)
  EXPECT_NEAR(report["emitted_lm"].get<double>(), std::numbers::pi * peak, 1e-6 * std::numbers::pi * peak);
  EXPECT_NEAR(report["escaped_lm"].get<double>(), report["emitted_lm"].get<double>(), 1e-9);

  Result<io::PhotometricFile> f = io::read_photometric_file((out / "panel.ies").string());
  ASSERT_TRUE(f.ok()) << to_string(f.error());
  const photometry::Distribution& d = f->distribution;
  double icw = 0.0, ccw = 0.0;
  for (std::size_t h = 0; h < d.horizontal_count(); ++h)
    for (std::size_t v = 0; v < d.vertical_count(); ++v) {
      const double g = d.vertical_deg[v] * std::numbers::pi / 180.0;
      if (d.vertical_deg[v] <= 90.0) continue;
      const double c = -std::cos(g), w = std::sin(g);
      icw += d.at(h, v) * c * w;
      ccw += c * c * w;
    }
  ASSERT_GT(ccw, 0.0);
  EXPECT_NEAR(icw / ccw, peak, 0.01 * peak) << "the Lambertian fit's peak";
  EXPECT_NEAR(mean_intensity(out / "panel.ies", 180.0, 180.0), peak, 0.12 * peak) << "the zenith's bin";
  EXPECT_LT(mean_intensity(out / "panel.ies", 0.0, 87.5), 1e-3 * peak) << "one-sided: nothing below the panel";
}

// A reflector whose face is written reversed (issue 45) must reflect as the
// one written forward. Mistake: the exact-surface normals of a REVERSED face
// not flipped, so that they point against the facets and the reader falls
// back to the facets' normals averaged at each vertex (up to 1.7° off the
// surface at the default δ = 2°): a reflected ray turns by twice that, and
// the collimated beam widens. An ideal mirror (mirror = 1) and an isotropic
// source of Φ at the focus give, in closed form, the nadir cap (γ < 1.25°)
// I₀ = Φ·(f_r + Ω_cap/4π)/Ω_cap, f_r the share of the sphere the mirror
// subtends from the focus (0.654), and beside it, at γ = 2.5°, little more
// than the direct light Φ/4π.
// Measured at 2¹⁸ photons: both files 437 256 cd at the nadir (closed form
// 437 368) and 97 cd at 2.5° (Φ/4π = 79.6); with the mistake the reversed file's beam spills 592 cd
// into 2.5° and its peak falls 0.9 %. An ideal mirror's beam is narrower
// than the grid, so the IES file's flux misses the escaped flux by ~13 %:
// --flux-tolerance 0.5.
TEST(SimulateCad, ReversedReflectorCollimatesAsTheForwardOne) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  test::TempDir dir;
  const double f = 10.0, r0 = 4.0, r1 = 30.0;  // make_parts.py [mm]
  auto polar = [&](double r) { return std::atan2(r, f - r * r / (4 * f)); };
  const double share = (std::cos(polar(r0)) - std::cos(polar(r1))) / 2.0;
  const double cap = 2 * std::numbers::pi * (1 - std::cos(1.25 * std::numbers::pi / 180));
  const double nadir = kFlux * (share + cap / (4 * std::numbers::pi)) / cap;
  double peaks[2] = {}, beside[2] = {};
  int i = 0;
  for (const char* stem : {"reflector", "reflector_reversed"}) {
    SCOPED_TRACE(stem);
    const fs::path model = dir / (std::string(stem) + ".step");
    fs::copy_file(parts / (std::string(stem) + ".step"), model);
    test::write_file(dir / (std::string(stem) + ".gonio.toml"), R"(
[materials.mirror]
mirror = 1.0

[[parts]]
match = "Reflector*"
material = "mirror"

[[emitters]]
name = "lamp"
position = [0, 0, 0]
flux_lm = )" + std::to_string(kFlux) + "\n");
    const fs::path out = dir / stem;
    const auto r = gonio({"simulate", model.string(), "--out", out.string(), "--photons", "262144", "--iterations",
                          "1", "--format", "ies", "--flux-tolerance", "0.5", "--cache", (dir / "cache").string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const fs::path ies = out / (std::string(stem) + ".ies");
    peaks[i] = mean_intensity(ies, 0.0, 0.0);
    beside[i] = mean_intensity(ies, 2.5, 2.5);
    EXPECT_NEAR(peaks[i], nadir, 0.01 * nadir) << "the beam's peak against the closed form";
    EXPECT_LT(beside[i], 1.5 * kDirect) << "the beam's width: light beside the nadir cap beyond the direct light";
    ++i;
  }
  // The same mesh, its facets wound the other way: the same far field.
  EXPECT_NEAR(peaks[1], peaks[0], 0.002 * peaks[0]) << "reversed against forward";
  EXPECT_NEAR(beside[1], beside[0], 0.05 * beside[0]) << "reversed against forward";
}

TEST(SimulateCad, OptionsAreCheckedAndDocumented) {
  test::TempDir dir;
  const std::string out = (dir / "out").string();
  for (const char* bad : {"0", "91", "abc", "2,", "2,-1", "2,x"}) {
    const auto r = gonio({"simulate", (dir / "lamp.step").string(), "--out", out, "--tessellation", bad});
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find("--tessellation"), std::string::npos) << r.err;
  }
  // A glTF model says its own materials and is meshed already.
  for (const char* option : {"--parts", "--tessellation"}) {
    const auto r = gonio({"simulate", (dir / "lamp.glb").string(), "--out", out, option, "2"});
    EXPECT_EQ(r.exit_code, 2) << option;
    EXPECT_NE(r.err.find(option), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("CAD models"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(out));
  for (const char* command : {"simulate", "watch", "bench"}) {
    const auto help = gonio({command, "--help"});
    EXPECT_EQ(help.exit_code, 0);
    for (const char* word : {"--parts", "--tessellation", ".step"})
      EXPECT_NE(help.out.find(word), std::string::npos) << command << " --help lacks " << word;
  }
}

TEST(BenchCad, TakesAStepModelWithItsSidecar) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  test::TempDir dir;
  const fs::path model = reflector_with_sidecar(parts, dir.path());
  const auto r = gonio({"bench", model.string(), "--out", (dir / "out").string(), "--photons", "16384", "--first",
                        "4096", "--reference", "65536", "--no-png", "--threads", "2", "--sampler", "random",
                        "--tessellation", "4"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "out" / "series.csv"));
  EXPECT_TRUE(fs::is_regular_file(dir / "out" / "bench.json"));
  EXPECT_NE(r.out.find("reflector"), std::string::npos) << r.out;
}

// `gonio watch` runs in the background while the test edits files.
class Background {
 public:
  Background(const std::vector<std::string>& args, const fs::path& log) {
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    if (posix_spawn(&pid_, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  ~Background() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  bool running() {
    int status = 0;
    if (pid_ <= 0) return false;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      return false;
    }
    return true;
  }
  // Ctrl-C, then its exit code (-1: it had to be killed, or died of a signal).
  int interrupt(std::chrono::seconds patience) {
    if (pid_ > 0) ::kill(pid_, SIGINT);
    const auto until = std::chrono::steady_clock::now() + patience;
    while (running() && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    return running() ? -1 : exit_code_;
  }

 private:
  pid_t pid_ = -1;
  int exit_code_ = -1;
};

// Waits until `file` holds JSON for which `done` is true (the watch writes
// report.json atomically after each finished run).
std::optional<nlohmann::json> wait_for_report(const fs::path& file, Background& watch,
                                              const std::function<bool(const nlohmann::json&)>& done) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::minutes(3);
  while (std::chrono::steady_clock::now() < until && watch.running()) {
    std::error_code ec;
    if (fs::is_regular_file(file, ec)) {
      const nlohmann::json j = nlohmann::json::parse(test::read_file(file), nullptr, false);
      if (!j.is_discarded() && done(j)) return j;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return std::nullopt;
}

// The sidecar is one of the files watch watches: halving its flux starts a
// new run whose report says so, with the mesh from the cache; a change to
// the model starts another that meshes it again. A watch that followed the
// model only would never see the new flux.
TEST(WatchCad, AnEditedSidecarStartsANewRun) {
  GONIO_REQUIRE_CAD_PARTS(parts);
  test::TempDir dir;
  const fs::path model = reflector_with_sidecar(parts, dir.path());
  const fs::path out = dir / "out";
  Background watch({GONIO_EXECUTABLE, "watch", model.string(), "--port", "0", "--out", out.string(), "--photons",
                    "20000", "--iterations", "1", "--format", "ies", "--cache", (dir / "cache").string(),
                    "--threads", "2"},
                   dir / "watch.log");
  auto escaped_near = [](double flux) {
    return [flux](const nlohmann::json& j) {
      return j.contains("escaped_lm") && std::abs(j["escaped_lm"].get<double>() - flux) < 1e-3 * flux;
    };
  };
  const auto first = wait_for_report(out / "report.json", watch, escaped_near(kFlux));
  ASSERT_TRUE(first) << test::read_file(dir / "watch.log");
  EXPECT_EQ((*first)["cad"]["parts_file"], (dir / "reflector.gonio.toml").string());
  test::write_file(dir / "reflector.gonio.toml", reflector_sidecar(kFlux / 2));
  const auto second = wait_for_report(out / "report.json", watch, escaped_near(kFlux / 2));
  ASSERT_TRUE(second) << test::read_file(dir / "watch.log");
  EXPECT_TRUE((*second)["cad"]["from_cache"].get<bool>());  // the model itself did not change
  // The model changes (a byte more at its end: another content hash), so
  // the next run reads and meshes it afresh.
  test::write_file(model, test::read_file(model) + "\n");
  const auto third = wait_for_report(out / "report.json", watch, [](const nlohmann::json& j) {
    return j.contains("cad") && !j["cad"]["from_cache"].get<bool>() && j["escaped_lm"].get<double>() < 0.75 * kFlux;
  });
  ASSERT_TRUE(third) << test::read_file(dir / "watch.log");
  EXPECT_EQ(watch.interrupt(std::chrono::seconds(30)), 0) << test::read_file(dir / "watch.log");
}

}  // namespace
}  // namespace gonio
