#include "sim/detectors/resample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "photometry/flux.h"
#include "photometry/frame.h"
#include "sim/detectors/symmetry.h"
#include "tests/sim/synthetic_far_field.h"

namespace gonio::sim {
namespace {

using photometry::PhotometricFrame;
using photometry::Symmetry;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// A frame in general position: no axis along a cube axis.
PhotometricFrame tilted_frame() { return photometry::make_frame({0.3, 1.0, 0.2}, {1.0, 0.1, -0.4}); }

// Local (C, γ) [rad] of a world direction under a frame.
photometry::CGamma local_angles(const PhotometricFrame& frame, const Vec3& world) {
  return photometry::c_gamma_from_direction(frame.to_local(world));
}

// Angular bounds of a bin [rad]: γ from lo to hi, C from lo to hi (caps: full circle).
struct BinBounds {
  double g_lo, g_hi, c_lo, c_hi;
};
BinBounds bounds(const CGammaGrid& g, int i, int j) {
  const double dg = g.gamma_step_deg * kDeg, dc = g.c_step_deg * kDeg;
  if (j == 0) return {0.0, 0.5 * dg, 0.0, 2.0 * kPi};
  if (j == g.gamma_count() - 1) return {kPi - 0.5 * dg, kPi, 0.0, 2.0 * kPi};
  return {(j - 0.5) * dg, (j + 0.5) * dg, (i - 0.5) * dc, (i + 0.5) * dc};
}

// Mean intensity over a bin by Gauss-Legendre quadrature in (C, cos γ):
// independent of the cube map altogether.
double bin_mean(const CGammaGrid& g, int i, int j,
                const std::function<double(double c, double gamma)>& intensity) {
  static constexpr double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                  0.8611363115940526};
  static constexpr double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                  0.3478548451374538};
  const BinBounds b = bounds(g, i, j);
  const int n = 8;  // panels per direction
  const double u_lo = std::cos(b.g_hi), u_hi = std::cos(b.g_lo);
  double sum = 0.0;
  for (int pc = 0; pc < n; ++pc) {
    for (int pu = 0; pu < n; ++pu) {
      const double c0 = b.c_lo + (b.c_hi - b.c_lo) * pc / n, hc = 0.5 * (b.c_hi - b.c_lo) / n;
      const double u0 = u_lo + (u_hi - u_lo) * pu / n, hu = 0.5 * (u_hi - u_lo) / n;
      for (int a = 0; a < 4; ++a) {
        for (int k = 0; k < 4; ++k) {
          const double c = c0 + hc * (1 + x[a]), u = u0 + hu * (1 + x[k]);
          sum += w[a] * w[k] * hc * hu * intensity(c, std::acos(std::clamp(u, -1.0, 1.0)));
        }
      }
    }
  }
  return sum / ((b.c_hi - b.c_lo) * (u_hi - u_lo));
}

TEST(Resample, GridValidation) {
  EXPECT_TRUE(validate(CGammaGrid{}).ok());
  EXPECT_TRUE(validate(CGammaGrid{1.0, 1.0}).ok());
  EXPECT_TRUE(validate(CGammaGrid{90.0, 90.0}).ok());
  EXPECT_TRUE(validate(CGammaGrid{7.5, 0.5}).ok());
  for (auto [c, g] : {std::pair{0.0, 2.5}, {-5.0, 2.5}, {7.0, 2.5}, {5.0, 7.0}, {0.25, 2.5},
                      {5.0, 120.0}, {NAN, 2.5}, {5.0, INFINITY}}) {
    const Status s = validate(CGammaGrid{c, g});
    ASSERT_FALSE(s.ok()) << c << " " << g;
    EXPECT_NE(s.error().message.find("step"), std::string::npos) << s.error().message;
  }
  EXPECT_NE(validate(CGammaGrid{7.0, 2.5}).error().message.find("does not divide 360"),
            std::string::npos);
}

TEST(Resample, BinLayoutTilesTheSphere) {
  const CGammaGrid g;
  EXPECT_EQ(g.c_count(), 72);
  EXPECT_EQ(g.gamma_count(), 73);
  EXPECT_EQ(g.bin_count(), 2u + 72u * 71u);
  EXPECT_EQ(g.bin(17, 0), g.bin(0, 0));
  EXPECT_EQ(g.bin(17, 72), g.bin(3, 72));
  EXPECT_NE(g.bin(1, 1), g.bin(2, 1));
  double sum = 0.0;
  for (std::size_t b = 0; b < g.bin_count(); ++b) sum += exact_bin_solid_angle(g, b);
  EXPECT_NEAR(sum, 4.0 * kPi, 1e-12);
}

TEST(Resample, FaceSizeFollowsTheFinerStep) {
  EXPECT_EQ(face_size_for(CGammaGrid{5.0, 2.5}), 128);
  EXPECT_EQ(face_size_for(CGammaGrid{2.5, 5.0}), 128);
  EXPECT_EQ(face_size_for(CGammaGrid{10.0, 10.0}), 32);
  EXPECT_EQ(face_size_for(CGammaGrid{1.0, 1.0}), 256);
  // Two texels per step at the face centre, where texels are largest.
  for (double step : {0.5, 1.0, 2.5, 5.0, 15.0}) {
    const int n = face_size_for(CGammaGrid{step, step});
    EXPECT_LE(2.0 * std::atan(1.0 / n) / kDeg, step / 2.0) << step;
  }
}

TEST(Resample, OverlapsCoverEachBinsExactSolidAngle) {
  for (const PhotometricFrame& frame : {PhotometricFrame{}, tilted_frame()}) {
    for (const CGammaGrid& g : {CGammaGrid{}, CGammaGrid{15.0, 10.0}, CGammaGrid{10.0, 5.0},
                                CGammaGrid{90.0, 90.0}, CGammaGrid{3.0, 2.0}}) {
      const int n = face_size_for(g);
      const Resampler r(n, frame, g);
      double sum = 0.0, worst = 0.0;
      for (std::size_t b = 0; b < g.bin_count(); ++b) {
        const double exact = exact_bin_solid_angle(g, b);
        worst = std::max(worst, std::abs(r.bin_solid_angle_sr()[b] / exact - 1.0));
        sum += r.bin_solid_angle_sr()[b];
      }
      EXPECT_NEAR(sum, 4.0 * kPi, 1e-11);
      // Cutting leaves along chords of the γ-circles (sagitta below 1/400 of
      // a leaf) leaves slivers of about 1e-4 of a bin's area on each edge.
      EXPECT_LT(worst, 1e-3) << "grid " << g.c_step_deg << "x" << g.gamma_step_deg << " face " << n;
    }
  }
}

TEST(Resample, ConservesFluxOfAnyMap) {
  std::mt19937_64 rng(5);
  std::exponential_distribution<double> e(1.0);
  for (const PhotometricFrame& frame : {PhotometricFrame{}, tilted_frame()}) {
    const CGammaGrid g{10.0, 5.0};
    const int n = face_size_for(g);
    const Resampler r(n, frame, g);
    FarField field(n);
    for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, e(rng) * 3.0, 1 + rng() % 9);
    // A few bright texels: flux must not leak however it is distributed.
    field.add(17, 1e4);
    field.add(field.texel_count() - 3, 5e3);
    const BinnedField b = r.bin(field);
    double carried = 0.0, photons = 0.0;
    for (std::size_t k = 0; k < g.bin_count(); ++k) {
      carried += b.intensity_cd(k) * b.solid_angle_sr[k];
      photons += b.photons[k];
    }
    EXPECT_NEAR(b.total_flux_lm() / field.total_flux_lm(), 1.0, 1e-13);
    EXPECT_NEAR(carried / field.total_flux_lm(), 1.0, 1e-13);
    EXPECT_NEAR(photons / static_cast<double>(field.total_photons()), 1.0, 1e-13);
  }
}

TEST(Resample, IsotropicMapIsFlatToRounding) {
  const CGammaGrid g;
  const int n = face_size_for(g);
  const double i0 = 795.77;
  FarField field(n);
  for (std::size_t t = 0; t < field.texel_count(); ++t)
    field.add(t, i0 * field.grid().texel_solid_angle(t));
  const BinnedField b = Resampler(n, tilted_frame(), g).bin(field);
  for (std::size_t k = 0; k < g.bin_count(); ++k) ASSERT_NEAR(b.intensity_cd(k), i0, 1e-9 * i0) << k;
}

// cosⁿ γ on the lower hemisphere, around the frame's nadir.
struct CosineLobe {
  int n;
  double operator()(double /*c*/, double gamma) const {
    return gamma < kPi / 2 ? std::pow(std::cos(gamma), n) : 0.0;
  }
  // Closed-form mean over the band γ in [lo, hi]: ∫cosⁿ sin / ∫sin.
  double band_mean(double lo, double hi) const {
    const double clo = std::cos(std::min(lo, kPi / 2)), chi = std::cos(std::min(hi, kPi / 2));
    return (std::pow(clo, n + 1) - std::pow(chi, n + 1)) / ((n + 1) * (std::cos(lo) - std::cos(hi)));
  }
  // Largest |dI/dγ| [1/rad] over [lo, hi].
  double max_slope(double lo, double hi) const {
    double m = 0.0;
    for (int k = 0; k <= 64; ++k) {
      const double g = std::min(lo + (hi - lo) * k / 64.0, kPi / 2);
      m = std::max(m, n * std::pow(std::cos(g), n - 1) * std::sin(g));
    }
    return m;
  }
};

TEST(Resample, CosinePowerLobesMatchTheirClosedForms) {
  const CGammaGrid g;
  const int face = face_size_for(g);
  // Largest texel diagonal on the map [rad]: the centre texel's.
  const double texel = 2.0 * std::atan(std::sqrt(2.0) / face);
  for (const PhotometricFrame& frame : {PhotometricFrame{}, tilted_frame()}) {
    const Resampler r(face, frame, g);
    for (int n : {1, 2, 8}) {
      const CosineLobe lobe{n};
      const FarField field = test::integrate_far_field(face, [&](const Vec3& d) {
        const auto cg = local_angles(frame, d);
        return 1000.0 * lobe(cg.c_rad, cg.gamma_rad);
      });
      const BinnedField b = r.bin(field);
      double sum2 = 0.0, worst = 0.0;
      int count = 0;
      for (int j = 0; j < g.gamma_count(); ++j) {
        const BinBounds bb = bounds(g, 0, j);
        const double mean = 1000.0 * lobe.band_mean(bb.g_lo, bb.g_hi);
        // Splitting a texel between bins assumes its flux uniform: the error
        // is at most the intensity's variation across one texel.
        const double bound =
            1000.0 * lobe.max_slope(std::max(0.0, bb.g_lo - texel), bb.g_hi + texel) * texel + 1e-9;
        for (int i = 0; i < g.c_count(); ++i) {
          const double got = b.intensity_cd(g.bin(i, j));
          ASSERT_NEAR(got, mean, bound) << "n " << n << " C " << g.c_deg(i) << " γ " << g.gamma_deg(j);
          worst = std::max(worst, std::abs(got - mean));
          sum2 += (got - mean) * (got - mean);
          ++count;
        }
      }
      // Over the whole grid the splitting errors mostly cancel: RMS below
      // 0.1 % of the peak.
      EXPECT_LT(std::sqrt(sum2 / count), 1.0) << "n " << n;
      if (n == 1) {
        // The closed form against the grid angle itself: a band of half-width
        // h around γ has mean cos γ · cos h, so a cosine emitter resamples to
        // I₀ cos γ_j cos(Δγ/2), 1 − cos(1.25°) = 2.4e-4 below the point value.
        const double h = 0.5 * g.gamma_step_deg * kDeg;
        for (int j = 1; (j + 0.5) * g.gamma_step_deg <= 90.0; ++j) {
          const double gamma = g.gamma_deg(j) * kDeg;
          const double bound = 1000.0 * std::sin(std::min(gamma + texel, kPi / 2)) * texel;
          for (int i = 0; i < g.c_count(); i += 7)
            EXPECT_NEAR(b.intensity_cd(g.bin(i, j)), 1000.0 * std::cos(gamma) * std::cos(h), bound);
        }
      }
    }
  }
}

TEST(Resample, AsymmetricLobeMatchesItsBinMeans) {
  // I = 1000 · max(0, d·d0)^20 around (C 30°, γ 40°) of a tilted frame;
  // reference bin means by quadrature in (C, cos γ), without the cube.
  const CGammaGrid g;
  const int face = face_size_for(g);
  const double texel = 2.0 * std::atan(std::sqrt(2.0) / face);
  const PhotometricFrame frame = tilted_frame();
  const Vec3 axis = photometry::direction_from_c_gamma(30.0 * kDeg, 40.0 * kDeg);
  const auto lobe_local = [&](const Vec3& local) {
    return 1000.0 * std::pow(std::max(0.0, dot(local, axis)), 20);
  };
  const FarField field = test::integrate_far_field(
      face, [&](const Vec3& d) { return lobe_local(frame.to_local(d)); });
  const BinnedField b = Resampler(face, frame, g).bin(field);
  // Steepest slope of cos^20 θ: 20 cos^19 θ sin θ at tan²θ = 1/19.
  const double theta = std::atan(1.0 / std::sqrt(19.0));
  const double slope = 1000.0 * 20.0 * std::pow(std::cos(theta), 19) * std::sin(theta);
  double sum2 = 0.0;
  int count = 0;
  std::size_t peak = 0;
  for (int j = 0; j < g.gamma_count(); ++j) {
    for (int i = 0; i < g.c_count(); ++i) {
      if ((j == 0 || j == g.gamma_count() - 1) && i > 0) continue;
      const std::size_t k = g.bin(i, j);
      if (b.intensity_cd(k) > b.intensity_cd(peak)) peak = k;
      // Only where the lobe is: elsewhere both are 0.
      if (std::abs(g.gamma_deg(j) - 40.0) > 60.0) continue;
      const double mean = bin_mean(g, i, j, [&](double c, double gamma) {
        return lobe_local(photometry::direction_from_c_gamma(c, gamma));
      });
      ASSERT_NEAR(b.intensity_cd(k), mean, slope * texel) << "C " << g.c_deg(i) << " γ " << g.gamma_deg(j);
      sum2 += (b.intensity_cd(k) - mean) * (b.intensity_cd(k) - mean);
      ++count;
    }
  }
  EXPECT_LT(std::sqrt(sum2 / count), 1.0);
  EXPECT_EQ(peak, g.bin(6, 16));  // C 30°, γ 40°
}

// Where a narrow lobe (cos^400, 3.4° to half intensity) around world
// direction d peaks on a 15° grid.
std::pair<double, double> peak_of_lobe(const Resampler& r, const Vec3& world) {
  const CGammaGrid& g = r.grid();
  const Vec3 d0 = normalize(world);
  const FarField field = test::integrate_far_field(
      r.face_size(), [&](const Vec3& d) { return std::pow(std::max(0.0, dot(d, d0)), 400); }, 2);
  const BinnedField b = r.bin(field);
  std::pair<double, double> best{-1.0, -1.0};
  double best_i = -1.0;
  for (int j = 0; j < g.gamma_count(); ++j) {
    for (int i = 0; i < g.c_count(); ++i) {
      const double v = b.intensity_cd(g.bin(i, j));
      if (v > best_i) {
        best_i = v;
        best = {j == 0 || j == g.gamma_count() - 1 ? 0.0 : g.c_deg(i), g.gamma_deg(j)};
      }
    }
  }
  return best;
}

TEST(Resample, HonoursThePhotometricFrame) {
  using P = std::pair<double, double>;
  // Gonio's default in glTF's Y-up world: nadir −Y, C0 along +X, C90 along −Z.
  const CGammaGrid g{15.0, 15.0};
  const Resampler y_up(32, PhotometricFrame{}, g);
  EXPECT_EQ(peak_of_lobe(y_up, {1, -1, 0}), P(0.0, 45.0));
  EXPECT_EQ(peak_of_lobe(y_up, {0, -1, -1}), P(90.0, 45.0));
  EXPECT_EQ(peak_of_lobe(y_up, {-1, 0, 0}), P(180.0, 90.0));
  EXPECT_EQ(peak_of_lobe(y_up, {0, -0.5, std::sqrt(0.75)}), P(270.0, 60.0));
  EXPECT_EQ(peak_of_lobe(y_up, {0, -1, 0}), P(0.0, 0.0));
  EXPECT_EQ(peak_of_lobe(y_up, {0, 1, 0}), P(0.0, 180.0));
  // A Z-up frame with C0 along +X has C90 along +Y (C0 × C90 = up).
  const Resampler z_up(32, photometry::make_frame({0, 0, 1}, {1, 0, 0}), g);
  EXPECT_EQ(peak_of_lobe(z_up, {0, 1, -1}), P(90.0, 45.0));
  EXPECT_EQ(peak_of_lobe(z_up, {-1, 0, -1}), P(180.0, 45.0));
  EXPECT_EQ(peak_of_lobe(z_up, {0, -1, -std::sqrt(3.0)}), P(270.0, 30.0));
}

TEST(Resample, DistributionsCarryTheSymmetrysRange) {
  const CGammaGrid g{15.0, 10.0};
  const int face = face_size_for(g);
  std::mt19937_64 rng(3);
  std::exponential_distribution<double> e(1.0);
  FarField field(face);
  for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, e(rng), 1);
  const BinnedField b = Resampler(face, tilted_frame(), g).bin(field);
  struct Case {
    Symmetry symmetry;
    double first, last;
    std::size_t planes;
  };
  for (const Case& c : {Case{Symmetry::None, 0, 360, 25}, Case{Symmetry::C0_C180, 0, 180, 13},
                        Case{Symmetry::C90_C270, 90, 270, 13}, Case{Symmetry::Quadrant, 0, 90, 7},
                        Case{Symmetry::Rotational, 0, 0, 1}}) {
    const photometry::Distribution d = to_distribution(b, c.symmetry);
    ASSERT_TRUE(photometry::validate(d).ok()) << photometry::validate(d).error().message;
    EXPECT_EQ(d.symmetry, c.symmetry);
    EXPECT_EQ(d.type, photometry::PhotometricType::C);
    ASSERT_EQ(d.horizontal_count(), c.planes);
    EXPECT_DOUBLE_EQ(d.horizontal_deg.front(), c.first);
    EXPECT_DOUBLE_EQ(d.horizontal_deg.back(), c.last);
    ASSERT_EQ(d.vertical_count(), 19u);
    EXPECT_DOUBLE_EQ(d.vertical_deg.back(), 180.0);
    // One nadir value for every plane.
    for (std::size_t h = 1; h < d.horizontal_count(); ++h) EXPECT_EQ(d.at(h, 0), d.at(0, 0));
  }
  const photometry::Distribution none = to_distribution(b, Symmetry::None);
  for (std::size_t v = 0; v < none.vertical_count(); ++v) EXPECT_EQ(none.at(24, v), none.at(0, v));
  EXPECT_EQ(none.at(3, 5), b.intensity_cd(g.bin(3, 5)));
}

// Non-uniform grids (issue 44): a narrow beam's γ list, fine near the nadir
// and coarse beyond, and an uneven C list mirrored about C0-C180 (not about
// C90-C270: 10° has no 170°).
CGammaGrid narrow_beam_grid() {
  CGammaGrid g;
  for (int k = 0; k <= 20; ++k) g.gamma_angles_deg.push_back(0.5 * k);      // 0 … 10 every 0.5
  for (int k = 1; k <= 68; ++k) g.gamma_angles_deg.push_back(10.0 + 2.5 * k);  // 12.5 … 180
  g.c_angles_deg = {0, 10, 20, 45, 90, 150, 180, 210, 270, 315, 340, 350};
  return g;
}

TEST(ResampleNonUniform, ListValidation) {
  EXPECT_TRUE(validate(narrow_beam_grid()).ok()) << validate(narrow_beam_grid()).error().message;
  // Uniform γ down to 0.1° (C steps stay at 0.5° or more).
  EXPECT_TRUE(validate(CGammaGrid{5.0, 0.1}).ok());
  EXPECT_FALSE(validate(CGammaGrid{5.0, 0.05}).ok());
  EXPECT_FALSE(validate(CGammaGrid{0.1, 2.5}).ok());
  struct Bad {
    std::vector<double> gamma, c;
    const char* says;
  };
  const std::vector<double> ok_gamma = {0, 45, 90, 135, 180};
  const std::vector<double> ok_c = {0, 90, 180, 270};
  for (const Bad& bad : {Bad{{0, 10, 5, 180}, {}, "ascending"}, Bad{{0, 10, 10, 180}, {}, "ascending"},
                         Bad{{1, 10, 180}, {}, "first angle must be 0"},
                         Bad{{0, 10, 170}, {}, "last angle must be 180"},
                         Bad{{0, 10, 190}, {}, "last angle must be 180"},
                         Bad{{0, 0.05, 180}, {}, "closer than"}, Bad{{0, 100, 180}, {}, "more than 90"},
                         Bad{{0, NAN, 180}, {}, "not a number"}, Bad{ok_gamma, {0, 90, 360}, "outside"},
                         Bad{ok_gamma, {0, 200, 100}, "ascending"}, Bad{ok_gamma, {10, 90, 180}, "first angle"},
                         Bad{ok_gamma, {0, 90}, "more than 90"}, Bad{ok_gamma, {0, 90, 359.95, 180}, "ascending"},
                         Bad{{0}, ok_c, "at least two"}}) {
    CGammaGrid g;
    g.gamma_angles_deg = bad.gamma;
    g.c_angles_deg = bad.c;
    const Status s = validate(g);
    ASSERT_FALSE(s.ok()) << bad.says;
    EXPECT_NE(s.error().message.find(bad.says), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find(bad.gamma == ok_gamma ? "C angles" : "gamma angles"), std::string::npos)
        << s.error().message;
  }
  std::vector<double> too_many;
  for (std::size_t k = 0; k <= kMaxGridAngles; ++k) too_many.push_back(0.1 * static_cast<double>(k));
  CGammaGrid g;
  g.gamma_angles_deg = too_many;
  EXPECT_NE(validate(g).error().message.find("more than"), std::string::npos);
}

TEST(ResampleNonUniform, BinsAreTheMidpointIntervals) {
  const CGammaGrid g = narrow_beam_grid();
  EXPECT_EQ(g.gamma_count(), 89);
  EXPECT_EQ(g.c_count(), 12);
  EXPECT_DOUBLE_EQ(g.gamma_upper_deg(0), 0.25);
  EXPECT_DOUBLE_EQ(g.gamma_lower_deg(20), 9.75);
  EXPECT_DOUBLE_EQ(g.gamma_upper_deg(20), 11.25);
  EXPECT_DOUBLE_EQ(g.gamma_lower_deg(88), 178.75);
  EXPECT_DOUBLE_EQ(g.c_lower_deg(0), -5.0);
  EXPECT_DOUBLE_EQ(g.c_upper_deg(3), 67.5);
  EXPECT_DOUBLE_EQ(g.c_upper_deg(11), 355.0);
  EXPECT_EQ(g.c_index_of(210.0), 7);
  EXPECT_EQ(g.c_index_of(-10.0), 11);
  EXPECT_EQ(g.c_index_of(30.0), -1);
  EXPECT_DOUBLE_EQ(g.finest_gamma_step_deg(), 0.5);
  EXPECT_DOUBLE_EQ(g.finest_c_step_deg(), 10.0);
  EXPECT_EQ(face_size_for(g), 512);
  EXPECT_EQ(face_size_for(CGammaGrid{5.0, 0.25}), 1024);
  EXPECT_EQ(face_size_for(CGammaGrid{5.0, 0.1}), kMaxAutoFaceSize);
  double sum = 0.0;
  for (std::size_t b = 0; b < g.bin_count(); ++b) sum += exact_bin_solid_angle(g, b);
  EXPECT_NEAR(sum, 4.0 * kPi, 1e-12);
}

TEST(ResampleNonUniform, OverlapsCoverEachBinsExactSolidAngleAndKeepFlux) {
  const CGammaGrid g = narrow_beam_grid();
  std::mt19937_64 rng(11);
  std::exponential_distribution<double> e(1.0);
  for (const PhotometricFrame& frame : {PhotometricFrame{}, tilted_frame()}) {
    // Coarser than face_size_for (512): texels are shared between several
    // fine bins, which the overlaps must still split exactly.
    const int n = 128;
    const Resampler r(n, frame, g);
    double sum = 0.0, worst = 0.0;
    for (std::size_t b = 0; b < g.bin_count(); ++b) {
      const double exact = exact_bin_solid_angle(g, b);
      worst = std::max(worst, std::abs(r.bin_solid_angle_sr()[b] / exact - 1.0));
      sum += r.bin_solid_angle_sr()[b];
    }
    EXPECT_NEAR(sum, 4.0 * kPi, 1e-11);
    EXPECT_LT(worst, 1e-3);
    FarField field(n);
    for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, e(rng), 1);
    EXPECT_NEAR(r.bin(field).total_flux_lm(), field.total_flux_lm(), 1e-9 * field.total_flux_lm());
  }
}

TEST(ResampleNonUniform, ListsOfUniformAnglesGiveTheStepsBins) {
  // The same angles as a list and as steps: the same bins, to rounding.
  const CGammaGrid steps{10.0, 5.0};
  CGammaGrid lists;
  for (int k = 0; k < 36; ++k) lists.c_angles_deg.push_back(10.0 * k);
  for (int k = 0; k <= 36; ++k) lists.gamma_angles_deg.push_back(5.0 * k);
  const int n = 64;
  const Resampler a(n, tilted_frame(), steps), b(n, tilted_frame(), lists);
  ASSERT_EQ(a.grid().bin_count(), b.grid().bin_count());
  std::mt19937_64 rng(2);
  std::exponential_distribution<double> e(1.0);
  FarField field(n);
  for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, e(rng), 1);
  const BinnedField fa = a.bin(field), fb = b.bin(field);
  for (std::size_t k = 0; k < steps.bin_count(); ++k) {
    EXPECT_NEAR(fa.solid_angle_sr[k], fb.solid_angle_sr[k], 1e-12) << k;
    EXPECT_NEAR(fa.flux_lm[k], fb.flux_lm[k], 1e-9 * fa.flux_lm[k] + 1e-12) << k;
  }
  const photometry::Distribution da = to_distribution(fa, Symmetry::C0_C180);
  const photometry::Distribution db = to_distribution(fb, Symmetry::C0_C180);
  EXPECT_EQ(da.horizontal_deg, db.horizontal_deg);
  EXPECT_EQ(da.vertical_deg, db.vertical_deg);
}

// A narrow beam with a hard edge, as flat mirror facets around a point
// source give (the paraboloid of tests/tools/cli/cmd_simulate_grid_test.cpp):
// uniform within 3° of the nadir, nothing beyond. What a luminaire file holds
// of its flux (photometry::total_flux_lm, the readers' integration of the
// grid values, which gonio simulate checks against the escaped flux) on a
// uniform 2.5° grid and on a list fine near the axis; the bins themselves
// keep all of it. (Smooth beams, cos^2693 γ for a 2.6° beam, integrate to
// 1e-4 on either grid: the edge is what the coarse grid cannot place.)
TEST(ResampleNonUniform, NarrowBeamKeepsItsFluxOnAFineList) {
  const auto beam = [](const Vec3& d) {
    const double g = photometry::c_gamma_from_direction(d).gamma_rad / kDeg;
    return g < 3.0 ? 1e5 : 0.0;
  };
  const int face = 256;
  const FarField field = test::integrate_far_field(face, beam, 2);
  const double total = field.total_flux_lm();
  CGammaGrid fine;  // 0.1° to 5°, then 1°
  for (int k = 0; k <= 50; ++k) fine.gamma_angles_deg.push_back(0.1 * k);
  for (int k = 6; k <= 180; ++k) fine.gamma_angles_deg.push_back(k);
  ASSERT_TRUE(validate(fine).ok());
  const auto file_flux = [&](const CGammaGrid& g) {
    const BinnedField b = Resampler(face, PhotometricFrame{}, g).bin(field);
    EXPECT_NEAR(b.total_flux_lm(), total, 1e-9 * total);  // the bins keep it all
    return photometry::total_flux_lm(to_distribution(b, Symmetry::Rotational));
  };
  const double coarse_flux = file_flux(CGammaGrid{});
  const double fine_flux = file_flux(fine);
  std::printf("hard-edged 6 deg disc: file flux / binned flux %.5f at 2.5 deg steps, %.5f on 0:0.1:5,6:1:180\n",
              coarse_flux / total, fine_flux / total);
  // 2.5° steps: the file misses the flux check's 0.5 %, as issue 44 found.
  EXPECT_GT(std::abs(coarse_flux / total - 1.0), 0.005) << coarse_flux;
  EXPECT_LT(std::abs(fine_flux / total - 1.0), 0.005) << fine_flux;
}

TEST(ResampleNonUniform, SymmetryNeedsMirroredPlanes) {
  const CGammaGrid g = narrow_beam_grid();  // mirrored about C0-C180 only
  EXPECT_TRUE(grid_supports(g, Symmetry::C0_C180));
  EXPECT_FALSE(grid_supports(g, Symmetry::C90_C270));
  EXPECT_FALSE(grid_supports(g, Symmetry::Quadrant));
  EXPECT_NE(check_grid_supports(g, Symmetry::Quadrant).error().message.find("C angles"), std::string::npos);
  CGammaGrid unmirrored = g;
  unmirrored.c_angles_deg[1] = 15.0;  // 15 without 345
  EXPECT_FALSE(grid_supports(unmirrored, Symmetry::C0_C180));
  // C0-C180 output: the planes 0 … 180 of the list, averaged with their mirror images.
  std::mt19937_64 rng(4);
  std::exponential_distribution<double> e(1.0);
  FarField field(64);
  for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, e(rng), 1);
  const BinnedField b = Resampler(64, tilted_frame(), g).bin(field);
  const photometry::Distribution d = to_distribution(b, Symmetry::C0_C180);
  ASSERT_TRUE(photometry::validate(d).ok()) << photometry::validate(d).error().message;
  EXPECT_EQ(d.horizontal_deg, (std::vector<double>{0, 10, 20, 45, 90, 150, 180}));
  EXPECT_EQ(d.vertical_deg, g.gamma_angles_deg);
  const std::size_t b20 = g.bin(2, 30), b340 = g.bin(10, 30);
  EXPECT_NEAR(d.at(2, 30), (b.flux_lm[b20] + b.flux_lm[b340]) / (b.solid_angle_sr[b20] + b.solid_angle_sr[b340]),
              1e-9 * d.at(2, 30));
  const photometry::Distribution none = to_distribution(b, Symmetry::None);
  EXPECT_EQ(none.horizontal_deg.back(), 360.0);
  EXPECT_EQ(none.horizontal_count(), 13u);
  // The same flux to the γ quadrature's rounding (each file integrates its own values).
  EXPECT_NEAR(photometry::total_flux_lm(none), photometry::total_flux_lm(d), 1e-4 * photometry::total_flux_lm(d));
}

// bin_flux (the estimate's tables, issue 40) sums each bin as bin() does:
// the same doubles, not merely close ones.
TEST(Resample, BinFluxGivesBinsFluxExactly) {
  std::mt19937_64 rng(11);
  std::exponential_distribution<double> e(1.0);
  for (const PhotometricFrame& frame : {PhotometricFrame{}, tilted_frame()}) {
    const CGammaGrid g{10.0, 5.0};
    const int n = face_size_for(g);
    const Resampler r(n, frame, g);
    FarField field(n);
    for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, e(rng) * 3.0, 1 + rng() % 9);
    const BinnedField b = r.bin(field);
    const std::vector<double> flux = r.bin_flux(field.flux_lm());
    ASSERT_EQ(flux.size(), b.flux_lm.size());
    for (std::size_t k = 0; k < flux.size(); ++k) ASSERT_EQ(flux[k], b.flux_lm[k]) << "bin " << k;
  }
}

}  // namespace
}  // namespace gonio::sim
