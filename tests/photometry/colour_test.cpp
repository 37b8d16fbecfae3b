#include "photometry/colour.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "tests/support/test_support.h"

namespace gonio::photometry {
namespace {

namespace fs = std::filesystem;

const fs::path kColord = "/usr/share/colord";

// A colord CGATS spectrum (.sp: SPECTRAL_START_NM, SPECTRAL_END_NM,
// SPECTRAL_BANDS, then one data row), read in place.
std::optional<SampledSpectrum> read_colord_sp(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const auto number_after = [&text](const std::string& key) {
    const std::size_t at = text.find(key);
    return at == std::string::npos ? std::nan("") : std::stod(text.substr(at + key.size()));
  };
  const double first = number_after("SPECTRAL_START_NM"), last = number_after("SPECTRAL_END_NM");
  const double bands = number_after("SPECTRAL_BANDS");
  const std::size_t begin = text.find("BEGIN_DATA\n");
  if (begin == std::string::npos || !(bands >= 2)) return std::nullopt;
  std::istringstream data(text.substr(begin + 11));
  SampledSpectrum s;
  const auto n = static_cast<int>(bands);
  for (int i = 0; i < n; ++i) {
    double v = 0.0;
    if (!(data >> v)) return std::nullopt;
    s.wavelengths_nm.push_back(first + (last - first) * i / (n - 1));
    s.values.push_back(v);
  }
  return s;
}

// Two columns, wavelength [nm] and value, as the corpus' LED spectra are.
std::optional<SampledSpectrum> read_two_columns(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  SampledSpectrum s;
  double w = 0.0, v = 0.0;
  while (in >> w >> v) {
    s.wavelengths_nm.push_back(w);
    s.values.push_back(v);
  }
  return s;
}

#define GONIO_COLORD_SPECTRUM(var, name)                                                  \
  const std::optional<SampledSpectrum> var = read_colord_sp(kColord / "illuminant" / (name));    \
  if (!var) GONIO_MISSING("colord-data's " + std::string(name) + " under " + kColord.string())

// CIE 15:2004 Table T.3 / ISO 11664-2: illuminant A, x = 0.44758,
// y = 0.40745, X = 109.85, Z = 35.58 (Y = 100), CCT 2856 K; read in place
// from colord-data's 1 nm table.
TEST(Colour, IlluminantAMatchesCie15) {
  GONIO_COLORD_SPECTRUM(a, "CIE-A.sp");
  const Tristimulus t = tristimulus(*a);
  const Chromaticity c = chromaticity(t);
  EXPECT_NEAR(c.x, 0.44758, 5e-5);
  EXPECT_NEAR(c.y, 0.40745, 5e-5);
  EXPECT_NEAR(100.0 * t.X / t.Y, 109.85, 0.01);
  EXPECT_NEAR(100.0 * t.Z / t.Y, 35.58, 0.01);
  const CctDuv cd = cct_duv(t);
  EXPECT_NEAR(cd.cct_k, 2856.0, 1.0);
  EXPECT_NEAR(cd.duv, 0.0, 1e-4);  // a Planckian radiator (c₂ = 1.435e-2 at 2848 K)
}

// CIE 15:2004: D65 x = 0.31272, y = 0.32903, X = 95.04, Z = 108.88;
// CCT about 6504 K, above the locus (Duv ≈ +0.0032).
TEST(Colour, IlluminantD65MatchesCie15) {
  GONIO_COLORD_SPECTRUM(d65, "CIE-D65.sp");
  const Tristimulus t = tristimulus(*d65);
  const Chromaticity c = chromaticity(t);
  EXPECT_NEAR(c.x, 0.31272, 5e-5);
  EXPECT_NEAR(c.y, 0.32903, 5e-5);
  EXPECT_NEAR(100.0 * t.X / t.Y, 95.04, 0.01);
  EXPECT_NEAR(100.0 * t.Z / t.Y, 108.88, 0.02);  // 108.897 from colord's 5 nm table
  const CctDuv cd = cct_duv(t);
  EXPECT_NEAR(cd.cct_k, 6504.0, 2.0);
  EXPECT_NEAR(cd.duv, 0.0032, 1e-4);
}

// colour-science's documented example of Ohno's method (colour 0.4,
// colour.temperature.uv_to_CCT_Ohno2013 with the CIE 1931 2° observer at
// 1 nm): CIE 1960 (u, v) = (0.1978, 0.3122) → 6507.47 K, Duv 0.0032233.
// A different CMF sampling (5 nm here) moves it by a fraction of a kelvin.
TEST(Colour, OhnoAgreesWithColourSciencesExample) {
  const CctDuv cd = cct_duv(UvPrime{0.1978, 0.3122 * 1.5});
  EXPECT_NEAR(cd.cct_k, 6507.47, 1.0);
  EXPECT_NEAR(cd.duv, 0.0032233, 2e-6);
}

// A blackbody keeps its CCT and Duv 0 over the whole range, and points set
// off the locus along its normal by ±Duv come back (triangular branch for
// |Duv| < 0.002, parabolic beyond).
TEST(Colour, BlackbodyKeepsItsCctAndOffsetsComeBack) {
  for (double t_k : {1200.0, 1850.0, 2700.0, 4000.0, 6500.0, 10000.0, 25000.0, 100000.0}) {
    const CctDuv cd = cct_duv(tristimulus(blackbody_spectrum(t_k)));
    EXPECT_NEAR(cd.cct_k / t_k, 1.0, 1e-5) << t_k;
    EXPECT_NEAR(cd.duv, 0.0, 1e-6) << t_k;
    // The locus' unit tangent in CIE 1960 (u, v), and its normal to the upper side.
    const UvPrime a = planckian_uv_prime(t_k * 0.9999), b = planckian_uv_prime(t_k * 1.0001);
    const double du = b.u_prime - a.u_prime, dv = (b.v_prime - a.v_prime) * (2.0 / 3.0);
    const double len = std::hypot(du, dv);
    const UvPrime o = planckian_uv_prime(t_k);
    for (double duv : {-0.03, -0.01, -0.001, 0.001, 0.01, 0.03}) {
      const double nu = -dv / len, nv = du / len;  // rotate the tangent by +90°
      const double sign = nv > 0.0 ? 1.0 : -1.0;   // "above" is larger v
      const UvPrime p{o.u_prime + sign * duv * nu, o.v_prime + 1.5 * sign * duv * nv};
      const CctDuv back = cct_duv(p);
      EXPECT_NEAR(back.cct_k / t_k, 1.0, std::abs(duv) > 0.002 ? 2e-4 : 2e-5) << t_k << " " << duv;
      EXPECT_NEAR(back.duv, duv, 2e-6) << t_k << " " << duv;
    }
  }
}

// A value another tool published: the Lighting Toolbox's documentation of
// cieuv2cct (frudawski.de/cieuv2cct, CIE 15:2018) gives CIE 1960 (u, v) =
// (0.2308, 0.2825) as 7519.3 K by its 'exact' method (7513 K by Robertson's).
// Ohno's combined method is within 1 K of exact (LEUKOS 10:47, 2014); this
// point lies 0.041 below the locus, where the parabolic solution holds.
// Mistakes it catches: the locus searched in (u′, v′) instead of (u′, 2/3 v′)
// (put in and seen to fail, 2026-12-07), Robertson's isotemperature lines in
// place of the nearest Planckian point (6 K off).
TEST(Colour, CctOfAPointAnotherToolPublished) {
  const CctDuv r = cct_duv(UvPrime{0.2308, 1.5 * 0.2825});
  EXPECT_NEAR(r.cct_k, 7519.3, 0.5);
  EXPECT_LT(r.duv, -0.03);
}

// Issue 45, case 12: between |Duv| 0.002 and 0.02 Ohno's combined method
// takes the parabolic solution (Ohno 2014, LEUKOS 10(1):47–55, section on
// the combined method): the triangular one, exact on the locus, drifts
// with |Duv|. No worked value of Ohno's at |Duv| ≈ 0.01 was found to test
// against (the search found the paper's abstract and colour-science's
// example at Duv 0.0032, tested above, but no table of chromaticities with
// their CCT and Duv), so the reference is the definition itself: the
// temperature whose Planckian (u, v) lies nearest, found here by a golden-
// section search on planckian_uv_prime, independent of the method's table
// and interpolation. Measured at Duv ±0.01: the parabolic solution is
// within 0.009 K of it at 2700 K to 10000 K; the triangular solution (the
// threshold taken as 0.02) is 0.04 K off at 2700 K, 0.17 K at 6500 K and
// 0.22 K at 10000 K.
TEST(Colour, CctBetweenDuv0002And002IsTheNearestPlanckianPointByTheParabolicSolution) {
  const auto uv1960 = [](double t_k) {
    const UvPrime p = planckian_uv_prime(t_k);
    return std::pair{p.u_prime, p.v_prime * (2.0 / 3.0)};
  };
  for (double t_k : {2700.0, 4000.0, 6500.0, 10000.0}) {
    const auto [au, av] = uv1960(t_k * 0.9999);
    const auto [bu, bv] = uv1960(t_k * 1.0001);
    const auto [ou, ov] = uv1960(t_k);
    const double len = std::hypot(bu - au, bv - av);
    const double nu = -(bv - av) / len, nv = (bu - au) / len, up = nv > 0.0 ? 1.0 : -1.0;
    for (double duv : {-0.01, 0.01}) {
      const double pu = ou + up * duv * nu, pv = ov + up * duv * nv;
      const auto distance = [&](double t) {
        const auto [qu, qv] = uv1960(t);
        return std::hypot(pu - qu, pv - qv);
      };
      double lo = 0.97 * t_k, hi = 1.03 * t_k;
      for (int i = 0; i < 200; ++i) {
        const double m1 = hi - 0.6180339887498949 * (hi - lo), m2 = lo + 0.6180339887498949 * (hi - lo);
        if (distance(m1) < distance(m2)) {
          hi = m2;
        } else {
          lo = m1;
        }
      }
      const double nearest = 0.5 * (lo + hi);
      const CctDuv cd = cct_duv(UvPrime{pu, pv * 1.5});
      EXPECT_NEAR(cd.cct_k, nearest, 0.03) << t_k << " K, Duv " << duv;
      EXPECT_NEAR(cd.duv, duv, 2e-6) << t_k << " K, Duv " << duv;
    }
  }
}

TEST(Colour, ConversionsAgree) {
  const Chromaticity c{0.31272, 0.32903};
  const UvPrime uv = uv_prime(c);
  EXPECT_NEAR(uv.u_prime, 0.19783, 1e-5);  // CIE 15: D65 u′ = 0.1978, v′ = 0.4683
  EXPECT_NEAR(uv.v_prime, 0.46834, 1e-5);
  const Chromaticity back = chromaticity(uv);
  EXPECT_NEAR(back.x, c.x, 1e-12);
  EXPECT_NEAR(back.y, c.y, 1e-12);
  EXPECT_TRUE(std::isnan(cct_duv(Tristimulus{}).cct_k));
  EXPECT_TRUE(std::isnan(cct_duv(UvPrime{0.6, 0.5}).cct_k));  // far red, beyond 1000 K
  // The table is colord's, unchanged: ȳ(555 nm) = 1, and illuminant E sits
  // at x = y = 1/3 (to the 5 nm summation's precision).
  EXPECT_DOUBLE_EQ(cie1931_cmf(555.0).y_bar, 1.0);
  EXPECT_DOUBLE_EQ(cie1931_cmf(557.5).y_bar, 0.5 * (1.0 + 0.995));
  const Chromaticity e = chromaticity(tristimulus(SampledSpectrum{{360.0, 830.0}, {1.0, 1.0}}));
  EXPECT_NEAR(e.x, 1.0 / 3.0, 2e-4);
  EXPECT_NEAR(e.y, 1.0 / 3.0, 2e-4);
}

// The corpus' measured spectra of the white chip of an OSRAM LERTDUW S2WP
// (bin BQ), read in place: OSRAM gives them in two parts, the blue chip's
// emission (393–510 nm) and the phosphor's (510–810 nm), each scaled on its
// own. The blue part alone is deep blue, the phosphor's yellow, and some
// mixture of the two crosses the Planckian locus at a white CCT.
TEST(Colour, CorpusWhiteLedPartsMixToWhite) {
  GONIO_REQUIRE_CORPUS();
  const fs::path dir = test::corpus_dir() / "spectra";
  const auto blue = read_two_columns(dir / "LERTDUW_S2WP_binBQ_white-blue_20110706_spectrum.txt");
  const auto yellow = read_two_columns(dir / "LERTDUW_S2WP_binBQ_white-yellow_20110706_spectrum.txt");
  ASSERT_TRUE(blue && yellow);
  ASSERT_TRUE(validate_spectrum(*blue).ok());
  ASSERT_TRUE(validate_spectrum(*yellow).ok());
  const Tristimulus b = tristimulus(*blue), y = tristimulus(*yellow);
  EXPECT_LT(chromaticity(b).x, 0.2);
  EXPECT_LT(chromaticity(b).y, 0.2);
  EXPECT_GT(chromaticity(y).x, 0.4);
  EXPECT_GT(chromaticity(y).y, 0.5);
  double best_duv = 1.0, best_cct = 0.0, best_w = 0.0;
  for (double w = 0.0; w <= 1.0; w += 0.001) {  // blue's share of the mixture's Y
    const Tristimulus m{w * b.X / b.Y + (1 - w) * y.X / y.Y, 1.0, w * b.Z / b.Y + (1 - w) * y.Z / y.Y};
    const CctDuv cd = cct_duv(m);
    if (std::isfinite(cd.duv) && std::abs(cd.duv) < std::abs(best_duv)) best_duv = cd.duv, best_cct = cd.cct_k, best_w = w;
  }
  EXPECT_LT(std::abs(best_duv), 0.002);
  EXPECT_GT(best_cct, 3000.0);
  EXPECT_LT(best_cct, 8000.0);
  std::printf("on the locus at a blue share of Y of %.3f: %.0f K (Duv %.4f)\n", best_w, best_cct, best_duv);
}

}  // namespace
}  // namespace gonio::photometry
