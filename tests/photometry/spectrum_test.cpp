#include "photometry/spectrum.h"

#include <cmath>

#include <gtest/gtest.h>

namespace gonio::photometry {
namespace {

TEST(SampledSpectrum, InterpolatesLinearlyAndIsZeroOutside) {
  const SampledSpectrum s{{400.0, 500.0, 600.0}, {1.0, 3.0, 2.0}};
  EXPECT_DOUBLE_EQ(s.at(400.0), 1.0);
  EXPECT_DOUBLE_EQ(s.at(450.0), 2.0);
  EXPECT_DOUBLE_EQ(s.at(500.0), 3.0);
  EXPECT_DOUBLE_EQ(s.at(575.0), 2.25);
  EXPECT_DOUBLE_EQ(s.at(600.0), 2.0);
  EXPECT_EQ(s.at(399.9), 0.0);
  EXPECT_EQ(s.at(600.1), 0.0);
  EXPECT_EQ(s.at(std::nan("")), 0.0);
}

TEST(SampledSpectrum, ValidationNamesTheSample) {
  EXPECT_TRUE(validate_spectrum({{400.0, 500.0}, {1.0, 0.0}}).ok());
  const auto message = [](const SampledSpectrum& s, double max = 1e300) {
    const Status st = validate_spectrum(s, max);
    return st.ok() ? std::string("ok") : st.error().message;
  };
  EXPECT_EQ(message({{400.0, 500.0}, {1.0}}), "2 wavelengths but 1 values");
  EXPECT_EQ(message({{400.0}, {1.0}}), "a spectrum needs at least two samples");
  EXPECT_EQ(message({{400.0, 400.0}, {1.0, 1.0}}), "wavelength 1 (400 nm) does not increase");
  EXPECT_EQ(message({{-1.0, 400.0}, {1.0, 1.0}}), "wavelength 0 (-1 nm) must be finite and in (0, 100000) nm");
  EXPECT_EQ(message({{400.0, 500.0}, {1.0, -0.5}}), "value 1 (-0.5) must be finite and >= 0");
  EXPECT_EQ(message({{400.0, 500.0}, {1.0, std::nan("")}}), "value 1 (nan) must be finite and >= 0");
  EXPECT_EQ(message({{400.0, 500.0}, {0.0, 0.0}}), "every value of the spectrum is 0");
  EXPECT_EQ(message({{400.0, 500.0}, {0.5, 1.2}}, 1.0), "value 1 (1.2) exceeds 1");
}

TEST(SampledSpectrum, ProductSamplesBothGridsOverTheCommonRange) {
  const SampledSpectrum a{{400.0, 600.0}, {1.0, 3.0}};
  const SampledSpectrum b{{450.0, 500.0, 700.0}, {0.5, 1.0, 1.0}};
  const SampledSpectrum p = product(a, b);
  ASSERT_EQ(p.wavelengths_nm, (std::vector<double>{450.0, 500.0, 600.0}));
  EXPECT_DOUBLE_EQ(p.values[0], 1.5 * 0.5);
  EXPECT_DOUBLE_EQ(p.values[1], 2.0 * 1.0);
  EXPECT_DOUBLE_EQ(p.values[2], 3.0 * 1.0);
}

// Planck's law against two constants published independently of c₁ and c₂
// as this code spells them: Wien's displacement constant (CODATA 2018,
// b = 2.897771955e-3 m·K) and Stefan–Boltzmann's (σ = 5.670374419e-8
// W·m⁻²·K⁻⁴): π ∫ L dλ = σT⁴.
TEST(Planck, PeaksWhereWienSaysAndIntegratesToStefanBoltzmann) {
  for (double t_k : {2856.0, 5000.0}) {
    double best_nm = 0.0, best = 0.0;
    for (double nm = 300.0; nm <= 2000.0; nm += 0.001) {
      const double l = planck_radiance(nm, t_k);
      if (l > best) best = l, best_nm = nm;
    }
    EXPECT_NEAR(best_nm * 1e-9 * t_k, 2.897771955e-3, 2.897771955e-3 * 5e-5) << t_k;
    double integral = 0.0;  // W/(m² sr): trapezoid in λ up to 100 µm
    const double step_nm = 0.5;
    for (double nm = 50.0; nm < 100000.0; nm += step_nm)
      integral += 0.5 * (planck_radiance(nm, t_k) + planck_radiance(nm + step_nm, t_k)) * step_nm * 1e-9;
    EXPECT_NEAR(M_PI * integral / (5.670374419e-8 * std::pow(t_k, 4)), 1.0, 2e-4) << t_k;
  }
  EXPECT_EQ(planck_radiance(500.0, 0.0), 0.0);
  const SampledSpectrum bb = blackbody_spectrum(3000.0, 380.0, 780.0, 5.0);
  ASSERT_EQ(bb.wavelengths_nm.size(), 81u);
  EXPECT_DOUBLE_EQ(bb.values.back(), 1.0);  // 3000 K still rises at 780 nm
}

}  // namespace
}  // namespace gonio::photometry
