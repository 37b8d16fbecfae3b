// gonio info and convert on IES TM-25 ray files, run as a user would.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "io/outputs/exr.h"
#include "io/photometric/photometric_file.h"
#include "io/photometric/tm25.h"
#include "photometry/distribution.h"
#include "photometry/flux.h"
#include "tests/tools/cli/cli_fixtures.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;
using test::contains;
using test::gonio;

constexpr double kPi = std::numbers::pi;

// A Lambertian disc of radius 2 mm emitting along +z: 1000 lm over 200,000
// rays of equal flux on a Fibonacci lattice in cosine-weighted (u1, u2)
// (u1 = (i + ½)/N, u2 = frac(i·φ⁻¹); r = √u1, φ = 2π u2), positions likewise
// over the disc. Its far field: I(γ) = (1000/π) cos γ about the ray file's
// +z (the nadir).
io::Tm25RaySet lambertian_disc() {
  const int n = 200000;
  const double golden = (std::sqrt(5.0) - 1.0) / 2.0;
  std::vector<float> rays;
  rays.reserve(static_cast<std::size_t>(n) * 7);
  for (int i = 0; i < n; ++i) {
    const double u1 = (i + 0.5) / n, u2 = std::fmod(i * golden, 1.0);
    const double r = std::sqrt(u1), phi = 2.0 * kPi * u2;
    const double pr = 2.0 * std::sqrt(u2), pphi = 2.0 * kPi * u1;
    for (double v : {pr * std::cos(pphi), pr * std::sin(pphi), 0.0, r * std::cos(phi), r * std::sin(phi),
                     std::sqrt(1.0 - u1), 1000.0 / n})
      rays.push_back(static_cast<float>(v));
  }
  return io::make_luminous_ray_set(std::move(rays));
}

TEST(CliRayFile, InfoShowsTheRaysAndTheirFarField) {
  test::TempDir dir;
  const auto path = dir / "disc.tm25ray";
  ASSERT_TRUE(io::write_tm25_file(path.string(), lambertian_disc()).ok());
  auto r = gonio({"info", path.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "TM-25")) << r.out;
  EXPECT_TRUE(contains(r.out, "200000 (simulated)")) << r.out;
  EXPECT_TRUE(contains(r.out, "luminous (Tri_Y) per ray; rays' sum 1000 lm")) << r.out;
  EXPECT_TRUE(contains(r.out, "Ray extent            x -2 to 1.999, y -1.999 to 1.999, z 0 to 0 mm")) << r.out;
  EXPECT_TRUE(contains(r.out, "Total flux            999.9 lm")) << r.out;
  EXPECT_TRUE(contains(r.err, "[tm25-far-field]")) << r.err;

  r = gonio({"info", path.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["format"], "TM-25");
  EXPECT_EQ(j["ray_set"]["rays"], 200000);
  EXPECT_NEAR(j["ray_set"]["rays_flux_lm"].get<double>(), 1000.0, 1e-3);
  // The flux integral of the binned grid (photometry::total_flux_lm).
  EXPECT_NEAR(j["flux_lm"].get<double>(), 1000.0, 1.0);
  // Lambertian: the beam angle (50 %) is 120°, the field angle (10 %) 2 acos 0.1.
  // (The peak is one bin's: 346 cd against 318 at γ 2.5°, where a bin holds
  // about 10 rays; so half of it lies a little further in.)
  EXPECT_NEAR(j["beam_angle_c0_c180_deg"].get<double>(), 120.0, 2.5);
  EXPECT_NEAR(j["field_angle_c90_c270_deg"].get<double>(), 2.0 * std::acos(0.1) * 180.0 / kPi, 1.0);
}

TEST(CliRayFile, ConvertWritesTheLambertianFarField) {
  test::TempDir dir;
  const auto path = dir / "disc.tm25ray", ies = dir / "disc.ies";
  ASSERT_TRUE(io::write_tm25_file(path.string(), lambertian_disc()).ok());
  auto r = gonio({"convert", path.string(), ies.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto file = io::read_photometric_file(ies.string());
  ASSERT_TRUE(file.ok()) << to_string(file.error());
  const photometry::Distribution& d = file->distribution;
  EXPECT_NEAR(photometry::total_flux_lm(d), 1000.0, 1.0);
  const double i0 = 1000.0 / kPi;
  // Per γ, the mean over the planes within 1 % of I0 cos γ to 70° (a bin's
  // own noise is that of its few rays: ~10 at γ 2.5°, ~60 at 45°; each bin
  // within 35 %).
  const std::size_t nv = d.vertical_deg.size();
  for (std::size_t v = 0; v < nv; ++v) {
    const double g = d.vertical_deg[v];
    const double expected = g < 90.0 ? i0 * std::cos(g * kPi / 180.0) : 0.0;
    double mean = 0.0;
    for (std::size_t h = 0; h < d.horizontal_deg.size(); ++h) {
      const double cd = d.candela[h * nv + v];
      mean += cd / static_cast<double>(d.horizontal_deg.size());
      if (g <= 70.0) {
        EXPECT_NEAR(cd, expected, 0.35 * expected) << "C " << d.horizontal_deg[h] << " gamma " << g;
      }
      if (g > 92.5) {
        EXPECT_EQ(cd, 0.0) << g;
      }
    }
    if (g <= 70.0) {
      EXPECT_NEAR(mean, expected, 0.01 * expected) << "gamma " << g;
    }
  }
  // A ray file is never written from a far field.
  r = gonio({"convert", ies.string(), (dir / "x.tm25ray").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "cannot write a TM-25 ray file")) << r.err;
}

TEST(CliRayFile, HostileRayFileIsAClearError) {
  test::TempDir dir;
  const auto path = dir / "cut.tm25ray";
  auto bytes = io::write_tm25(lambertian_disc());
  ASSERT_TRUE(bytes.ok());
  test::write_file(path, bytes->substr(0, bytes->size() - 10));
  auto r = gonio({"info", path.string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.err, "cut.tm25ray: byte 36288: the header (byte 20) declares 200000 rays of 28 bytes"))
      << r.err;
}

TEST(CliRayFile, OsramRaySetConvertsWithItsPublishedFlux) {
  GONIO_REQUIRE_CORPUS();
  const fs::path osram =
      test::corpus_dir() / "rayfiles" / "rayfile_LERTDUW_S2WP_blue_100k_20161013_IES_TM25.TM25RAY";
  if (!fs::exists(osram)) GONIO_MISSING("the OSRAM ray file " + osram.string());
  test::TempDir dir;
  const auto ies = dir / "osram.ies";
  auto r = gonio({"convert", osram.string(), ies.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto file = io::read_photometric_file(ies.string());
  ASSERT_TRUE(file.ok());
  // The header's 54.6 lm (SOURCES.md), all of it below the horizon: a
  // surface-mount LED emitting along +z, the nadir.
  EXPECT_NEAR(photometry::total_flux_lm(file->distribution), 54.644, 0.05);
  const photometry::Keyword* other = file->distribution.find_keyword("OTHER");
  ASSERT_NE(other, nullptr);
  EXPECT_TRUE(contains(other->value, "C every 5 deg, gamma every 2.5 deg")) << other->value;
}

}  // namespace
}  // namespace gonio

namespace gonio {
namespace {

// A model of one node carrying the Lambertian disc as its ray file, turned
// so that the file's +z points down (−Y, the nadir of Gonio's default frame).
std::string ray_file_model(const std::string& uri, double flux_lm = -1.0) {
  nlohmann::json g;
  g["asset"] = {{"version", "2.0"}};
  g["scene"] = 0;
  g["scenes"] = nlohmann::json::array({nlohmann::json{{"nodes", nlohmann::json::array({0})}}});
  nlohmann::json node = {{"name", "led"}, {"rotation", {0.7071067811865476, 0.0, 0.0, 0.7071067811865476}}};
  node["extras"]["gonio"]["ray_file"] = uri;
  if (flux_lm >= 0.0) node["extras"]["gonio"]["flux_lm"] = flux_lm;
  g["nodes"] = nlohmann::json::array({node});
  return g.dump();
}

TEST(CliRayFile, RaySetEmitterGivesTheSetsFarFieldAndSaysWhenOversampled) {
  test::TempDir dir;
  ASSERT_TRUE(io::write_tm25_file((dir / "disc.tm25ray").string(), lambertian_disc()).ok());
  test::write_file(dir / "led.gltf", ray_file_model("disc.tm25ray"));
  const auto out = dir / "out";
  auto r = gonio({"simulate", (dir / "led.gltf").string(), "--out", out.string(), "--photons", "200000",
                  "--iterations", "1", "--format", "ies"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // 200,000 photons from 200,000 rays of equal flux: at the rule's limit, no warning.
  EXPECT_FALSE(contains(r.err, "ray-set-oversampled")) << r.err;
  const auto report = nlohmann::json::parse(test::read_file(out / "report.json"));
  // The file's flux (float rays summed): 1000 lm to float rounding.
  EXPECT_NEAR(report["emitted_lm"].get<double>(), 1000.0, 1e-4);
  EXPECT_NEAR(report["escaped_lm"].get<double>(), report["emitted_lm"].get<double>(), 1e-9);
  auto file = io::read_photometric_file((out / "led.ies").string());
  ASSERT_TRUE(file.ok()) << to_string(file.error());
  const photometry::Distribution& d = file->distribution;
  // Relative photometry of a 1000 lm lamp: I0 cos γ, plane means within 4 %
  // (each γ ring draws a few thousand photons) from 5° (the nadir cap holds
  // a few dozen) to 60°.
  const double i0 = 1000.0 / kPi;
  const std::size_t nv = d.vertical_deg.size();
  for (std::size_t v = 0; v < nv; ++v) {
    const double g = d.vertical_deg[v];
    if (g > 60.0) break;
    if (g < 5.0) continue;
    double mean = 0.0;
    for (std::size_t h = 0; h < d.horizontal_deg.size(); ++h)
      mean += d.candela[h * nv + v] / static_cast<double>(d.horizontal_deg.size());
    EXPECT_NEAR(mean, i0 * std::cos(g * kPi / 180.0), 0.04 * i0) << "gamma " << g;
  }
  // More photons than rays: the warning, with the rule's factor.
  r = gonio({"simulate", (dir / "led.gltf").string(), "--out", (dir / "out2").string(), "--photons", "400000",
             "--iterations", "1", "--format", "ies"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "gives about 400000 photons from 200000 rays (effective 200000)")) << r.err;
  EXPECT_TRUE(contains(r.err, "1.22 times the set's own")) << r.err;
  EXPECT_TRUE(contains(r.err, "[ray-set-oversampled]")) << r.err;
}

TEST(CliRayFile, RayFileUriFollowsTheModelsFolderRules) {
  test::TempDir dir;
  ASSERT_TRUE(io::write_tm25_file((dir / "disc.tm25ray").string(), lambertian_disc()).ok());
  fs::create_directories(dir / "model");
  test::write_file(dir / "model" / "led.gltf", ray_file_model("../disc.tm25ray"));
  auto r = gonio({"simulate", (dir / "model" / "led.gltf").string(), "--out", (dir / "out").string(),
                  "--photons", "1000", "--iterations", "1"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.err, "extras.gonio.ray_file '../disc.tm25ray'")) << r.err;
  test::write_file(dir / "model" / "led.gltf", ray_file_model("missing.tm25ray"));
  r = gonio({"simulate", (dir / "model" / "led.gltf").string(), "--out", (dir / "out").string(), "--photons",
             "1000", "--iterations", "1"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.err, "missing.tm25ray")) << r.err;
}

TEST(CliRayFile, SimulateWritesTheEscapingRaysThatKeepFluxAndFarField) {
  // The Lambertian disc, read, traced through nothing and written again.
  test::TempDir dir;
  ASSERT_TRUE(io::write_tm25_file((dir / "disc.tm25ray").string(), lambertian_disc()).ok());
  test::write_file(dir / "led.gltf", ray_file_model("disc.tm25ray"));
  const auto out = dir / "out";
  auto r = gonio({"simulate", (dir / "led.gltf").string(), "--out", out.string(), "--photons", "100000",
                  "--iterations", "2", "--format", "ies,tm25", "--tm25-rays", "150000", "--threads", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "led.tm25ray: 150000 rays")) << r.out;
  const auto report = nlohmann::json::parse(test::read_file(out / "report.json"));
  auto set = io::read_tm25_file((out / "led.tm25ray").string());
  ASSERT_TRUE(set.ok()) << to_string(set.error());
  EXPECT_TRUE(set->findings.empty());
  EXPECT_EQ(set->ray_count(), 150000u);
  // The rays add up to the escaped flux; the header says so.
  EXPECT_NEAR(set->total_luminous_flux_lm(), report["escaped_lm"].get<double>(), 1e-3);
  EXPECT_NEAR(set->header.luminous_flux_lm, report["escaped_lm"].get<double>(), 1e-3);
  // Every ray starts on the bounding sphere: the disc's box is 4 × 4 mm
  // (its rays' start points), so the radius is 2√2 mm about its centre.
  for (std::size_t i = 0; i < set->ray_count(); i += 997)
    EXPECT_NEAR(length(set->position_mm(i)), 2.0 * std::sqrt(2.0), 2e-3) << i;
  // And its far field is the Lambertian one, +z down as in the file read.
  const auto ies = dir / "again.ies";
  r = gonio({"convert", (out / "led.tm25ray").string(), ies.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto file = io::read_photometric_file(ies.string());
  ASSERT_TRUE(file.ok());
  const photometry::Distribution& d = file->distribution;
  EXPECT_NEAR(photometry::total_flux_lm(d), 1000.0, 2.0);
  const double i0 = 1000.0 / kPi;
  const std::size_t nv = d.vertical_deg.size();
  for (std::size_t v = 0; v < nv; ++v) {
    const double g = d.vertical_deg[v];
    if (g > 60.0) break;
    if (g < 5.0) continue;
    double mean = 0.0;
    for (std::size_t h = 0; h < d.horizontal_deg.size(); ++h)
      mean += d.candela[h * nv + v] / static_cast<double>(d.horizontal_deg.size());
    EXPECT_NEAR(mean, i0 * std::cos(g * kPi / 180.0), 0.05 * i0) << "gamma " << g;
  }
  // The same run on one thread: the same bytes.
  r = gonio({"simulate", (dir / "led.gltf").string(), "--out", (dir / "out1").string(), "--photons", "100000",
             "--iterations", "2", "--format", "tm25", "--tm25-rays", "150000", "--threads", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string a = test::read_file(out / "led.tm25ray"), b = test::read_file(dir / "out1" / "led.tm25ray");
  // (The creation dates may differ at midnight; the rays may not.)
  EXPECT_EQ(a.substr(36288), b.substr(36288));
  r = gonio({"simulate", (dir / "led.gltf").string(), "--out", (dir / "out2").string(), "--tm25-rays", "10"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "--tm25-rays applies to --format tm25 only")) << r.err;
}

TEST(CliNearField, SimulateWritesPlanesTheirFiguresAndTheFarFieldDistance) {
  // The disc set of radius 2 mm (its lattice ties positions to directions,
  // so it is no uniform-radiance disc: the closed forms are
  // gonio_sim_tests NearField.*): 2 mm below it the near field is far from
  // its far field; 1 m below, the same photons land in the same pixels to
  // within a few.
  test::TempDir dir;
  ASSERT_TRUE(io::write_tm25_file((dir / "disc.tm25ray").string(), lambertian_disc()).ok());
  test::write_file(dir / "led.gltf", ray_file_model("disc.tm25ray"));
  const auto run = [&](const std::string& out, const char* threads) {
    return gonio({"simulate", (dir / "led.gltf").string(), "--out", (dir / out).string(), "--photons", "100000",
                  "--iterations", "2", "--format", "ies,report", "--near-field", "1,0.002", "--threads", threads});
  };
  auto r = run("out", "2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "near field at 0.002 m:")) << r.out;
  EXPECT_TRUE(contains(r.out, "far-field distance:")) << r.out;
  const auto out = dir / "out";
  const auto report = nlohmann::json::parse(test::read_file(out / "report.json"));
  ASSERT_EQ(report["near_field"].size(), 2u);
  const auto& near = report["near_field"][0];  // sorted by distance
  EXPECT_EQ(near["distance_m"].get<double>(), 0.002);
  EXPECT_EQ(near["file"].get<std::string>(), "led.near-field-0.002m.exr");
  EXPECT_NEAR(near["extent_m"].get<double>(), 0.008, 1e-12);
  EXPECT_LT(near["on_axis_lx"].get<double>() / near["far_field_on_axis_lx"].get<double>(), 0.5);
  EXPECT_GT(near["max_deviation_pct"].get<double>(), 30.0);
  const auto& far = report["near_field"][1];
  EXPECT_NEAR(far["on_axis_lx"].get<double>() / far["far_field_on_axis_lx"].get<double>(), 1.0, 0.02);
  EXPECT_TRUE(report.contains("far_field_distance_m"));
  EXPECT_TRUE(report.contains("far_field_distance_method"));
  bool listed = false;
  for (const auto& w : report["written"]) listed |= contains(w.get<std::string>(), "led.near-field-1m.exr");
  EXPECT_TRUE(listed);
  // The image: E and E_far in lux, the centre pixel as in the report.
  auto image = io::read_exr((out / "led.near-field-0.002m.exr").string());
  ASSERT_TRUE(image.ok()) << to_string(image.error());
  EXPECT_EQ(image->width, 41);
  ASSERT_NE(image->find_float("E"), nullptr);
  ASSERT_NE(image->find_float("E_far"), nullptr);
  ASSERT_NE(image->find_attribute("gonio:pixel_size_m"), nullptr);
  EXPECT_NEAR(image->find_float("E")->values[41 * 20 + 20], near["on_axis_lx"].get<double>(),
              1e-5 * near["on_axis_lx"].get<double>());
  // The datasheet prints the table and the distance.
  const std::string html = test::read_file(out / "led.html");
  EXPECT_TRUE(contains(html, "Far-field distance")) << html.substr(0, 200);
  // One thread: the same images, byte for byte.
  r = run("out1", "1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"led.near-field-0.002m.exr", "led.near-field-1m.exr"})
    EXPECT_EQ(test::read_file(out / name), test::read_file(dir / "out1" / name)) << name;
  // A distance that is not one.
  for (const char* bad : {"0", "-1", "1,x", "nan"}) {
    r = gonio({"simulate", (dir / "led.gltf").string(), "--out", (dir / "bad").string(), "--near-field", bad});
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_TRUE(contains(r.err, "--near-field")) << r.err;
  }
}


// The IES file's peak: its C and γ [deg].
std::pair<double, double> peak_of(const photometry::Distribution& d) {
  const std::size_t nv = d.vertical_deg.size();
  std::size_t best = 0;
  for (std::size_t i = 0; i < d.candela.size(); ++i)
    if (d.candela[i] > d.candela[best]) best = i;
  return {d.horizontal_deg[best / nv], d.vertical_deg[best % nv]};
}

// Issue 34, case 3 (read): rays all pointing at C 30°, γ 40° of the ray
// file's frame (+x C0, −y C90, +z the nadir: k = (sin γ cos C, −sin γ sin C,
// cos γ)) give a far field whose peak is there. Read as (ky, kx, kz) the
// peak moves to C 240°; with +y taken along C90, to C 330°.
TEST(CliRayFile, OneObliqueDirectionPeaksAtItsCAndGamma) {
  test::TempDir dir;
  const double g = 40.0 * kPi / 180.0, c = 30.0 * kPi / 180.0;
  std::vector<float> rays;
  for (int i = 0; i < 1000; ++i)
    for (double v : {0.0, 0.0, 0.0, std::sin(g) * std::cos(c), -std::sin(g) * std::sin(c), std::cos(g), 1.0})
      rays.push_back(static_cast<float>(v));
  ASSERT_TRUE(io::write_tm25_file((dir / "oblique.tm25ray").string(), io::make_luminous_ray_set(std::move(rays))).ok());
  auto r = gonio({"convert", (dir / "oblique.tm25ray").string(), (dir / "oblique.ies").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto file = io::read_photometric_file((dir / "oblique.ies").string());
  ASSERT_TRUE(file.ok()) << to_string(file.error());
  const auto [peak_c, peak_gamma] = peak_of(file->distribution);
  EXPECT_EQ(peak_c, 30.0);
  EXPECT_EQ(peak_gamma, 40.0);
}

// Issue 34, case 3 (written): a narrow spot aimed at C 90°, γ 60° (a
// KHR_lights_punctual spot down its node's −Z, turned −30° about X: −Z
// becomes (0, −½, −√3/2), i.e. γ 60° toward −Z, the default frame's C90).
// The run's own IES file peaks there, and so must the far field of the ray
// file it writes (+x C0, −y C90, +z nadir); written with +y along C90, the
// ray file's peak would be at C 270°.
TEST(CliRayFile, WrittenRayFileOfASpotAimedAtC90PeaksWhereTheRunsIesDoes) {
  test::TempDir dir;
  const double half = -15.0 * kPi / 180.0;
  nlohmann::json g;
  g["asset"] = {{"version", "2.0"}};
  g["scene"] = 0;
  g["scenes"] = nlohmann::json::array({nlohmann::json{{"nodes", nlohmann::json::array({0})}}});
  g["extensionsUsed"] = nlohmann::json::array({"KHR_lights_punctual"});
  g["extensions"]["KHR_lights_punctual"]["lights"] = nlohmann::json::array(
      {{{"type", "spot"}, {"intensity", 100.0}, {"spot", {{"innerConeAngle", 0.05}, {"outerConeAngle", 0.15}}}}});
  g["nodes"] = nlohmann::json::array({{{"name", "spot"},
                                       {"rotation", {std::sin(half), 0.0, 0.0, std::cos(half)}},
                                       {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}});
  test::write_file(dir / "spot.gltf", g.dump());
  const auto out = dir / "out";
  auto r = gonio({"simulate", (dir / "spot.gltf").string(), "--out", out.string(), "--photons", "100000",
                  "--iterations", "1", "--format", "ies,tm25", "--tm25-rays", "50000"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = gonio({"convert", (out / "spot.tm25ray").string(), (dir / "rays.ies").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto run = io::read_photometric_file((out / "spot.ies").string());
  auto rays = io::read_photometric_file((dir / "rays.ies").string());
  ASSERT_TRUE(run.ok()) << to_string(run.error());
  ASSERT_TRUE(rays.ok()) << to_string(rays.error());
  const auto run_peak = peak_of(run->distribution), ray_peak = peak_of(rays->distribution);
  EXPECT_EQ(run_peak.first, 90.0) << "the run's IES file";
  EXPECT_EQ(run_peak.second, 60.0) << "the run's IES file";
  EXPECT_EQ(ray_peak.first, run_peak.first) << "C of the ray file's peak";
  EXPECT_EQ(ray_peak.second, run_peak.second) << "gamma of the ray file's peak";
}

// Issue 34, case 5 (the written image): the Lambertian disc set moved 50 mm
// toward C90 (the ray file's −y) and 30 mm toward C0 (+x), with one weak ray
// as far the other way pointing up, so the luminaire's centre stays between
// them. 50 mm below, the near-field EXR's channel E is brightest about row
// 10 of 41 from the top and column 26 from the left ((0.1 − 0.05) / 0.2 × 41,
// (0.1 + 0.03) / 0.2 × 41), as its gonio:axes attribute says ("columns along
// C0 (left -, right +), rows along C90 (top +, bottom -)"); written
// bottom-up, row 30.
TEST(CliNearField, EmitterTowardC90AndC0LightsTheExrsTopRight) {
  test::TempDir dir;
  io::Tm25RaySet set = lambertian_disc();
  std::vector<float> rays = set.items;
  for (std::size_t i = 0; i < rays.size(); i += 7) {
    rays[i] += 30.0f;      // toward C0
    rays[i + 1] -= 50.0f;  // toward C90
  }
  for (float v : {-30.0f, 50.0f, 0.0f, 0.0f, 0.0f, -1.0f, 0.001f}) rays.push_back(v);  // the other way, pointing up
  ASSERT_TRUE(io::write_tm25_file((dir / "moved.tm25ray").string(), io::make_luminous_ray_set(std::move(rays))).ok());
  test::write_file(dir / "led.gltf", ray_file_model("moved.tm25ray"));
  const auto out = dir / "out";
  auto r = gonio({"simulate", (dir / "led.gltf").string(), "--out", out.string(), "--photons", "100000",
                  "--iterations", "1", "--format", "ies,report", "--near-field", "0.05"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto image = io::read_exr((out / "led.near-field-0.05m.exr").string());
  ASSERT_TRUE(image.ok()) << to_string(image.error());
  const io::ExrImage::FloatChannel* e = image->find_float("E");
  ASSERT_NE(e, nullptr);
  const auto n = static_cast<std::size_t>(image->width);
  std::vector<double> rows(n, 0.0), columns(n, 0.0);
  for (std::size_t i = 0; i < e->values.size(); ++i) {
    rows[i / n] += static_cast<double>(e->values[i]);
    columns[i % n] += static_cast<double>(e->values[i]);
  }
  const auto brightest = [](const std::vector<double>& v) {
    return static_cast<std::size_t>(std::max_element(v.begin(), v.end()) - v.begin());
  };
  EXPECT_EQ(brightest(rows), 10u) << "brightest row of E (0 = +C90, the top)";
  EXPECT_EQ(brightest(columns), 26u) << "brightest column of E (0 = -C0, the left)";
  double top = 0.0, bottom = 0.0;
  for (std::size_t k = 0; k < n / 2; ++k) {
    top += rows[k];
    bottom += rows[n - 1 - k];
  }
  EXPECT_GT(top, 3.0 * bottom);
}

}  // namespace
}  // namespace gonio
