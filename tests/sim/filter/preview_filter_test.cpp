#include "sim/filter/preview_filter.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <atomic>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <new>
#include <numbers>
#include <utility>
#include <random>
#include <span>
#include <vector>

#include "sim/filter/cube_neighbours.h"
#include "sim/detectors/far_field_sampler.h"

// Counts every allocation of this test program, to show that apply()
// allocates nothing once the filter exists. (GCC cannot see that the
// replaced operator new is malloc, hence the pragma.)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace gonio::sim {
namespace {

// The thesis's filter: a fixed threshold.
PreviewFilterParams params_with(Interpolation interpolation, double threshold, int levels) {
  PreviewFilterParams p;
  p.adaptive = false;
  p.interpolation = interpolation;
  p.threshold_photons = threshold;
  p.levels = levels;
  return p;
}

// The thesis's bilinear filter at threshold 300 over 4 levels, on faces of
// equal texels (solid angle 1), with and without the shadow-border rule,
// each applied to `field`.
std::pair<PreviewFilter, PreviewFilter> border_rule_on_and_off(const FarField& field) {
  const int n = field.grid().face_size();
  const std::vector<double> equal(static_cast<std::size_t>(n) * n, 1.0);
  const PreviewFilterParams with = params_with(Interpolation::Bilinear, 300.0, 4);
  PreviewFilterParams without = with;
  without.shadow_borders = false;
  std::pair<PreviewFilter, PreviewFilter> filters{PreviewFilter(n, with, equal), PreviewFilter(n, without, equal)};
  filters.first.apply(field);
  filters.second.apply(field);
  return filters;
}

// The reference thesis's worked example (figures 6.5–6.8) on face 0 of an
// 8-texel cube map whose texels all have solid angle 1, photons of 1 lm:
// columns 0–2 dark, columns 3–7 with 200 photons each, as in figure 6.5.
// With two levels the coarser one holds the raw sums 0 | 400 | 800 … of
// figure 6.6b. The highlighted texel is column 1 of an inner row.
struct WorkedExample {
  static constexpr int kN = 8;
  std::vector<double> equal_texels = std::vector<double>(kN * kN, 1.0);
  FarField field{kN};
  WorkedExample() {
    for (int y = 0; y < kN; ++y)
      for (int x = 3; x < kN; ++x) field.add(field.grid().index(0, x, y), 200.0, 200);
  }
  double filtered(const PreviewFilterParams& p, int x = 1, int y = 3) const {
    PreviewFilter filter(kN, p, equal_texels);
    filter.apply(field);
    return filter.intensity_cd()[field.grid().index(0, x, y)];
  }
};

TEST(PreviewFilter, WorkedExampleBilinearGivesTwentyFive) {
  // Thesis 6.4.3: the bilinear interpolation of 0 and 400 a quarter of the
  // way, divided by four: 25 photons' worth in the shadow texel.
  const WorkedExample ex;
  EXPECT_EQ(ex.filtered(params_with(Interpolation::Bilinear, 100.0, 2)), 25.0);
  // The dark column at the face edge interpolates dark texels only.
  EXPECT_EQ(ex.filtered(params_with(Interpolation::Bilinear, 100.0, 2), 0, 3), 0.0);
}

TEST(PreviewFilter, WorkedExampleBilateralStopsTheLeak) {
  // Thesis 6.4.4 with σ_d = 0.5, σ_r = 0.2, written out: closeness
  // exp(−d²/2σ_d²) at the four coarse centres, d² = 1/8, 5/8, 5/8, 9/8 (the
  // texel centre is a quarter texel from the nearest coarse centre); range
  // exp(−δ²/2σ_r²) with δ the difference from the bilinear estimate 25 over
  // the range scale; coarse intensities 0, 100 (sums over 4 texels of 1 sr).
  const WorkedExample ex;
  const auto closed_form = [](double scale) {
    const double sd2 = 2.0 * 0.5 * 0.5, sr2 = 2.0 * 0.2 * 0.2;
    const double d0 = 25.0 / scale, d1 = 75.0 / scale;
    const double w_dark = std::exp(-0.125 / sd2 - d0 * d0 / sr2) + std::exp(-0.625 / sd2 - d0 * d0 / sr2);
    const double w_lit = std::exp(-0.625 / sd2 - d1 * d1 / sr2) + std::exp(-1.125 / sd2 - d1 * d1 / sr2);
    return 100.0 * w_lit / (w_dark + w_lit);
  };
  PreviewFilterParams p = params_with(Interpolation::Bilateral, 100.0, 2);
  p.range_scale = RangeScale::LocalMax;
  const double local_max = ex.filtered(p);
  EXPECT_NEAR(local_max, closed_form(100.0), 1e-8 * local_max);
  EXPECT_NEAR(local_max, 0.0710, 0.0005);  // the thesis's "about 0.1"
  p.range_scale = RangeScale::Estimate;
  const double estimate = ex.filtered(p);
  EXPECT_NEAR(estimate, closed_form(25.0), 1e-7 * estimate);
  EXPECT_LT(estimate, 1e-40);
}

TEST(PreviewFilter, WorkedExampleUpsamplesTheShadowTexelOnLevelsZeroAndOne) {
  // Column 2 is dark beside the 200-photon column 3: its pair sums with its
  // three right-hand neighbours reach twice the threshold, so on levels ≥ 2
  // the shadow-border rule would keep it dark. On level 0 the rule is off and
  // it is upsampled: bilinear 0 · 1/4 + 100 · 3/4 = 75.
  const WorkedExample ex;
  EXPECT_TRUE(is_shadow_border(0, std::vector<double>{0, 200, 0, 200, 0, 200, 0, 0}, 100.0));
  for (bool rule : {true, false}) {
    PreviewFilterParams p = params_with(Interpolation::Bilinear, 100.0, 2);
    p.shadow_borders = rule;
    EXPECT_EQ(ex.filtered(p, 2, 3), 75.0) << rule;
    p.interpolation = Interpolation::Bilateral;
    EXPECT_GT(ex.filtered(p, 2, 3), 50.0) << rule;  // nearer the lit coarse texel
  }
  // Three levels: on level 1 (faces of 4) column 0 is dark beside column 1's
  // 400 photons, a border texel by the rule's count, and is upsampled too:
  // from level 2's 0 (the dark face beyond the edge) and 50 (800 photons over
  // 16 texels), 3/4 · 50 = 37.5. Level 0 then interpolates 37.5 and 100:
  // columns 1 and 2 get 53.125 and 84.375 (with level 1 kept dark they would
  // get 25 and 75).
  EXPECT_TRUE(is_shadow_border(0, std::vector<double>{0, 400, 0, 400, 0, 400, 0, 0}, 100.0));
  for (bool rule : {true, false}) {
    PreviewFilterParams p = params_with(Interpolation::Bilinear, 100.0, 3);
    p.shadow_borders = rule;
    EXPECT_EQ(ex.filtered(p, 1, 3), 53.125) << rule;
    EXPECT_EQ(ex.filtered(p, 2, 3), 84.375) << rule;
    EXPECT_EQ(ex.filtered(p, 3, 3), 200.0) << rule;  // stable: its own value
  }
}

TEST(PreviewFilter, ShadowBorderRuleLooksAcrossFaceEdgesAndACubeCorner) {
  // Faces +X and +Y lit (50 photons in every texel of 1 sr), the other four
  // dark; threshold 300, four levels on faces of 16. On face +Z, +X lies
  // beyond the left edge and +Y beyond the top one, so its corner (0, 0) is
  // the cube corner where the three meet. On level 2 (faces of 4, 800 photons
  // per lit texel) +Z's texels along those two edges find their stable
  // neighbours on the other faces only: three each along an edge, four of
  // seven at the corner. They are border texels and stay dark, and the
  // bilinear leak on levels 1 and 0 reaches only the two level-0 rows and
  // columns next to the edges: texels 3…8 from both edges get nothing. (The
  // level-2 texels at +Z's other two corners see one lit face only, two
  // stable neighbours, and take light from above; texels beyond 8 see it.)
  // Without the rule level 2 takes light from level 3 across both edges and
  // the corner, and passes it down into that square.
  const int n = 16;
  const int pos_x = 0, pos_y = 2, pos_z = 4;
  const CubeNeighbours neighbours(n);
  for (int p = 0; p < n; ++p) {
    ASSERT_EQ(static_cast<int>(neighbours.across_edge(pos_z, FaceEdge::Left, p) / (n * n)), pos_x);
    ASSERT_EQ(static_cast<int>(neighbours.across_edge(pos_z, FaceEdge::Top, p) / (n * n)), pos_y);
  }
  FarField field(n);
  for (int face : {pos_x, pos_y})
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) field.add(field.grid().index(face, x, y), 50.0, 50);
  const auto [with_rule, without_rule] = border_rule_on_and_off(field);
  for (int y = 3; y <= 8; ++y)
    for (int x = 3; x <= 8; ++x)
      EXPECT_EQ(with_rule.intensity_cd()[field.grid().index(pos_z, x, y)], 0.0) << x << "," << y;
  EXPECT_GT(without_rule.intensity_cd()[field.grid().index(pos_z, 3, 3)], 0.01);
  EXPECT_GT(without_rule.intensity_cd()[field.grid().index(pos_z, 3, 8)], 0.01);
  EXPECT_GT(without_rule.intensity_cd()[field.grid().index(pos_z, 8, 3)], 0.01);
  // Next to the edges the leak is there with the rule too.
  EXPECT_GT(with_rule.intensity_cd()[field.grid().index(pos_z, 0, 5)], 1.0);
  EXPECT_GT(with_rule.intensity_cd()[field.grid().index(pos_z, 5, 0)], 1.0);
}

TEST(PreviewFilter, ShadowBorderRuleCountsStableNeighbourPairs) {
  // 6.4.2: pairs summing to at least 2 × threshold; three to six of them.
  const double t = 100.0;
  EXPECT_FALSE(is_shadow_border(0, std::vector<double>{0, 0, 0, 0, 0, 0, 0, 0}, t));
  EXPECT_FALSE(is_shadow_border(0, std::vector<double>{200, 200, 0, 0, 0, 0, 0, 0}, t));
  EXPECT_TRUE(is_shadow_border(0, std::vector<double>{200, 200, 200, 0, 0, 0, 0, 0}, t));
  EXPECT_TRUE(is_shadow_border(10, std::vector<double>{190, 190, 190, 190, 190, 190, 0, 0}, t));
  EXPECT_FALSE(is_shadow_border(10, std::vector<double>{190, 190, 190, 190, 190, 190, 190, 0}, t));
  EXPECT_FALSE(is_shadow_border(0, std::vector<double>{199, 199, 199, 199, 0, 0, 0, 0}, t));
  // A cube-corner texel has seven neighbours; the rule is the same.
  EXPECT_TRUE(is_shadow_border(0, std::vector<double>{200, 200, 200, 200, 200, 200, 0}, t));
  EXPECT_FALSE(is_shadow_border(0, std::vector<double>{200, 200, 200, 200, 200, 200, 200}, t));
}

TEST(PreviewFilter, ShadowBordersOnCoarseLevelsKeepDarkRegionsDark) {
  // Face 0 of 16 equal texels: left half dark, right half 50 photons per
  // texel; threshold 300, so the bright region is stable on level 2 (800
  // photons per texel) and above, unstable below. With the rule, the dark
  // level-2 texels beside the border keep their 0, and the bilinear leak on
  // levels 1 and 0 reaches only the dark level-0 column next to the border;
  // without it, light leaks from level 3 down into the whole dark half.
  // Rows 7 and 8 are the ones whose interpolation never reaches the level-2
  // texels at the face's top and bottom edges (where the other, dark faces
  // leave fewer than three bright neighbours, so the rule does not apply).
  const int n = 16;
  FarField field(n);
  for (int y = 0; y < n; ++y)
    for (int x = n / 2; x < n; ++x) field.add(field.grid().index(0, x, y), 50.0, 50);
  const auto [with_rule, without_rule] = border_rule_on_and_off(field);
  for (int y = 7; y <= 8; ++y) {
    for (int x = 1; x < 5; ++x) {
      const std::size_t t = field.grid().index(0, x, y);
      EXPECT_EQ(with_rule.intensity_cd()[t], 0.0) << x << "," << y;
      EXPECT_GT(without_rule.intensity_cd()[t], 0.01) << x << "," << y;
    }
    EXPECT_GT(with_rule.intensity_cd()[field.grid().index(0, 5, y)], 1.0);
  }
}

// A field where every texel holds at least `min_photons`, with random flux.
FarField busy_field(int n, std::uint64_t min_photons, unsigned seed) {
  FarField field(n);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::uint64_t> extra(0, 50);
  std::uniform_real_distribution<double> flux(0.5, 1.5);
  for (std::size_t t = 0; t < field.texel_count(); ++t) {
    const std::uint64_t k = min_photons + extra(rng);
    field.add(t, static_cast<double>(k) * flux(rng), k);
  }
  return field;
}

TEST(PreviewFilter, EqualsTheRawMapOnceEveryTexelIsStable) {
  const int n = 32;
  const FarField field = busy_field(n, 101, 1);
  for (Interpolation kind : {Interpolation::Bilinear, Interpolation::Bilateral}) {
    for (bool adaptive : {false, true}) {
      PreviewFilterParams p = params_with(kind, 100.0, 99);
      p.adaptive = adaptive;
      PreviewFilter filter(n, p);
      const PreviewStats& s = filter.apply(field);
      EXPECT_EQ(s.levels_used, 6);
      EXPECT_EQ(s.stable_texels, field.texel_count());
      EXPECT_EQ(s.upsampled_texels, 0u);
      for (std::size_t t = 0; t < field.texel_count(); ++t)
        ASSERT_EQ(filter.intensity_cd()[t], field.intensity_cd(t)) << t;
      EXPECT_NEAR(s.preview_flux_lm / s.raw_flux_lm, 1.0, 1e-12);
    }
  }
}

TEST(PreviewFilter, StabilityNeedsMoreThanTheThreshold) {
  // A texel with exactly the threshold's count is not stable (thesis: "more
  // photons than the threshold").
  const int n = 16;
  FarField field = busy_field(n, 101, 2);
  const std::size_t t = field.grid().index(3, 5, 6);
  std::vector<double> flux(field.flux_lm().begin(), field.flux_lm().end());
  std::vector<std::uint64_t> photons(field.photons().begin(), field.photons().end());
  photons[t] = 100;
  flux[t] = 1000.0;  // far brighter than its neighbourhood
  const FarField edge(n, flux, photons);
  PreviewFilter filter(n, params_with(Interpolation::Bilinear, 100.0, 99));
  const PreviewStats& s = filter.apply(edge);
  EXPECT_EQ(s.upsampled_texels, 1u);
  EXPECT_LT(filter.intensity_cd()[t], edge.intensity_cd(t) / 2.0);
  for (std::size_t u = 0; u < edge.texel_count(); ++u) {
    if (u == t) continue;
    ASSERT_EQ(filter.intensity_cd()[u], edge.intensity_cd(u));
  }
}

TEST(PreviewFilter, NoneAndOneLevelGiveTheRawMap) {
  const int n = 16;
  const FarField field = busy_field(n, 0, 3);
  for (const PreviewFilterParams& p :
       {params_with(Interpolation::None, 1e9, 99), params_with(Interpolation::Bilateral, 1e9, 1)}) {
    PreviewFilter filter(n, p);
    EXPECT_EQ(filter.apply(field).levels_used, 1);
    for (std::size_t t = 0; t < field.texel_count(); ++t)
      ASSERT_EQ(filter.intensity_cd()[t], field.intensity_cd(t));
  }
}

TEST(PreviewFilter, EmptyFieldGivesAnEmptyPreview) {
  const int n = 16;
  const FarField field(n);
  for (Interpolation kind : {Interpolation::Bilinear, Interpolation::Bilateral}) {
    for (bool adaptive : {false, true}) {
      PreviewFilterParams p = params_with(kind, 100.0, 99);
      p.adaptive = adaptive;
      PreviewFilter filter(n, p);
      const PreviewStats& s = filter.apply(field);
      EXPECT_EQ(s.preview_flux_lm, 0.0);
      for (double v : filter.intensity_cd()) ASSERT_EQ(v, 0.0);
    }
  }
}

TEST(PreviewFilter, ExtremeThresholdsStayFiniteAndBounded) {
  // Threshold 0: only empty texels are filled in. A threshold no texel
  // reaches: the whole map comes from the coarsest level, a smooth map with
  // no NaN and intensities within the raw map's range of coarse means.
  const int n = 32;
  const CubeMapGrid grid(n);
  const std::vector<double> expected =
      expected_texel_flux(grid, [](const Vec3& d) { return 1.0 + d.y * d.y; }, 2);
  FarField field(n);
  std::mt19937_64 rng(4);
  FarFieldSampler(expected).add_photons(field, 3000, 1.0, rng);
  for (Interpolation kind : {Interpolation::Bilinear, Interpolation::Bilateral}) {
    PreviewFilter zero(n, params_with(kind, 0.0, 99));
    const PreviewStats& s0 = zero.apply(field);
    std::size_t empty = 0;
    for (std::size_t t = 0; t < field.texel_count(); ++t) {
      if (field.photons(t) == 0) {
        ++empty;
      } else {
        ASSERT_EQ(zero.intensity_cd()[t], field.intensity_cd(t));
      }
    }
    EXPECT_EQ(s0.upsampled_texels, empty);

    PreviewFilter all(n, params_with(kind, std::numeric_limits<double>::max(), 99));
    const PreviewStats& s = all.apply(field);
    EXPECT_EQ(s.upsampled_texels, field.texel_count());
    const double mean = field.total_flux_lm() / (4.0 * std::numbers::pi);
    for (double v : all.intensity_cd()) {
      ASSERT_TRUE(std::isfinite(v));
      ASSERT_GT(v, 0.5 * mean);
      ASSERT_LT(v, 2.0 * mean);
    }
    EXPECT_NEAR(s.preview_flux_lm / s.raw_flux_lm, 1.0, 0.02);
  }
}

// Texels by where they sit on their face: 0 the centre (at least a quarter
// of the face from every edge), 1 along an edge (outermost ring, not a
// corner), 2 at a cube corner (2 × 2 at each face corner); −1 the rest.
int band_of(int n, std::size_t t) {
  const int x = static_cast<int>(t % n), y = static_cast<int>((t / n) % n);
  const int dx = std::min(x, n - 1 - x), dy = std::min(y, n - 1 - y);
  if (dx < 2 && dy < 2) return 2;
  if (dx < 1 || dy < 1) return 1;
  return dx >= n / 4 && dy >= n / 4 ? 0 : -1;
}

double smooth_lobe(const Vec3& d) { return 1.0 + 0.5 * d.x + 0.3 * d.y * d.z + 0.2 * d.z * d.z; }

// Far fields of photons drawn from the smooth lobe on faces of n texels, as
// a tracer fills its histogram.
class SmoothLobePhotons {
 public:
  explicit SmoothLobePhotons(int n)
      : grid_(n), expected_(expected_texel_flux(grid_, smooth_lobe, 4)), sampler_(expected_) {
    for (double f : expected_) total_ += f;
  }
  FarField draw(std::uint64_t photons, unsigned seed) const {
    FarField field(grid_.face_size());
    std::mt19937_64 rng(seed);
    sampler_.add_photons(field, photons, total_ / static_cast<double>(photons), rng);
    return field;
  }
  const CubeMapGrid& grid() const { return grid_; }
  const std::vector<double>& expected() const { return expected_; }

 private:
  CubeMapGrid grid_;
  std::vector<double> expected_;
  FarFieldSampler sampler_;
  double total_ = 0.0;
};

// Squared relative errors of a preview and of its raw map against the true
// texel fluxes, summed per band (band_of); rms() and raw_rms() of a band.
struct BandErrors {
  double preview[3] = {0, 0, 0}, raw[3] = {0, 0, 0}, count[3] = {0, 0, 0};
  void add(const CubeMapGrid& grid, const std::vector<double>& expected_flux, const FarField& field,
           const PreviewFilter& filter) {
    for (std::size_t t = 0; t < field.texel_count(); ++t) {
      const int band = band_of(grid.face_size(), t);
      if (band < 0) continue;
      const double truth = expected_flux[t] / grid.texel_solid_angle(t);
      const double p = filter.intensity_cd()[t] / truth - 1.0, r = field.intensity_cd(t) / truth - 1.0;
      preview[band] += p * p;
      raw[band] += r * r;
      count[band] += 1.0;
    }
  }
  double rms(int band) const { return std::sqrt(preview[band] / count[band]); }
  double raw_rms(int band) const { return std::sqrt(raw[band] / count[band]); }
};

TEST(PreviewFilter, ConstantFieldStaysConstantAcrossEdgesAndCorners) {
  // The exact map of an isotropic source, every texel forced through
  // interpolation from the coarsest level down: a wrong neighbour across an
  // edge or a missing one at a cube corner would show as a seam or a dark
  // corner; the preview is the constant everywhere.
  const int n = 32;
  FarField field(n);
  for (std::size_t t = 0; t < field.texel_count(); ++t) field.add(t, 7.0 * field.grid().texel_solid_angle(t), 1);
  for (Interpolation kind : {Interpolation::Bilinear, Interpolation::Bilateral}) {
    PreviewFilter filter(n, params_with(kind, 1e9, 99));
    EXPECT_EQ(filter.apply(field).upsampled_texels, field.texel_count());
    for (std::size_t t = 0; t < field.texel_count(); ++t) ASSERT_NEAR(filter.intensity_cd()[t], 7.0, 1e-12) << t;
  }
}

TEST(PreviewFilter, InterpolationBiasIsNoLargerAtFaceEdgesAndCorners) {
  // The exact (noise-free) map of a smooth lobe with gradients across every
  // face edge, every texel interpolated: what remains is the interpolation's
  // bias, printed as "[ measured ]" (faces of 64, automatic 3 levels: about
  // 0.0022 at centres, 0.0025 along edges, 0.0019 at cube corners). A wrong
  // neighbour across an edge costs several percent.
  const int n = 64;
  const CubeMapGrid grid(n);
  const std::vector<double> expected = expected_texel_flux(grid, smooth_lobe, 4);
  const FarField field(n, expected, std::vector<std::uint64_t>(expected.size(), 1));
  for (Interpolation kind : {Interpolation::Bilinear, Interpolation::Bilateral}) {
    PreviewFilter filter(n, params_with(kind, 1e9, 0));
    filter.apply(field);
    double sum[3] = {0, 0, 0}, count[3] = {0, 0, 0};
    for (std::size_t t = 0; t < field.texel_count(); ++t) {
      const int band = band_of(n, t);
      if (band < 0) continue;
      const double r = filter.intensity_cd()[t] / field.intensity_cd(t) - 1.0;
      sum[band] += r * r;
      count[band] += 1.0;
    }
    const double centre = std::sqrt(sum[0] / count[0]), edge = std::sqrt(sum[1] / count[1]),
                 corner = std::sqrt(sum[2] / count[2]);
    std::printf("[ measured ] %s interpolation bias: centre %.5f, edges %.5f (%.2f×), corners %.5f (%.2f×)\n",
                kind == Interpolation::Bilinear ? "bilinear" : "bilateral", centre, edge, edge / centre, corner,
                corner / centre);
    EXPECT_LT(centre, 0.005);
    EXPECT_LT(edge, 1.3 * centre);
    EXPECT_LT(corner, 1.3 * centre);
  }
}

TEST(PreviewFilter, SparseSmoothFieldHasNoSeams) {
  // Photons drawn from a smooth lobe, 2 per texel on average, filtered with
  // the defaults; four seeds. Cube-corner texels are 5.2× smaller than centre
  // ones and so hold 5.2× fewer photons: the raw histogram's relative error
  // is 1.6× (edges) and 2.0× (corners) that of the centres, and the coarse
  // levels the preview draws on inherit it (preview ratios about 1.6 and
  // 1.9). A seam would make the filter help less at edges and corners than
  // at centres; it helps as much: about 6.6× less error than the raw map at
  // centres, 6.9× along edges, 6.4× at cube corners. The figures are printed
  // as "[ measured ]".
  const int n = 64;
  const SmoothLobePhotons lobe(n);
  BandErrors errors;
  PreviewFilter filter(n, PreviewFilterParams{});
  for (unsigned seed = 1; seed <= 4; ++seed) {
    const FarField field = lobe.draw(2 * lobe.grid().texel_count(), seed);
    filter.apply(field);
    errors.add(lobe.grid(), lobe.expected(), field, filter);
  }
  double improvement[3], rms[3], raw_rms[3];
  for (int b = 0; b < 3; ++b) {
    rms[b] = errors.rms(b);
    raw_rms[b] = errors.raw_rms(b);
    improvement[b] = raw_rms[b] / rms[b];
  }
  std::printf("[ measured ] relative RMS error of the preview (raw map): centre %.4f (%.4f), edges %.4f (%.4f), "
              "corners %.4f (%.4f); edges/centre %.2f (%.2f), corners/centre %.2f (%.2f); improvement over the raw "
              "map %.1f× centre, %.1f× edges, %.1f× corners\n",
              rms[0], raw_rms[0], rms[1], raw_rms[1], rms[2], raw_rms[2], rms[1] / rms[0], raw_rms[1] / raw_rms[0],
              rms[2] / rms[0], raw_rms[2] / raw_rms[0], improvement[0], improvement[1], improvement[2]);
  EXPECT_GT(improvement[0], 4.0);
  EXPECT_GT(improvement[1], 0.9 * improvement[0]);
  EXPECT_GT(improvement[2], 0.85 * improvement[0]);
}

// A smooth field has no detail the size of one texel: a preview texel far
// below or above all its neighbours is noise the adaptive test took for
// detail. By chance a texel's count contradicts its estimate at z = 3.5 in
// ~5·10⁻⁴ of the texels where a few photons are expected (one with none
// where eight are expected: e⁻⁸ alone); kept as they were, they showed as
// dark specks in a bright region. A contradiction is kept only where a
// neighbour shows it too. Smooth lobe, 64-texel faces, 10 and 40 photons
// per texel, four seeds each, the specks counted among face-interior texels
// ("[ measured ]": 0; without the neighbour rule 144 of the 154 texels kept
// raw).
TEST(PreviewFilter, NoLoneSpecksOnASmoothField) {
  const int n = 64;
  const SmoothLobePhotons lobe(n);
  PreviewFilter filter(n, PreviewFilterParams{});
  int specks = 0;
  std::size_t kept = 0;
  for (std::uint64_t per_texel : {10u, 40u}) {
    for (unsigned seed = 1; seed <= 4; ++seed) {
      kept += filter.apply(lobe.draw(per_texel * lobe.grid().texel_count(), seed)).stable_texels;
      const std::span<const double> preview = filter.intensity_cd();
      for (int face = 0; face < 6; ++face)
        for (int y = 1; y + 1 < n; ++y)
          for (int x = 1; x + 1 < n; ++x) {
            const auto at = [&](int dx, int dy) {
              return preview[static_cast<std::size_t>((face * n + y + dy) * n + x + dx)];
            };
            double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx)
                if (dx != 0 || dy != 0) {
                  lo = std::min(lo, at(dx, dy));
                  hi = std::max(hi, at(dx, dy));
                }
            specks += at(0, 0) < 0.7 * lo || at(0, 0) > 1.4 * hi;
          }
    }
  }
  std::printf("[ measured ] lone specks in 8 previews of a smooth field: %d (texels kept raw: %zu)\n", specks, kept);
  EXPECT_EQ(specks, 0);
}

TEST(PreviewFilter, UniformNoiseGivesNoMoreErrorAtFaceEdgesAndCornersThanAtCentres) {
  // The requirement read literally: with the same expected photon count in
  // every texel (2), the raw map's relative noise is the same everywhere, and
  // the preview's relative RMS error along face edges and at cube corners is
  // no worse than at face centres. Counts are Poisson, and a texel's photons
  // carry its share of the smooth lobe (flux = count × expected flux / 2), so
  // the field is smooth across every edge while the noise is uniform.
  // Measured over 20 sets of 128 seeds: edges 0.97× (bilinear) and 0.95×
  // (bilateral) the centres' error, cube corners 1.055 ± 0.021× and
  // 1.033 ± 0.019×, at most 1.093×. Those few per cent at the corners are the
  // cube's geometry: three faces meet there, so the look-up past the corner
  // is the mean of three coarse texels and the interpolation averages three
  // independent values instead of four (+9 % variance at the corner texel on
  // each level). The bound 1.12 lies three standard deviations above the
  // bilinear corners' mean; leaving the look-up past a cube corner dark
  // measured 1.22×. (Biases small against this noise, a neighbour a few
  // texels off along an edge, are InterpolationBiasIsNoLargerAtFaceEdges…'s
  // to find.) The seeds are fixed: the figures printed as "[ measured ]" are
  // the same at every run.
  // The thesis's filter at its fixed threshold, bilinear and bilateral: the
  // adaptive default is left out, since it predicts a texel's count from the
  // map's photons per lumen, which assumes photons of equal power. (Equal
  // powers with uniform counts need I ∝ 1 / texel solid angle, a field with a
  // ridge along every edge that any interpolation rounds off.)
  const int n = 64;
  const double per_texel = 2.0;
  const CubeMapGrid grid(n);
  const std::vector<double> expected = expected_texel_flux(grid, smooth_lobe, 4);
  for (Interpolation kind : {Interpolation::Bilinear, Interpolation::Bilateral}) {
    PreviewFilter filter(n, params_with(kind, PreviewFilterParams::kFixedThreshold, 0));
    BandErrors errors;
    for (unsigned seed = 1; seed <= 128; ++seed) {
      std::mt19937_64 rng(seed);
      std::poisson_distribution<std::uint64_t> poisson(per_texel);
      std::vector<double> flux(grid.texel_count());
      std::vector<std::uint64_t> photons(grid.texel_count());
      for (std::size_t t = 0; t < flux.size(); ++t) {
        photons[t] = poisson(rng);
        flux[t] = static_cast<double>(photons[t]) * expected[t] / per_texel;
      }
      const FarField field(n, std::move(flux), std::move(photons));
      filter.apply(field);
      errors.add(grid, expected, field, filter);
    }
    double rms[3], raw_rms[3];
    for (int b = 0; b < 3; ++b) {
      rms[b] = errors.rms(b);
      raw_rms[b] = errors.raw_rms(b);
    }
    std::printf("[ measured ] uniform noise, %s: preview error centre %.4f, edges %.3f×, corners %.3f× the centre's "
                "(raw map %.4f, %.3f×, %.3f×)\n",
                kind == Interpolation::Bilinear ? "bilinear" : "bilateral", rms[0], rms[1] / rms[0], rms[2] / rms[0],
                raw_rms[0], raw_rms[1] / raw_rms[0], raw_rms[2] / raw_rms[0]);
    // The premise: uniform raw noise (1/√2 everywhere, within the sampling
    // spread of 96 corner texels × 128 seeds).
    EXPECT_NEAR(raw_rms[1] / raw_rms[0], 1.0, 0.03);
    EXPECT_NEAR(raw_rms[2] / raw_rms[0], 1.0, 0.05);
    EXPECT_LT(rms[0], 0.2 * raw_rms[0]);  // and the filter does smooth
    EXPECT_LE(rms[1], 1.12 * rms[0]);
    EXPECT_LE(rms[2], 1.12 * rms[0]);
  }
}

TEST(PreviewFilter, BilateralLeaksLessThanBilinearAcrossASharpEdge) {
  // A 30° spot (1 inside, 0.01 outside) at 2.5 photons per texel on faces
  // of 64 (automatic levels). Leak: the preview's flux more than 3° outside
  // the cut-off over the raw map's there, − 1. Measured (printed as
  // "[ measured ]"): with the thesis's fixed threshold bilinear +12 %,
  // bilateral +2.5 %; with the adaptive default +1.3 % (bilinear), +0.3 %
  // (bilateral). Total flux of the preview against the raw map: fixed +4.8 %
  // (bilinear), +3.7 % (bilateral): dark texels take in light while bright
  // ones keep theirs; adaptive −2.9 %, −2.3 %: unstable texels on the bright
  // side of the cut-off take in some of the dark.
  const int n = 64;
  const CubeMapGrid grid(n);
  const double cut = 30.0 * std::numbers::pi / 180.0, margin = 3.0 * std::numbers::pi / 180.0;
  const auto angle = [](const Vec3& d) { return std::acos(std::clamp(-d.y, -1.0, 1.0)); };
  const std::vector<double> expected =
      expected_texel_flux(grid, [&](const Vec3& d) { return angle(d) < cut ? 1.0 : 0.01; }, 4);
  double total = 0.0;
  for (double f : expected) total += f;
  FarField field(n);
  std::mt19937_64 rng(1);
  const std::uint64_t photons = 5 * field.texel_count() / 2;
  FarFieldSampler(expected).add_photons(field, photons, total / static_cast<double>(photons), rng);
  const auto leak_and_flux = [&](const PreviewFilterParams& p) {
    PreviewFilter filter(n, p);
    const PreviewStats& s = filter.apply(field);
    double dark = 0.0, dark_raw = 0.0;
    for (std::size_t t = 0; t < field.texel_count(); ++t) {
      if (angle(grid.texel_direction(t)) < cut + margin) continue;
      dark += filter.intensity_cd()[t] * grid.texel_solid_angle(t);
      dark_raw += field.flux_lm(t);
    }
    return std::pair{dark / dark_raw - 1.0, s.preview_flux_lm / s.raw_flux_lm};
  };
  const auto [bilinear_leak, bilinear_flux] = leak_and_flux(params_with(Interpolation::Bilinear, 100.0, 0));
  const auto [bilateral_leak, bilateral_flux] = leak_and_flux(params_with(Interpolation::Bilateral, 100.0, 0));
  std::printf("[ measured ] fixed threshold: leak bilinear %+.1f %%, bilateral %+.1f %%; preview/raw flux %.3f, %.3f\n",
              100 * bilinear_leak, 100 * bilateral_leak, bilinear_flux, bilateral_flux);
  EXPECT_GT(bilinear_leak, 0.08);
  EXPECT_LT(bilateral_leak, 0.5 * bilinear_leak);
  EXPECT_GT(bilinear_flux, 1.0);
  EXPECT_LT(bilinear_flux, 1.08);
  EXPECT_GT(bilateral_flux, 1.0);
  EXPECT_LT(bilateral_flux, bilinear_flux);
  for (Interpolation kind : {Interpolation::Bilinear, Interpolation::Bilateral}) {
    PreviewFilterParams p;
    p.interpolation = kind;
    const auto [leak, flux] = leak_and_flux(p);
    std::printf("[ measured ] adaptive %s: leak %+.1f %%, preview/raw flux %.3f\n",
                kind == Interpolation::Bilinear ? "bilinear" : "bilateral", 100 * leak, flux);
    EXPECT_LT(std::abs(leak), 0.03);
    EXPECT_NEAR(flux, 0.975, 0.02);
  }
}

TEST(PreviewFilter, SparseMapsGiveFiniteIntensitiesInEveryConfiguration) {
  // Single photons in a dark sky: repeated bilateral interpolation drives
  // values towards 1e-200 and below; nothing may turn into NaN.
  const int n = 64;
  FarField field(n);
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<std::size_t> texel(0, field.texel_count() - 1);
  for (int i = 0; i < 40; ++i) field.add(texel(rng), 1.0);
  for (Interpolation kind : {Interpolation::Bilinear, Interpolation::Bilateral}) {
    for (RangeScale scale : {RangeScale::LocalMax, RangeScale::Estimate}) {
      for (bool adaptive : {false, true}) {
        for (int levels : {0, 3, 99}) {
          PreviewFilterParams p;
          p.interpolation = kind;
          p.range_scale = scale;
          p.adaptive = adaptive;
          p.levels = levels;
          p.threshold_photons = adaptive ? 6400.0 : 100.0;
          for (double sigma : {0.5, 0.01}) {
            p.sigma_d = p.sigma_r = sigma;
            PreviewFilter filter(n, p);
            const PreviewStats& s = filter.apply(field);
            ASSERT_TRUE(std::isfinite(s.preview_flux_lm));
            for (double v : filter.intensity_cd()) ASSERT_TRUE(std::isfinite(v) && v >= 0.0);
          }
        }
      }
    }
  }
}

TEST(PreviewFilter, FaceSizesThatAreNotPowersOfTwoUseTheLevelsTheyHave) {
  // 24 halves to 12, 6 and 3: four levels at most, two automatically (the
  // automatic choice stops at 16 texels or the first odd size). An odd face
  // size has level 0 only: the preview is the raw map.
  EXPECT_EQ(PreviewFilter::auto_levels(24), 2);
  EXPECT_EQ(PreviewFilter::auto_levels(128), 4);
  EXPECT_EQ(PreviewFilter::auto_levels(256), 5);
  EXPECT_EQ(PreviewFilter::auto_levels(16), 2);
  EXPECT_EQ(PreviewFilter::auto_levels(9), 1);
  for (int n : {24, 9}) {
    const FarField field = busy_field(n, 0, 11);
    PreviewFilter filter(n, params_with(Interpolation::Bilateral, 1e9, 99));
    const PreviewStats& s = filter.apply(field);
    EXPECT_EQ(s.levels_used, n == 24 ? 4 : 1);
    for (std::size_t t = 0; t < field.texel_count(); ++t) {
      ASSERT_TRUE(std::isfinite(filter.intensity_cd()[t]));
      if (n == 9) {
        ASSERT_EQ(filter.intensity_cd()[t], field.intensity_cd(t));
      }
    }
  }
}

TEST(PreviewFilter, SameResultWithOneThreadOrMany) {
  const int n = 128;
  const CubeMapGrid grid(n);
  const std::vector<double> expected =
      expected_texel_flux(grid, [](const Vec3& d) { return d.y < -0.3 ? 1.0 : 0.05; }, 1);
  FarField field(n);
  std::mt19937_64 rng(6);
  FarFieldSampler(expected).add_photons(field, 200'000, 1.0, rng);
  PreviewFilterParams p;
  p.adaptive = true;
  PreviewFilter many(n, p), one(n, p);
  const PreviewStats s_many = many.apply(field);
  PreviewStats s_one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    s_one = one.apply(field);
  }
  EXPECT_EQ(s_one.preview_flux_lm, s_many.preview_flux_lm);
  EXPECT_EQ(s_one.stable_texels, s_many.stable_texels);
  for (std::size_t t = 0; t < field.texel_count(); ++t)
    ASSERT_EQ(one.intensity_cd()[t], many.intensity_cd()[t]);
}

TEST(PreviewFilter, ApplyAllocatesNothing) {
  const int n = 64;
  const FarField field = busy_field(n, 0, 7);
  PreviewFilterParams p;
  p.adaptive = true;
  PreviewFilter filter(n, p);
  filter.apply(field);
  const long before = g_allocations.load();
  for (int i = 0; i < 3; ++i) {
    filter.apply(field);
    p.interpolation = i == 1 ? Interpolation::Bilinear : Interpolation::Bilateral;
    p.levels = 3 + i;
    filter.set_params(p);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
}

}  // namespace
}  // namespace gonio::sim
