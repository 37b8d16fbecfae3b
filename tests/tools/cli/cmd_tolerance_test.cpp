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
#include <limits>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "design/reflector_design.h"
#include "design/tolerance.h"
#include "io/model/gltf_writer.h"
#include "io/photometric/photometric_file.h"
#include "io/photometric/tm25.h"
#include "photometry/colour.h"
#include "photometry/compare.h"
#include "photometry/intensity_sampler.h"
#include "photometry/spectrum.h"
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
fs::path write_paraboloid(const fs::path& dir, bool smooth = true, double aperture = kAperture) {
  sim::Mesh mirror = smooth ? sim::paraboloid(kF, aperture, 0.0, 48, 192) : sim::paraboloid(kF, aperture, 0.0, 8, 32);
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

// The regularised lower incomplete gamma function P(a, x) by its series
// (x up to a few hundred: the terms fall once n > x), for χ² probabilities.
double lower_gamma_p(double a, double x) {
  if (x <= 0.0) return 0.0;
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 2000; ++n) {
    term *= x / (a + n);
    sum += term;
    if (term < 1e-17 * sum) break;
  }
  return std::exp(a * std::log(x) - x - std::lgamma(a)) * sum;
}

// Kolmogorov's distribution: P(√N·D > λ) for the one-sample statistic D,
// with Stephens' finite-N factor (√N + 0.12 + 0.11/√N).
double ks_p_value(double d, std::size_t n) {
  const double rn = std::sqrt(static_cast<double>(n));
  const double lambda = (rn + 0.12 + 0.11 / rn) * d;
  if (lambda < 0.2) return 1.0;
  double p = 0.0;
  for (int k = 1; k <= 100; ++k) p += 2.0 * ((k % 2) ? 1.0 : -1.0) * std::exp(-2.0 * k * k * lambda * lambda);
  return std::clamp(p, 0.0, 1.0);
}

// The distribution function of N(0, σ) truncated at ±kσ.
double truncated_normal_cdf(double x, double sigma, double k) {
  const auto phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  const double z = std::clamp(x / sigma, -k, k);
  return (phi(z) - phi(-k)) / (phi(k) - phi(-k));
}

// A statistical test of the Monte Carlo against the closed form. The source
// is displaced by Δ ~ N(0, σ = 1 mm) truncated at ±3σ (the default) along
// C0; the beam then leaves tilted by arctan(Δ/f) towards C180. 40 trials on
// a 0.5° γ, 5° C grid. Each trial's peak (C, γ) gives the tilt projected on
// the C0-C180 plane, t = atan(tan γ · cos C), and the displacement it
// implies, Δ' = −f·tan t; the grid's quantisation makes that an interval
// [Δ'_lo, Δ'_hi] (the peak anywhere in its bin: γ ± 0.25°, C ± 2.5°).
//  - Kolmogorov–Smirnov at α = 0.01: the smallest KS distance between the
//    law of Δ and any placement of the Δ' within their intervals (the
//    empirical distribution lies between the counts of upper and of lower
//    ends); the test fails where its p-value is below α.
//  - χ² on the variance at α = 0.01 (two-sided): (N − 1)s²/σ_t² against
//    χ²(N − 1), σ_t² the truncated law's variance; the quantisation moves
//    √(N − 1)·s by at most √N·w (w the largest half interval), and the test
//    fails only where no s in that range is accepted.
// Both tests assume independent draws; the Latin hypercube's stratified
// draws are closer to the law than independent ones, which makes both
// conservative (they reject less often than α), never anti-conservative.
TEST(ToleranceCli, MonteCarloBeamDirectionsPassKolmogorovSmirnovAndChiSquaredAgainstArctanDeltaOverF) {
  test::TempDir dir;
  // A paraxial cap: the rim at 20° from the axis seen from the focus
  // (aperture 2f·tan 10°), where every ray's turn, Δ·cos θ·(1 + cos θ)/2f,
  // is within 9 % of the vertex ray's Δ/f (on the whole dish, out to 90°,
  // the rays far from the vertex turn less and pull the peak bin below
  // arctan(Δ/f)).
  write_paraboloid(dir.path(), true, 2.0 * kF * std::tan(10.0 * std::numbers::pi / 180.0));
  constexpr std::size_t kTrials = 40;
  constexpr double kSigma = 2.0, kTruncate = 2.0, kAlpha = 0.05, kGammaHalf = 0.25, kCHalf = 2.5;
  const json report = run_tolerance(dir.path(), "[emitter.lamp]\nx = { normal = 2.0, truncate = 2 }\n",
                                    {"--photons", "100000", "--gamma-step", "0.5", "--c-step", "5", "--trials",
                                     std::to_string(kTrials), "--noise-seeds", "0"});
  ASSERT_FALSE(report.is_null());
  ASSERT_EQ(report["monte_carlo"]["trials"].size(), kTrials);
  const double f_mm = kF * 1000.0, deg = std::numbers::pi / 180.0;
  std::vector<double> lo, hi, mid;
  int inside = 0;
  for (const json& trial : report["monte_carlo"]["trials"]) {
    const double gamma = trial["figures"]["peak_gamma"].get<double>(), c = trial["figures"]["peak_c"].get<double>();
    double a = std::numeric_limits<double>::infinity(), b = -a;
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j <= 10; ++j) {
        const double g = std::max(0.0, gamma - kGammaHalf + 2.0 * kGammaHalf * i / 10.0);
        const double cc = c - kCHalf + 2.0 * kCHalf * j / 10.0;
        const double implied = -f_mm * std::tan(g * deg) * std::cos(cc * deg);  // −f·tan t, tan t = tan γ·cos C
        a = std::min(a, implied);
        b = std::max(b, implied);
      }
    lo.push_back(a);
    hi.push_back(b);
    mid.push_back(0.5 * (a + b));
    inside += trial["values"]["lamp.x"].get<double>() >= a && trial["values"]["lamp.x"].get<double>() <= b;
    std::printf("drawn %+.4f implied [%+.4f, %+.4f] (peak C %g, γ %g)\n", trial["values"]["lamp.x"].get<double>(), a,
                b, c, gamma);
  }
  std::printf("%d of %zu drawn Δ within their trial's interval\n", inside, kTrials);
  const std::size_t n = kTrials;
  // KS: D ≥ max over x of (F(x) − #{lo ≤ x}/N, #{hi ≤ x}/N − F(x)).
  std::vector<double> slo = lo, shi = hi;
  std::sort(slo.begin(), slo.end());
  std::sort(shi.begin(), shi.end());
  double d = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    d = std::max(d, truncated_normal_cdf(slo[i], kSigma, kTruncate) - static_cast<double>(i) / n);
    d = std::max(d, static_cast<double>(i + 1) / n - truncated_normal_cdf(shi[i], kSigma, kTruncate));
  }
  const double p_ks = ks_p_value(d, n);
  std::printf("KS: smallest D over the bins %.4f, p = %.3g (α = %g)\n", d, p_ks, kAlpha);
  EXPECT_GT(p_ks, kAlpha) << "D = " << d;
  // χ² on the variance.
  const double k = kTruncate, pdf_k = std::exp(-0.5 * k * k) / std::sqrt(2.0 * std::numbers::pi);
  const double var_t = kSigma * kSigma * (1.0 - 2.0 * k * pdf_k / std::erf(k / std::sqrt(2.0)));
  double mean = 0.0, w = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    mean += mid[i] / n;
    w = std::max(w, 0.5 * (hi[i] - lo[i]));
  }
  double ss = 0.0;
  for (double m : mid) ss += (m - mean) * (m - mean);
  const double root = std::sqrt(ss), slack = std::sqrt(static_cast<double>(n)) * w;
  const double nu = static_cast<double>(n - 1);
  const double chi_lo = std::pow(std::max(0.0, root - slack), 2) / var_t, chi_hi = std::pow(root + slack, 2) / var_t;
  // Accepted where some χ² in [chi_lo, chi_hi] has a two-sided p-value above α.
  const double p_lo_end = lower_gamma_p(nu / 2.0, chi_hi / 2.0);  // P(χ² ≤ chi_hi)
  const double p_hi_end = 1.0 - lower_gamma_p(nu / 2.0, chi_lo / 2.0);  // P(χ² ≥ chi_lo)
  std::printf("variance: s² = %.4f mm² (σ_t² = %.4f), χ² in [%.2f, %.2f] on %g degrees of freedom, "
              "P(χ² ≤ hi) = %.3g, P(χ² ≥ lo) = %.3g\n",
              ss / nu, var_t, chi_lo, chi_hi, nu, p_lo_end, p_hi_end);
  EXPECT_GT(p_lo_end, kAlpha / 2.0) << "the spread of the beam directions is too small for the law";
  EXPECT_GT(p_hi_end, kAlpha / 2.0) << "the spread of the beam directions is too large for the law";
}

// A spot light (KHR_lights_punctual: a rotational Type C profile, outer
// cone 30°, smooth falloff) pointing at the nadir, "lamp", beside the
// paraboloid above it (the spot never reaches the mirror).
fs::path write_spot(const fs::path& dir) {
  io::GltfWriter w("gonio tolerance test");
  const int material = w.material({{"name", "mirror"}, {"pbrMetallicRoughness",
                                 {{"baseColorFactor", {kMirror, kMirror, kMirror, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.0}}}});
  w.node({{"name", "reflector"}, {"mesh", w.mesh(sim::paraboloid(kF, kAperture, 0.0, 8, 32), material, "reflector")}});
  const int light = w.khr_light({{"name", "lamp"}, {"type", "spot"}, {"intensity", 100.0},
                                 {"spot", {{"innerConeAngle", 0.0}, {"outerConeAngle", std::numbers::pi / 6.0}}}});
  // The spot shines along the node's −Z: turned −90° about X it shines along −Y, the nadir.
  w.node({{"name", "lamp"}, {"rotation", {-std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)}},
          {"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}});
  std::string bin;
  const std::string text = w.finish("paraboloid.bin", bin);
  test::write_file(dir / "paraboloid.bin", bin);
  test::write_file(dir / "paraboloid.gltf", text);
  return dir / "paraboloid.gltf";
}

// A tilt of a rotationally symmetric emitter turns its distribution by the
// tilt. The spot tilted by 10° about the C0 axis (tilt_x, one value):
//  - its beam axis (the mean direction of the light at ≥ half the peak)
//    moves by 10° towards C90 and not towards C0, to a tenth of the 2.5° γ
//    step (the axis is a quadrature over the grid's points);
//  - the whole tilted table (the one Monte Carlo trial, best.ies) equals the
//    nominal table turned by 10°, looked up at each direction turned back:
//    its RMS difference from that is below the noise floor (the mean RMS
//    difference of an independent seed from the nominal), where its RMS
//    difference from the nominal itself is many times the floor. On common
//    random numbers every photon leaves turned by exactly the tilt, so what
//    remains is the grid's binning and interpolation.
TEST(ToleranceCli, TiltOfASymmetricEmitterTurnsTheDistributionByTheTilt) {
  test::TempDir dir;
  write_spot(dir.path());
  constexpr double kTilt = 10.0;
  const json report = run_tolerance(dir.path(), "[emitter.lamp]\ntilt_x = { values = [10] }\n",
                                    {"--photons", "300000", "--trials", "1", "--noise-seeds", "2"});
  ASSERT_FALSE(report.is_null());
  EXPECT_NEAR(report["nominal"]["axis_c0"].get<double>(), 0.0, 0.25);
  EXPECT_NEAR(report["nominal"]["axis_c90"].get<double>(), 0.0, 0.25);
  const json& turned = row(report, "axis_c90", "lamp.tilt_x");
  const json& across = row(report, "axis_c0", "lamp.tilt_x");
  std::printf("axis change towards C90 %.4f, towards C0 %.4f\n", turned["change_high"].get<double>(),
              across["change_high"].get<double>());
  EXPECT_NEAR(turned["change_high"].get<double>(), kTilt, 0.25);
  EXPECT_NEAR(across["change_high"].get<double>(), 0.0, 0.25);

  Result<io::PhotometricFile> nominal = io::read_photometric_file((dir.path() / "out" / "nominal.ies").string());
  Result<io::PhotometricFile> tilted = io::read_photometric_file((dir.path() / "out" / "best.ies").string());
  ASSERT_TRUE(nominal.ok() && tilted.ok());
  const photometry::IntensitySampler sampler(nominal->distribution);
  photometry::Distribution expected = tilted->distribution;
  const double deg = std::numbers::pi / 180.0, a = -kTilt * deg;  // turned back about the C0 axis (x)
  for (std::size_t h = 0; h < expected.horizontal_count(); ++h)
    for (std::size_t v = 0; v < expected.vertical_count(); ++v) {
      const double c = expected.horizontal_deg[h] * deg, g = expected.vertical_deg[v] * deg;
      const double x = std::sin(g) * std::cos(c), y = std::sin(g) * std::sin(c), z = -std::cos(g);
      const double y2 = y * std::cos(a) - z * std::sin(a), z2 = y * std::sin(a) + z * std::cos(a);
      double c2 = std::atan2(y2, x) / deg;
      if (c2 < 0.0) c2 += 360.0;
      expected.at(h, v) = sampler.cd(c2, std::acos(std::clamp(-z2, -1.0, 1.0)) / deg);
    }
  Result<photometry::Comparison> to_turned = photometry::compare(expected, tilted->distribution);
  Result<photometry::Comparison> to_nominal = photometry::compare(nominal->distribution, tilted->distribution);
  ASSERT_TRUE(to_turned.ok() && to_nominal.ok());
  const double floor = report["noise"]["floor"]["rms"].get<double>();
  std::printf("RMS difference [%% of peak]: from the nominal turned by the tilt %.4f, from the nominal %.4f, "
              "noise floor %.4f\n", 100.0 * to_turned->rms_relative, 100.0 * to_nominal->rms_relative, floor);
  EXPECT_LT(100.0 * to_turned->rms_relative, floor);
  EXPECT_GT(100.0 * to_nominal->rms_relative, 10.0 * floor);
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

// The traced inverse sensitivity against the closed form: the mirror's
// reflectance ±10 % changes the flux linearly (±0.1·R·Φ/2 at the limits),
// so the largest factor k of the tolerance that keeps flux ≥ nominal − 20 lm
// is 20 lm over the change at the low limit (k ≈ 0.5). The bisection (4
// steps from [0, 1]) must bracket it: [held, failed] contains k_lin to 5
// standard deviations of the staircase (on common random numbers the change
// at k counts the photons whose roulette number falls between R(1 − 0.1k)
// and R: binomial, so k is known to √(k/(n·p)) with n = N/2, p = 0.08, and
// k_lin through the low limit's own count to k·√(1/(n·p))).
TEST(ToleranceCli, TracedInverseSensitivityBracketsTheLinearClosedForm) {
  test::TempDir dir;
  write_paraboloid(dir.path(), false);
  const long long photons = 400000;
  const std::string tol = "[material.mirror]\nreflectance = { uniform = 10 }\n";
  const json first = run_tolerance(dir.path(), tol,
                                   {"--photons", std::to_string(photons), "--trials", "0", "--noise-seeds", "0"});
  ASSERT_FALSE(first.is_null());
  const double nominal = first["nominal"]["flux"].get<double>();
  const double limit = nominal - 20.0;
  const json report = run_tolerance(dir.path(), tol,
                                    {"--photons", std::to_string(photons), "--trials", "0", "--noise-seeds", "2",
                                     "--spec", "flux>=" + std::to_string(limit), "--inverse-steps", "4"});
  ASSERT_FALSE(report.is_null());
  ASSERT_EQ(report["inverse_sensitivity"].size(), 1u);
  const json& e = report["inverse_sensitivity"][0];
  const double change_low = row(report, "flux", "mirror.reflectance")["change_low"].get<double>();
  const double k_lin = (nominal - limit) / -change_low;
  EXPECT_NEAR(e["scale"].get<double>(), k_lin, 1e-9);  // the linear estimate, as before
  const double held = e["traced_scale"].get<double>(), failed = e["traced_fails_at"].get<double>();
  const double np = 0.5 * static_cast<double>(photons) * 0.1 * kMirror;
  const double sd = std::sqrt(k_lin / np + k_lin * k_lin / np);
  std::printf("k_lin %.4f, traced [%.4f, %.4f], 5 sd %.4f, %d traces\n", k_lin, held, failed, 5 * sd,
              e["traces"].get<int>());
  EXPECT_EQ(failed - held, 1.0 / 16.0);  // 4 halvings of [0, 1]
  EXPECT_LE(held, k_lin + 5.0 * sd);
  EXPECT_GE(failed, k_lin - 5.0 * sd);
  EXPECT_DOUBLE_EQ(e["traced_low"].get<double>(), -10.0 * held);
  // 4 steps, each tracing the low limit and, where that held, the high one.
  EXPECT_GE(e["traces"].get<int>(), 4);
  EXPECT_LE(e["traces"].get<int>(), 8);
}

// The traced inverse sensitivity stops where the model ends: a reflectance
// of 0.8 ± 10 % may grow by at most (1 − 0.8)/(0.8 · 0.1) = 2.5 before the
// mirror would reflect more than it receives; a limit far away (flux ≥ 0)
// holds there, and the factor is reported as held up to 2.5 (no failure),
// not traced beyond (where the model would be refused).
TEST(ToleranceCli, TracedInverseSensitivityStopsWhereTheMaterialEnds) {
  test::TempDir dir;
  write_paraboloid(dir.path(), false);
  const json report = run_tolerance(dir.path(), "[material.mirror]\nreflectance = { uniform = 10 }\n",
                                    {"--photons", "50000", "--trials", "0", "--noise-seeds", "1", "--spec", "flux>=0"});
  ASSERT_FALSE(report.is_null());
  const json& e = report["inverse_sensitivity"][0];
  EXPECT_GT(e["scale"].get<double>(), 2.5);  // the linear estimate knows no material
  EXPECT_DOUBLE_EQ(e["traced_scale"].get<double>(), 2.5);
  EXPECT_TRUE(e["traced_fails_at"].is_null());
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

// A conic dish over an isotropic LED as a design file, its radius a variable.
std::string dish_design(double radius, const std::string& tolerances) {
  return "length_unit = \"mm\"\n[materials.mirror]\nreflectance = 0.9\n[[emitters]]\nname = \"LED\"\n"
         "position = [0, 0, 0]\nflux_lm = 1000\n[[reflectors]]\nname = \"dish\"\nmaterial = \"mirror\"\n"
         "profile = \"conic\"\nradius = { value = " + std::to_string(radius) + ", min = " + std::to_string(radius - 0.5) +
         ", max = " + std::to_string(radius + 0.5) + " }\n"
         "conic = -1.5\nvertex = 5\naperture = [2, 30]\n\n" + tolerances;
}

// [tolerances] in a design file, on its variables: the trial with radius
// +1 (outside the optimiser's bounds, which a tolerance ignores) is, figure
// for figure, the design written with radius 11 (common random numbers: the
// same photons). A name the design lacks is an error naming the line and
// the design's variables; a variable for a model that is not a design, and
// a design without [tolerances] and without --tolerances, are errors too.
TEST(ToleranceCli, DesignVariablesCarryTolerancesInTheDesignFile) {
  test::TempDir dir;
  const std::vector<std::string> settings = {"--photons", "20000", "--trials", "1", "--noise-seeds", "0", "--threads",
                                             "2", "--c-step", "10", "--gamma-step", "5"};
  const auto run = [&](const std::string& name, const std::string& text) {
    test::write_file(dir / name, text);
    std::vector<std::string> args = {"tolerance", (dir / name).string(), "--out", (dir / (name + ".out")).string()};
    args.insert(args.end(), settings.begin(), settings.end());
    return gonio(args);
  };
  test::ProcessResult r = run("a.design.toml", dish_design(10, "[tolerances]\n\"reflectors[0].radius\" = { values = [1] }\n"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run("b.design.toml", dish_design(11, "[tolerances]\n\"reflectors[0].radius\" = { values = [0] }\n"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json a = json::parse(test::read_file(dir / "a.design.toml.out" / "report.json"));
  const json b = json::parse(test::read_file(dir / "b.design.toml.out" / "report.json"));
  EXPECT_TRUE(a["settings"].is_object() && a["tolerances_from_design"].get<bool>());
  EXPECT_EQ(a["tolerances"][0]["name"], "reflectors[0].radius");
  EXPECT_EQ(a["tolerances"][0]["line"], 18);
  json trial = a["monte_carlo"]["trials"][0]["figures"], nominal = b["nominal"];
  EXPECT_GT(trial["rms"].get<double>(), 0.0);  // the radius changed the distribution
  trial.erase("rms");
  nominal.erase("rms");
  EXPECT_EQ(trial, nominal);
  EXPECT_NE(a["nominal"]["peak_cd"], b["nominal"]["peak_cd"]);

  r = run("c.design.toml", dish_design(10, "[tolerances]\n\n\"reflectors[0].conic\" = { uniform = 0.1 }\n"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("gonio: tolerance: " + (dir / "c.design.toml").string() + ":19: the design " + (dir / "c.design.toml").string() +
                       " has no variable 'reflectors[0].conic' (it has 'reflectors[0].radius')"),
            std::string::npos)
      << r.err;
  r = run("d.design.toml", dish_design(10, ""));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--tolerances FILE is required: the design has no [tolerances] table"), std::string::npos) << r.err;
  write_paraboloid(dir.path());
  test::write_file(dir / "t.toml", "[variable]\n\"reflectors[0].radius\" = { uniform = 1 }\n");
  r = gonio({"tolerance", (dir / "paraboloid.gltf").string(), "--tolerances", (dir / "t.toml").string(), "--out",
             (dir / "out").string(), "--photons", "1000"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("t.toml:2: 'reflectors[0].radius': a tolerance on a variable needs a design file as the model"),
            std::string::npos)
      << r.err;
}

// Trials in parallel and a resumed run give the same report.json, byte for
// byte: every trace is deterministic in its values and the common seed, and
// report.json holds no wall times (timing.json does). The resumed run gets
// the journal of a finished run cut after its third Monte Carlo trial, with
// half of the next line (as an interrupted write leaves it): it reads the
// complete lines back and traces only the three trials they lack.
TEST(ToleranceCli, ParallelTrialsAndResumeGiveTheSameReportBytes) {
  test::TempDir dir;
  write_paraboloid(dir.path());
  test::write_file(dir / "t.toml", "[emitter.lamp]\nx = { normal = 0.5 }\ntilt_y = { uniform = 1 }\n"
                                   "[material.mirror]\nreflectance = { uniform = 3 }\n");
  const auto run = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {"tolerance", (dir / "paraboloid.gltf").string(), "--tolerances",
                                     (dir / "t.toml").string(), "--out", (dir / out).string(), "--threads", "1",
                                     "--photons", "20000", "--trials", "6", "--noise-seeds", "1", "--spec",
                                     "flux>=880", "--inverse-steps", "2"};
    args.insert(args.end(), extra.begin(), extra.end());
    return gonio(args);
  };
  test::ProcessResult r = run("one", {});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run("two", {"--parallel-trials", "3"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string one = test::read_file(dir / "one" / "report.json");
  EXPECT_EQ(one, test::read_file(dir / "two" / "report.json"));
  EXPECT_EQ(test::read_file(dir / "one" / "worst.ies"), test::read_file(dir / "two" / "worst.ies"));
  const json report = json::parse(one);
  ASSERT_EQ(report["monte_carlo"]["trials"].size(), 6u);
  EXPECT_NE(report["monte_carlo"]["trials"][0]["figures"], report["monte_carlo"]["trials"][1]["figures"]);

  // The journal cut after the third trial: the last 6 lines are the trials
  // (then the best and worst traced again add none: they are there).
  const std::string journal = test::read_file(dir / "one" / "journal.jsonl");
  std::vector<std::size_t> ends;
  for (std::size_t i = 0; i < journal.size(); ++i)
    if (journal[i] == '\n') ends.push_back(i + 1);
  ASSERT_GE(ends.size(), 8u);
  const std::size_t keep = ends[ends.size() - 4];
  fs::create_directories(dir / "resumed");
  test::write_file(dir / "resumed" / "journal.jsonl",
                   journal.substr(0, keep) + journal.substr(keep, (ends[ends.size() - 3] - keep) / 2));
  r = run("resumed", {"--resume"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(one, test::read_file(dir / "resumed" / "report.json"));
  EXPECT_NE(r.out.find("resume: " + std::to_string(ends.size() - 4) + " traces read back from the journal"),
            std::string::npos)
      << r.out;
  std::size_t from_journal = 0, pos = 0;
  while ((pos = r.out.find("from the journal,", pos)) != std::string::npos) ++from_journal, ++pos;
  EXPECT_EQ(from_journal, 3u) << r.out;
  EXPECT_EQ(json::parse(test::read_file(dir / "resumed" / "timing.json"))["read_from_journal"].get<std::size_t>(),
            ends.size() - 4);
  // Another run's journal is not read back.
  r = run("resumed", {"--resume", "--seed", "2"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("journal.jsonl: written by another run"), std::string::npos) << r.err;
}

// A journal line that is JSON but not a trace's (a key that is not a
// string, figures that are not an object, seconds that are not a number, an
// array) is dropped on --resume like a line cut short, and its trace made
// again: no crash (an uncaught type error aborted the process), the same
// report bytes.
TEST(ToleranceCli, ResumeDropsJournalLinesOfTheWrongShape) {
  test::TempDir dir;
  write_paraboloid(dir.path());
  test::write_file(dir / "t.toml", "[emitter.lamp]\nx = { uniform = 0.5 }\n");
  const auto run = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {"tolerance", (dir / "paraboloid.gltf").string(), "--tolerances",
                                     (dir / "t.toml").string(), "--out", (dir / out).string(), "--threads", "1",
                                     "--photons", "20000", "--trials", "2", "--noise-seeds", "1"};
    args.insert(args.end(), extra.begin(), extra.end());
    return gonio(args);
  };
  test::ProcessResult r = run("one", {});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string journal = test::read_file(dir / "one" / "journal.jsonl");
  const std::size_t first = journal.find('\n') + 1, second = journal.find('\n', first) + 1;
  const json nominal = json::parse(journal.substr(first, second - first));
  fs::create_directories(dir / "resumed");
  test::write_file(dir / "resumed" / "journal.jsonl",
                   journal.substr(0, second) + "{\"key\": 5, \"figures\": {}}\n" +
                       "{\"key\": \"x\", \"figures\": 3}\n" + "[1, 2]\n" +
                       json{{"key", "1"}, {"figures", nominal["figures"]}, {"seconds", "slow"}}.dump() + "\n");
  r = run("resumed", {"--resume"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(test::read_file(dir / "one" / "report.json"), test::read_file(dir / "resumed" / "report.json"));
  EXPECT_NE(r.out.find("resume: 1 traces read back from the journal"), std::string::npos) << r.out;
}

// A table or a trace's report that cannot be written (here best.ies, a
// path taken by a folder) after every trace is made loses nothing else: the
// other files and report.json are written, report.json lists the failure
// under output_failures, stderr names the file, and the exit code is 1.
TEST(ToleranceCli, AFileThatCannotBeWrittenAfterTheTracesKeepsTheReport) {
  test::TempDir dir;
  write_paraboloid(dir.path());
  test::write_file(dir / "t.toml", "[emitter.lamp]\nx = { uniform = 0.5 }\n");
  fs::create_directories(dir / "out" / "best.ies");
  const test::ProcessResult r =
      gonio({"tolerance", (dir / "paraboloid.gltf").string(), "--tolerances", (dir / "t.toml").string(), "--out",
             (dir / "out").string(), "--threads", "1", "--photons", "20000", "--trials", "2", "--noise-seeds", "1",
             "--percentile", "50"});
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("best.ies: cannot write"), std::string::npos) << r.err;
  ASSERT_TRUE(fs::exists(dir / "out" / "report.json")) << r.err;
  const json report = json::parse(test::read_file(dir / "out" / "report.json"));
  ASSERT_EQ(report["output_failures"].size(), 1u) << report["output_failures"];
  EXPECT_NE(report["output_failures"][0].get<std::string>().find("best.ies: cannot write"), std::string::npos);
  EXPECT_EQ(report["monte_carlo"]["trials"].size(), 2u);
  for (const char* f : {"best.ldt", "best.json", "worst.ies", "worst.json", "p50_rms.ies", "p50_rms.json",
                        "timing.json", "nominal.ies"})
    EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
  const json& files = report["files"];
  EXPECT_EQ(std::find(files.begin(), files.end(), json("best.ies")), files.end()) << files;
  EXPECT_NE(std::find(files.begin(), files.end(), json("best.ldt")), files.end()) << files;
}

// gonio tolerance never writes over its inputs: a design whose emitter
// profile is nominal.ies, analysed with --out its own folder, would have
// the profile replaced by the nominal's table (and every later trace loads
// the model again, so it would read that table); the run stops before
// anything is written, the error naming the file.
TEST(ToleranceCli, NeverWritesOverItsInputs) {
  test::TempDir dir;
  std::vector<double> g, cd;
  for (int i = 0; i <= 36; ++i) {
    g.push_back(5.0 * i);
    cd.push_back(g.back() <= 90.0 ? 0.0 : -318.31 * std::cos(g.back() * std::numbers::pi / 180.0));
  }
  ASSERT_TRUE(io::write_photometric_file((dir / "nominal.ies").string(), design::rotational_distribution(g, cd), {},
                                         nullptr)
                  .ok());
  test::write_file(dir / "lamp.design.toml",
                   "length_unit = \"mm\"\n[materials.mirror]\nreflectance = 0.9\n[[emitters]]\nname = \"LED\"\n"
                   "position = [0, 0, 0]\nprofile = \"nominal.ies\"\n[[reflectors]]\nname = \"dish\"\n"
                   "material = \"mirror\"\nprofile = \"conic\"\nradius = 10\nconic = -1.5\nvertex = 5\n"
                   "aperture = [2, 30]\n");
  test::write_file(dir / "t.toml", "[emitter.LED]\nx = { uniform = 0.5 }\n");
  const std::string profile = test::read_file(dir / "nominal.ies");
  const test::ProcessResult r =
      gonio({"tolerance", (dir / "lamp.design.toml").string(), "--tolerances", (dir / "t.toml").string(), "--out",
             dir.path().string(), "--threads", "1", "--photons", "5000", "--trials", "1", "--noise-seeds", "0"});
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("nominal.ies: gonio tolerance would write"), std::string::npos) << r.err;
  EXPECT_TRUE(test::read_file(dir / "nominal.ies") == profile) << "the emitter's profile nominal.ies was overwritten";
  EXPECT_FALSE(fs::exists(dir / "report.json"));
  EXPECT_FALSE(fs::exists(dir / "journal.jsonl"));
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


// Two point lamps at one point, "warm" (a 2700 K blackbody) and "cool"
// (6500 K), 500 lm each, above a mirror disc: the mirror catches the same
// share of both, so its reflectance cannot change the luminaire's colour
// (a grey mirror: the CCT change is below the noise floor), while the warm
// lamp's flux ±50 % moves the CCT of the mix as the closed form says: the
// mix's X, Y, Z is the sum of each lamp's flux × (x/y, 1, z/y) of its
// Planckian chromaticity, its CCT by photometry::cct_duv. With a spectral
// reflectance (red) on the mirror, its reflectance +20 % adds red light and
// lowers the CCT, −20 % raises it.
fs::path write_two_lamps(const fs::path& dir, bool red_mirror) {
  sim::Mesh disc = sim::disc(0.05, 32);
  io::GltfWriter w("gonio tolerance colour test");
  json mirror = {{"name", "mirror"},
                 {"pbrMetallicRoughness",
                  {{"baseColorFactor", {0.5, 0.5, 0.5, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.0}}}};
  if (red_mirror)
    mirror["extras"]["gonio"]["spectral_reflectance"] = {{"wavelengths_nm", {360.0, 560.0, 600.0, 830.0}},
                                                         {"values", {0.1, 0.1, 0.8, 0.8}}};
  const int material = w.material(mirror);
  w.node({{"name", "mirror"}, {"mesh", w.mesh(disc, material, "mirror")}, {"translation", {0.0, -0.02, 0.0}}});
  for (const auto& [name, kelvin] : {std::pair{"warm", 2700.0}, std::pair{"cool", 6500.0}}) {
    const int light = w.khr_light({{"name", name},
                                   {"type", "point"},
                                   {"intensity", 500.0 / (4.0 * std::numbers::pi)},
                                   {"extras", {{"gonio", {{"spectrum", {{"blackbody_k", kelvin}}}}}}}});
    w.node({{"name", name}, {"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}});
  }
  std::string bin;
  const std::string text = w.finish("paraboloid.bin", bin);
  test::write_file(dir / "paraboloid.bin", bin);
  test::write_file(dir / "paraboloid.gltf", text);
  return dir / "paraboloid.gltf";
}

// The CCT of warm_lm of a 2700 K and cool_lm of a 6500 K blackbody mixed.
double mixed_cct(double warm_lm, double cool_lm) {
  photometry::Tristimulus sum;
  for (const auto& [lm, kelvin] : {std::pair{warm_lm, 2700.0}, std::pair{cool_lm, 6500.0}}) {
    const photometry::Chromaticity c = photometry::chromaticity(photometry::planckian_uv_prime(kelvin));
    sum.X += lm * c.x / c.y;
    sum.Y += lm;
    sum.Z += lm * (1.0 - c.x - c.y) / c.y;
  }
  return photometry::cct_duv(sum).cct_k;
}

// The red mirror's reflectance: 0.1 up to 560 nm, rising linearly to 0.8
// at 600 nm and above.
double red_reflectance(double nm) { return nm <= 560.0 ? 0.1 : nm >= 600.0 ? 0.8 : 0.1 + 0.7 * (nm - 560.0) / 40.0; }

// The CCT of both lamps (500 lm each) with the red mirror's reflectance
// scaled by `scale`: the mirror disc (radius a = 50 mm, h = 20 mm below the
// lamps) catches f = (1 − h/√(h² + a²))/2 of each lamp's light and sends
// back its spectrum × scale·ρ(λ); the rest leaves directly.
double red_mirror_cct(double scale) {
  const double a = 0.05, h = 0.02, f = 0.5 * (1.0 - h / std::hypot(h, a));
  photometry::Tristimulus sum;
  for (double kelvin : {2700.0, 6500.0}) {
    const photometry::SampledSpectrum lamp = photometry::blackbody_spectrum(kelvin, 360.0, 830.0, 1.0);
    photometry::SampledSpectrum reflected = lamp;
    for (std::size_t i = 0; i < reflected.values.size(); ++i)
      reflected.values[i] *= scale * red_reflectance(reflected.wavelengths_nm[i]);
    const photometry::Tristimulus direct = photometry::tristimulus(lamp), back = photometry::tristimulus(reflected);
    const double lm = 500.0 / direct.Y;  // the lamp's spectrum to 500 lm
    sum.X += lm * ((1.0 - f) * direct.X + f * back.X);
    sum.Y += lm * ((1.0 - f) * direct.Y + f * back.Y);
    sum.Z += lm * ((1.0 - f) * direct.Z + f * back.Z);
  }
  return photometry::cct_duv(sum).cct_k;
}

TEST(ToleranceCli, CctMovesWithTheMixOfTwoSpectraNotWithAGreyMirror) {
  test::TempDir dir;
  write_two_lamps(dir.path(), false);
  const json report = run_tolerance(dir.path(),
                                    "[emitter.warm]\nflux = { uniform = 50 }\n[material.mirror]\nreflectance = { uniform = 20 }\n",
                                    {"--photons", "200000", "--trials", "0", "--noise-seeds", "3", "--c-step", "15",
                                     "--gamma-step", "5"});
  ASSERT_FALSE(report.is_null());
  const double nominal = report["nominal"]["cct"].get<double>();
  const double noise = report["noise"]["floor"]["cct"].get<double>();
  const double expected = mixed_cct(500.0, 500.0);
  const json& grey = row(report, "cct", "mirror.reflectance");
  const json& flux = row(report, "cct", "warm.flux");
  const double want_high = mixed_cct(750.0, 500.0) - expected, want_low = mixed_cct(250.0, 500.0) - expected;
  std::printf("CCT nominal %.1f K (closed form %.1f), noise %.2f K; warm.flux change %.1f %.1f (closed form %.1f %.1f); "
              "grey mirror change %.2f %.2f\n",
              nominal, expected, noise, flux["change_low"].get<double>(), flux["change_high"].get<double>(), want_low,
              want_high, grey["change_low"].get<double>(), grey["change_high"].get<double>());
  EXPECT_NEAR(nominal, expected, std::max(4.0 * noise, 0.01 * expected));
  EXPECT_TRUE(grey["below_noise"].get<bool>());
  EXPECT_LT(std::abs(grey["change_low"].get<double>()), 2.0 * noise);
  EXPECT_LT(std::abs(grey["change_high"].get<double>()), 2.0 * noise);
  EXPECT_FALSE(flux["below_noise"].get<bool>());
  // More warm light: lower CCT; the size within 5 % of the closed form's change and 4 σ.
  EXPECT_LT(flux["change_high"].get<double>(), 0.0);
  EXPECT_GT(flux["change_low"].get<double>(), 0.0);
  EXPECT_NEAR(flux["change_high"].get<double>(), want_high, 0.05 * std::abs(want_high) + 4.0 * noise);
  EXPECT_NEAR(flux["change_low"].get<double>(), want_low, 0.05 * std::abs(want_low) + 4.0 * noise);
  // Δu′v′ over angle: one colour in every direction, nothing above noise.
  EXPECT_TRUE(row(report, "duv_max", "mirror.reflectance")["below_noise"].get<bool>());

  // A red mirror: its reflectance moves the CCT, down for more reflectance.
  test::TempDir red;
  write_two_lamps(red.path(), true);
  const json coloured = run_tolerance(red.path(), "[material.mirror]\nreflectance = { uniform = 20 }\n",
                                      {"--photons", "200000", "--trials", "0", "--noise-seeds", "3", "--c-step", "15",
                                       "--gamma-step", "5"});
  ASSERT_FALSE(coloured.is_null());
  const json& r = row(coloured, "cct", "mirror.reflectance");
  std::printf("red mirror: CCT nominal %.1f K, change %.2f %.2f, noise %.2f\n", coloured["nominal"]["cct"].get<double>(),
              r["change_low"].get<double>(), r["change_high"].get<double>(),
              coloured["noise"]["floor"]["cct"].get<double>());
  const double red_nominal = red_mirror_cct(1.0);
  const double red_high = red_mirror_cct(1.2) - red_nominal, red_low = red_mirror_cct(0.8) - red_nominal;
  std::printf("red mirror closed form: nominal %.1f K, change %.2f %.2f\n", red_nominal, red_low, red_high);
  EXPECT_FALSE(r["below_noise"].get<bool>());
  EXPECT_LT(r["change_high"].get<double>(), 0.0);
  EXPECT_GT(r["change_low"].get<double>(), 0.0);
  // The disc is a 32-gon (0.6 % less area than the circle): 1 % on the CCT, 5 % on its changes.
  EXPECT_NEAR(coloured["nominal"]["cct"].get<double>(), red_nominal, 0.01 * red_nominal);
  const double red_noise = coloured["noise"]["floor"]["cct"].get<double>();
  EXPECT_NEAR(r["change_high"].get<double>(), red_high, 0.05 * std::abs(red_high) + 4.0 * red_noise);
  EXPECT_NEAR(r["change_low"].get<double>(), red_low, 0.05 * std::abs(red_low) + 4.0 * red_noise);
}


// --percentile: with N = 10 trials of the displaced lamp, the RMS
// difference's 50th percentile is the trial at rank ⌈0.5·10⌉ = 5 of the
// trials sorted by it, its 100th the worst trial (the same bytes as
// worst.ies), its 0th the best; peak_gamma:90 the trial at rank 9 by peak γ
// (ties by trial number). Each written table, read back, has its trial's
// figures: its RMS difference from nominal.ies and its peak γ.
TEST(ToleranceCli, PercentileTrialsAreTheNearestRankOfTheirFigure) {
  test::TempDir dir;
  write_paraboloid(dir.path(), false);
  const json report = run_tolerance(dir.path(), "[emitter.lamp]\nx = { normal = 1.0 }\n",
                                    {"--photons", "50000", "--trials", "10", "--noise-seeds", "0", "--percentile",
                                     "50,100,0,peak_gamma:90"});
  ASSERT_FALSE(report.is_null());
  const json& mc = report["monte_carlo"];
  ASSERT_EQ(mc["trials"].size(), 10u);
  ASSERT_EQ(mc["percentile_trials"].size(), 4u);
  // The nearest rank from the trials' figures in report.json, done here by hand.
  const auto at_rank = [&](const std::string& figure, std::size_t rank) {
    std::vector<std::pair<double, std::size_t>> sorted;
    for (const json& t : mc["trials"]) sorted.emplace_back(t["figures"][figure].get<double>(), t["trial"].get<std::size_t>());
    std::stable_sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    return sorted[rank - 1].second;
  };
  const std::vector<std::tuple<std::string, double, std::size_t, std::string>> want = {
      {"rms", 50.0, 5, "p50_rms"}, {"rms", 100.0, 10, "p100_rms"}, {"rms", 0.0, 1, "p0_rms"},
      {"peak_gamma", 90.0, 9, "p90_peak_gamma"}};
  Result<io::PhotometricFile> nominal = io::read_photometric_file((dir.path() / "out" / "nominal.ies").string());
  ASSERT_TRUE(nominal.ok());
  for (std::size_t k = 0; k < want.size(); ++k) {
    const auto& [figure, percent, rank, stem] = want[k];
    const json& p = mc["percentile_trials"][k];
    EXPECT_EQ(p["figure"], figure);
    EXPECT_EQ(p["percentile"].get<double>(), percent);
    EXPECT_EQ(p["rank"].get<std::size_t>(), rank);
    EXPECT_EQ(p["of"].get<std::size_t>(), 10u);
    const std::size_t trial = at_rank(figure, rank);
    EXPECT_EQ(p["trial"].get<std::size_t>(), trial) << stem;
    const json& figures = mc["trials"][trial - 1]["figures"];
    EXPECT_EQ(p["value"], figures[figure]);
    EXPECT_EQ(p["files"], json::array({stem + ".ies", stem + ".ldt", stem + ".json"}));
    // The written trial's own report: its entry of report.json, the percentile and its tables.
    json own = json::parse(test::read_file(dir.path() / "out" / (stem + ".json")));
    EXPECT_EQ(own["percentile"], (json{{"figure", figure}, {"percent", percent}}));
    EXPECT_EQ(own["tables"], json::array({stem + ".ies", stem + ".ldt"}));
    own.erase("percentile");
    own.erase("tables");
    EXPECT_EQ(own, mc["trials"][trial - 1]) << stem;
    Result<io::PhotometricFile> written = io::read_photometric_file((dir.path() / "out" / (stem + ".ies")).string());
    ASSERT_TRUE(written.ok()) << stem;
    ASSERT_TRUE(fs::exists(dir.path() / "out" / (stem + ".ldt")));
    Result<design::FigureValues> f = design::figures_of(written->distribution, nominal->distribution, 5.0, 2.5);
    ASSERT_TRUE(f.ok());
    EXPECT_NEAR((*f)[design::kRms], figures["rms"].get<double>(), 1e-3 * figures["rms"].get<double>() + 1e-6) << stem;
    EXPECT_EQ((*f)[design::kPeakGamma], figures["peak_gamma"].get<double>()) << stem;
  }
  EXPECT_EQ(mc["percentile_trials"][1]["trial"], mc["worst_trial"]);
  EXPECT_EQ(mc["percentile_trials"][2]["trial"], mc["best_trial"]);
  // best, worst and the nominal: each table with its report (the trial's entry, the nominal's figures).
  for (const std::string stem : {"best", "worst"}) {
    json own = json::parse(test::read_file(dir.path() / "out" / (stem + ".json")));
    EXPECT_EQ(own["tables"], json::array({stem + ".ies", stem + ".ldt"}));
    own.erase("tables");
    EXPECT_EQ(own, mc["trials"][mc[stem + "_trial"].get<std::size_t>() - 1]) << stem;
  }
  const json nominal_own = json::parse(test::read_file(dir.path() / "out" / "nominal.json"));
  EXPECT_EQ(nominal_own["trial"], "nominal");
  EXPECT_EQ(nominal_own["figures"], report["nominal"]);
  EXPECT_EQ(test::read_file(dir.path() / "out" / "p100_rms.ies"), test::read_file(dir.path() / "out" / "worst.ies"));
  EXPECT_EQ(test::read_file(dir.path() / "out" / "p0_rms.ldt"), test::read_file(dir.path() / "out" / "best.ldt"));
  const std::vector<std::string> files = report["files"].get<std::vector<std::string>>();
  EXPECT_NE(std::find(files.begin(), files.end(), "p90_peak_gamma.ldt"), files.end());

  // A bad item is a usage error naming it.
  test::write_file(dir.path() / "t.toml", "[emitter.lamp]\nx = { uniform = 1 }\n");
  const test::ProcessResult r = gonio({"tolerance", (dir.path() / "paraboloid.gltf").string(), "--tolerances",
                                       (dir.path() / "t.toml").string(), "--out", (dir.path() / "bad").string(),
                                       "--percentile", "5,beam:95"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--percentile 'beam:95': unknown figure"), std::string::npos) << r.err;
}


// gonio report --tolerance DIR/report.json: the datasheet's yield table
// holds, per --spec limit, the trials within it counted from report.json's
// verdicts, the yield report.json gives (%.1f %), the nominal and the
// trials' range of the figure (%.5g), and the same for all limits.
TEST(ToleranceCli, DatasheetYieldTableEqualsTheReport) {
  test::TempDir dir;
  write_paraboloid(dir.path(), false);
  const json report = run_tolerance(dir.path(), "[emitter.lamp]\nx = { normal = 1.0 }\n",
                                    {"--photons", "50000", "--trials", "10", "--noise-seeds", "0", "--spec",
                                     "peak_gamma<=2,flux=0..,rms=..8", "--inverse-steps", "0"});
  ASSERT_FALSE(report.is_null());
  const fs::path sheet = dir.path() / "sheet.html";
  test::ProcessResult r = gonio({"report", (dir.path() / "out" / "nominal.ies").string(), "--tolerance",
                                 (dir.path() / "out" / "report.json").string(), "--out", sheet.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = test::read_file(sheet);
  ASSERT_NE(html.find("<h2>Tolerance yield</h2>"), std::string::npos);
  const json& mc = report["monte_carlo"];
  const auto g5 = [](double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.5g", v);
    return std::string(b);
  };
  const auto f1 = [](double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.1f", v);
    return std::string(b);
  };
  std::size_t limits = 0;
  bool some_pass = false, some_fail = false;
  for (const auto& [text, yield] : mc["yield"].items()) {
    if (text == "all") continue;
    ++limits;
    const std::string figure = text.substr(0, text.find_first_of("=<>"));
    std::size_t within = 0;
    double lo = 1e300, hi = -1e300;
    for (const json& t : mc["trials"]) {
      within += t["limits"][text].get<bool>() ? 1 : 0;
      lo = std::min(lo, t["figures"][figure].get<double>());
      hi = std::max(hi, t["figures"][figure].get<double>());
    }
    some_pass = some_pass || within > 0;
    some_fail = some_fail || within < 10;
    EXPECT_DOUBLE_EQ(yield.get<double>(), static_cast<double>(within) / 10.0) << text;
    const std::string row = "<tr><th class=l>" + text + "</th><td>" + g5(report["nominal"][figure].get<double>()) +
                            "</td><td>" + g5(lo) + "</td><td>" + g5(hi) + "</td><td>" + std::to_string(within) +
                            " of 10</td><td>" + f1(100.0 * yield.get<double>()) + " %</td></tr>";
    EXPECT_NE(html.find(row), std::string::npos) << row;
  }
  EXPECT_EQ(limits, 3u);
  EXPECT_TRUE(some_pass && some_fail) << "the limits should split the trials";
  std::size_t all = 0;
  for (const json& t : mc["trials"]) all += t["in_spec"].get<bool>() ? 1 : 0;
  const std::string all_row = "<tr><th class=l>all limits</th><td></td><td></td><td></td><td>" + std::to_string(all) +
                              " of 10</td><td>" + f1(100.0 * mc["yield"]["all"].get<double>()) + " %</td></tr>";
  EXPECT_NE(html.find(all_row), std::string::npos) << all_row;

  // Not a tolerance report: an error naming the file, nothing written.
  const fs::path none = dir.path() / "none.html";
  r = gonio({"report", (dir.path() / "out" / "nominal.ies").string(), "--tolerance",
             (dir.path() / "out" / "timing.json").string(), "--out", none.string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("timing.json: not a gonio tolerance report.json"), std::string::npos) << r.err;
  r = gonio({"report", (dir.path() / "out" / "nominal.ies").string(), "--tolerance",
             (dir.path() / "out" / "nominal.ies").string(), "--out", none.string()});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("nominal.ies"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(none));
}

}  // namespace
}  // namespace gonio

namespace gonio {
namespace {

// Two spots (outer cone 5°) shining up at two flat 20 mm mirrors 50 mm
// above them, facing down, so that each beam comes back to the nadir after
// one bounce. `instanced`: both mirror nodes, "mirrorA" and "mirrorB", place
// one glTF mesh "mirror" (loaded as one instanced mesh with two instances);
// otherwise each node has its own copy of it (world meshes
// "mirrorA/mirror/0", "mirrorB/mirror/0"), the same model un-instanced.
fs::path write_mirror_pair(const fs::path& dir, bool instanced) {
  sim::Mesh square;
  constexpr float a = 0.01f;
  square.positions = {{-a, 0.0f, -a}, {a, 0.0f, -a}, {a, 0.0f, a}, {-a, 0.0f, a}};
  square.normals.assign(4, {0.0f, -1.0f, 0.0f});
  square.indices = {0, 1, 2, 0, 2, 3};  // wound to face −Y
  io::GltfWriter w("gonio tolerance test");
  const int material = w.material({{"name", "mirror"}, {"pbrMetallicRoughness",
                                 {{"baseColorFactor", {kMirror, kMirror, kMirror, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.0}}}});
  const int shared = w.mesh(square, material, "mirror");
  for (const auto& [name, x] : {std::pair{"A", 0.03}, std::pair{"B", -0.03}}) {
    w.node({{"name", std::string("mirror") + name},
            {"mesh", instanced ? shared : w.mesh(square, material, "mirror")},
            {"translation", {x, 0.05, 0.0}}});
    const int light = w.khr_light({{"name", std::string("spot") + name}, {"type", "spot"}, {"intensity", 100.0},
                                   {"spot", {{"innerConeAngle", 0.0}, {"outerConeAngle", 5.0 * std::numbers::pi / 180.0}}}});
    // The spot shines along the node's −Z: turned +90° about X it shines up (+Y).
    w.node({{"name", std::string("spot") + name}, {"translation", {x, 0.0, 0.0}},
            {"rotation", {std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)}},
            {"extensions", {{"KHR_lights_punctual", {{"light", light}}}}}});
  }
  std::string bin;
  const std::string name = instanced ? "instanced" : "flat";
  const std::string text = w.finish(name + ".bin", bin);
  test::write_file(dir / (name + ".bin"), bin);
  test::write_file(dir / (name + ".gltf"), text);
  return dir / (name + ".gltf");
}

json tolerance_of(const fs::path& model, const fs::path& dir, const std::string& out, const std::string& tolerances,
                  std::vector<std::string> extra = {}) {
  test::write_file(dir / (out + ".toml"), tolerances);
  std::vector<std::string> args = {"tolerance", model.string(), "--tolerances", (dir / (out + ".toml")).string(),
                                   "--out", (dir / out).string(), "--threads", "2", "--photons", "100000",
                                   "--noise-seeds", "1"};
  args.insert(args.end(), extra.begin(), extra.end());
  const test::ProcessResult r = gonio(args);
  EXPECT_EQ(r.exit_code, 0) << r.err << r.out;
  if (r.exit_code != 0) return {};
  return json::parse(test::read_file(dir / out / "report.json"));
}

double rms_between(const fs::path& a, const fs::path& b) {
  Result<io::PhotometricFile> x = io::read_photometric_file(a.string()), y = io::read_photometric_file(b.string());
  EXPECT_TRUE(x.ok() && y.ok());
  if (!x.ok() || !y.ok()) return 1.0;
  Result<photometry::Comparison> c = photometry::compare(x->distribution, y->distribution);
  EXPECT_TRUE(c.ok());
  return c.ok() ? c->rms_relative : 1.0;
}

// A mirror tilted by θ turns its reflected beam by 2θ. Both copies of the
// instanced mirror named by their mesh ("mirror": each turned about its own
// centre, one draw) at ±3° about the C0 axis: the beam axis moves by ±6°
// towards C90 (a normal −Y turned by θ about +X reflects the upward ray to
// (0, −cos 2θ, −sin 2θ): C90 is world −Z), not towards C0, to a tenth of
// the 2.5° γ step. One copy alone (its node, "mirrorA") turns half the
// light by 2θ: the axis, a mean over the light at ≥ half the peak, moves
// by about θ.
TEST(ToleranceCli, TiltedInstancedMirrorTurnsItsBeamByTwiceTheTilt) {
  test::TempDir dir;
  const fs::path model = write_mirror_pair(dir.path(), true);
  const json report = tolerance_of(model, dir.path(), "both", "[part.mirror]\ntilt_x = { uniform = 3 }\n",
                                   {"--trials", "0"});
  ASSERT_FALSE(report.is_null());
  EXPECT_NEAR(report["nominal"]["axis_c90"].get<double>(), 0.0, 0.25);
  const json& turned = row(report, "axis_c90", "mirror.tilt_x");
  const json& across = row(report, "axis_c0", "mirror.tilt_x");
  std::printf("both copies ±3°: axis towards C90 %.4f / %.4f, towards C0 %.4f / %.4f\n",
              turned["change_low"].get<double>(), turned["change_high"].get<double>(),
              across["change_low"].get<double>(), across["change_high"].get<double>());
  EXPECT_NEAR(turned["change_high"].get<double>(), 6.0, 0.25);
  EXPECT_NEAR(turned["change_low"].get<double>(), -6.0, 0.25);
  EXPECT_NEAR(across["change_high"].get<double>(), 0.0, 0.25);
  const json one = tolerance_of(model, dir.path(), "one", "[part.mirrorA]\ntilt_x = { uniform = 3 }\n",
                                {"--trials", "0"});
  ASSERT_FALSE(one.is_null());
  const double half = row(one, "axis_c90", "mirrorA.tilt_x")["change_high"].get<double>();
  std::printf("one copy +3°: axis towards C90 %.4f\n", half);
  EXPECT_GT(half, 1.5);
  EXPECT_LT(half, 4.5);
}

// The round trip: the instanced model with its copies moved by a tolerance
// gives the figures and tables of the same model written with the copies
// un-instanced and the same moves — the mesh's name (both copies, one
// value) against each copy's node with that value, and one copy's node on
// both. Each with one Monte Carlo trial at the value (a law of one value).
// The two models place their vertices through different float roundings
// (a world mesh transformed and stored as float, an instance's transform
// applied by the tracer), so the photons are not bit for bit the same: the
// tables must agree to 0.1 % of the peak (RMS) and the beam axis to 0.01°.
TEST(ToleranceCli, InstancedPartsGiveTheFiguresOfTheirUninstancedCopies) {
  test::TempDir dir;
  const fs::path instanced = write_mirror_pair(dir.path(), true), flat = write_mirror_pair(dir.path(), false);
  const std::string moves = "tilt_x = { values = [2.5] }\ntilt_y = { values = [-1.5] }\nz = { values = [1] }\n";
  struct Case {
    std::string instanced, flat, out;
  };
  for (const Case& c : {Case{"[part.mirror]\n" + moves, "[part.mirrorA]\n" + moves + "[part.mirrorB]\n" + moves, "mesh"},
                        Case{"[part.mirrorB]\n" + moves, "[part.mirrorB]\n" + moves, "node"}}) {
    const json a = tolerance_of(instanced, dir.path(), c.out + "-instanced", c.instanced, {"--trials", "1"});
    const json b = tolerance_of(flat, dir.path(), c.out + "-flat", c.flat, {"--trials", "1"});
    ASSERT_FALSE(a.is_null() || b.is_null());
    const json& fa = a["monte_carlo"]["trials"][0]["figures"];
    const json& fb = b["monte_carlo"]["trials"][0]["figures"];
    for (const char* f : {"axis_c0", "axis_c90"}) EXPECT_NEAR(fa[f].get<double>(), fb[f].get<double>(), 0.01) << c.out << " " << f;
    EXPECT_NEAR(fa["flux"].get<double>(), fb["flux"].get<double>(), 1e-3 * fb["flux"].get<double>()) << c.out;
    const double moved = rms_between(dir.path() / (c.out + "-instanced") / "best.ies", dir.path() / (c.out + "-flat") / "best.ies");
    const double nominal = rms_between(dir.path() / (c.out + "-instanced") / "nominal.ies", dir.path() / (c.out + "-flat") / "nominal.ies");
    const double off = rms_between(dir.path() / (c.out + "-instanced") / "best.ies", dir.path() / (c.out + "-flat") / "nominal.ies");
    std::printf("%s: RMS difference [%% of peak] instanced/flat trial %.5f, nominal %.5f; trial from the nominal %.3f; "
                "axis_c90 %.5f / %.5f\n", c.out.c_str(), 100.0 * moved, 100.0 * nominal, 100.0 * off,
                fa["axis_c90"].get<double>(), fb["axis_c90"].get<double>());
    EXPECT_LT(moved, 1e-3) << c.out;
    EXPECT_LT(nominal, 1e-3) << c.out;
    EXPECT_GT(off, 0.01) << c.out;  // the moves are seen
  }
  // independent = true: a tolerance per copy, as the flat model's per node;
  // the same Latin hypercube, so the same values trial by trial.
  const std::string law = "tilt_x = { uniform = 3 }\n";
  const json a = tolerance_of(instanced, dir.path(), "independent", "[part.mirror]\nindependent = true\n" + law,
                              {"--trials", "4"});
  const json b = tolerance_of(flat, dir.path(), "per-node", "[part.mirrorA]\n" + law + "[part.mirrorB]\n" + law,
                              {"--trials", "4"});
  ASSERT_FALSE(a.is_null() || b.is_null());
  ASSERT_EQ(a["tolerances"].size(), 2u);
  EXPECT_EQ(a["tolerances"][0]["name"], "mirrorA/mirror/0.tilt_x");
  EXPECT_EQ(a["tolerances"][1]["name"], "mirrorB/mirror/0.tilt_x");
  for (std::size_t n = 0; n < 4; ++n) {
    const json& ta = a["monte_carlo"]["trials"][n];
    const json& tb = b["monte_carlo"]["trials"][n];
    EXPECT_EQ(ta["values"]["mirrorA/mirror/0.tilt_x"], tb["values"]["mirrorA.tilt_x"]);
    EXPECT_EQ(ta["values"]["mirrorB/mirror/0.tilt_x"], tb["values"]["mirrorB.tilt_x"]);
    EXPECT_NE(ta["values"]["mirrorA/mirror/0.tilt_x"], ta["values"]["mirrorB/mirror/0.tilt_x"]);
    for (const char* f : {"axis_c0", "axis_c90"})
      EXPECT_NEAR(ta["figures"][f].get<double>(), tb["figures"][f].get<double>(), 0.01) << n << " " << f;
  }
}

// The spot's test with a ray file in place of the point light: how a real
// LED comes. A ray file (a 30° cone about the file's −Y from a 1 mm disc,
// a Fibonacci lattice and its mirror images in x and z: symmetric) in a
// glTF node at the paraboloid's focus, tilted by 10° about C0 (tilt_x):
// its rays turn about the ray file's origin, and the beam's axis moves by
// 10° towards C90 and not towards C0, to a tenth of the 2.5° γ step.
TEST(ToleranceCli, TiltOfASymmetricRayFileTurnsItsBeamAxisByTheTilt) {
  test::TempDir dir;
  std::vector<float> rays;
  const int n = 5000;
  const double golden = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int i = 0; i < n; ++i) {
    const double u1 = (i + 0.5) / n, u2 = std::fmod(i * golden, 1.0);
    const double r = 0.5 * std::sqrt(u1), phi = 2.0 * std::numbers::pi * u2;
    const double pr = std::sqrt(u2), pphi = 2.0 * std::numbers::pi * u1;
    for (double sx : {-1.0, 1.0})
      for (double sz : {-1.0, 1.0})
        for (double v : {sx * pr * std::cos(pphi), 0.0, sz * pr * std::sin(pphi), sx * r * std::cos(phi),
                         -std::sqrt(1.0 - r * r), sz * r * std::sin(phi), 1.0})
          rays.push_back(static_cast<float>(v));
  }
  ASSERT_TRUE(io::write_tm25_file((dir.path() / "cone.tm25ray").string(), io::make_luminous_ray_set(std::move(rays))).ok());
  io::GltfWriter w("gonio tolerance test");
  const int material = w.material({{"name", "mirror"}, {"pbrMetallicRoughness",
                                 {{"baseColorFactor", {kMirror, kMirror, kMirror, 1.0}}, {"metallicFactor", 1.0}, {"roughnessFactor", 0.0}}}});
  w.node({{"name", "reflector"}, {"mesh", w.mesh(sim::paraboloid(kF, kAperture, 0.0, 8, 32), material, "reflector")}});
  w.node({{"name", "led"}, {"extras", {{"gonio", {{"ray_file", "cone.tm25ray"}, {"flux_lm", kFlux}}}}}});
  std::string bin;
  const std::string text = w.finish("paraboloid.bin", bin);
  test::write_file(dir.path() / "paraboloid.bin", bin);
  test::write_file(dir.path() / "paraboloid.gltf", text);
  const json report = run_tolerance(dir.path(), "[emitter.\"node 'led' (#1) (cone.tm25ray)\"]\ntilt_x = { values = [10] }\n",
                                    {"--photons", "300000", "--trials", "1", "--noise-seeds", "2"});
  ASSERT_FALSE(report.is_null());
  EXPECT_NEAR(report["nominal"]["axis_c0"].get<double>(), 0.0, 0.25);
  EXPECT_NEAR(report["nominal"]["axis_c90"].get<double>(), 0.0, 0.25);
  const json& turned = row(report, "axis_c90", "node 'led' (#1) (cone.tm25ray).tilt_x");
  const json& across = row(report, "axis_c0", "node 'led' (#1) (cone.tm25ray).tilt_x");
  std::printf("ray file: axis change towards C90 %.4f, towards C0 %.4f\n", turned["change_high"].get<double>(),
              across["change_high"].get<double>());
  EXPECT_NEAR(turned["change_high"].get<double>(), 10.0, 0.25);
  EXPECT_NEAR(across["change_high"].get<double>(), 0.0, 0.25);
}

}  // namespace
}  // namespace gonio
