// The files of `gonio simulate` made from far fields with known content.
#include "tools/run/simulation_outputs.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <filesystem>

#include "io/outputs/exr.h"
#include "io/photometric/ies.h"
#include "io/photometric/ldt.h"
#include "photometry/flux.h"
#include "photometry/frame.h"
#include "tests/sim/scenes.h"
#include "tests/support/test_support.h"

namespace gonio::app {
namespace {

TEST(OutputFormats, ParseListsAllAndRefuseUnknownNames) {
  auto all = parse_formats("all");
  ASSERT_TRUE(all.ok());
  EXPECT_EQ(all->size(), 5u);
  // The datasheet only when named: "all" is the five files it always was.
  EXPECT_EQ(std::count(all->begin(), all->end(), OutputFormat::Report), 0);
  auto with_report = parse_formats("all,report");
  ASSERT_TRUE(with_report.ok());
  EXPECT_EQ(with_report->back(), OutputFormat::Report);
  EXPECT_STREQ(to_string(OutputFormat::Report), "report");
  auto some = parse_formats(" ldt ,ies,ldt");
  ASSERT_TRUE(some.ok());
  EXPECT_EQ(*some, (std::vector<OutputFormat>{OutputFormat::Ldt, OutputFormat::Ies}));
  for (const char* bad : {"", ",", "ies,,ldt", "pdf", "IES"}) {
    auto r = parse_formats(bad);
    EXPECT_FALSE(r.ok()) << bad;
    if (!r.ok()) {
      EXPECT_NE(r.error().message.find("--format"), std::string::npos);
    }
  }
}

sim::SceneDesc bare_scene(double flux_lm) {
  sim::SceneDesc scene;
  sim::Emitter e;
  e.name = "lamp";
  e.flux_lm = flux_lm;
  scene.emitters = {e};
  return scene;
}

sim::Ledger ledger_for(const sim::FarField& f, double emitted_lm) {
  sim::Ledger l;
  l.emitted.flux_lm = emitted_lm;
  l.emitted.photons = f.total_photons();
  l.escaped.flux_lm = f.total_flux_lm();
  l.escaped.photons = f.total_photons();
  return l;
}

// One bright spot at a world direction: the latlong map's brightest pixel
// is where OpenEXR's convention puts that direction, and the IES peak is at
// the C, γ the photometric frame gives it.
TEST(SimulationOutputs, LatLongAndCandelaTablesPutALobeWhereTheFramesSay) {
  const int n = 32;
  sim::FarField field(n);
  for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, 1e-3, 10);
  const Vec3 d = normalize(Vec3{0.6, -0.5, 0.3});
  const std::size_t spot = field.grid().texel_of(d);
  field.add(spot, 50.0, 100000);
  const sim::SceneDesc scene = bare_scene(1000.0);
  const sim::Ledger ledger = ledger_for(field, 1000.0);

  test::TempDir dir;
  OutputRequest req;
  req.directory = dir.path().string();
  req.stem = "spot";
  req.formats = {OutputFormat::LatLong, OutputFormat::Ies};
  req.grid = {10.0, 5.0};
  req.symmetry = photometry::Symmetry::None;
  req.run = {"test", "spot.gltf", 1000, 1, 10, "2024-01-01"};
  auto result = write_outputs(field, scene, ledger, req);
  ASSERT_TRUE(result.ok()) << result.error().message;
  ASSERT_EQ(result->files.size(), 2u);

  auto image = io::read_exr((dir / "farfield-latlong.exr").string());
  ASSERT_TRUE(image.ok());
  const auto& y = image->find_float("Y")->values;
  std::size_t best = 0;
  for (std::size_t i = 0; i < y.size(); ++i)
    if (y[i] > y[best]) best = i;
  const Vec3 at = io::latlong_direction(image->width, image->height, static_cast<int>(best % image->width),
                                        static_cast<int>(best / image->width));
  // Within a texel of the face (≤ 90°/32 · √2 at the centre) plus a pixel.
  EXPECT_GT(dot(at, d), std::cos((90.0 / n * 1.5 + 1.5) * M_PI / 180.0)) << at.x << " " << at.y << " " << at.z;
  EXPECT_NEAR(result->files[0].flux_lm, field.total_flux_lm(), 1e-5 * field.total_flux_lm());

  // Gonio's default frame: C0 = +X, C90 = −Z, nadir −Y.
  auto ies = io::read_ies((dir / "spot.ies").string());
  ASSERT_TRUE(ies.ok());
  const photometry::Distribution& dist = ies->distribution;
  std::size_t peak = 0;
  for (std::size_t i = 0; i < dist.candela.size(); ++i)
    if (dist.candela[i] > dist.candela[peak]) peak = i;
  const double c = dist.horizontal_deg[peak / dist.vertical_count()];
  const double g = dist.vertical_deg[peak % dist.vertical_count()];
  const double c_expected = std::atan2(-d.z, d.x) * 180.0 / M_PI + 360.0;  // C90 is −Z
  const double g_expected = std::acos(-d.y) * 180.0 / M_PI;
  EXPECT_NEAR(std::remainder(c - c_expected, 360.0), 0.0, 10.0);
  EXPECT_NEAR(g, g_expected, 5.0);
  EXPECT_EQ(dist.file_generation, photometry::FileGenerationType::ComputerSimulation);
  EXPECT_EQ(dist.lamps.at(0).flux_lm, 1000.0);
  EXPECT_EQ(dist.lamps.at(0).count, 1);
}

// A uniform sphere: every file holds 1/4π of the flux per steradian, LORL
// equals escaped / emitted, DFF is one half, and the symmetry test finds
// the highest symmetry.
TEST(SimulationOutputs, AnIsotropicFieldGivesIsotropicFilesWithExactEnergy) {
  const int n = 32;
  sim::FarField field(n);
  const sim::CubeMapGrid& grid = field.grid();
  for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, 800.0 * grid.texel_solid_angle(t) / (4 * M_PI), 1000000);
  const sim::SceneDesc scene = bare_scene(1000.0);
  const sim::Ledger ledger = ledger_for(field, 1000.0);
  test::TempDir dir;
  OutputRequest req;
  req.directory = dir.path().string();
  req.stem = "iso";
  req.formats = {OutputFormat::Ies, OutputFormat::Ldt, OutputFormat::Exr};
  req.grid = {15.0, 5.0};
  req.run = {"test", "iso.gltf", 1000, 1, 10, "2024-01-01"};
  auto result = write_outputs(field, scene, ledger, req);
  ASSERT_TRUE(result.ok()) << result.error().message;
  EXPECT_EQ(result->symmetry, photometry::Symmetry::Rotational) << result->symmetry_reason;
  for (const WrittenFile& f : result->files) {
    EXPECT_TRUE(f.clean()) << f.path;
    EXPECT_NEAR(f.flux_lm, 800.0, 1e-4) << f.path;
  }
  auto ldt = io::read_ldt((dir / "iso.ldt").string());
  ASSERT_TRUE(ldt.ok());
  EXPECT_NEAR(ldt->distribution.declared_lor_percent, 80.0, 1e-9);
  EXPECT_NEAR(ldt->distribution.declared_dff_percent, 50.0, 1e-3);
  for (double cd : ldt->distribution.candela) EXPECT_NEAR(cd, 800.0 / (4 * M_PI), 1e-3);
  ASSERT_EQ(ldt->distribution.direct_ratios.size(), 10u);
  EXPECT_GT(ldt->distribution.direct_ratios[9], ldt->distribution.direct_ratios[0]);
  EXPECT_LT(ldt->distribution.direct_ratios[9], 0.5);
}

// Issue 41: a run that built the output grid's resampler for its estimate
// hands it to the files (OutputRequest::resampler) rather than building it
// again: the same IES and LDT bytes as one built here; a resampler of
// another frame changes them (so the one given is the one binned with); one
// of another face size is not used.
TEST(SimulationOutputs, AGivenResamplerGivesTheSameBytesAsOneMadeHere) {
  const int n = 32;
  sim::FarField field(n);
  for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, 1e-3, 10);
  field.add(field.grid().texel_of(normalize(Vec3{0.6, -0.5, 0.3})), 50.0, 100000);
  const sim::SceneDesc scene = bare_scene(1000.0);
  const sim::Ledger ledger = ledger_for(field, 1000.0);
  const sim::CGammaGrid grid{10.0, 5.0};
  const sim::Resampler same(n, scene.frame, grid);
  const sim::Resampler turned(n, photometry::make_frame({0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}), grid);
  const sim::Resampler coarser(n / 2, scene.frame, grid);
  test::TempDir dir;
  const auto write = [&](const std::string& name, const sim::Resampler* resampler) {
    OutputRequest req;
    req.directory = (dir / name).string();
    std::filesystem::create_directories(req.directory);
    req.stem = "spot";
    req.formats = {OutputFormat::Ies, OutputFormat::Ldt};
    req.grid = grid;
    req.symmetry = photometry::Symmetry::None;
    req.run = {"test", "spot.gltf", 1000, 1, 10, "2024-01-01"};
    req.resampler = resampler;
    auto result = write_outputs(field, scene, ledger, req);
    EXPECT_TRUE(result.ok()) << result.error().message;
    return test::read_file(dir / name / "spot.ies") + test::read_file(dir / name / "spot.ldt");
  };
  const std::string made = write("made", nullptr);
  ASSERT_FALSE(made.empty());
  EXPECT_EQ(write("given", &same), made);
  EXPECT_NE(write("turned", &turned), made);
  EXPECT_EQ(write("coarser", &coarser), made);
}

// A file that cannot be written (the plot program missing, a path taken by
// a folder) is listed with its error; every other file is still written,
// read back and listed, and report.json's "outputs" names both kinds.
TEST(SimulationOutputs, FilesThatCannotBeWrittenAreListedAndTheOthersWritten) {
  const int n = 16;
  sim::FarField field(n);
  const sim::CubeMapGrid& grid = field.grid();
  for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, 800.0 * grid.texel_solid_angle(t) / (4 * M_PI), 1000);
  const sim::SceneDesc scene = bare_scene(1000.0);
  const sim::Ledger ledger = ledger_for(field, 1000.0);
  test::TempDir dir;
  std::filesystem::create_directories(dir / "iso.ldt");  // the LDT's path is a folder
  OutputRequest req;
  req.directory = dir.path().string();
  req.stem = "iso";
  req.formats = {OutputFormat::Ies, OutputFormat::Ldt, OutputFormat::Exr, OutputFormat::LatLong, OutputFormat::Plot};
  req.grid = {15.0, 5.0};
  req.run = {"test", "iso.gltf", 1000, 1, 10, "2024-01-01"};
  const test::ScopedEnv no_gnuplot("GONIO_GNUPLOT", "/nonexistent/gnuplot");
  auto result = write_outputs(field, scene, ledger, req);
  ASSERT_TRUE(result.ok()) << result.error().message;
  ASSERT_EQ(result->failed.size(), 2u);
  EXPECT_EQ(result->failed[0].format, OutputFormat::Ldt);
  EXPECT_EQ(result->failed[0].path, (dir / "iso.ldt").string());
  EXPECT_EQ(result->failed[1].format, OutputFormat::Plot);
  EXPECT_NE(to_string(result->failed[1].error).find("gnuplot"), std::string::npos) << to_string(result->failed[1].error);
  EXPECT_FALSE(std::filesystem::exists(dir / "iso.svg"));
  ASSERT_EQ(result->files.size(), 3u);
  const OutputFormat written[] = {OutputFormat::Ies, OutputFormat::Exr, OutputFormat::LatLong};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(result->files[i].format, written[i]);
    EXPECT_TRUE(std::filesystem::is_regular_file(result->files[i].path)) << result->files[i].path;
    EXPECT_NEAR(result->files[i].flux_lm, 800.0, 1e-3) << result->files[i].path;
  }
  const nlohmann::json j = to_json(*result, req.grid, 800.0);
  ASSERT_EQ(j["files"].size(), 3u);
  ASSERT_EQ(j["failed"].size(), 2u);
  EXPECT_EQ(j["failed"][0]["format"], "ldt");
  EXPECT_EQ(j["failed"][1]["path"], (dir / "iso.svg").string());
  EXPECT_NE(j["failed"][1]["error"].get<std::string>().find("gnuplot"), std::string::npos);
}

// Books that close: 1000 photons of 1 lm, 600 escaped, 350 absorbed, 50 cut off.
sim::Ledger closed_books() {
  sim::Ledger l;
  l.photon_power_lm = 1.0;
  l.emitted = {1000, 1000.0};
  l.escaped = {600, 600.0};
  l.absorbed = {350, 350.0};
  l.cutoff = {50, 50.0};
  return l;
}

TEST(EnergyCheck, BooksThatDoNotCloseFailTheRunWithAClearMessage) {
  WrittenFile ies;
  ies.path = "out/lamp.ies";
  ies.flux_lm = 600.3;
  ies.flux_difference = 0.0005;
  const EnergyCheck good = check_energy(closed_books(), {ies}, 0.0, 0.005);
  EXPECT_TRUE(good.passed());
  EXPECT_NEAR(good.lor, 0.6, 1e-15);
  EXPECT_TRUE(good.json["passed"].get<bool>());
  testing::internal::CaptureStderr();
  EXPECT_EQ(energy_exit_code("lamp.gltf", good), 0);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");

  // Ten photons vanished between the tracer and the books.
  sim::Ledger lost = closed_books();
  lost.absorbed = {340, 340.0};
  const EnergyCheck bad = check_energy(lost, {ies}, 0.0, 0.005);
  ASSERT_EQ(bad.failures.size(), 1u);
  EXPECT_FALSE(bad.json["passed"].get<bool>());
  EXPECT_FALSE(bad.json["photons_close"].get<bool>());
  EXPECT_NEAR(bad.json["flux_imbalance_lm"].get<double>(), 10.0, 1e-12);
  testing::internal::CaptureStderr();
  EXPECT_EQ(energy_exit_code("lamp.gltf", bad), 1);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_EQ(err,
            "gonio: lamp.gltf: energy check failed: the books do not close: emitted 1000 photons (1000 lm), "
            "escaped + absorbed + cut off 990 photons (990 lm)\n");

  // Photons that add up but lumens that do not (a photon's power misbooked).
  sim::Ledger misbooked = closed_books();
  misbooked.cutoff.flux_lm = 50.001;
  const EnergyCheck flux = check_energy(misbooked, {ies}, 0.0, 0.005);
  ASSERT_EQ(flux.failures.size(), 1u);
  EXPECT_TRUE(flux.json["photons_close"].get<bool>());
  EXPECT_NE(flux.failures[0].find("1000 photons (1000.001 lm)"), std::string::npos) << flux.failures[0];
  testing::internal::CaptureStderr();
  EXPECT_EQ(energy_exit_code("lamp.gltf", flux), 1);
  EXPECT_NE(testing::internal::GetCapturedStderr().find("energy check failed: the books do not close"),
            std::string::npos);
  // Rounding is not a failure: 1e-12 of the emitted flux.
  misbooked.cutoff.flux_lm = 50.0 + 1e-9;
  EXPECT_TRUE(check_energy(misbooked, {ies}, 0.0, 0.005).passed());
}

TEST(EnergyCheck, EveryFailedCheckIsListed) {
  sim::Ledger lost = closed_books();
  lost.escaped = {590, 590.0};
  WrittenFile ldt;
  ldt.path = "out/lamp.ldt";
  ldt.flux_lm = 620.0;
  ldt.flux_difference = 620.0 / 590.0 - 1.0;
  Finding lorl;
  lorl.code = "ldt-lorl";
  lorl.message = "declared LORL differs";
  lorl.where.file = "out/lamp.ldt";
  ldt.findings.push_back(lorl);
  const EnergyCheck c = check_energy(lost, {ldt}, 0.7, 0.005);
  ASSERT_EQ(c.failures.size(), 4u);
  EXPECT_NE(c.failures[0].find("the books do not close"), std::string::npos);
  EXPECT_NE(c.failures[1].find("light output ratio 0.59"), std::string::npos) << c.failures[1];
  EXPECT_NE(c.failures[1].find("--min-lor"), std::string::npos);
  EXPECT_NE(c.failures[2].find("out/lamp.ldt: flux 620"), std::string::npos) << c.failures[2];
  EXPECT_NE(c.failures[2].find("+5.085 %"), std::string::npos) << c.failures[2];
  EXPECT_NE(c.failures[3].find("[ldt-lorl]"), std::string::npos) << c.failures[3];
  EXPECT_EQ(c.json["failures"].size(), 4u);
  EXPECT_FALSE(c.json["files"][0]["flux_ok"].get<bool>());
  EXPECT_FALSE(c.json["files"][0]["clean"].get<bool>());
}

}  // namespace
}  // namespace gonio::app

namespace gonio::app {
namespace {

// The luminous opening from the trace's own escapes (issue 40) against the
// same photons traced again by simulated_opening: the same points in the
// same order, so every field equal (the centre's height is a sum in order).
sim::Simulation traced_mixed_scene(sim::SamplerKind sampler, sim::NextEventMode next_event, std::uint64_t capture,
                                   int threads) {
  sim::SimulationSettings s = sim::test_scenes::small_run(threads, 40'000, 2, 7);
  s.sampler = sampler;
  s.next_event = next_event;
  s.capture_escaped_photons = capture;
  Result<sim::Simulation> created = sim::Simulation::create(sim::test_scenes::mixed_scene(), s);
  EXPECT_TRUE(created.ok());
  sim::Simulation simulation = std::move(created.value());
  simulation.run_iteration();
  simulation.run_iteration();
  return simulation;
}

void expect_same_opening(const SimulatedOpening& a, const SimulatedOpening& b) {
  EXPECT_EQ(a.exits, b.exits);
  EXPECT_EQ(a.opening.shape, b.opening.shape);
  EXPECT_EQ(a.opening.length_m, b.opening.length_m);
  EXPECT_EQ(a.opening.width_m, b.opening.width_m);
  EXPECT_EQ(a.centre_m.x, b.centre_m.x);
  EXPECT_EQ(a.centre_m.y, b.centre_m.y);
  EXPECT_EQ(a.centre_m.z, b.centre_m.z);
}

TEST(SimulatedOpening, FromTheTracesEscapesEqualsTracingThemAgain) {
  // Both samplers, one and two threads; a capture beyond the opening's
  // photons (TM-25 rays) is left out.
  struct Case {
    sim::SamplerKind sampler;
    int threads;
    std::uint64_t capture;
  };
  for (const Case& c : {Case{sim::SamplerKind::Random, 1, kOpeningPhotons},
                        Case{sim::SamplerKind::Random, 2, kOpeningPhotons + 5000},
                        Case{sim::SamplerKind::Sobol, 2, kOpeningPhotons},
                        Case{sim::SamplerKind::Sobol, 1, kOpeningPhotons + 5000}}) {
    const sim::Simulation simulation = traced_mixed_scene(c.sampler, sim::NextEventMode::Off, c.capture, c.threads);
    ASSERT_TRUE(opening_from_trace(simulation));
    const SimulatedOpening traced = simulated_opening(simulation);
    const SimulatedOpening again =
        simulated_opening(simulation.tracer(), simulation.scene(), simulation.settings().seed);
    EXPECT_GT(traced.exits, 1000u);
    expect_same_opening(traced, again);
  }
}

TEST(SimulatedOpening, TracesAgainWhereTheTraceCannotTell) {
  // Too few escapes kept, or next-event connections drew from the photons'
  // random numbers (their paths differ from record_rays'): traced again.
  const sim::Simulation few = traced_mixed_scene(sim::SamplerKind::Random, sim::NextEventMode::Off, 1000, 2);
  EXPECT_FALSE(opening_from_trace(few));
  const sim::Simulation nee = traced_mixed_scene(sim::SamplerKind::Random, sim::NextEventMode::On, kOpeningPhotons, 2);
  ASSERT_TRUE(nee.next_event().enabled);
  EXPECT_FALSE(opening_from_trace(nee));
  expect_same_opening(simulated_opening(nee), simulated_opening(nee.tracer(), nee.scene(), nee.settings().seed));
  // Fewer photons traced than the opening needs.
  sim::SimulationSettings s = sim::test_scenes::small_run(2, 1000, 1, 7);
  s.capture_escaped_photons = kOpeningPhotons;
  Result<sim::Simulation> small = sim::Simulation::create(sim::test_scenes::mixed_scene(), s);
  ASSERT_TRUE(small.ok());
  small->run_iteration();
  EXPECT_FALSE(opening_from_trace(*small));
}

}  // namespace
}  // namespace gonio::app
