// gonio tolerance's CIE 232 figures and emitter bins through the executable
// (issue 42, docs/tolerance.md "Fourth slice"): with --luminance-image every
// trace gives CIE 232:2019's ΔUGR (dugr) and the corrected UGR; the nominal's
// equals gonio simulate's for the same model and photons; one of two equal
// LEDs dimmed below the glare threshold changes ΔUGR by the amount CIE 232's
// formula gives; a bin that changes nothing changes nothing, bit for bit.
// Colour bins give each trial the CCT of its bin's spectrum; flux bins scale
// the flux by their factor.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/model/gltf_writer.h"
#include "photometry/colour.h"
#include "photometry/spectrum.h"
#include "sim/shapes.h"
#include "tests/support/test_support.h"

namespace gonio {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kLuminance = 20000.0;  // each square's luminance [cd/m²]
constexpr double kSide = 0.03;          // each square's side [m]

test::ProcessResult gonio(std::vector<std::string> args) {
  args.insert(args.begin(), GONIO_EXECUTABLE);
  return test::run_process(args);
}

// A square of side kSide in the plane y = 0 around (x, 0, 0), facing −Y (the
// nadir): two triangles wound so that their normal is −Y.
sim::Mesh square(double x) {
  sim::Mesh m;
  const float h = static_cast<float>(kSide / 2.0), c = static_cast<float>(x);
  m.positions = {{c - h, 0.0f, -h}, {c + h, 0.0f, -h}, {c + h, 0.0f, h}, {c - h, 0.0f, h}};
  m.normals.assign(4, sim::Vec3f{0.0f, -1.0f, 0.0f});
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

// `count` Lambertian squares of kLuminance ("led1", "led2"), 80 mm apart
// along X, nothing else: a uniform source (one) or two equal LEDs with a dark
// gap of 50 mm between them (more than 9σ of CIE 232's 12 mm filter).
fs::path write_squares(const fs::path& dir, int count) {
  io::GltfWriter w("gonio tolerance glare test");
  const int material = w.material({{"name", "led"},
                                   {"pbrMetallicRoughness", {{"baseColorFactor", {0.0, 0.0, 0.0, 1.0}}}},
                                   {"extras", {{"gonio", {{"luminance_cd_m2", kLuminance}}}}}});
  for (int k = 0; k < count; ++k) {
    const std::string name = "led" + std::to_string(k + 1);
    const double x = count == 1 ? 0.0 : (k == 0 ? -0.04 : 0.04);
    w.node({{"name", name}, {"mesh", w.mesh(square(x), material, name)}});
  }
  std::string bin;
  const std::string text = w.finish("squares.bin", bin);
  test::write_file(dir / "squares.bin", bin);
  test::write_file(dir / "squares.gltf", text);
  return dir / "squares.gltf";
}

json run(const fs::path& dir, const fs::path& model, const std::string& tolerances, std::vector<std::string> extra) {
  test::write_file(dir / "t.toml", tolerances);
  std::vector<std::string> args = {"tolerance", model.string(), "--tolerances", (dir / "t.toml").string(),
                                   "--out", (dir / "out").string(), "--threads", "2"};
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

// CIE 232's ΔUGR of a uniform square of side a and luminance L seen
// straight on (γ = 0), in closed form: the filtered image is L·g(x)·g(y),
// g(x) = Φ((x + a/2)/σ) − Φ((x − a/2)/σ) (σ = 12 mm / 2.35482); the glare
// source R where it is ≥ 500 cd/m², A_eff its area, L_eff·A_eff = ∫_R L g g;
// I = L a², A_p = a² (the opening: the square itself). k² = (L_eff A_eff)² /
// A_eff · A_p / I², integrated on a 0.02 mm grid. A small bright face has a
// blurred rim that counts as glare source: k² < 1.
double uniform_square_delta_ugr() {
  const double sigma = 0.012 / (2.0 * std::sqrt(2.0 * std::log(2.0)));
  const auto g = [&](double x) {
    return 0.5 * (std::erfc(-(x + kSide / 2.0) / (sigma * std::numbers::sqrt2)) -
                  std::erfc(-(x - kSide / 2.0) / (sigma * std::numbers::sqrt2)));
  };
  const double h = 2e-5, reach = kSide / 2.0 + 4.0 * sigma;
  std::vector<double> gx;
  for (double x = -reach + h / 2.0; x < reach; x += h) gx.push_back(g(x));
  double area = 0.0, light = 0.0;
  for (double a : gx)
    for (double b : gx)
      if (kLuminance * a * b >= 500.0) {
        area += h * h;
        light += kLuminance * a * b * h * h;
      }
  const double ap = kSide * kSide, intensity = kLuminance * ap;
  return 8.0 * std::log10(light * light / area * ap / (intensity * intensity));
}

// A uniform source: the nominal's ΔUGR is gonio simulate's cie232.delta_ugr
// for the same model, photons and seed, to the bit (the same code, the same
// photons), and the closed form above to the pixels' accuracy (1.2 mm pixels
// against the continuous image: 0.05); a flux bin of factor 1 is traced (not
// read back) and changes neither ΔUGR nor the corrected UGR, bit for bit.
// Without --luminance-image both figures are not defined.
TEST(ToleranceGlareCli, NominalDeltaUgrEqualsGonioSimulateAndAUnitBinChangesNothing) {
  test::TempDir dir;
  const fs::path model = write_squares(dir.path(), 1);
  const std::vector<std::string> common = {"--photons", "100000", "--c-step", "15", "--gamma-step", "5",
                                           "--luminance-image", "0:0"};
  std::vector<std::string> extra = common;
  extra.insert(extra.end(), {"--trials", "2", "--noise-seeds", "2"});
  const json report = run(dir.path(), model, "[emitter.\"led1/led1/0\"]\nflux_bin = { factors = [1.0] }\n", extra);
  ASSERT_FALSE(report.is_null());
  const json& nominal = report["nominal"];
  ASSERT_TRUE(nominal["dugr"].is_number()) << nominal.dump();
  std::vector<std::string> sim_args = {"simulate", model.string(), "--out", (dir / "sim").string(), "--iterations",
                                       "1", "--symmetry", "none", "--threads", "2", "--format", "ies"};
  sim_args.insert(sim_args.end(), common.begin(), common.end());
  const test::ProcessResult s = gonio(sim_args);
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const json simulated = json::parse(test::read_file(dir / "sim" / "report.json"));
  EXPECT_EQ(nominal["dugr"].get<double>(), simulated["cie232"]["delta_ugr"].get<double>());
  EXPECT_EQ(nominal["ugr_cie232"].get<double>(), nominal["ugr"].get<double>() + nominal["dugr"].get<double>());
  const double closed = uniform_square_delta_ugr();
  std::printf("uniform square: dugr %.4f, closed form %.4f\n", nominal["dugr"].get<double>(), closed);
  EXPECT_NEAR(nominal["dugr"].get<double>(), closed, 0.05);
  EXPECT_TRUE(report["noise"]["floor"]["dugr"].is_number());
  for (const char* figure : {"dugr", "ugr_cie232"}) {
    const json& r = row(report, figure, "led1/led1/0.flux_bin");
    EXPECT_EQ(r["change_low"].get<double>(), 0.0) << figure;
    for (const json& t : report["monte_carlo"]["trials"])
      EXPECT_EQ(t["figures"][figure].get<double>(), nominal[figure].get<double>()) << figure;
  }
  // Without luminance images: not defined.
  const json grey = run(dir.path(), model, "[emitter.\"led1/led1/0\"]\nflux = { uniform = 1 }\n",
                        {"--photons", "20000", "--trials", "0", "--noise-seeds", "0", "--c-step", "15"});
  ASSERT_FALSE(grey.is_null());
  EXPECT_TRUE(grey["nominal"]["dugr"].is_null());
  EXPECT_TRUE(grey["sensitivity"]["dugr"]["rows"].empty());
  // The journal's header names the views: resuming with other views (here
  // none, after a run with 0:0) is refused rather than mixing their figures.
  const test::ProcessResult again =
      gonio({"tolerance", model.string(), "--tolerances", (dir / "t.toml").string(), "--out", (dir / "out").string(),
             "--photons", "20000", "--trials", "0", "--noise-seeds", "0", "--c-step", "15", "--luminance-image", "0:0",
             "--resume"});
  EXPECT_EQ(again.exit_code, 1);
  EXPECT_NE(again.err.find("written by another run"), std::string::npos) << again.err;
}

// Two equal LEDs (L = 20 000 cd/m², 30 mm squares, 50 mm apart). CIE 232:
// k² = L_eff² A_eff A_p / I², L_eff A_eff the filtered light over the glare
// source. Nominal: both squares are glare sources, A_eff = 2A₁, L_eff A_eff =
// c·2I₁ (c: the share of a square's blurred light at ≥ 500 cd/m², the same
// for both), I = 2I₁. With LED 2's flux × s (s = 0.01: 200 cd/m², below the
// 500 cd/m² threshold after any blur) only LED 1 is a glare source: A_eff =
// A₁, L_eff A_eff = c·I₁, I = (1 + s)I₁. So k²(s)/k²(1) = 2/(1 + s)², and
// ΔUGR moves by 8 log₁₀(2/(1 + s)²) = +2.339 in every view, whatever c, the
// pixels or the view (the luminous opening, and so A_p, stays the bounding
// rectangle of both squares). The bin of factor 1 changes nothing, bit for bit.
TEST(ToleranceGlareCli, OneOfTwoLedsDimmedBelowTheThresholdMovesDeltaUgrAsCie232Says) {
  test::TempDir dir;
  const fs::path model = write_squares(dir.path(), 2);
  const json report =
      run(dir.path(), model,
          "[emitter.\"led2/led2/0\"]\nflux_bin = { factors = [0.01, 1.0], probabilities = [0.5, 0.5] }\n",
          {"--photons", "200000", "--c-step", "15", "--gamma-step", "5", "--luminance-image", "ugr", "--trials", "4",
           "--noise-seeds", "3", "--spec", "dugr<=0", "--inverse-steps", "2"});
  ASSERT_FALSE(report.is_null());
  const double s = 0.01, expected = 8.0 * std::log10(2.0 / ((1.0 + s) * (1.0 + s)));
  const json& r = row(report, "dugr", "led2/led2/0.flux_bin");
  const double noise = report["sensitivity"]["dugr"]["noise"].get<double>();
  const double change = r["change_low"].get<double>();
  std::printf("nominal dugr %.4f, noise %.4g, change at bin 1 %.4f (closed form %.4f)\n",
              report["nominal"]["dugr"].get<double>(), noise, change, expected);
  EXPECT_NEAR(change, expected, std::max(4.0 * noise, 0.02));
  EXPECT_FALSE(r["below_noise"].get<bool>());
  EXPECT_EQ(r["change_high"].get<double>(), 0.0);  // factor 1
  const double nominal = report["nominal"]["dugr"].get<double>();
  int dimmed = 0;
  for (const json& t : report["monte_carlo"]["trials"]) {
    const double bin = t["values"]["led2/led2/0.flux_bin"].get<double>();
    if (bin == 2.0) EXPECT_EQ(t["figures"]["dugr"].get<double>(), nominal);
    else {
      ++dimmed;
      EXPECT_EQ(t["figures"]["dugr"].get<double>(), nominal + change);  // the same trace as the sensitivity's
    }
  }
  EXPECT_EQ(dimmed, 2);  // 4 Latin-hypercube draws of two bins of 0.5: two each
  // The yield of dugr<=0: the two trials of bin 2 (ΔUGR −1.7), not those of bin 1 (+0.6).
  EXPECT_EQ(report["monte_carlo"]["yield"]["all"].get<double>(), 0.5);
  // A bin number is not scaled by the inverse sensitivity.
  ASSERT_EQ(report["inverse_sensitivity"].size(), 1u);
  EXPECT_EQ(report["inverse_sensitivity"][0]["why"], "bins");
  EXPECT_FALSE(report["inverse_sensitivity"][0].contains("traced_scale"));
}

// The spectrum of a text file of two columns, read here on its own (not
// through design::read_spectrum_table).
photometry::SampledSpectrum two_columns(const fs::path& file) {
  std::ifstream in(file);
  photometry::SampledSpectrum s;
  double nm = 0.0, v = 0.0;
  while (in >> nm >> v) {
    s.wavelengths_nm.push_back(nm);
    s.values.push_back(v);
  }
  return s;
}

// One isotropic point lamp "led" (a 4000 K blackbody, 1000 lm) and nothing
// else: every photon leaves directly, so the luminaire's colour is the
// lamp's spectrum's.
fs::path write_lamp(const fs::path& dir) {
  io::GltfWriter w("gonio tolerance bins test");
  const int light = w.khr_light({{"name", "led"},
                                 {"type", "point"},
                                 {"intensity", 1000.0 / (4.0 * std::numbers::pi)},
                                 {"extras", {{"gonio", {{"spectrum", {{"blackbody_k", 4000.0}}}}}}}});
  w.node({{"name", "led"}, {"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}});
  // A small black disc far above: the scene needs a surface.
  const int black = w.material({{"name", "black"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.0, 0.0, 0.0, 1.0}}}}});
  w.node({{"name", "disc"}, {"mesh", w.mesh(sim::disc(0.001, 8), black, "disc")}, {"translation", {0.0, 1.0, 0.0}}});
  std::string bin;
  const std::string text = w.finish("lamp.bin", bin);
  test::write_file(dir / "lamp.bin", bin);
  test::write_file(dir / "lamp.gltf", text);
  return dir / "lamp.gltf";
}

// Colour bins: bin 1 a 2700 K blackbody (its CCT is 2700 K, the Planckian
// locus' own point), bin 2 a measured spectrum from the corpus (its CCT the
// project's colour code gives for the file's samples, read here on their
// own). The sensitivity traces the first and last bin; every Monte Carlo
// trial's CCT is its bin's. Flux bins: the trial's flux is the nominal's ×
// the bin's factor.
TEST(ToleranceGlareCli, ColourBinsGiveTheirSpectrumsCctAndFluxBinsScaleTheFlux) {
  GONIO_REQUIRE_CORPUS();
  test::TempDir dir;
  const fs::path model = write_lamp(dir.path());
  const fs::path measured = test::corpus_dir() / "spectra" / "LERTDUW_S2WP_binBQ_white-yellow_20110706_spectrum.txt";
  fs::copy_file(measured, dir / "yellow.txt");
  const double measured_cct = photometry::cct_duv(photometry::tristimulus(two_columns(measured))).cct_k;
  const double planck_cct = photometry::cct_duv(photometry::planckian_uv_prime(2700.0)).cct_k;
  ASSERT_NEAR(planck_cct, 2700.0, 0.5);
  const json report = run(dir.path(), model,
                          "[emitter.led]\n"
                          "colour_bin = { spectra = [{ blackbody_k = 2700 }, \"yellow.txt\"], probabilities = [0.25, 0.75] }\n"
                          "flux_bin = { factors = [0.9, 1.1] }\n",
                          {"--photons", "100000", "--c-step", "15", "--gamma-step", "5", "--trials", "8",
                           "--noise-seeds", "2"});
  ASSERT_FALSE(report.is_null());
  const double nominal_cct = report["nominal"]["cct"].get<double>();
  const double cct_noise = report["sensitivity"]["cct"]["noise"].get<double>();
  const json& c = row(report, "cct", "led.colour_bin");
  std::printf("nominal CCT %.2f K (noise %.3g); bin 1 %.2f K (closed form %.2f), bin 2 %.2f K (file's own %.2f)\n",
              nominal_cct, cct_noise, nominal_cct + c["change_low"].get<double>(), planck_cct,
              nominal_cct + c["change_high"].get<double>(), measured_cct);
  EXPECT_NEAR(nominal_cct, 4000.0, 1.0);
  EXPECT_NEAR(nominal_cct + c["change_low"].get<double>(), planck_cct, std::max(4.0 * cct_noise, 1.0));
  EXPECT_NEAR(nominal_cct + c["change_high"].get<double>(), measured_cct, std::max(4.0 * cct_noise, 1.0));
  const double nominal_flux = report["nominal"]["flux"].get<double>();
  const json& f = row(report, "flux", "led.flux_bin");
  EXPECT_NEAR(f["change_low"].get<double>(), -0.1 * nominal_flux, 1e-9 * nominal_flux);
  EXPECT_NEAR(f["change_high"].get<double>(), 0.1 * nominal_flux, 1e-9 * nominal_flux);
  int bin1 = 0;
  for (const json& t : report["monte_carlo"]["trials"]) {
    const double bin = t["values"]["led.colour_bin"].get<double>();
    const double cct = t["figures"]["cct"].get<double>();
    const double want = bin == 1.0 ? planck_cct : measured_cct;
    bin1 += bin == 1.0 ? 1 : 0;
    EXPECT_NEAR(cct, want, std::max(4.0 * cct_noise, 1.0)) << t.dump();
    const double factor = t["values"]["led.flux_bin"].get<double>() == 1.0 ? 0.9 : 1.1;
    EXPECT_NEAR(t["figures"]["flux"].get<double>(), factor * nominal_flux, 1e-9 * nominal_flux);
  }
  EXPECT_EQ(bin1, 2);  // 8 strata, P = 0.25: exactly 2
  // report.json names each bin.
  for (const json& t : report["tolerances"]) {
    ASSERT_TRUE(t.contains("bins")) << t.dump();
    if (t["name"] == "led.colour_bin") {
      EXPECT_EQ(t["bins"][0]["name"], "2700 K");
      EXPECT_EQ(t["bins"][1]["name"], "yellow.txt");
      EXPECT_EQ(t["bins"][1]["probability"].get<double>(), 0.75);
    } else {
      EXPECT_EQ(t["bins"][1]["factor"].get<double>(), 1.1);
    }
  }
}

// Mistakes name the file and line: an unknown spectrum file, probabilities
// that do not sum to 1, a colour bin on an emitter without a spectrum.
TEST(ToleranceGlareCli, BadBinsAreErrorsNamingTheLine) {
  test::TempDir dir;
  const fs::path model = write_lamp(dir.path());
  const auto fails = [&](const std::string& toml, const std::string& message) {
    test::write_file(dir / "t.toml", toml);
    const test::ProcessResult r = gonio({"tolerance", model.string(), "--tolerances", (dir / "t.toml").string(),
                                         "--out", (dir / "out").string(), "--photons", "1000"});
    EXPECT_EQ(r.exit_code, 1) << toml;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  };
  fails("[emitter.led]\n\ncolour_bin = { spectra = [\"missing.txt\"] }\n",
        "t.toml:3: emitter.led.colour_bin.spectra: no spectrum file '" + (dir / "missing.txt").string() + "'");
  fails("[emitter.led]\nflux_bin = { factors = [0.9, 1.1], probabilities = [0.5, 0.4] }\n",
        "t.toml:2: emitter.led.flux_bin.probabilities sum to 0.9, not 1");
  test::write_file(dir / "bad.txt", "nm value\n400 1\n500 x\n");
  fails("[emitter.led]\ncolour_bin = { spectra = [\"bad.txt\"] }\n",
        (dir / "bad.txt").string() + ":3: write two numbers per line");
  const fs::path squares = write_squares(dir.path(), 1);
  test::write_file(dir / "t.toml", "[emitter.\"led1/led1/0\"]\ncolour_bin = { cct = [3000] }\n");
  const test::ProcessResult r = gonio({"tolerance", squares.string(), "--tolerances", (dir / "t.toml").string(),
                                       "--out", (dir / "out").string(), "--photons", "1000"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("t.toml:2: led1/led1/0.colour_bin: 'led1/led1/0' has no spectrum in the model"),
            std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace gonio
