#include "sim/detectors/symmetry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>
#include <string>

#include "photometry/frame.h"
#include "tests/sim/synthetic_far_field.h"

namespace gonio::sim {
namespace {

using photometry::PhotometricFrame;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

PhotometricFrame tilted_frame() { return photometry::make_frame({0.3, 1.0, 0.2}, {1.0, 0.1, -0.4}); }

// An intensity given in local (C, γ) [rad], seen in the world through a frame.
test::IntensityFn in_world(const PhotometricFrame& frame,
                           std::function<double(double c, double gamma)> local) {
  return [frame, local](const Vec3& d) {
    const auto cg = photometry::c_gamma_from_direction(frame.to_local(d));
    return local(cg.c_rad, cg.gamma_rad);
  };
}

TEST(Symmetry, ParsesTheCommandLineNames) {
  EXPECT_EQ(parse_symmetry("none"), Symmetry::None);
  EXPECT_EQ(parse_symmetry("C0-C180"), Symmetry::C0_C180);
  EXPECT_EQ(parse_symmetry("c90-c270"), Symmetry::C90_C270);
  EXPECT_EQ(parse_symmetry("Quadrant"), Symmetry::Quadrant);
  EXPECT_EQ(parse_symmetry("rotational"), Symmetry::Rotational);
  EXPECT_EQ(parse_symmetry("auto"), std::nullopt);
  EXPECT_EQ(parse_symmetry("lateral"), std::nullopt);
  EXPECT_EQ(parse_symmetry(""), std::nullopt);
  EXPECT_EQ(parse_symmetry("C0-C18"), std::nullopt);
}

TEST(Symmetry, GridSupportAndOrder) {
  const CGammaGrid g5;
  for (Symmetry s : {Symmetry::None, Symmetry::C0_C180, Symmetry::C90_C270, Symmetry::Quadrant,
                     Symmetry::Rotational})
    EXPECT_TRUE(grid_supports(g5, s)) << photometry::to_string(s);
  EXPECT_FALSE(grid_supports(g5, Symmetry::Lateral));
  const CGammaGrid g40{40.0, 10.0};  // 9 planes: no plane at 90° or 180°
  EXPECT_TRUE(grid_supports(g40, Symmetry::None));
  EXPECT_TRUE(grid_supports(g40, Symmetry::Rotational));
  EXPECT_FALSE(grid_supports(g40, Symmetry::C0_C180));
  EXPECT_FALSE(grid_supports(g40, Symmetry::Quadrant));
  const CGammaGrid g60{60.0, 10.0};  // planes at 0, 60, 120, 180, …: none at 90°
  EXPECT_TRUE(grid_supports(g60, Symmetry::C0_C180));
  EXPECT_FALSE(grid_supports(g60, Symmetry::C90_C270));
  EXPECT_TRUE(check_grid_supports(g5, Symmetry::Quadrant).ok());
  const Status no_quadrant = check_grid_supports(g40, Symmetry::Quadrant);
  ASSERT_FALSE(no_quadrant.ok());
  EXPECT_EQ(no_quadrant.error().message, "symmetry quadrant needs a C step dividing 90°, not 40°");
  EXPECT_EQ(check_grid_supports(g40, Symmetry::C0_C180).error().message,
            "symmetry C0-C180 needs a C step dividing 180°, not 40°");
  EXPECT_FALSE(check_grid_supports(g5, Symmetry::Lateral).ok());
  EXPECT_EQ(symmetry_order(g5, Symmetry::None), 1);
  EXPECT_EQ(symmetry_order(g5, Symmetry::C0_C180), 2);
  EXPECT_EQ(symmetry_order(g5, Symmetry::C90_C270), 2);
  EXPECT_EQ(symmetry_order(g5, Symmetry::Quadrant), 4);
  EXPECT_EQ(symmetry_order(g5, Symmetry::Rotational), 72);
}

TEST(Symmetry, EquivalentBinsPartitionTheGridIntoMirrorImages) {
  const CGammaGrid g{30.0, 30.0};  // planes 0, 30, …, 330
  const int j = 3;                 // γ = 90°
  const auto group_of = [&](Symmetry s, int c_deg) {
    for (const auto& group : equivalent_bins(g, s)) {
      if (std::find(group.begin(), group.end(), g.bin(c_deg / 30, j)) == group.end()) continue;
      std::set<int> planes;
      for (std::size_t b : group) planes.insert(static_cast<int>((b - 2) % 12) * 30);
      return planes;
    }
    return std::set<int>{};
  };
  EXPECT_EQ(group_of(Symmetry::None, 30), (std::set<int>{30}));
  EXPECT_EQ(group_of(Symmetry::C0_C180, 30), (std::set<int>{30, 330}));
  EXPECT_EQ(group_of(Symmetry::C0_C180, 0), (std::set<int>{0}));
  EXPECT_EQ(group_of(Symmetry::C0_C180, 180), (std::set<int>{180}));
  EXPECT_EQ(group_of(Symmetry::C90_C270, 30), (std::set<int>{30, 150}));
  EXPECT_EQ(group_of(Symmetry::C90_C270, 90), (std::set<int>{90}));
  EXPECT_EQ(group_of(Symmetry::C90_C270, 0), (std::set<int>{0, 180}));
  EXPECT_EQ(group_of(Symmetry::Quadrant, 30), (std::set<int>{30, 150, 210, 330}));
  EXPECT_EQ(group_of(Symmetry::Quadrant, 90), (std::set<int>{90, 270}));
  EXPECT_EQ(group_of(Symmetry::Rotational, 60).size(), 12u);
  for (Symmetry s : {Symmetry::None, Symmetry::C0_C180, Symmetry::C90_C270, Symmetry::Quadrant,
                     Symmetry::Rotational}) {
    std::vector<int> seen(g.bin_count(), 0);
    for (const auto& group : equivalent_bins(g, s))
      for (std::size_t b : group) ++seen[b];
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }))
        << photometry::to_string(s);
  }
}

TEST(Symmetry, AveragingConservesFlux) {
  const CGammaGrid g{10.0, 5.0};
  const int face = face_size_for(g);
  const FarField field = test::sample_far_field(
      face, in_world(tilted_frame(), [](double c, double gamma) {
        return 1.0 + 0.8 * std::cos(c - 0.5) * std::sin(gamma);
      }), 1.8, 200'000, 1000.0, 1);
  const BinnedField b = Resampler(face, tilted_frame(), g).bin(field);
  for (Symmetry s : {Symmetry::None, Symmetry::C0_C180, Symmetry::C90_C270, Symmetry::Quadrant,
                     Symmetry::Rotational}) {
    const std::vector<double> intensity = symmetric_intensity_cd(b, s);
    double flux = 0.0;
    for (std::size_t k = 0; k < g.bin_count(); ++k) flux += intensity[k] * b.solid_angle_sr[k];
    EXPECT_NEAR(flux, 1000.0, 1e-9) << photometry::to_string(s);
  }
}

// Photons from an isotropic source: every bin's expected intensity is Φ/4π
// exactly. Over many bins and runs, the mean squared error of the averaged
// intensities is the plain one divided by the symmetry's order, for bins
// whose equivalent bins share no texels (off the mirror planes, away from
// the poles).
TEST(Symmetry, AveragingDividesTheVarianceByTheOrder) {
  const CGammaGrid g{10.0, 10.0};
  const int face = 128;
  const Resampler r(face, PhotometricFrame{}, g);
  const double flux = 1000.0, expected = flux / (4.0 * kPi);
  const int runs = 16;
  std::vector<Symmetry> symmetries = {Symmetry::C0_C180, Symmetry::C90_C270, Symmetry::Quadrant,
                                      Symmetry::Rotational};
  std::vector<double> plain(symmetries.size(), 0.0), averaged(symmetries.size(), 0.0);
  for (int run = 0; run < runs; ++run) {
    const FarField field = test::sample_far_field(
        face, [](const Vec3&) { return 1.0; }, 1.0, 300'000, flux, 100 + run);
    const BinnedField b = r.bin(field);
    for (std::size_t s = 0; s < symmetries.size(); ++s) {
      const std::vector<double> avg = symmetric_intensity_cd(b, symmetries[s]);
      for (int j = 4; j <= 14; ++j) {      // γ 40°…140°
        for (int i = 0; i < g.c_count(); ++i) {
          if (i % 9 == 0) continue;        // planes 0, 90, 180, 270: on a mirror
          const std::size_t k = g.bin(i, j);
          const double e_plain = b.intensity_cd(k) - expected, e_avg = avg[k] - expected;
          plain[s] += e_plain * e_plain;
          averaged[s] += e_avg * e_avg;
        }
      }
    }
  }
  for (std::size_t s = 0; s < symmetries.size(); ++s) {
    const double order = symmetry_order(g, symmetries[s]);
    const double factor = plain[s] / averaged[s];
    // Statistical spread of the estimate: about √(2·order / samples) of the
    // averaged sum (≤ 9 % for rotational with 16 runs × 11 rings); the
    // rotational factor also loses ~5 % to texels shared by neighbouring
    // C-bins of one ring.
    const double tolerance = symmetries[s] == Symmetry::Rotational ? 0.3 : 0.15;
    EXPECT_NEAR(factor / order, 1.0, tolerance)
        << photometry::to_string(symmetries[s]) << ": variance factor " << factor;
  }
}

struct Sampled {
  const char* name;
  std::function<double(double, double)> intensity;  // local (C, γ) [rad]
  double max_intensity;
  Symmetry expected;
  std::uint64_t photons = 300'000;
};

std::vector<Sampled> sampled_cases() {
  return {
      {"rotational cos² lobe", [](double, double g) {
         return 0.2 + (g < kPi / 2 ? std::pow(std::cos(g), 2) : 0.0);
       }, 1.2, Symmetry::Rotational},
      {"quadrant (cos 2C)", [](double c, double g) {
         return 1.0 + 0.5 * std::cos(2.0 * c) * std::sin(g);
       }, 1.5, Symmetry::Quadrant},
      {"C0-C180 (cos C)", [](double c, double g) {
         return 1.0 + 0.5 * std::cos(c) * std::sin(g);
       }, 1.5, Symmetry::C0_C180},
      {"C90-C270 (sin C)", [](double c, double g) {
         return 1.0 + 0.5 * std::sin(c) * std::sin(g);
       }, 1.5, Symmetry::C90_C270},
      {"lobe at C 30°, γ 40°", [](double c, double g) {
         const Vec3 axis = photometry::direction_from_c_gamma(30.0 * kDeg, 40.0 * kDeg);
         return 0.3 + std::pow(std::max(0.0, dot(photometry::direction_from_c_gamma(c, g), axis)), 8);
       }, 1.3, Symmetry::None},
      {"weak asymmetry (12 % cos(C − 30°))", [](double c, double g) {
         return 1.0 + 0.12 * std::cos(c - 30.0 * kDeg) * std::sin(g);
       }, 1.12, Symmetry::None, 800'000},
  };
}

TEST(Symmetry, AutoPicksTheSymmetryOfSampledMaps) {
  const CGammaGrid g;
  const int face = face_size_for(g);
  for (const PhotometricFrame& frame : {PhotometricFrame{}, tilted_frame()}) {
    const Resampler r(face, frame, g);
    std::uint64_t seed = 7;
    for (const Sampled& c : sampled_cases()) {
      const FarField field = test::sample_far_field(face, in_world(frame, c.intensity),
                                                    c.max_intensity, c.photons, 1000.0, ++seed);
      const SymmetryDecision d = detect_symmetry(r.bin(field));
      EXPECT_EQ(d.symmetry, c.expected) << c.name << ": " << d.explanation;
      EXPECT_NE(d.explanation.find(std::string("symmetry auto: ") +
                                   photometry::to_string(d.symmetry)),
                std::string::npos);
      EXPECT_EQ(d.tests.size(), 4u);
    }
  }
}

TEST(Symmetry, AutoOnExactMapsUsesTheTolerance) {
  // No photon counts: only the discretisation tolerance separates
  // symmetric from not. A rotational cos³ lobe in a tilted frame differs
  // from ring to ring only by the resampling's own error (< 0.1 %).
  const CGammaGrid g{10.0, 5.0};
  const int face = face_size_for(g);
  const PhotometricFrame frame = tilted_frame();
  const Resampler r(face, frame, g);
  const auto lobe = [](double, double gamma) {
    return 0.1 + (gamma < kPi / 2 ? std::pow(std::cos(gamma), 3) : 0.0);
  };
  const SymmetryDecision sym = detect_symmetry(r.bin(test::integrate_far_field(face, in_world(frame, lobe))));
  EXPECT_EQ(sym.symmetry, Symmetry::Rotational) << sym.explanation;
  // 2 % of C0-C180 asymmetry is far outside the 0.5 % tolerance.
  const auto tilted = [&](double c, double gamma) { return lobe(c, gamma) * (1.0 + 0.02 * std::sin(c)); };
  const SymmetryDecision asym =
      detect_symmetry(r.bin(test::integrate_far_field(face, in_world(frame, tilted))));
  EXPECT_EQ(asym.symmetry, Symmetry::C90_C270) << asym.explanation;
}

TEST(Symmetry, AutoClaimsNothingWithoutData) {
  const CGammaGrid g{15.0, 15.0};
  const Resampler r(16, PhotometricFrame{}, g);
  const SymmetryDecision empty = detect_symmetry(r.bin(FarField(16)));
  EXPECT_EQ(empty.symmetry, Symmetry::None);
  EXPECT_NE(empty.explanation.find("no flux"), std::string::npos);
  // Ten photons: no group reaches the photon count the test needs.
  const FarField few = test::sample_far_field(16, [](const Vec3&) { return 1.0; }, 1.0, 10, 1.0, 3);
  const SymmetryDecision d = detect_symmetry(r.bin(few));
  EXPECT_EQ(d.symmetry, Symmetry::None) << d.explanation;
  EXPECT_NE(d.explanation.find("untestable"), std::string::npos) << d.explanation;
}

TEST(Symmetry, AutoDetectsAFivePercentAsymmetryOrStatesWhatItCouldMiss) {
  // A rotational cos² lobe 5 % brighter towards C0 and 5 % dimmer towards
  // C180: I(γ) · (1 + 0.05 cos C), an RMS deviation of 0.05/√2 = 3.5 % from
  // each ring's mean. It keeps C0-C180 only. At 10⁵ photons (19 per bin on
  // the 5° × 2.5° grid) the rotational test cannot see it, and the
  // explanation says so: it states a detectable deviation above 3.5 %. At
  // 8 · 10⁵ the stated figure falls by √8 to well under 3.5 %, and then the
  // test does reject rotational symmetry. (Measured with a 2.5 % amplitude,
  // an RMS deviation of 1.77 %, over 10 seeds: rejected 2 times in 10 where
  // the statement said 2.2 %, 8 times where it said 1.5 %.)
  const CGammaGrid g;
  const int face = face_size_for(g);
  const Resampler r(face, PhotometricFrame{}, g);
  const double amplitude = 0.05, rms_deviation = amplitude / std::sqrt(2.0);
  const auto lobe = [&](double c, double gamma) {
    return (0.2 + (gamma < kPi / 2 ? std::pow(std::cos(gamma), 2) : 0.0)) * (1.0 + amplitude * std::cos(c));
  };
  const auto decide = [&](std::uint64_t photons, std::uint64_t seed) {
    return detect_symmetry(r.bin(test::sample_far_field(face, in_world(PhotometricFrame{}, lobe),
                                                        1.2 * (1.0 + amplitude), photons, 1000.0, seed)));
  };
  const auto test_of = [](const SymmetryDecision& d, Symmetry s) {
    for (const SymmetryTest& t : d.tests)
      if (t.symmetry == s) return t;
    ADD_FAILURE() << "no test of " << photometry::to_string(s);
    return SymmetryTest{};
  };
  const auto states_its_power = [](const SymmetryDecision& d, const SymmetryTest& t) {
    char figure[32];
    std::snprintf(figure, sizeof figure, "%.2g %% RMS", 100.0 * t.detectable_deviation);
    return d.explanation.find(std::string("power: ") + photometry::to_string(t.symmetry) +
                              " is rejected 9 times in 10 when equivalent directions deviate from their mean by " +
                              figure) != std::string::npos;
  };

  const SymmetryDecision few = decide(100'000, 5);
  const SymmetryTest few_rotational = test_of(few, Symmetry::Rotational);
  if (few.symmetry == Symmetry::C0_C180 || few.symmetry == Symmetry::None) {
    SUCCEED() << "detected at 10^5 photons: " << few.explanation;
  } else {
    // A claim the asymmetry breaks: the explanation must say that it could
    // not have seen an asymmetry this size.
    const SymmetryTest chosen = test_of(few, few.symmetry);
    EXPECT_TRUE(states_its_power(few, chosen)) << few.explanation;
    EXPECT_GT(chosen.detectable_deviation, rms_deviation) << few.explanation;
  }
  EXPECT_GT(few_rotational.detectable_deviation, 1.3 * rms_deviation) << few.explanation;

  const SymmetryDecision many = decide(800'000, 6);
  const SymmetryTest many_rotational = test_of(many, Symmetry::Rotational);
  EXPECT_LT(many_rotational.detectable_deviation, 0.75 * rms_deviation) << many.explanation;
  EXPECT_TRUE(many_rotational.rejected) << many.explanation;
  EXPECT_TRUE(test_of(many, Symmetry::Quadrant).rejected) << many.explanation;
  EXPECT_TRUE(test_of(many, Symmetry::C90_C270).rejected) << many.explanation;
  EXPECT_EQ(many.symmetry, Symmetry::C0_C180) << many.explanation;
  EXPECT_TRUE(states_its_power(many, test_of(many, Symmetry::C0_C180))) << many.explanation;
  // The detectable deviation falls as 1/√photons (the tolerance's floor,
  // 0.5 % per bin, is far below the noise here).
  EXPECT_NEAR(few_rotational.detectable_deviation / many_rotational.detectable_deviation, std::sqrt(8.0), 0.25);
}

TEST(Symmetry, PowerFallsToTheToleranceFloorWithoutNoise) {
  // No photon counts (an integrated map): only the tolerance ε bounds the
  // variance, σ = ε · Ī, so a deviation is seen once its χ² contribution
  // beats the critical value over dof bins: about ε · √(λ / dof), a fraction
  // of ε.
  const CGammaGrid g{10.0, 5.0};
  const int face = face_size_for(g);
  const Resampler r(face, PhotometricFrame{}, g);
  const SymmetryDecision d =
      detect_symmetry(r.bin(test::integrate_far_field(face, [](const Vec3&) { return 1.0; })));
  ASSERT_EQ(d.symmetry, Symmetry::Rotational) << d.explanation;
  const double floor = d.tests[0].detectable_deviation;
  EXPECT_GT(floor, 0.0);
  EXPECT_LT(floor, 0.005);
  EXPECT_NE(d.explanation.find("power: rotational"), std::string::npos) << d.explanation;
  // Nothing tested, nothing stated.
  const SymmetryDecision empty = detect_symmetry(r.bin(FarField(face)));
  EXPECT_EQ(empty.explanation.find("power"), std::string::npos) << empty.explanation;
}

}  // namespace
}  // namespace gonio::sim
