// Emitters' flux and colour bins as tolerances (issue 42, docs/tolerance.md
// "Fourth slice"): parsing with lines, spectrum files, exact application,
// and the draws of a discrete law against its probabilities.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "design/tolerance.h"
#include "design/tolerance_spec.h"
#include "photometry/spectrum.h"
#include "sim/scene.h"
#include "tests/support/test_support.h"

namespace gonio::design {
namespace {

sim::SceneDesc lamp_scene() {
  sim::SceneDesc s;
  sim::Emitter led;
  led.name = "LED";
  led.flux_lm = 100.0;
  led.spectrum.over_gamma = {{0.0, photometry::blackbody_spectrum(4000.0)}};
  s.emitters.push_back(led);
  sim::Emitter panel;
  panel.name = "panel";
  panel.kind = sim::Emitter::Kind::Area;
  panel.flux_lm = 50.0;
  s.emitters.push_back(panel);
  return s;
}

Result<ToleranceSpec> parse(const std::string& text, const std::string& path = "t.toml") {
  return parse_tolerances(text, path);
}
std::string error_of(const std::string& text, const std::string& path = "t.toml") {
  Result<ToleranceSpec> s = parse(text, path);
  return s.ok() ? std::string("(parsed)") : to_string(s.error());
}

TEST(EmitterBins, ParseWithTheirLines) {
  Result<ToleranceSpec> s = parse(
      "[emitter.LED]\n"
      "flux_bin = { factors = [0.9, 1.0, 1.1], probabilities = [0.25, 0.5, 0.25] }\n"
      "colour_bin = { cct = [2700, 3000] }\n"
      "[emitter.panel]\n"
      "flux_bin = { factors = [0.95, 1.05] }\n");
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  ASSERT_EQ(s->tolerances.size(), 3u);
  const Tolerance& f = s->tolerances[1].quantity == "flux_bin" ? s->tolerances[1] : s->tolerances[0];
  EXPECT_EQ(f.label(), "LED.flux_bin");
  EXPECT_EQ(f.line, 2);
  EXPECT_EQ(f.law.kind, ToleranceLaw::Kind::Bins);
  EXPECT_EQ(f.law.low(), 1.0);
  EXPECT_EQ(f.law.high(), 3.0);
  EXPECT_EQ(std::string(f.unit()), "bin");
  EXPECT_EQ(f.law.text(), "bins {0.25, 0.5, 0.25}");
  EXPECT_EQ(f.bin_factors, (std::vector<double>{0.9, 1.0, 1.1}));
  const Tolerance& c = s->tolerances[1].quantity == "colour_bin" ? s->tolerances[1] : s->tolerances[0];
  EXPECT_EQ(c.line, 3);
  ASSERT_EQ(c.bin_spectra.size(), 2u);
  EXPECT_EQ(c.law.probabilities, (std::vector<double>{0.5, 0.5}));  // none given: equally likely
  EXPECT_EQ(c.bin_spectra[0].values, photometry::blackbody_spectrum(2700.0).values);
  EXPECT_EQ(c.bin_names[1], "3000 K");
  // A flux bin on an area emitter is fine; position is not.
  EXPECT_TRUE(check_tolerances(*s, lamp_scene()).ok());
}

TEST(EmitterBins, MistakesNameTheLine) {
  EXPECT_EQ(error_of("[emitter.LED]\n\nflux_bin = { factors = [0.9, 1.1], probabilities = [0.5, 0.6] }\n"),
            "t.toml:3: emitter.LED.flux_bin.probabilities sum to 1.1, not 1");
  EXPECT_EQ(error_of("[emitter.LED]\nflux_bin = { factors = [0.9, 1.1], probabilities = [1] }\n"),
            "t.toml:2: emitter.LED.flux_bin.probabilities: 1 for 2 bins");
  EXPECT_EQ(error_of("[emitter.LED]\nflux_bin = { factors = [0.9, 1.1], probabilities = [1.5, -0.5] }\n"),
            "t.toml:2: emitter.LED.flux_bin.probabilities must be ≥ 0");
  EXPECT_EQ(error_of("[emitter.LED]\nflux_bin = { factors = [0.9, -1] }\n"),
            "t.toml:2: emitter.LED.flux_bin.factors: a factor must be > 0 (-1)");
  EXPECT_EQ(error_of("[emitter.LED]\ncolour_bin = { cct = [3000], spectra = [{ blackbody_k = 3000 }] }\n")
                .rfind("t.toml:2: emitter.LED.colour_bin: give exactly one list of bins", 0),
            0u);
  EXPECT_EQ(error_of("[emitter.LED]\ncolour_bin = { cct = [300] }\n"),
            "t.toml:2: emitter.LED.colour_bin.cct: 300 K is outside 1000 … 25000 K");
  EXPECT_EQ(error_of("[emitter.LED]\ncolour_bin = { factors = [1] }\n"),
            "t.toml:2: emitter.LED.colour_bin: unknown key 'factors' (spectra, cct, probabilities)");
  EXPECT_EQ(error_of("[emitter.LED]\ncolour_bin = { probabilities = [1] }\n").rfind(
                "t.toml:2: emitter.LED.colour_bin: give exactly one list of bins", 0),
            0u);
  // A colour bin needs the model's emitter to have a spectrum (the nominal is then spectral).
  Result<ToleranceSpec> s = parse("[emitter.panel]\ncolour_bin = { cct = [3000] }\n");
  ASSERT_TRUE(s.ok());
  const Status st = check_tolerances(*s, lamp_scene());
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(to_string(st.error()).rfind("t.toml:2: panel.colour_bin: 'panel' has no spectrum in the model", 0), 0u)
      << to_string(st.error());
}

// Spectrum files: two columns (spaces, tabs, commas, semicolons; CRLF; a
// header line; # comments); a bad line or decreasing wavelengths name the
// file and line; the file is found beside the tolerance file.
TEST(EmitterBins, SpectrumFilesAreReadWithTheirLines) {
  test::TempDir dir;
  test::write_file(dir / "a.txt", "wavelength,value\r\n# measured\r\n400,0.5\r\n500;1\r\n600\t0.25 # red\r\n");
  Result<photometry::SampledSpectrum> a = read_spectrum_table((dir / "a.txt").string());
  ASSERT_TRUE(a.ok()) << to_string(a.error());
  EXPECT_EQ(a->wavelengths_nm, (std::vector<double>{400.0, 500.0, 600.0}));
  EXPECT_EQ(a->values, (std::vector<double>{0.5, 1.0, 0.25}));
  test::write_file(dir / "b.txt", "400 1\n500 1\n450 1\n");
  Result<photometry::SampledSpectrum> b = read_spectrum_table((dir / "b.txt").string());
  ASSERT_FALSE(b.ok());
  EXPECT_EQ(to_string(b.error()), (dir / "b.txt").string() + ":3: wavelengths must increase (450 nm after 500 nm)");
  test::write_file(dir / "c.txt", "400 1\n500 1 2\n");
  Result<photometry::SampledSpectrum> c = read_spectrum_table((dir / "c.txt").string());
  ASSERT_FALSE(c.ok());
  EXPECT_EQ(to_string(c.error()), (dir / "c.txt").string() + ":2: write two numbers per line: wavelength [nm] and value");
  // Through a tolerance file in that folder: the name is relative to it.
  Result<ToleranceSpec> s =
      parse("[emitter.LED]\ncolour_bin = { spectra = [\"a.txt\", { blackbody_k = 5000 }] }\n",
            (dir / "t.toml").string());
  ASSERT_TRUE(s.ok()) << to_string(s.error());
  EXPECT_EQ(s->tolerances[0].bin_spectra[0].values, a->values);
  EXPECT_EQ(s->tolerances[0].bin_names[0], "a.txt");
  EXPECT_EQ(s->tolerances[0].bin_names[1], "5000 K");
}

// Bin k scales the flux by its factor exactly (one multiplication) and
// replaces the spectrum; 0 is the nominal, bit for bit.
TEST(EmitterBins, ApplyScalesExactlyAndReplacesTheSpectrum) {
  Result<ToleranceSpec> s = parse(
      "[emitter.LED]\nflux_bin = { factors = [0.93, 1.07] }\ncolour_bin = { cct = [2700, 6500] }\n");
  ASSERT_TRUE(s.ok());
  const std::size_t flux = s->tolerances[0].quantity == "flux_bin" ? 0 : 1, colour = 1 - flux;
  for (int bin = 0; bin <= 2; ++bin) {
    sim::SceneDesc scene = lamp_scene();
    ASSERT_TRUE(check_tolerances(*s, scene).ok());
    std::vector<double> values(2, 0.0);
    values[flux] = bin;
    values[colour] = bin;
    apply_tolerances(*s, values, scene);
    const sim::Emitter& e = scene.emitters[0];
    if (bin == 0) {
      EXPECT_EQ(e.flux_lm, 100.0);
      EXPECT_EQ(e.spectrum.over_gamma[0].spectrum.values, photometry::blackbody_spectrum(4000.0).values);
      continue;
    }
    EXPECT_EQ(e.flux_lm, 100.0 * (bin == 1 ? 0.93 : 1.07));
    ASSERT_EQ(e.spectrum.over_gamma.size(), 1u);
    EXPECT_EQ(e.spectrum.over_gamma[0].spectrum.values,
              photometry::blackbody_spectrum(bin == 1 ? 2700.0 : 6500.0).values);
    EXPECT_EQ(scene.emitters[1].flux_lm, 50.0);  // the other emitter untouched
  }
}

// splitmix64, for independent uniform draws.
struct SplitMix {
  std::uint64_t state;
  double uniform() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }
};

// P(X ≤ k) of a binomial (n, p), summed from its terms (log-gamma).
double binomial_cdf(std::size_t k, std::size_t n, double p) {
  double sum = 0.0;
  for (std::size_t i = 0; i <= k; ++i)
    sum += std::exp(std::lgamma(static_cast<double>(n) + 1.0) - std::lgamma(static_cast<double>(i) + 1.0) -
                    std::lgamma(static_cast<double>(n - i) + 1.0) + static_cast<double>(i) * std::log(p) +
                    static_cast<double>(n - i) * std::log1p(-p));
  return std::min(1.0, sum);
}

// The draws of bins with probabilities 0.1, 0.2, 0.3, 0.4 (ANSI-style flux
// bins: a few bins of unequal share):
// - independent uniforms through the law's quantile: each bin's count of
//   n = 20 000 passes the two-sided exact binomial test at α = 0.001
//   (2·min(P(X ≤ k), P(X ≥ k)) > α) against its probability;
// - the Latin hypercube gonio tolerance draws (one u per stratum of
//   [0, 1)): bin k gets N·P(k) ± 2 of N = 1000 draws (an interval of length
//   N·P(k) strata holds all but at most two of the strata it touches).
// Both fail where the quantile ignores the probabilities (equal bins).
TEST(EmitterBins, DrawsMatchTheProbabilities) {
  Result<ToleranceSpec> s =
      parse("[emitter.LED]\nflux_bin = { factors = [0.9, 0.95, 1.0, 1.05], probabilities = [0.1, 0.2, 0.3, 0.4] }\n");
  ASSERT_TRUE(s.ok());
  const ToleranceLaw& law = s->tolerances[0].law;
  const std::vector<double> p = {0.1, 0.2, 0.3, 0.4};
  {
    constexpr std::size_t n = 20000;
    std::vector<std::size_t> count(4, 0);
    SplitMix rng{12345};
    for (std::size_t i = 0; i < n; ++i) {
      const double bin = law.quantile(rng.uniform());
      ASSERT_TRUE(bin == 1.0 || bin == 2.0 || bin == 3.0 || bin == 4.0) << bin;
      ++count[static_cast<std::size_t>(bin) - 1];
    }
    for (std::size_t k = 0; k < 4; ++k) {
      const double lower = binomial_cdf(count[k], n, p[k]);
      const double upper = count[k] == 0 ? 1.0 : 1.0 - binomial_cdf(count[k] - 1, n, p[k]);
      EXPECT_GT(2.0 * std::min(lower, upper), 0.001) << "bin " << k + 1 << ": " << count[k] << " of " << n;
    }
  }
  {
    constexpr std::size_t n = 1000;
    const std::vector<std::vector<double>> u = latin_hypercube(n, 1, 7);
    std::vector<std::size_t> count(4, 0);
    for (const std::vector<double>& draw : u) ++count[static_cast<std::size_t>(law.quantile(draw[0])) - 1];
    for (std::size_t k = 0; k < 4; ++k)
      EXPECT_LE(std::abs(static_cast<double>(count[k]) - static_cast<double>(n) * p[k]), 2.0) << "bin " << k + 1;
  }
  // The edges: u = 0 is bin 1, u just below 1 the last bin.
  EXPECT_EQ(law.quantile(0.0), 1.0);
  EXPECT_EQ(law.quantile(0.1 - 1e-12), 1.0);
  EXPECT_EQ(law.quantile(0.1 + 1e-12), 2.0);
  EXPECT_EQ(law.quantile(std::nextafter(1.0, 0.0)), 4.0);
}

}  // namespace
}  // namespace gonio::design
