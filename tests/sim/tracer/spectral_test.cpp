// Spectral transport (sim/tracer/spectral.h) against closed forms: a bare blackbody
// keeps its chromaticity, light off one diffuse surface has the product
// spectrum's, a dielectric refracts each wavelength as Snell's law with its
// index says; and the determinism and grey-path guarantees.
#include "sim/tracer/spectral.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "sim/shapes.h"
#include "sim/simulation.h"
#include "sim/tracer/tracer.h"
#include "tests/sim/scenes.h"
#include "tests/support/test_support.h"

namespace gonio::sim {
namespace {

using photometry::SampledSpectrum;

SimulationSettings settings(int threads, std::uint64_t per_iteration, int iterations) {
  return test_scenes::small_run(threads, per_iteration, iterations, 5);
}

EmitterSpectrum single(SampledSpectrum s) { return EmitterSpectrum{{{0.0, std::move(s)}}}; }

// A point emitter, isotropic, with a far-away black speck so the scene has geometry.
SceneDesc bare_point(EmitterSpectrum spectrum) {
  SceneDesc s;
  Material black;
  black.name = "black";
  s.materials = {black};
  Mesh speck = disc(1e-3, 8);
  transform(speck, translation({100.0, 100.0, 100.0}));
  s.meshes = {speck};
  Emitter e;
  e.name = "lamp";
  e.flux_lm = 1000.0;
  e.spectrum = std::move(spectrum);
  s.emitters = {e};
  return s;
}

// The 3000 K bare point inside a diffuser shell (radius 0.5 m; 60 % diffuse
// transmission, 30 % diffuse reflection), grey, or with a transmittance
// rising linearly from tau_400 at 400 nm to tau_700 at 700 nm (its material
// is s.materials[1]).
SceneDesc lamp_in_shell(std::optional<std::pair<double, double>> tau = std::nullopt) {
  SceneDesc s = bare_point(single(photometry::blackbody_spectrum(3000.0)));
  Material opal;
  opal.name = tau ? "opal" : "grey opal";
  opal.diffuse_transmit = 0.6;
  opal.diffuse_reflect = 0.3;
  if (tau) opal.spectral_transmittance = {{400.0, 700.0}, {tau->first, tau->second}};
  s.materials.push_back(opal);
  Mesh shell = sphere(0.5, 16, 8);
  shell.material = 1;
  s.meshes.push_back(shell);
  return s;
}

// X, Y and Z far fields byte for byte.
void expect_same_colour_bytes(const Simulation& one, const Simulation& two) {
  const ColourFarField a = one.colour_far_field(), b = two.colour_far_field();
  ASSERT_EQ(a.x_lm.size(), b.x_lm.size());
  EXPECT_EQ(std::memcmp(a.x_lm.data(), b.x_lm.data(), a.x_lm.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(a.z_lm.data(), b.z_lm.data(), a.z_lm.size() * sizeof(double)), 0);
  const FarField fa = one.far_field(), fb = two.far_field();
  EXPECT_EQ(std::memcmp(fa.flux_lm().data(), fb.flux_lm().data(), fa.texel_count() * sizeof(double)), 0);
}

photometry::Tristimulus totals(const Simulation& sim, bool upper_only = false) {
  const FarField f = sim.far_field();
  const ColourFarField c = sim.colour_far_field();
  photometry::Tristimulus t;
  for (std::size_t i = 0; i < f.texel_count(); ++i) {
    if (upper_only && f.grid().texel_direction(i).y <= 0.0) continue;
    t.X += c.x_lm[i];
    t.Y += f.flux_lm(i);
    t.Z += c.z_lm[i];
  }
  return t;
}

// The X/Y and Z/Y a spectrum's photons carry on average, and their
// per-photon standard deviations (for tolerances from photon statistics).
struct Ratios {
  double x, z, sx, sz;
};
Ratios expected_ratios(const WavelengthSampler& w, std::uint32_t emitter) {
  Ratios r{};
  double x2 = 0.0, z2 = 0.0;
  for (int k = 0; k < kWavelengthCount; ++k) {
    const double p = w.pmf(emitter, 1.0, k);
    const double xk = static_cast<double>(w.x_units()[static_cast<std::size_t>(k)]) / kColourUnits;
    const double zk = static_cast<double>(w.z_units()[static_cast<std::size_t>(k)]) / kColourUnits;
    r.x += p * xk;
    r.z += p * zk;
    x2 += p * xk * xk;
    z2 += p * zk * zk;
  }
  r.sx = std::sqrt(x2 - r.x * r.x);
  r.sz = std::sqrt(z2 - r.z * r.z);
  return r;
}

// The sampler's expectation is CIE 15's summation of the spectrum, to the
// rounding of the per-wavelength ratios (< 4e-6 relative).
TEST(Spectral, SamplerExpectationIsTheTristimulusSum) {
  for (double t_k : {2000.0, 2856.0, 6500.0}) {
    const SampledSpectrum bb = photometry::blackbody_spectrum(t_k);
    auto w = WavelengthSampler::create(bare_point(single(bb)));
    ASSERT_TRUE(w.ok()) << w.error().message;
    const photometry::Tristimulus t = photometry::tristimulus(bb);
    const Ratios r = expected_ratios(*w, 0);
    EXPECT_NEAR(r.x / (t.X / t.Y), 1.0, 4e-6) << t_k;
    EXPECT_NEAR(r.z / (t.Z / t.Y), 1.0, 4e-6) << t_k;
    double sum = 0.0;
    for (int k = 0; k < kWavelengthCount; ++k) sum += w->pmf(0, 0.3, k);
    EXPECT_NEAR(sum, 1.0, 1e-12);
  }
}

// A bare blackbody: the whole far field's X, Y, Z give its chromaticity
// exactly (no material draws a wavelength, so every photon carries the
// spectrum's expected X/Y and Z/Y: only the 2⁻¹⁷ rounding remains); the Y
// far field is the grey run's, byte for byte (the spectrum shapes the colour
// only).
TEST(Spectral, BareBlackbodyKeepsItsChromaticity) {
  const double t_k = 2856.0;
  const SceneDesc scene = bare_point(single(photometry::blackbody_spectrum(t_k)));
  const std::uint64_t n = 1 << 20;
  auto sim = simulate(scene, settings(2, n / 2, 2));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const photometry::Tristimulus t = totals(*sim);
  auto w = WavelengthSampler::create(scene);
  const Ratios r = expected_ratios(*w, 0);
  EXPECT_NEAR(t.X / t.Y / r.x, 1.0, 1e-5);
  EXPECT_NEAR(t.Z / t.Y / r.z, 1.0, 1e-5);
  const photometry::CctDuv cd = photometry::cct_duv(t);
  EXPECT_NEAR(cd.cct_k, t_k, 0.5);
  EXPECT_NEAR(cd.duv, 0.0, 1e-5);
  std::printf("bare %.0f K blackbody, %llu photons: CCT %.1f K, Duv %.5f, Δu'v' from exact %.6f\n", t_k,
              static_cast<unsigned long long>(n), cd.cct_k, cd.duv,
              photometry::delta_uv_prime(photometry::uv_prime(t),
                                         photometry::uv_prime(photometry::tristimulus(
                                             photometry::blackbody_spectrum(t_k)))));

  SceneDesc grey = scene;
  grey.emitters[0].spectrum = {};
  auto plain = simulate(grey, settings(2, n / 2, 2));
  ASSERT_TRUE(plain.ok());
  const FarField a = sim->far_field(), b = plain->far_field();
  EXPECT_EQ(std::memcmp(a.flux_lm().data(), b.flux_lm().data(), a.texel_count() * sizeof(double)), 0);
  EXPECT_TRUE(plain->colour_far_field().empty());
  EXPECT_FALSE(plain->tracer().spectral());
}

// Light that meets one diffuse surface of spectral reflectance ρ(λ) leaves
// with the chromaticity of S(λ)·ρ(λ): a small emitter facing down onto a
// wide floor; everything that goes up was reflected once.
TEST(Spectral, OneDiffuseBounceGivesTheProductSpectrum) {
  const SampledSpectrum source = photometry::blackbody_spectrum(4000.0);
  const SampledSpectrum rho{{360.0, 480.0, 560.0, 650.0, 830.0}, {0.1, 0.15, 0.7, 0.8, 0.8}};
  SceneDesc s;
  Material floor;
  floor.name = "floor";
  floor.diffuse_reflect = 0.5;  // the spectrum overrides the total
  floor.spectral_reflectance = rho;
  Material black;
  black.name = "black";
  s.materials = {floor, black};
  Mesh f = disc(50.0, 64);
  f.material = 0;
  Mesh lamp = disc(0.02, 16);
  flip(lamp);  // faces −Y
  transform(lamp, translation({0.0, 0.1, 0.0}));
  lamp.material = 1;
  s.meshes = {f, lamp};
  Emitter e;
  e.kind = Emitter::Kind::Area;
  e.name = "chip";
  e.mesh = 1;
  e.flux_lm = 100.0;
  e.spectrum = single(source);
  s.emitters = {e};
  auto sim = simulate(s, settings(2, 1 << 19, 2));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const photometry::Tristimulus up = totals(*sim, true);
  const photometry::UvPrime expected = photometry::uv_prime(photometry::tristimulus(product(source, rho)));
  const double d = photometry::delta_uv_prime(photometry::uv_prime(up), expected);
  std::printf("one diffuse bounce: Δu'v' from the product spectrum %.6f\n", d);
  // Hero wavelengths (sim/tracer/spectral.h): 0.000028 at 10⁶ photons, where one
  // wavelength per photon gave 0.000225.
  EXPECT_LT(d, 1e-4);
  // The source's own chromaticity is far from it: the test can tell.
  EXPECT_GT(photometry::delta_uv_prime(photometry::uv_prime(photometry::tristimulus(source)), expected), 0.02);
  // Luminous reflectance: the escaped Y over the emitted flux is ρ_v =
  // Σ S ρ ȳ / Σ S ȳ (minus the photons that fall back on the black lamp).
  const double rho_v = photometry::tristimulus(product(source, rho)).Y / photometry::tristimulus(source).Y;
  EXPECT_NEAR(up.Y / 1e2, rho_v, 0.01);
}

// The largest Δu′v′ of a lit texel from `source`, and how many are lit.
std::pair<double, int> worst_texel_delta_uv(const Simulation& sim, const photometry::UvPrime& source) {
  const FarField f = sim.far_field();
  const ColourFarField c = sim.colour_far_field();
  double worst = 0.0;
  int lit = 0;
  for (std::size_t i = 0; i < f.texel_count(); ++i) {
    if (f.photons(i) == 0) continue;
    ++lit;
    const photometry::UvPrime uv = photometry::uv_prime(photometry::Tristimulus{c.x_lm[i], f.flux_lm(i), c.z_lm[i]});
    worst = std::max(worst, photometry::delta_uv_prime(uv, source));
  }
  return {worst, lit};
}

// Grey materials never draw a wavelength: light through a grey opal shell
// keeps the source's chromaticity in every texel, without colour noise.
TEST(Spectral, GreyMaterialsAddNoColourNoise) {
  SceneDesc s = lamp_in_shell();
  auto sim = simulate(s, settings(2, 100000, 1));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const photometry::UvPrime source =
      photometry::uv_prime(photometry::tristimulus(photometry::blackbody_spectrum(3000.0)));
  const auto [worst, lit] = worst_texel_delta_uv(*sim, source);
  EXPECT_LT(worst, 1e-5);
  EXPECT_GT(lit, 1000);
}

// An integrating sphere of spectral reflectance ρ(λ) with a port of area
// fraction f: per wavelength the escaped fraction is f/(1 − ρ(λ)(1 − f)),
// so the escaped X, Y, Z are Σ S(λ)·{x̄, ȳ, z̄}(λ)·f/(1 − ρ(λ)(1 − f)) —
// the sphere's colour amplification, which a grey ρ would miss.
TEST(Spectral, IntegratingSphereFollowsTheSphereFormulaPerWavelength) {
  const double radius = 0.1;
  const double alpha = std::acos(0.9);
  std::vector<ProfilePoint> profile;
  for (int k = 0; k <= 64; ++k) {
    const double theta = (M_PI - alpha) * k / 64;
    profile.push_back({k == 0 ? 0.0 : radius * std::sin(theta), -radius * std::cos(theta)});
  }
  LatheOptions options;
  options.segments = 128;
  Mesh wall = lathe(profile, options);
  std::vector<ProfilePoint> cap_arc;
  for (int k = 0; k <= 16; ++k) {
    const double theta = M_PI - alpha + alpha * k / 16;
    cap_arc.push_back({k == 16 ? 0.0 : radius * std::sin(theta), -radius * std::cos(theta)});
  }
  const double port_area = surface_area_m2(lathe(cap_arc, options));
  const double f = port_area / (port_area + surface_area_m2(wall));

  const SampledSpectrum source = photometry::blackbody_spectrum(4000.0);
  const SampledSpectrum rho{{360.0, 450.0, 550.0, 650.0, 830.0}, {0.5, 0.55, 0.8, 0.95, 0.95}};
  SceneDesc s = bare_point(single(source));
  s.materials[0].name = "coating";
  s.materials[0].diffuse_reflect = 0.8;
  s.materials[0].spectral_reflectance = rho;
  s.meshes = {wall};
  const std::uint64_t n = 1 << 20;
  auto sim = simulate(s, settings(2, n / 2, 2));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  photometry::Tristimulus want, emitted;
  for (int k = 0; k < kWavelengthCount; ++k) {
    const double nm = wavelength_nm(k), p = source.at(nm), r = rho.at(nm);
    const photometry::CmfValue c = photometry::cie1931_cmf_sample(k);
    const double esc = f / (1.0 - r * (1.0 - f));
    want.X += p * c.x_bar * esc;
    want.Y += p * c.y_bar * esc;
    want.Z += p * c.z_bar * esc;
    emitted.Y += p * c.y_bar;
  }
  const photometry::Tristimulus got = totals(*sim);
  const double fraction = got.Y / 1000.0, want_fraction = want.Y / emitted.Y;
  const double d = photometry::delta_uv_prime(photometry::uv_prime(got), photometry::uv_prime(want));
  std::printf("integrating sphere: escaped %.5f (formula %.5f), delta u'v' %.6f\n", fraction, want_fraction, d);
  EXPECT_NEAR(fraction, want_fraction, 0.01 * want_fraction);
  // 0.000026 with hero wavelengths; one wavelength per photon gave 0.000358.
  EXPECT_LT(d, 1e-4);
  // A grey sphere of the same luminous reflectance keeps the source's colour:
  // the test tells the two apart.
  EXPECT_GT(photometry::delta_uv_prime(photometry::uv_prime(photometry::tristimulus(source)), photometry::uv_prime(want)),
            0.01);
  EXPECT_TRUE(sim->ledger().photons_close());
}

// colord's CIE 1931 ȳ (the CGATS file's second data row, 360–830 nm in
// 5 nm steps), read in place: the reference the radiant books are checked
// against does not go through Gonio's own table.
std::vector<double> colord_y_bar() {
  std::ifstream in("/usr/share/colord/cmf/CIE1931-2deg-XYZ.cmf");
  std::string line;
  bool data = false;
  int row = 0;
  while (std::getline(in, line)) {
    if (line.rfind("BEGIN_DATA", 0) == 0 && line.rfind("BEGIN_DATA_FORMAT", 0) != 0) {
      data = true;
      continue;
    }
    if (!data) continue;
    if (++row == 2) {
      std::istringstream values(line);
      std::vector<double> y;
      for (double v; values >> v;) y.push_back(v);
      return y;
    }
  }
  return {};
}

// The radiant books: a bare blackbody's radiant/luminous ratio is the closed
// form Σ S / (Km Σ S ȳ) over 360–830 nm (Planck's law at the 5 nm grid,
// colord's ȳ, Km = 683.002 lm/W), for every photon alike (none draws a
// wavelength); and with a spectral diffuser in the way (photons draw
// wavelengths) the books close in watts as in lumens, bin by bin.
TEST(Spectral, RadiantBooksClose) {
  const std::vector<double> y_bar = colord_y_bar();
  if (y_bar.size() != 95u) GONIO_MISSING("colord-data's /usr/share/colord/cmf/CIE1931-2deg-XYZ.cmf");
  for (double t_k : {2856.0, 6500.0}) {
    double s_sum = 0.0, sy_sum = 0.0;
    for (int k = 0; k < 95; ++k) {
      const double s = photometry::planck_radiance(360.0 + 5.0 * k, t_k);
      s_sum += s;
      sy_sum += s * y_bar[static_cast<std::size_t>(k)];
    }
    const double want_w_per_lm = s_sum / (683.002 * sy_sum);
    auto sim = simulate(bare_point(single(photometry::blackbody_spectrum(t_k))), settings(2, 50000, 2));
    ASSERT_TRUE(sim.ok()) << sim.error().message;
    const Ledger l = sim->ledger();
    ASSERT_TRUE(l.spectral);
    EXPECT_NEAR(l.radiant.emitted_w / l.emitted.flux_lm / want_w_per_lm, 1.0, 1e-9) << t_k;
    EXPECT_NEAR(l.radiant.escaped_w / l.escaped.flux_lm / want_w_per_lm, 1.0, 1e-9) << t_k;
    EXPECT_NEAR(l.radiant.imbalance_w(), 0.0, 1e-9 * l.radiant.emitted_w);
    double bands = 0.0;
    for (double w : l.radiant.escaped_band_w) bands += w;
    EXPECT_NEAR(bands / l.radiant.escaped_w, 1.0, 1e-12);
    // The escaped spectrum is Planck's law band by band.
    const double scale = l.radiant.escaped_band_w[60] / photometry::planck_radiance(660.0, t_k);
    for (int k = 0; k < 95; k += 10)
      EXPECT_NEAR(l.radiant.escaped_band_w[static_cast<std::size_t>(k)] /
                      (scale * photometry::planck_radiance(360.0 + 5.0 * k, t_k)),
                  1.0, 1e-6)
          << k;
    std::printf("bare %.0f K blackbody: %.6g W / %.6g lm = %.9g W/lm, closed form %.9g W/lm\n", t_k,
                l.radiant.emitted_w, l.emitted.flux_lm, l.radiant.emitted_w / l.emitted.flux_lm, want_w_per_lm);
  }

  // A spectral diffuser around the lamp: every photon draws its wavelength
  // there; the books close, and the escaped watts converge to the closed
  // form (the far red, seldom drawn, pools its fate with the bands nearby:
  // 0.9 % low at 8·10⁴ photons, 0.06 % high at 8·10⁵).
  SceneDesc s = lamp_in_shell(std::pair{0.5, 0.7});
  const Material& opal = s.materials[1];
  auto sim = simulate(s, settings(2, 400000, 2));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const Ledger l = sim->ledger();
  ASSERT_TRUE(l.spectral);
  EXPECT_GT(l.radiant.absorbed_w, 0.05 * l.radiant.emitted_w);
  EXPECT_NEAR(l.radiant.imbalance_w(), 0.0, 1e-12 * l.radiant.emitted_w);
  EXPECT_NEAR(l.flux_imbalance_lm(), 0.0, 1e-9 * l.emitted.flux_lm);
  std::printf("opal shell: emitted %.6g W, escaped %.6g W, absorbed %.6g W, cut off %.6g W, imbalance %.3g W\n",
              l.radiant.emitted_w, l.radiant.escaped_w, l.radiant.absorbed_w, l.radiant.cutoff_w,
              l.radiant.imbalance_w());
  // The emitted watts are exact (the closed form), and the escaped watts
  // follow the shell's closed form per wavelength: light leaves a diffuse
  // shell of transmittance τ(λ) and reflectance 0.3 (all of it back onto
  // the shell) with the fraction τ(λ)/(1 − 0.3), τ held at its end values.
  double s_sum = 0.0, sy_sum = 0.0, escaped_sum = 0.0;
  for (int k = 0; k < 95; ++k) {
    const double nm = 360.0 + 5.0 * k;
    const double p = photometry::planck_radiance(nm, 3000.0);
    s_sum += p;
    sy_sum += p * y_bar[static_cast<std::size_t>(k)];
    escaped_sum += p * opal.spectral_transmittance.at(std::clamp(nm, 400.0, 700.0)) / 0.7;
  }
  const double w_per_lm = s_sum / (683.002 * sy_sum);
  EXPECT_NEAR(l.radiant.emitted_w / l.emitted.flux_lm / w_per_lm, 1.0, 1e-9);
  const double want_escaped_w = l.radiant.emitted_w * escaped_sum / s_sum;
  EXPECT_NEAR(l.radiant.escaped_w / want_escaped_w, 1.0, 0.005);
  std::printf("opal shell: escaped %.6g W, closed form %.6g W\n", l.radiant.escaped_w, want_escaped_w);
  // Band by band where photons are drawn often (±3 % at 8·10⁵ photons).
  for (int k : {20, 40, 50, 60}) {
    const double nm = 360.0 + 5.0 * k;
    const double emitted_band_w = l.radiant.emitted_w * photometry::planck_radiance(nm, 3000.0) / s_sum;
    EXPECT_NEAR(l.radiant.escaped_band_w[static_cast<std::size_t>(k)] / emitted_band_w,
                opal.spectral_transmittance.at(nm) / 0.7, 0.03)
        << nm;
  }

  // A grey run keeps no radiant books.
  SceneDesc grey = bare_point({});
  auto plain = simulate(grey, settings(1, 1000, 1));
  ASSERT_TRUE(plain.ok());
  EXPECT_FALSE(plain->ledger().spectral);
}

// Guided emission (sim/emitters/emission_guide.h) with a spectral model: photons of
// unequal power carry X and Z in proportion to it, so the colour is the
// plain run's (within photon noise), the books close in lumens and watts,
// and the bytes do not depend on the thread split.
TEST(Spectral, GuidedEmissionCarriesColourWithItsWeights) {
  // A 3000 K lamp in a shell of coloured diffuser: light leaves tinted.
  SceneDesc s = lamp_in_shell(std::pair{0.2, 0.7});
  const Material& opal = s.materials[1];
  SimulationSettings guided = settings(2, 100000, 4);
  guided.importance.enabled = true;
  guided.importance.emission_face_size = 8;
  auto a = simulate(s, guided);
  ASSERT_TRUE(a.ok()) << a.error().message;
  auto plain = simulate(s, settings(2, 100000, 4));
  ASSERT_TRUE(plain.ok());
  // The closed form: the shell passes τ(λ)/(1 − 0.3) of each wavelength
  // (τ held at its end values), so the light leaves with S(λ)·τ(λ)'s colour.
  photometry::SampledSpectrum product = photometry::blackbody_spectrum(3000.0);
  for (std::size_t i = 0; i < product.values.size(); ++i)
    product.values[i] *= opal.spectral_transmittance.at(std::clamp(product.wavelengths_nm[i], 400.0, 700.0));
  const photometry::UvPrime want = photometry::uv_prime(photometry::tristimulus(product));
  const photometry::Tristimulus tg = totals(*a), tp = totals(*plain);
  const double dg = photometry::delta_uv_prime(photometry::uv_prime(tg), want);
  const double dp = photometry::delta_uv_prime(photometry::uv_prime(tp), want);
  std::printf("delta u'v' from the closed form, 4e5 photons: guided %.6f, plain %.6f; Y %.5g against %.5g lm\n", dg,
              dp, tg.Y, tp.Y);
  // 0.00017 and 0.00011 with hero wavelengths (0.00056 and 0.00070 with one
  // wavelength per photon).
  EXPECT_LT(dg, 5e-4);
  EXPECT_LT(dp, 5e-4);
  // The colour is the shell's, not the lamp's: the test tells them apart.
  EXPECT_GT(photometry::delta_uv_prime(want, photometry::uv_prime(photometry::tristimulus(
                                                 photometry::blackbody_spectrum(3000.0)))),
            0.005);
  const Ledger l = a->ledger();
  EXPECT_NEAR(l.flux_imbalance_lm(), 0.0, 1e-9 * l.emitted.flux_lm);
  ASSERT_TRUE(l.spectral);
  EXPECT_NEAR(l.radiant.imbalance_w(), 0.0, 1e-12 * l.radiant.emitted_w);
  EXPECT_NEAR(l.radiant.escaped_w / plain->ledger().radiant.escaped_w, 1.0, 0.01);
  // Same bytes for another thread split.
  SimulationSettings one = guided;
  one.threads = 1;
  auto b = simulate(s, one);
  ASSERT_TRUE(b.ok());
  expect_same_colour_bytes(*a, *b);
}

TEST(Spectral, SameBytesForAnyThreadAndIterationSplit) {
  SceneDesc s = lamp_in_shell(std::pair{0.5, 0.7});
  auto one = simulate(s, settings(1, 20000, 3));
  auto two = simulate(s, settings(2, 60000, 1));
  ASSERT_TRUE(one.ok()) << one.error().message;
  ASSERT_TRUE(two.ok());
  expect_same_colour_bytes(*one, *two);
}

// Dispersion: a beam inside a glass block meets its top face at 30° and
// leaves with sin θt = n(λ) sin 30° (the sides reflect it totally); n(λ)
// from the Abbe number's Cauchy curve, which for Schott N-BK7 (n_d 1.51680,
// V_d 64.17) gives the catalogue's n_F = 1.52238 and n_C = 1.51432 within
// 6e-5 (two Cauchy terms cannot follow the glass's partial dispersion).
TEST(Spectral, DielectricRefractsEachWavelengthBySnell) {
  Material bk7;
  bk7.name = "N-BK7";
  bk7.dielectric = 1.0;
  bk7.ior = 1.51680;
  bk7.abbe_number = 64.17;
  EXPECT_NEAR(ior_at(bk7, 486.13), 1.52238, 6e-5);
  EXPECT_NEAR(ior_at(bk7, 656.27), 1.51432, 6e-5);
  EXPECT_NEAR(ior_at(bk7, 486.13) - ior_at(bk7, 656.27), 0.51680 / 64.17, 1e-12);
  EXPECT_NEAR(ior_at(bk7, 587.56), 1.51680, 1e-12);

  Material flint = bk7;
  flint.name = "flint";
  flint.ior = 1.62;
  flint.abbe_number = 30.0;
  SceneDesc s = bare_point(single(photometry::blackbody_spectrum(5000.0)));
  s.materials = {flint};
  Mesh block = box(1.0, 1.0, 1.0);
  block.material = 0;
  s.meshes = {block};
  s.emitters[0].position = {0.0, -2.0, 0.0};  // outside; the beams start inside
  auto tracer = Tracer::create(s, 8);
  ASSERT_TRUE(tracer.ok()) << tracer.error().message;
  const Vec3 dir{0.5, std::sqrt(0.75), 0.0};
  for (int k : {8, 38, 68}) {  // 400, 550, 700 nm
    const double n = ior_at(flint, wavelength_nm(k));
    int checked = 0;
    for (std::uint64_t i = 0; i < 200; ++i) {
      PhotonRandom rng(11, i);
      const TraceResult r = tracer->trace({0.0, 0.0, 0.0}, dir, rng, k);
      if (r.fate != Fate::Escaped) continue;
      EXPECT_NEAR(std::abs(r.direction.x), 0.5 * n, 1e-6) << wavelength_nm(k);
      EXPECT_NEAR(r.direction.z, 0.0, 1e-9);
      ++checked;
    }
    EXPECT_GT(checked, 150);
  }
}

TEST(Spectral, OverGammaMixesTheNeighbouringSpectra) {
  EmitterSpectrum s;
  s.over_gamma.push_back({0.0, photometry::blackbody_spectrum(6500.0)});
  s.over_gamma.push_back({60.0, photometry::blackbody_spectrum(2700.0)});
  auto w = WavelengthSampler::create(bare_point(s));
  ASSERT_TRUE(w.ok()) << w.error().message;
  auto w0 = WavelengthSampler::create(bare_point(single(s.over_gamma[0].spectrum)));
  auto w1 = WavelengthSampler::create(bare_point(single(s.over_gamma[1].spectrum)));
  const double c30 = std::cos(30.0 * M_PI / 180.0), c80 = std::cos(80.0 * M_PI / 180.0);
  for (int k = 0; k < kWavelengthCount; k += 7) {
    EXPECT_NEAR(w->pmf(0, c30, k), 0.5 * (w0->pmf(0, 1.0, k) + w1->pmf(0, 1.0, k)), 1e-12);
    EXPECT_NEAR(w->pmf(0, c80, k), w1->pmf(0, 1.0, k), 1e-12);
    EXPECT_NEAR(w->pmf(0, 1.0, k), w0->pmf(0, 1.0, k), 1e-12);
  }
}

// Issue 34, case 1: a coloured lamp in grey materials under guided emission.
// No photon draws a wavelength, so each carries its spectrum's expected X/Y
// and Z/Y, scaled by its power: every texel keeps the source's u′v′ (the
// closed form) to the 2⁻¹⁷ rounding. Swapping X and Z on this path (the
// guided tracer's never-drew-a-wavelength branch) reads a 3000 K lamp as
// bluish (Δu′v′ ≈ 0.2) in every texel.
TEST(Spectral, GuidedEmissionThroughGreyMaterialsKeepsTheSourcesColourInEveryTexel) {
  const SceneDesc s = lamp_in_shell();
  SimulationSettings guided = settings(2, 50000, 3);
  guided.importance.enabled = true;
  guided.importance.emission_face_size = 8;
  auto sim = simulate(s, guided);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const photometry::UvPrime source =
      photometry::uv_prime(photometry::tristimulus(photometry::blackbody_spectrum(3000.0)));
  const auto [worst, lit] = worst_texel_delta_uv(*sim, source);
  EXPECT_GT(lit, 1000);
  EXPECT_LT(worst, 1e-5) << "largest delta u'v' of a texel from the 3000 K source's";
  // The run took the guided path: it dropped some photons (and gave the
  // others more power).
  EXPECT_LT(sim->stats().photons_traced, sim->stats().photons);
}

namespace {

// p(k) = S(λ_k) ȳ(λ_k) / Σ S ȳ of a spectrum on the 95 wavelengths, from
// the CIE table directly (not through WavelengthSampler).
std::vector<double> luminous_pmf(const SampledSpectrum& s) {
  std::vector<double> p(kWavelengthCount);
  double sum = 0.0;
  for (int k = 0; k < kWavelengthCount; ++k) {
    p[static_cast<std::size_t>(k)] = s.at(wavelength_nm(k)) * photometry::cie1931_cmf_sample(k).y_bar;
    sum += p[static_cast<std::size_t>(k)];
  }
  for (double& v : p) v /= sum;
  return p;
}

}  // namespace

// Issue 34, case 2: between two over_gamma entries the spectrum is the
// linear mix by γ — at a quarter of the way, three parts of the near entry
// and one of the far one. Halfway (the test above) a swap of the weights
// changes nothing; here it moves every figure: the density (pmf), the
// expected X/Y and Z/Y of photons that never draw (expected_units), and the
// wavelengths drawn (sample, counted over 2·10⁵ draws).
TEST(Spectral, OverGammaWeighsEachEntryByItsNearness) {
  EmitterSpectrum s;
  s.over_gamma.push_back({0.0, photometry::blackbody_spectrum(6500.0)});
  s.over_gamma.push_back({60.0, photometry::blackbody_spectrum(2700.0)});
  auto w = WavelengthSampler::create(bare_point(s));
  ASSERT_TRUE(w.ok()) << w.error().message;
  const std::vector<double> p0 = luminous_pmf(s.over_gamma[0].spectrum), p1 = luminous_pmf(s.over_gamma[1].spectrum);
  for (double gamma_deg : {15.0, 45.0, 54.0}) {
    const double t = gamma_deg / 60.0, cg = std::cos(gamma_deg * M_PI / 180.0);
    double want_x = 0.0, want_z = 0.0;
    for (int k = 0; k < kWavelengthCount; ++k) {
      const auto i = static_cast<std::size_t>(k);
      const double want = (1.0 - t) * p0[i] + t * p1[i];
      EXPECT_NEAR(w->pmf(0, cg, k), want, 1e-12) << "gamma " << gamma_deg << ", " << wavelength_nm(k) << " nm";
      want_x += want * static_cast<double>(w->x_units()[i]);
      want_z += want * static_cast<double>(w->z_units()[i]);
    }
    // Expected units: the mix of the entries' expectations, rounded once.
    const auto [x, z] = w->expected_units(0, cg);
    EXPECT_NEAR(static_cast<double>(x), want_x, 1.0) << "gamma " << gamma_deg;
    EXPECT_NEAR(static_cast<double>(z), want_z, 1.0) << "gamma " << gamma_deg;
    // Drawn wavelengths: their mean Z/Y within 5 standard errors of the mix's.
    const int n = 200000;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
      PhotonRandom rng(21, static_cast<std::uint64_t>(i));
      const double zk = static_cast<double>(w->z_units()[static_cast<std::size_t>(w->sample(0, cg, rng))]);
      sum += zk;
      sum2 += zk * zk;
    }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(mean, want_z, 5.0 * sd / std::sqrt(n)) << "gamma " << gamma_deg;
  }
}

// Issue 34, case 2, simulated: a lamp whose spectrum turns from 6500 K at
// the nadir to 2700 K at γ 90° above a wide mirror of spectral reflectance
// ρ(λ). The mirror keeps each photon's γ (light emitted at γ leaves at γ
// from the zenith; a black disc above the lamp takes the light that would
// go up directly), so each texel of the upper far field holds the per-γ
// product spectrum S_γ(λ)·ρ(λ) at its own γ: X/Y = Σ p(k | γ) ρ_k x̄_k/ȳ_k /
// Σ p(k | γ) ρ_k, computed here from the CIE table, the spectra and ρ alone,
// at each texel's centre and weighted by its flux, summed over rings of γ.
// Measured Δu′v′ at 4·10⁵ photons: 0.00006–0.0006 over seeds 1, 2, 3, 5 (photon
// noise: 0.00002–0.0001 at 3.2·10⁶). Swapping the two entries' weights
// gives the ring at γ 20…30° the colour of one at 60…70° (Δu′v′ 0.034).
TEST(Spectral, MirrorUnderALampOverGammaGivesThePerGammaProductSpectrum) {
  EmitterSpectrum spectrum;
  spectrum.over_gamma.push_back({0.0, photometry::blackbody_spectrum(6500.0)});
  spectrum.over_gamma.push_back({90.0, photometry::blackbody_spectrum(2700.0)});
  const SampledSpectrum rho{{380.0, 480.0, 580.0, 680.0, 780.0}, {0.3, 0.45, 0.7, 0.85, 0.9}};
  SceneDesc s = bare_point(spectrum);
  s.emitters[0].position = {0.0, 0.1, 0.0};
  Material mirror;
  mirror.name = "coloured mirror";
  mirror.mirror = 0.9;  // the spectrum overrides the total
  mirror.spectral_reflectance = rho;
  s.materials.push_back(mirror);
  Mesh floor = disc(100.0, 64);
  floor.material = 1;
  Mesh cap = disc(0.05, 32);
  transform(cap, translation({0.0, 0.105, 0.0}));
  cap.material = 0;  // black
  s.meshes = {floor, cap};
  const std::uint64_t n = 400000;
  SimulationSettings run = settings(2, n / 2, 2);
  run.face_size = 32;
  auto sim = simulate(s, run);
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const FarField f = sim->far_field();
  const ColourFarField c = sim->colour_far_field();

  const std::vector<double> p0 = luminous_pmf(spectrum.over_gamma[0].spectrum);
  const std::vector<double> p1 = luminous_pmf(spectrum.over_gamma[1].spectrum);
  // X/Y and Z/Y of the light that left the mirror at γ.
  const auto ratios = [&](double gamma_rad, bool swapped) {
    const double t = std::min(gamma_rad / (M_PI / 2.0), 1.0), a = swapped ? t : 1.0 - t;
    double x = 0.0, y = 0.0, z = 0.0;
    for (int k = 0; k < kWavelengthCount; ++k) {
      const auto j = static_cast<std::size_t>(k);
      const photometry::CmfValue cmf = photometry::cie1931_cmf_sample(k);
      if (!(cmf.y_bar > 0.0)) continue;
      const double p = (a * p0[j] + (1.0 - a) * p1[j]) * rho.at(std::clamp(wavelength_nm(k), 380.0, 780.0));
      x += p * cmf.x_bar / cmf.y_bar;
      y += p;
      z += p * cmf.z_bar / cmf.y_bar;
    }
    return std::pair{x / y, z / y};
  };
  for (const auto& [from, to] : {std::pair{20.0, 30.0}, std::pair{40.0, 50.0}, std::pair{60.0, 70.0}}) {
    photometry::Tristimulus got, want, want_swapped;
    for (std::size_t i = 0; i < f.texel_count(); ++i) {
      const Vec3 d = f.grid().texel_direction(i);
      const double zenith = std::acos(std::clamp(d.y, -1.0, 1.0));
      if (zenith * 180.0 / M_PI < from || zenith * 180.0 / M_PI >= to) continue;
      const double y = f.flux_lm(i);
      got.X += c.x_lm[i];
      got.Y += y;
      got.Z += c.z_lm[i];
      for (const bool swapped : {false, true}) {
        const auto [xr, zr] = ratios(zenith, swapped);
        photometry::Tristimulus& w = swapped ? want_swapped : want;
        w.X += xr * y;
        w.Y += y;
        w.Z += zr * y;
      }
    }
    const double d = photometry::delta_uv_prime(photometry::uv_prime(got), photometry::uv_prime(want));
    const double swapped = photometry::delta_uv_prime(photometry::uv_prime(want_swapped), photometry::uv_prime(want));
    std::printf("mirror ring %.0f-%.0f deg: delta u'v' from the per-gamma product %.6f (weights swapped: %.4f)\n",
                from, to, d, swapped);
    EXPECT_LT(d, 2e-3) << "ring " << from << "-" << to << " deg";
    if (from != 40.0) {
      EXPECT_GT(swapped, 0.01) << "the test could not tell swapped weights";
    }
  }
}

// Issue 34, case 2, behind a diffuser: the 3000 K-to-6500 K lamp in a shell
// of spectral diffuser. The shell mixes all γ, so the escaped light has the
// γ-average of the per-γ product spectrum: entry 1's share is
// ½[∫₀^{π/3} (γ/(π/3)) sin γ dγ + ∫_{π/3}^{π} sin γ dγ] = 0.91349 (entries
// at 0° and 60°), 0.83651 with the weights swapped.
TEST(Spectral, DiffuserShellMixesTheSpectrumOverGammaBySolidAngle) {
  SceneDesc s = lamp_in_shell(std::pair{0.2, 0.7});
  EmitterSpectrum spectrum;
  spectrum.over_gamma.push_back({0.0, photometry::blackbody_spectrum(6500.0)});
  spectrum.over_gamma.push_back({60.0, photometry::blackbody_spectrum(2700.0)});
  s.emitters[0].spectrum = spectrum;
  const Material& opal = s.materials[1];
  auto sim = simulate(s, settings(2, 50000, 2));
  ASSERT_TRUE(sim.ok()) << sim.error().message;
  const double a = M_PI / 3.0;
  const double share1 = 0.5 * ((std::sin(a) - a * std::cos(a)) / a + (1.0 + std::cos(a)));
  EXPECT_NEAR(share1, 0.91349, 1e-5);
  const std::vector<double> p0 = luminous_pmf(spectrum.over_gamma[0].spectrum);
  const std::vector<double> p1 = luminous_pmf(spectrum.over_gamma[1].spectrum);
  const auto expected = [&](double w1) {
    photometry::Tristimulus t;
    for (int k = 0; k < kWavelengthCount; ++k) {
      const auto j = static_cast<std::size_t>(k);
      const photometry::CmfValue cmf = photometry::cie1931_cmf_sample(k);
      if (!(cmf.y_bar > 0.0)) continue;
      const double p = ((1.0 - w1) * p0[j] + w1 * p1[j]) *
                       opal.spectral_transmittance.at(std::clamp(wavelength_nm(k), 400.0, 700.0));
      t.X += p * cmf.x_bar / cmf.y_bar;
      t.Y += p;
      t.Z += p * cmf.z_bar / cmf.y_bar;
    }
    return photometry::uv_prime(t);
  };
  const photometry::UvPrime want = expected(share1);
  const double d = photometry::delta_uv_prime(photometry::uv_prime(totals(*sim)), want);
  const double share1_swapped = 0.5 * ((1.0 - std::cos(a)) - (std::sin(a) - a * std::cos(a)) / a + (1.0 + std::cos(a)));
  EXPECT_NEAR(share1_swapped, 0.83651, 1e-5);
  const double swapped = photometry::delta_uv_prime(expected(share1_swapped), want);
  std::printf("diffuser shell, spectrum over gamma: delta u'v' %.6f (weights swapped: %.5f)\n", d, swapped);
  EXPECT_LT(d, 5e-4);
  EXPECT_GT(swapped, 2e-3);
}

// Issue 34, case 8 (the dispersion anchor), a check independent of the
// N-BK7 catalogue figures above: Schott's Sellmeier coefficients of N-BK7
// and N-F2 (Schott optical glass data sheets; the same coefficients
// refractiveindex.info lists) give n_d at the helium d line (587.5618 nm)
// and V_d = (n_d − 1)/(n_F − n_C); a material with those takes n_d at
// exactly that wavelength (1e-6: the d line's 587.56 nm against 587.5618).
// Anchored at the sodium D lines' 589.3 nm instead, N-BK7 would be 7e-5 and
// N-F2 1.5e-4 off there. Across 400–700 nm the two-term Cauchy curve
// follows the Sellmeier curve to 4e-4 (N-BK7) and 4e-3 (N-F2, which
// disperses more than Cauchy's two terms can follow), and blue bends more
// than red.
TEST(Spectral, DispersionIsAnchoredAtTheHeliumDLineBySchottsSellmeierData) {
  struct Glass {
    const char* name;
    std::array<double, 3> b, c;  // Sellmeier B1..3, C1..3 [µm²]
    double cauchy_tol;           // |Cauchy − Sellmeier| over 400–700 nm
  };
  const auto sellmeier = [](const Glass& g, double nm) {
    const double l2 = (nm / 1000.0) * (nm / 1000.0);
    double n2 = 1.0;
    for (int i = 0; i < 3; ++i) n2 += g.b[static_cast<std::size_t>(i)] * l2 / (l2 - g.c[static_cast<std::size_t>(i)]);
    return std::sqrt(n2);
  };
  const Glass glasses[] = {
      {"N-BK7", {1.03961212, 0.231792344, 1.01046945}, {0.00600069867, 0.0200179144, 103.560653}, 4e-4},
      {"N-F2", {1.39757037, 0.159201403, 1.26865430}, {0.00995906143, 0.0546931752, 119.248346}, 4.2e-3},
  };
  for (const Glass& g : glasses) {
    const double n_d = sellmeier(g, 587.5618), n_f = sellmeier(g, 486.1327), n_c = sellmeier(g, 656.2725);
    Material m;
    m.name = g.name;
    m.dielectric = 1.0;
    m.ior = n_d;
    m.abbe_number = (n_d - 1.0) / (n_f - n_c);
    EXPECT_NEAR(ior_at(m, 587.5618), n_d, 1e-6) << g.name;
    // The Abbe number's F and C lines (as ior_at takes them, to 0.01 nm).
    EXPECT_NEAR(ior_at(m, 486.13) - ior_at(m, 656.27), n_f - n_c, 1e-12) << g.name;
    for (double nm = 400.0; nm <= 700.0; nm += 25.0)
      EXPECT_NEAR(ior_at(m, nm), sellmeier(g, nm), g.cauchy_tol) << g.name << " at " << nm << " nm";
    EXPECT_GT(ior_at(m, 450.0), ior_at(m, 650.0)) << g.name;
  }
  // The catalogue's n_d of N-BK7 (1.51680) is what its Sellmeier curve gives.
  EXPECT_NEAR(sellmeier(glasses[0], 587.5618), 1.51680, 1e-5);
}

TEST(Spectral, BadInputIsAnErrorThatNamesIt) {
  EmitterSpectrum s;
  s.over_gamma.push_back({30.0, {{400.0, 700.0}, {1.0, 1.0}}});
  s.over_gamma.push_back({30.0, {{400.0, 700.0}, {1.0, 1.0}}});
  Status st = validate_emitter_spectrum(s);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().message, "spectrum at entry 1: gamma_deg 30 does not increase");
  s.over_gamma.resize(1);
  s.over_gamma[0].spectrum = {{900.0, 1000.0}, {1.0, 1.0}};
  st = validate_emitter_spectrum(s);
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.error().message, "spectrum: no power between 360 and 830 nm where the eye sees");

  SceneDesc scene = bare_point(single(photometry::blackbody_spectrum(3000.0)));
  scene.materials[0].name = "paint";
  scene.materials[0].diffuse_reflect = 0.5;
  scene.materials[0].mirror = 0.2;
  scene.materials[0].spectral_transmittance = {{400.0, 700.0}, {0.1, 0.4}};
  auto t = Tracer::create(scene, 8);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.error().message, "material 'paint': its weights sum to 1.005 > 1 at 605 nm");
}

}  // namespace
}  // namespace gonio::sim
