#include "photometry/resample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <initializer_list>
#include <numbers>

#include "photometry/angles.h"
#include "photometry/flux.h"
#include "photometry/frame.h"
#include "tests/support/photometry_fixtures.h"

namespace gonio::photometry {
namespace {

using test::angles;
using test::cos_lobe;
using test::sample_c;
using test::sample_direction;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// A smooth asymmetric beam, tilted towards C30 and wider along C90.
double beam(const Vec3& d) {
  const Vec3 axis = normalize(Vec3{0.3 * std::cos(30 * kDeg), 0.3 * std::sin(30 * kDeg), -1.0});
  const double c = dot(normalize(d), axis);
  return c > 0 ? 800.0 * std::pow(c, 6) * (1.0 + 0.3 * d.y * d.y) : 0.0;
}

TEST(Resample, TypeCOnAFinerGridComesBackUnchanged) {
  const Distribution d = sample_c(Symmetry::None, angles(0, 360, 2.5), angles(0, 180, 1.25),
                                  [](double c, double g) { return 100 + c + g * g / 100; });
  TypeCGrid grid;
  grid.c_step_deg = 5;
  grid.gamma_step_deg = 2.5;
  const Result<Distribution> r = to_type_c(d, grid);
  ASSERT_TRUE(r.ok()) << r.error().message;
  ASSERT_EQ(r->horizontal_count(), 73u);
  ASSERT_EQ(r->vertical_count(), 73u);
  for (std::size_t h = 0; h + 1 < r->horizontal_count(); ++h)
    for (std::size_t v = 1; v + 1 < r->vertical_count(); ++v)
      EXPECT_DOUBLE_EQ(r->at(h, v),
                       100 + r->horizontal_deg[h] + std::pow(r->vertical_deg[v], 2) / 100);
  EXPECT_EQ(r->type, PhotometricType::C);
  EXPECT_EQ(r->lamps.size(), 1u);  // metadata is carried over
}

// The mean of f over the C-cell [c − step/2, c + step/2] at γ [deg], by a
// 256-point midpoint rule: what to_type_c() gives for Types A and B.
double c_cell_mean(const std::function<double(const Vec3&)>& f, double c_deg, double gamma_deg,
                   double c_step_deg) {
  constexpr int kN = 256;
  double sum = 0;
  for (int k = 0; k < kN; ++k) {
    const double c = c_deg + c_step_deg * ((k + 0.5) / kN - 0.5);
    sum += f(direction_from_c_gamma(c * kDeg, gamma_deg * kDeg));
  }
  return sum / kN;
}

TEST(Resample, TypeBOfAKnownFunctionMapsBack) {
  // Type B samples of beam(direction), resampled to Type C, equal the mean of
  // beam() over each C-cell to within the error of the B grid's Hermite
  // model, which falls at least as h² with its step.
  double previous = 0;
  for (double step : {2.0, 1.0, 0.5}) {
    const Distribution b = sample_direction(PhotometricType::B, Symmetry::None,
                                            angles(-90, 90, step), angles(-90, 90, step), beam);
    const Result<Distribution> c = to_type_c(b);
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->symmetry, Symmetry::None);
    EXPECT_DOUBLE_EQ(c->horizontal_deg.back(), 360.0);
    EXPECT_DOUBLE_EQ(c->vertical_deg.back(), 90.0);  // Type B lies below the horizon
    double worst = 0;
    for (std::size_t h = 0; h < c->horizontal_count(); ++h)
      for (std::size_t v = 0; v < c->vertical_count(); ++v)
        worst = std::max(worst, std::abs(c->at(h, v) - c_cell_mean(beam, c->horizontal_deg[h],
                                                                   c->vertical_deg[v], 5.0)));
    EXPECT_LT(worst, 0.01 * 800 * step * step) << step;
    if (previous > 0) {
      EXPECT_GT(previous / worst, 3.0) << step;
    }
    previous = worst;
  }
}

TEST(Resample, FluxIsKeptWithinTheQuadratureError) {
  for (double n : {2.0, 10.0}) {
    const Distribution b =
        sample_direction(PhotometricType::B, Symmetry::Lateral, angles(0, 90, 2.5),
                         angles(-90, 90, 2.5), cos_lobe(1000, n));
    const Result<Distribution> c = to_type_c(b);
    ASSERT_TRUE(c.ok());
    EXPECT_EQ(c->symmetry, Symmetry::C0_C180);  // lateral symmetry is the C0-C180 mirror
    const double before = total_flux_lm(b), after = total_flux_lm(*c),
                 exact = 2 * kPi * 1000 / (n + 1);
    EXPECT_LT(std::abs(before / exact - 1), 1e-5);
    // 0.05 % (a bilinear model of the 2.5° B grid cost ~0.1 % for n = 10).
    EXPECT_LT(std::abs(after / before - 1), 5e-4) << n;
  }
  const Distribution asym = sample_direction(PhotometricType::B, Symmetry::None, angles(-90, 90, 1),
                                             angles(-90, 90, 1), beam);
  const Result<Distribution> c = to_type_c(asym, {2.5, 1.25, std::nullopt});
  ASSERT_TRUE(c.ok());
  EXPECT_LT(std::abs(total_flux_lm(*c) / total_flux_lm(asym) - 1), 5e-4);
}

TEST(Resample, TypeAIsTypeCRelabelledAndAveragedOverC) {
  // Type A is Type C relabelled (C = −H, γ = V + 90): on grids that line up,
  // each value is the mean over its C-cell, which for this f has a closed
  // form: cos C and sin C average to sinc(Δc/2) times their centre value.
  auto f = [](const Vec3& d) { return 50 + 20 * d.x + 5 * d.y * d.z; };
  const Distribution a = sample_direction(PhotometricType::A, Symmetry::None, angles(-90, 90, 5),
                                          angles(-90, 90, 2.5), f);
  const Result<Distribution> c = to_type_c(a);
  ASSERT_TRUE(c.ok());
  ASSERT_DOUBLE_EQ(c->vertical_deg.front(), 0.0);
  ASSERT_DOUBLE_EQ(c->vertical_deg.back(), 180.0);
  const double half = 2.5 * kDeg, sinc = std::sin(half) / half;
  double worst = 0;
  for (std::size_t h = 0; h < c->horizontal_count(); ++h) {
    const double cc = c->horizontal_deg[h];
    if (cc >= 90 && cc <= 270) continue;  // cells at or behind the edge of Type A's x >= 0
    for (std::size_t v = 1; v + 1 < c->vertical_count(); ++v) {
      const double g = c->vertical_deg[v] * kDeg;
      const double expected = 50 + sinc * (20 * std::sin(g) * std::cos(cc * kDeg) -
                                           5 * std::sin(g) * std::cos(g) * std::sin(cc * kDeg));
      worst = std::max(worst, std::abs(c->at(h, v) - expected));
    }
  }
  // The source's Hermite model with three-point slopes errs by O(h³ I‴):
  // 20 cd × (5° in rad)³ = 1.3e-2 cd bounds it; measured 2e-3.
  EXPECT_LT(worst, 5e-3);
}

TEST(Resample, LambertianTypeBBecomesCosGamma) {
  // I = I₀ cos H cos V is I₀ cos γ: independent of C, so the C-cell mean is
  // the value itself, and the Hermite model of the B grid carries it to
  // O(h³) (measured 5e-6 I₀; a bilinear model errs by up to
  // 1 − cos(h/2) = 2.4e-4 between the nodes).
  const double i0 = 1000;
  const Distribution b = sample_direction(PhotometricType::B, Symmetry::Lateral, angles(0, 90, 2.5),
                                          angles(-90, 90, 2.5),
                                          [&](const Vec3& d) { return std::max(0.0, -i0 * d.z); });
  for (const TypeCGrid& grid :
       {TypeCGrid{}, TypeCGrid{2.5, 0.5, std::nullopt}, TypeCGrid{15, 5, Symmetry::None}}) {
    const Result<Distribution> c = to_type_c(b, grid);
    ASSERT_TRUE(c.ok());
    double worst = 0;
    for (std::size_t h = 0; h < c->horizontal_count(); ++h)
      for (std::size_t v = 0; v < c->vertical_count(); ++v)
        worst = std::max(worst, std::abs(c->at(h, v) - i0 * std::cos(c->vertical_deg[v] * kDeg)));
    EXPECT_LT(worst, 1e-5 * i0) << grid.c_step_deg << " x " << grid.gamma_step_deg;
    EXPECT_LT(std::abs(total_flux_lm(*c) / (kPi * i0) - 1), 1e-5);
  }
}

// I₀ (cos H cos V)^20 on a 2.5° Type B grid: a 30° floodlight of ~29,920 lm,
// whose bilinear resampling onto 5° × 1° Type C gained 0.41 %.
Distribution floodlight_b() {
  const std::vector<double> hv = angles(-90, 90, 2.5);
  return sample_direction(PhotometricType::B, Symmetry::None, hv, hv, [](const Vec3& v) {
    const HV a = type_b_from_direction(v);
    return 1e5 * std::pow(std::cos(a.h_rad) * std::cos(a.v_rad), 20);
  });
}

// to_type_c(source, grid) keeps the source's flux within 0.05 % on each grid.
void expect_flux_kept(const Distribution& source, std::initializer_list<TypeCGrid> grids) {
  const double before = total_flux_lm(source);
  for (const TypeCGrid& grid : grids) {
    const Result<Distribution> c = to_type_c(source, grid);
    ASSERT_TRUE(c.ok());
    EXPECT_LT(std::abs(total_flux_lm(*c) / before - 1), 5e-4)
        << grid.c_step_deg << " x " << grid.gamma_step_deg;
  }
}

TEST(Resample, FloodlightKeepsItsFluxOnEveryGrid) {
  const Distribution b = floodlight_b();
  const double before = total_flux_lm(b), exact = 2 * kPi * 1e5 / 21;
  ASSERT_LT(std::abs(before / exact - 1), 1e-4);
  expect_flux_kept(b, {TypeCGrid{}, TypeCGrid{2.5, 0.5, std::nullopt},
                       TypeCGrid{10, 2.5, std::nullopt}, TypeCGrid{15, 5, Symmetry::None},
                       TypeCGrid{5, 1, Symmetry::Rotational}, TypeCGrid{5, 1, Symmetry::Quadrant}});
  // A narrower beam (cos^80, 15°) aimed 40° off the nadir towards C0: C-cells
  // of 10° at γ 40° span 6.4°, so point samples on the planes would miss its
  // shape between them; cell means keep the flux.
  const Vec3 axis{std::sin(40 * kDeg), 0, -std::cos(40 * kDeg)};
  const Distribution aimed = sample_direction(
      PhotometricType::B, Symmetry::Lateral, angles(0, 90, 1), angles(-90, 90, 1),
      [&](const Vec3& d) { return 1e5 * std::pow(std::max(0.0, dot(d, axis)), 80); });
  const double aimed_flux = total_flux_lm(aimed);
  ASSERT_LT(std::abs(aimed_flux / (2 * kPi * 1e5 / 81) - 1), 1e-3);
  expect_flux_kept(aimed, {TypeCGrid{}, TypeCGrid{10, 0.5, std::nullopt}});
}

TEST(Resample, TypeAFloodlightKeepsItsFlux) {
  // Type A's beam axis is the horizontal +x (C0, γ 90°), where the C-cells
  // are widest.
  const Distribution a = sample_direction(
      PhotometricType::A, Symmetry::Lateral, angles(0, 90, 2.5), angles(-90, 90, 2.5),
      [](const Vec3& d) { return 1e4 * std::pow(std::max(0.0, d.x), 20); });
  const double before = total_flux_lm(a);
  ASSERT_LT(std::abs(before / (2 * kPi * 1e4 / 21) - 1), 1e-4);
  expect_flux_kept(a, {TypeCGrid{}, TypeCGrid{2.5, 0.5, std::nullopt}});
}

TEST(Resample, SymmetryOfTheOutput) {
  const Distribution d =
      sample_c(Symmetry::None, angles(0, 360, 5), angles(0, 90, 5),
               [](double c, double g) { return 10 + std::cos(c * kDeg) + g / 10; });
  TypeCGrid quadrant{10, 5, Symmetry::Quadrant};
  const Result<Distribution> q = to_type_c(d, quadrant);
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(q->horizontal_deg, angles(0, 90, 10));
  EXPECT_EQ(q->vertical_deg, angles(0, 90, 5));  // γ range of the data
  EXPECT_DOUBLE_EQ(q->at(3, 4), 10 + std::cos(30 * kDeg) + 2);
  const Result<Distribution> c90 = to_type_c(d, {10, 5, Symmetry::C90_C270});
  ASSERT_TRUE(c90.ok());
  EXPECT_EQ(c90->horizontal_deg, angles(90, 270, 10));
  // Rotational: the mean over C at each γ (cos C averages to 0).
  const Result<Distribution> rot = to_type_c(d, {5, 5, Symmetry::Rotational});
  ASSERT_TRUE(rot.ok());
  ASSERT_EQ(rot->horizontal_deg, std::vector<double>{0.0});
  for (std::size_t v = 0; v < rot->vertical_count(); ++v)
    EXPECT_NEAR(rot->at(0, v), 10 + rot->vertical_deg[v] / 10, 1e-12);
}

TEST(Resample, BadGridsAreErrorsNotCrashes) {
  const Distribution d =
      sample_c(Symmetry::Rotational, {0}, angles(0, 180, 5), [](double, double) { return 1.0; });
  const TypeCGrid bad[] = {
      {0, 2.5, {}}, {-5, 2.5, {}}, {5, 0, {}},         {5, kNaN, {}},
      {7, 2.5, {}}, {5, 4, {}},    {0.001, 0.001, {}}, {5, 2.5, Symmetry::Lateral}};
  for (const TypeCGrid& g : bad) {
    const Result<Distribution> r = to_type_c(d, g);
    ASSERT_FALSE(r.ok()) << g.c_step_deg << " " << g.gamma_step_deg;
    EXPECT_FALSE(r.error().message.empty());
  }
  EXPECT_NE(to_type_c(d, {7, 2.5, {}}).error().message.find("does not divide"), std::string::npos);
  EXPECT_NE(to_type_c(d, {0.001, 0.001, {}}).error().message.find("10^7"), std::string::npos);
}

}  // namespace
}  // namespace gonio::photometry
