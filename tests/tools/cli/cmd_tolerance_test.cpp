// gonio tolerance through the executable (issue 42, docs/tolerance.md),
// against closed forms: a point source displaced by Δ across the focus of a
// mirror paraboloid (focal length f) tilts the collimated beam by
// arctan(Δ/f); a single-bounce reflector's flux scales with its
// reflectance; zero tolerances change nothing, bit for bit (common random
// numbers); bad tolerance files are errors naming the line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/model/gltf_writer.h"
#include "sim/shapes.h"
#include "tests/support/test_support.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kF = 0.02;         // focal length [m]
constexpr double kAperture = 0.04;  // aperture radius [m]: the rim at 90° from the axis, seen from the focus
constexpr double kMirror = 0.8;     // the mirror's reflectance
constexpr double kFlux = 1000.0;    // [lm]

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

// A mirror paraboloid with exact normals (focus at the origin, opening
// towards −Y, the nadir) and an isotropic 1000 lm point light "lamp" at its
// focus: the light the mirror catches leaves as a collimated beam straight
// down after one bounce, the rest directly.
// Flat facets (`smooth` false: no shading normals) spread the beam over a
// few degrees, so that the table's flux integrates it well.
fs::path write_paraboloid(const fs::path& dir, bool smooth = true) {
  sim::Mesh mirror = smooth ? sim::paraboloid(kF, kAperture, 0.0, 48, 192) : sim::paraboloid(kF, kAperture, 0.0, 8, 32);
  if (!smooth) mirror.normals.clear();
  io::GltfWriter w("gonio tolerance test");
  const int material = w.material({{"name", "mirror"}, {"pbrMetallicRoughness",
                                 {{"baseColorFactor", {kMirror, kMirror, kMirror, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.0}}}});
  w.node({{"name", "reflector"}, {"mesh", w.mesh(mirror, material, "reflector")}});
  const int light =
      w.khr_light({{"name", "lamp"}, {"type", "point"}, {"intensity", kFlux / (4.0 * std::numbers::pi)}});
  w.node({{"name", "lamp"}, {"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}});
  std::string bin;
  const std::string text = w.finish("paraboloid.bin", bin);
  test::write_file(dir / "paraboloid.bin", bin);
  test::write_file(dir / "paraboloid.gltf", text);
  return dir / "paraboloid.gltf";
}

json run_tolerance(const fs::path& dir, const std::string& tolerances, std::vector<std::string> extra) {
  test::write_file(dir / "t.toml", tolerances);
  std::vector<std::string> args = {"tolerance", (dir / "paraboloid.gltf").string(), "--tolerances",
                                   (dir / "t.toml").string(), "--out", (dir / "out").string(), "--threads", "2"};
  args.insert(args.end(), extra.begin(), extra.end());
  const test::ProcessResult r = gonio(args);
  EXPECT_EQ(r.exit_code, 0) << r.err << r.out;
  if (r.exit_code != 0) return {};
  return json::parse(test::read_file(dir / "out" / "report.json"));
}

const json& row(const json& report, const std::string& figure, const std::string& tolerance_prefix) {
  for (const json& r : report["sensitivity"][figure]["rows"])
    if (r["tolerance"].get<std::string>().rfind(tolerance_prefix, 0) == 0) return r;
  static const json none;
  ADD_FAILURE() << "no row " << tolerance_prefix << " for " << figure;
  return none;
}

// The source displaced by Δ = 2 mm along C0 (+X): the ray through the
// vertex leaves at arctan(Δ/f) = 5.71° on the far side (C180); rays that
// meet the mirror at distance r from the focus turn by about Δ·cos θ / r,
// less than that, so the beam's peak lies within [arctan(Δ/f) − 1.5 steps,
// arctan(Δ/f) + 1 step] on a 0.5° γ grid, and in C180 for +Δ, C0 for −Δ.
// Moving the mirror (a part) instead turns the beam the other way.
TEST(ToleranceCli, DisplacedSourceTiltsTheCollimatedBeamByArctanDeltaOverF) {
  test::TempDir dir;
  write_paraboloid(dir.path());
  const json report = run_tolerance(dir.path(), "[emitter.lamp]\nx = { uniform = 2.0 }\n[part.reflector]\nx = { uniform = 2.0 }\n",
                                    {"--photons", "400000", "--gamma-step", "0.5", "--c-step", "5", "--trials", "0",
                                     "--noise-seeds", "2"});
  ASSERT_FALSE(report.is_null());
  EXPECT_EQ(report["nominal"]["peak_gamma"].get<double>(), 0.0);
  const double tilt = std::atan(2.0 / 20.0) * 180.0 / std::numbers::pi;
  const json& gamma = row(report, "peak_gamma", "lamp.x");
  const json& c = row(report, "peak_c", "lamp.x");
  std::printf("peak gamma %.3f %.3f, arctan %.3f\n", gamma["change_high"].get<double>(), gamma["change_low"].get<double>(), tilt);
  EXPECT_GE(gamma["change_high"].get<double>(), tilt - 0.75);
  EXPECT_LE(gamma["change_high"].get<double>(), tilt + 0.5);
  EXPECT_GE(gamma["change_low"].get<double>(), tilt - 0.75);
  EXPECT_LE(gamma["change_low"].get<double>(), tilt + 0.5);
  EXPECT_FALSE(gamma["below_noise"].get<bool>());
  // The nominal's peak is at the nadir, C 0: +Δ (towards C0) sends the beam to C180.
  EXPECT_EQ(c["change_high"].get<double>(), 180.0);
  EXPECT_EQ(c["change_low"].get<double>(), 0.0);
  // The mirror moved by −Δ is the source moved by +Δ: the same tilt, mirrored limits.
  const json& part_gamma = row(report, "peak_gamma", "reflector.x");
  EXPECT_EQ(part_gamma["change_high"], gamma["change_low"]);
  EXPECT_EQ(part_gamma["change_low"], gamma["change_high"]);
  EXPECT_EQ(row(report, "peak_c", "reflector.x")["change_low"].get<double>(), 180.0);
  EXPECT_EQ(row(report, "peak_c", "reflector.x")["change_high"].get<double>(), 0.0);
}

// Monte Carlo with Δ ~ N(0, 1 mm) truncated at ±2σ: every trial's beam
// leaves at arctan(Δ/f) of its own drawn Δ, to C180 for Δ > 0 and C0 for
// Δ < 0 (the same bounds as above on a 0.5° grid), so the trials' spread of
// beam directions is the closed form's over the same draws.
TEST(ToleranceCli, MonteCarloBeamDirectionsFollowArctanDeltaOverF) {
  test::TempDir dir;
  write_paraboloid(dir.path());
  const json report = run_tolerance(dir.path(), "[emitter.lamp]\nx = { normal = 1.0, truncate = 2 }\n",
                                    {"--photons", "200000", "--gamma-step", "0.5", "--c-step", "5", "--trials", "8",
                                     "--noise-seeds", "0"});
  ASSERT_FALSE(report.is_null());
  ASSERT_EQ(report["monte_carlo"]["trials"].size(), 8u);
  std::vector<double> drawn;
  for (const json& trial : report["monte_carlo"]["trials"]) {
    const double delta = trial["values"]["lamp.x"].get<double>();
    drawn.push_back(delta);
    const double want = std::atan(delta / 20.0) * 180.0 / std::numbers::pi;
    const double gamma = trial["figures"]["peak_gamma"].get<double>();
    // Towards C180 (cos C < 0) for Δ > 0; near the nadir C may stray a plane or two.
    const double signed_tilt =
        std::cos(trial["figures"]["peak_c"].get<double>() * std::numbers::pi / 180.0) < 0.0 ? gamma : -gamma;
    EXPECT_GE(std::abs(signed_tilt), std::abs(want) - 0.75) << "Δ = " << delta;
    EXPECT_LE(std::abs(signed_tilt), std::abs(want) + 0.5) << "Δ = " << delta;
    if (gamma > 0.0) {
      EXPECT_EQ(signed_tilt > 0.0, delta > 0.0) << "Δ = " << delta;
    }
  }
  // The Latin hypercube spreads the draws over the law: one in each eighth.
  std::sort(drawn.begin(), drawn.end());
  EXPECT_LT(drawn.front(), -1.0);
  EXPECT_GT(drawn.back(), 1.0);
}

// Reflectance ±10 % of a mirror that every reflected photon meets once:
// the flux changes by ±0.1·R·Φ·(1 − cos θ_rim)/2, the share of an isotropic
// source the mirror catches (θ_rim = 90°: a half). With common random
// numbers the change is the photons whose roulette number falls between
// R and 1.1·R (or 0.9·R and R): binomial, n = N/2 photons with p = 0.08;
// the test allows 5 of its standard deviations.
TEST(ToleranceCli, SingleBounceFluxScalesWithReflectance) {
  test::TempDir dir;
  write_paraboloid(dir.path(), false);
  const long long photons = 400000;
  const json report = run_tolerance(dir.path(), "[material.mirror]\nreflectance = { uniform = 10 }\n",
                                    {"--photons", std::to_string(photons), "--trials", "0", "--noise-seeds", "0"});
  ASSERT_FALSE(report.is_null());
  const double caught = 0.5;
  const double expected = 0.1 * kMirror * kFlux * caught;  // [lm]
  const double n = static_cast<double>(photons) * caught, p = 0.1 * kMirror;
  const double bound = 5.0 * std::sqrt(n * p * (1.0 - p)) * kFlux / static_cast<double>(photons);
  const json& flux = row(report, "flux", "mirror.reflectance");
  std::printf("flux change %.4f %.4f expected ±%.4f bound %.4f nominal %.3f\n", flux["change_high"].get<double>(), flux["change_low"].get<double>(), expected, bound, report["nominal"]["flux"].get<double>());
  EXPECT_NEAR(flux["change_high"].get<double>(), expected, bound);
  EXPECT_NEAR(flux["change_low"].get<double>(), -expected, bound);
  // The nominal's flux: Φ·(1 − caught) + R·Φ·caught, within the grid's integration.
  EXPECT_NEAR(report["nominal"]["flux"].get<double>(), kFlux * (1.0 - caught + kMirror * caught), 0.01 * kFlux);
}

// Zero tolerances: every Monte Carlo trial is the nominal, bit for bit — the
// same photons, nothing changed — and best.ies is nominal.ies byte for
// byte. A tiny tolerance is reported below the noise floor.
TEST(ToleranceCli, ZeroToleranceChangesNothingBitForBit) {
  test::TempDir dir;
  write_paraboloid(dir.path());
  const json report = run_tolerance(dir.path(),
                                    "[emitter.lamp]\nx = { normal = 0 }\nflux = { values = [0] }\n"
                                    "[material.mirror]\nreflectance = { uniform = 0.01 }\n",
                                    {"--photons", "100000", "--trials", "3", "--noise-seeds", "3", "--spec",
                                     "flux=0..,rms=..0"});
  ASSERT_FALSE(report.is_null());
  for (const json& trial : report["monte_carlo"]["trials"]) {
    if (trial["values"]["mirror.reflectance"].get<double>() != 0.0) {
      // Only the tiny reflectance differs: on the same photons its RMS
      // difference is far below that of an independent seed.
      EXPECT_LT(trial["figures"]["rms"].get<double>(), 0.1 * report["noise"]["floor"]["rms"].get<double>());
      std::printf("trial rms %g, noise floor rms %g\n", trial["figures"]["rms"].get<double>(),
                  report["noise"]["floor"]["rms"].get<double>());
      continue;
    }
    EXPECT_EQ(trial["figures"], report["nominal"]);
  }
  EXPECT_TRUE(row(report, "flux", "mirror.reflectance")["below_noise"].get<bool>());
  EXPECT_EQ(row(report, "flux", "lamp.x")["change_high"].get<double>(), 0.0);
  EXPECT_EQ(row(report, "rms", "lamp.flux")["change_low"].get<double>(), 0.0);
}

TEST(ToleranceCli, ZeroTolerancesGiveTheNominalBytes) {
  test::TempDir dir;
  write_paraboloid(dir.path());
  const json report = run_tolerance(dir.path(), "[emitter.lamp]\nx = { normal = 0 }\ntilt_y = { uniform = 0 }\n",
                                    {"--photons", "50000", "--trials", "2", "--noise-seeds", "1", "--spec", "rms=..0"});
  ASSERT_FALSE(report.is_null());
  for (const json& trial : report["monte_carlo"]["trials"]) {
    EXPECT_EQ(trial["figures"], report["nominal"]);
    EXPECT_TRUE(trial["in_spec"].get<bool>());
  }
  EXPECT_EQ(report["monte_carlo"]["yield"]["all"].get<double>(), 1.0);
  EXPECT_EQ(test::read_file(dir.path() / "out" / "best.ies"), test::read_file(dir.path() / "out" / "nominal.ies"));
  EXPECT_EQ(test::read_file(dir.path() / "out" / "worst.ies"), test::read_file(dir.path() / "out" / "nominal.ies"));
  EXPECT_EQ(test::read_file(dir.path() / "out" / "best.ldt"), test::read_file(dir.path() / "out" / "nominal.ldt"));
  // The independent seed is not the nominal: the noise floor is real.
  EXPECT_GT(report["noise"]["floor"]["rms"].get<double>(), 0.0);
}

TEST(ToleranceCli, BadInputIsAnErrorNamingTheLine) {
  test::TempDir dir;
  write_paraboloid(dir.path());
  test::write_file(dir / "t.toml", "[emitter.lamp]\n\nx = { uniform = 1, normal = 1 }\n");
  test::ProcessResult r = gonio({"tolerance", (dir / "paraboloid.gltf").string(), "--tolerances",
                                 (dir / "t.toml").string(), "--out", (dir / "out").string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("t.toml:3: emitter.lamp.x: give exactly one of"), std::string::npos) << r.err;
  test::write_file(dir / "t.toml", "[emitter.LED]\nx = { uniform = 1 }\n");
  r = gonio({"tolerance", (dir / "paraboloid.gltf").string(), "--tolerances", (dir / "t.toml").string(), "--out",
             (dir / "out").string(), "--photons", "1000"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("t.toml:2: the model has no emitter 'LED' (it has 'lamp')"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "report.json"));
  r = gonio({"tolerance", (dir / "paraboloid.gltf").string(), "--tolerances", (dir / "t.toml").string(), "--out",
             (dir / "out").string(), "--spec", "beam=1..2"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--spec 'beam=1..2': unknown figure"), std::string::npos) << r.err;
  r = gonio({"tolerance", (dir / "paraboloid.gltf").string(), "--out", (dir / "out").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--tolerances FILE is required"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace gonio
