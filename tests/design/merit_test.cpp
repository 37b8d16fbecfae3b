// The merit of gonio optimize (design/merit.h) and its optimiser
// (design/optimize.h): smooth binning makes the merit continuous in the
// photons' directions where nearest-node binning is piecewise constant with
// jumps; both keep the flux; the target is sampled as the traced nodes
// estimate it; the [merit] table's mistakes name their line; NLopt's methods
// find a known minimum in their bounds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "design/design_file.h"
#include "design/merit.h"
#include "design/optimize.h"
#include "design/reflector_design.h"
#include "photometry/frame.h"

namespace gonio::design {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// A rotationally symmetric target: 1000 cd · cos γ below 90°.
photometry::Distribution cosine_target() {
  std::vector<double> g, c;
  for (int i = 0; i <= 180; ++i) {
    g.push_back(i);
    c.push_back(i < 90 ? 1000.0 * std::cos(i * kDeg) : 0.0);
  }
  return rotational_distribution(g, c);
}

// 400 photons on a fixed spread of directions (γ 10…70°, C 0…360°), every
// one turned by `shift_deg` in γ: a stand-in for a design variable that
// moves every photon continuously.
std::vector<MeritPhoton> photons_at(double shift_deg) {
  std::vector<MeritPhoton> out;
  for (int k = 0; k < 400; ++k) {
    const double gamma = (10.0 + 60.0 * ((k * 0.618034) - std::floor(k * 0.618034)) + shift_deg) * kDeg;
    const double c = 2.0 * kPi * ((k * 0.7548777) - std::floor(k * 0.7548777));
    out.push_back({photometry::direction_from_c_gamma(c, gamma), 1.0});
  }
  return out;
}

// The merit over a scan of 2000 steps of the shift across 0…5°.
std::vector<double> scan(bool smooth) {
  MeritSpec spec;
  spec.smooth = smooth;
  const MeritGrid grid = merit_grid(spec);
  const Result<MeritTarget> target = merit_target(grid, cosine_target());
  EXPECT_TRUE(target.ok());
  std::vector<double> merits;
  for (int i = 0; i <= 2000; ++i)
    merits.push_back(evaluate_merit(spec, grid, *target, bin_photons(grid, photons_at(5.0 * i / 2000)), 1.0).merit);
  return merits;
}

TEST(Merit, SmoothBinningIsContinuousWhereNearestNodeBinningJumps) {
  const std::vector<double> smooth = scan(true), binned = scan(false);
  double smooth_largest = 0.0, binned_largest = 0.0;
  int smooth_flat = 0, binned_flat = 0;
  for (std::size_t i = 1; i < smooth.size(); ++i) {
    smooth_largest = std::max(smooth_largest, std::abs(smooth[i] - smooth[i - 1]));
    binned_largest = std::max(binned_largest, std::abs(binned[i] - binned[i - 1]));
    smooth_flat += smooth[i] == smooth[i - 1];
    binned_flat += binned[i] == binned[i - 1];
  }
  // Smooth: every step of 0.0025° moves it a little (no plateau), and no
  // step by more than a tiny share of its range.
  const double range = *std::max_element(smooth.begin(), smooth.end()) - *std::min_element(smooth.begin(), smooth.end());
  EXPECT_EQ(smooth_flat, 0);
  EXPECT_LT(smooth_largest, 0.01 * range) << "range " << range;
  // Binned: mostly flat (a photon changes nodes only at a cell's edge), then
  // jumps by far more than any smooth step.
  EXPECT_GT(binned_flat, 1000);
  EXPECT_GT(binned_largest, 20.0 * smooth_largest);
}

TEST(Merit, BinningKeepsTheFluxAndAnIsotropicSourceIsFlat) {
  for (bool smooth : {true, false}) {
    MeritSpec spec;
    spec.smooth = smooth;
    spec.c_step_deg = 30.0;
    spec.gamma_step_deg = 10.0;
    const MeritGrid grid = merit_grid(spec);
    double omega = 0.0;
    for (double w : grid.solid_angle_sr) omega += w;
    EXPECT_NEAR(omega, 4.0 * kPi, 1e-3) << smooth;
    // 2·10⁵ directions uniform on the sphere (a Fibonacci lattice), 1 lm in all.
    std::vector<MeritPhoton> photons;
    const int n = 200'000;
    for (int k = 0; k < n; ++k) {
      const double z = 1.0 - (2.0 * k + 1.0) / n, r = std::sqrt(1.0 - z * z), phi = k * 2.399963229728653;
      photons.push_back({{r * std::cos(phi), r * std::sin(phi), z}, 1.0 / n});
    }
    const std::vector<double> cd = bin_photons(grid, photons);
    double flux = 0.0;
    for (std::size_t k = 0; k < cd.size(); ++k) {
      flux += cd[k] * grid.solid_angle_sr[k];
      // Each node 1/(4π) cd, but the poles' few photons (the smallest nodes).
      const std::size_t g = k % grid.gamma_deg.size();
      if (g > 1 && g + 2 < grid.gamma_deg.size()) {
        EXPECT_NEAR(cd[k], 1.0 / (4.0 * kPi), 0.01 / (4.0 * kPi)) << k;
      }
    }
    EXPECT_NEAR(flux, 1.0, 1e-12) << smooth;
  }
}

TEST(Merit, TargetIsSampledAsTheNodesEstimateIt) {
  MeritSpec spec;
  const MeritGrid grid = merit_grid(spec);
  std::vector<double> g, c;
  for (int i = 0; i <= 180; ++i) {
    g.push_back(i);
    c.push_back(100.0);
  }
  const Result<MeritTarget> t = merit_target(grid, rotational_distribution(g, c));
  ASSERT_TRUE(t.ok());
  for (double v : t->candela) EXPECT_NEAR(v, 100.0, 1e-9);
  EXPECT_NEAR(t->flux_lm, 400.0 * kPi, 0.05);
  // The traced nodes of that same distribution give merit ~0.
  const Result<MeritTarget> cosine = merit_target(grid, cosine_target());
  ASSERT_TRUE(cosine.ok());
  EXPECT_NEAR(evaluate_merit(spec, grid, *cosine, cosine->candela, 1.0).candela_rms_pct, 0.0, 1e-9);
  // Twice the candela: flux-normalised it is the same; absolute it is 100 %
  // of the peak wherever the target is the peak (RMS over every node).
  std::vector<double> twice = cosine->candela;
  for (double& v : twice) v *= 2.0;
  EXPECT_NEAR(evaluate_merit(spec, grid, *cosine, twice, 1.0).merit, 0.0, 1e-9);
  spec.absolute = true;
  EXPECT_GT(evaluate_merit(spec, grid, *cosine, twice, 1.0).merit, 20.0);
  // The LOR term: 100·(1 − LOR) per unit weight.
  spec.absolute = false;
  spec.candela_weight = 0.0;
  spec.lor_weight = 2.0;
  EXPECT_NEAR(evaluate_merit(spec, grid, *cosine, cosine->candela, 0.8).merit, 40.0, 1e-9);
}

TEST(Merit, TableMistakesNameTheirLine) {
  const auto merit_of = [](const std::string& table) {
    Result<Design> d = parse_design("length_unit = \"mm\"\n[merit]\n" + table, "lamp.design.toml");
    EXPECT_TRUE(d.ok());
    return read_merit(resolved_document(*d), "lamp.design.toml");
  };
  Result<MeritSpec> ok = merit_of("gamma_step = 10\nc_step = 90\nsmooth = false\nnormalize = \"absolute\"\n"
                                  "gamma_weights = [[0, 60, 1], [60, 180, 0.25]]\nlor = 1\n");
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  EXPECT_EQ(ok->gamma_step_deg, 10.0);
  EXPECT_EQ(ok->c_step_deg, 90.0);
  EXPECT_FALSE(ok->smooth);
  EXPECT_TRUE(ok->absolute);
  ASSERT_EQ(ok->gamma_weights.size(), 2u);
  EXPECT_EQ(ok->gamma_weights[1].weight, 0.25);
  struct Bad {
    const char* table;
    int line;
    const char* says;
  };
  for (const Bad& b : {Bad{"colour = 1\n", 3, "unknown key 'colour'"}, Bad{"gamma_step = 5\nc_step = 7\n", 4, "divide 360"},
                       Bad{"photons_per_bin = 10\n", 3, "photons_per_bin"}, Bad{"normalize = \"peak\"\n", 3, "normalize"},
                       Bad{"gamma_weights = [[60, 0, 1]]\n", 3, "from < to"}, Bad{"lor = -1\n", 3, "'lor'"}}) {
    Result<MeritSpec> r = merit_of(b.table);
    ASSERT_FALSE(r.ok()) << b.table;
    EXPECT_EQ(r.error().where.line, b.line) << b.table;
    EXPECT_NE(r.error().message.find(b.says), std::string::npos) << r.error().message;
  }
}

TEST(Optimize, MethodsFindAKnownMinimumWithinTheBounds) {
  const std::vector<OptimizeVariable> vars = {{"a", 9.0, 0.0, 10.0}, {"b", -4.0, -5.0, 5.0}};
  // A bowl at (3, 1.5), and a region (a > 9.5) where the design "fails".
  const MeritFunction bowl = [](const std::vector<double>& v, std::uint64_t, std::uint64_t) -> Result<double> {
    if (v[0] > 9.5) return make_error("no such design");
    return (v[0] - 3.0) * (v[0] - 3.0) + 2.0 * (v[1] - 1.5) * (v[1] - 1.5);
  };
  for (OptimizeMethod m : {OptimizeMethod::Bobyqa, OptimizeMethod::Cobyla}) {
    OptimizeOptions o;
    o.method = m;
    o.start_photons = 100;
    int calls = 0;
    std::vector<std::uint64_t> photons;
    std::vector<std::uint64_t> noise_seeds;
    Result<OptimizeResult> r = optimize(vars, bowl, o, [&](const EvaluationRecord& e) {
      ++calls;
      photons.push_back(e.photons);
      // Common random numbers: every evaluation of a stage traces the same
      // photons (the run's seed); the noise floor's traces independent ones.
      if (e.stage >= 0) {
        EXPECT_EQ(e.seed, o.seed) << e.index;
      } else {
        EXPECT_NE(e.seed, o.seed);
        EXPECT_EQ(std::count(noise_seeds.begin(), noise_seeds.end(), e.seed), 0);
        noise_seeds.push_back(e.seed);
      }
      return true;
    });
    ASSERT_TRUE(r.ok()) << to_string(m) << ": " << r.error().message;
    EXPECT_NEAR(r->best_values[0], 3.0, 0.02) << to_string(m);
    EXPECT_NEAR(r->best_values[1], 1.5, 0.02) << to_string(m);
    EXPECT_EQ(calls, r->evaluations + o.noise_seeds);
    // Photons grow 4× per stage: the last stage's 1600.
    EXPECT_EQ(r->final_photons, 1600u);
    EXPECT_EQ(photons.front(), 100u);
    // A deterministic merit has no noise.
    EXPECT_EQ(r->noise_floor, 0.0);
  }
  // Variables the optimiser cannot search.
  EXPECT_FALSE(optimize({}, bowl, {}).ok());
  EXPECT_FALSE(optimize({{"a", 1.0, 2.0, 3.0}}, bowl, {}).ok());
}

}  // namespace
}  // namespace gonio::design
