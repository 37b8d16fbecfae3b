#include "sim/filter/preview_filter.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "photometry/diagnostics.h"
#include "sim/filter/cube_neighbours.h"

namespace gonio::sim {
namespace {

void check_params(const PreviewFilterParams& p) {
  GONIO_CHECK_MSG(p.threshold_photons >= 0.0 && std::isfinite(p.threshold_photons),
                  "preview threshold must be a finite count ≥ 0");
  GONIO_CHECK_MSG(p.levels >= 0, "preview levels must be ≥ 0 (0: automatic)");
  GONIO_CHECK_MSG(p.sigma_d > 0.0 && std::isfinite(p.sigma_d), "sigma_d must be > 0");
  GONIO_CHECK_MSG(p.sigma_r > 0.0 && std::isfinite(p.sigma_r), "sigma_r must be > 0");
  GONIO_CHECK_MSG(p.adaptive_z > 0.0 && std::isfinite(p.adaptive_z), "adaptive_z must be > 0");
}

std::size_t padded_size(int m) {
  const std::size_t s = static_cast<std::size_t>(m) + 2;
  return static_cast<std::size_t>(kCubeFaces) * s * s;
}

// Runs body(row_begin, row_end) over rows, in parallel when there are enough
// texels to pay for it. Each row is written by one task only.
template <class Body>
void for_rows(std::size_t rows, std::size_t row_length, const Body& body) {
  if (rows * row_length < 16384) {
    body(std::size_t{0}, rows);
    return;
  }
  const std::size_t grain = std::max<std::size_t>(1, 4096 / row_length);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rows, grain),
                    [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
}

// Minimum and maximum by value: std::min and std::max select references,
// which keeps GCC from vectorising the loops below.
inline double min2(double a, double b) { return a < b ? a : b; }
inline double max2(double a, double b) { return a > b ? a : b; }

// e^(−x) for x ≥ 0 to a relative 1e-9, branch-free so that loops over a
// row vectorise: 2^(−x·log₂e) = 2^(−i) · e^z with i = round(x·log₂e) and
// |z| ≤ ln2 / 2, 2^(−i) built from its bits and e^z by a degree-8 Taylor
// polynomial. x is clipped at 700 (e^−700 = 1e-304). The range weights are
// most of the filter's time; std::exp, one value at a time, made the whole
// filter three times slower (measured), and its last digits buy nothing in
// weights that are normalised anyway.
inline double exp_neg(double x) {
  constexpr double kShift = 6755399441055744.0;  // 1.5 · 2^52: adding it rounds to an integer
  const double t = min2(x, 700.0) * 1.4426950408889634;
  const double shifted = t + kShift;
  const double i = shifted - kShift;  // round(t)
  const double z = (i - t) * 0.6931471805599453;
  const double z2 = z * z, z4 = z2 * z2;
  const double p = ((1.0 + z) + z2 * (1.0 / 2 + z * (1.0 / 6))) +
                   z4 * (((1.0 / 24 + z * (1.0 / 120)) + z2 * (1.0 / 720 + z * (1.0 / 5040))) +
                         z4 * (1.0 / 40320));
  // round(t) sits in the low bits of `shifted`; 2^(−i) has exponent field 1023 − i.
  const std::uint64_t n = std::bit_cast<std::uint64_t>(shifted) - std::bit_cast<std::uint64_t>(kShift);
  const double two_to_minus_i = std::bit_cast<double>((std::uint64_t{1023} - n) << 52);
  return p * two_to_minus_i;
}

// Fine texels are interpolated a row chunk at a time: the arithmetic runs in
// loops over the chunk that the compiler vectorises, instead of one long
// dependency chain per texel.
constexpr int kChunk = 32;

// The interpolation of fine texels from the 2 × 2 coarse texels around each
// centre. A fine texel centre sits a quarter of a coarse texel from the
// nearest coarse centre, so the bilinear weights are 3/4 and 1/4 per axis
// and the closeness terms take four values per parity of (x, y).
struct Kernel {
  Interpolation kind = Interpolation::Bilinear;
  RangeScale scale = RangeScale::Estimate;
  double inv_two_sigma_r2 = 0.0;
  // [2 · (y & 1) + (x & 1)][corner]: exp(−d² / 2σ_d²) with d the distance
  // to the coarse centre [coarse texels], scaled so the largest is 1.
  std::array<std::array<double, 4>, 4> closeness{};

  explicit Kernel(const PreviewFilterParams& p) : kind(p.interpolation), scale(p.range_scale) {
    inv_two_sigma_r2 = 0.5 / (p.sigma_r * p.sigma_r);
    const double inv_two_sigma_d2 = 0.5 / (p.sigma_d * p.sigma_d);
    for (int parity = 0; parity < 4; ++parity) {
      const double fx = (parity & 1) ? 0.25 : 0.75, fy = (parity & 2) ? 0.25 : 0.75;
      const double gx = 1.0 - fx, gy = 1.0 - fy;
      const double d2[4] = {fx * fx + fy * fy, gx * gx + fy * fy, fx * fx + gy * gy, gx * gx + gy * gy};
      const double d2_min = std::min({d2[0], d2[1], d2[2], d2[3]});
      for (std::size_t i = 0; i < 4; ++i)
        closeness[static_cast<std::size_t>(parity)][i] = std::exp(-(d2[i] - d2_min) * inv_two_sigma_d2);
    }
  }

  // Interpolates fine texels x0 … x0 + count − 1 (count ≤ kChunk) of fine row
  // y into out. `face` is the coarse level's padded face block, `stride` its
  // row length.
  void operator()(const double* face, std::size_t stride, int x0, int y, int count, double* out) const {
    const double* row0 = face + static_cast<std::size_t>((y + 1) >> 1) * stride;
    const double* row1 = row0 + stride;
    const double fy = (y & 1) ? 0.25 : 0.75;
    alignas(16) double v0[kChunk], v1[kChunk], v2[kChunk], v3[kChunk], fx[kChunk];
    for (int k = 0; k < count; ++k) {
      const int x = x0 + k;
      const std::size_t col = static_cast<std::size_t>((x + 1) >> 1);
      v0[k] = row0[col];
      v1[k] = row0[col + 1];
      v2[k] = row1[col];
      v3[k] = row1[col + 1];
      fx[k] = (x & 1) ? 0.25 : 0.75;
    }
    for (int k = 0; k < count; ++k)
      out[k] = (1.0 - fy) * ((1.0 - fx[k]) * v0[k] + fx[k] * v1[k]) + fy * ((1.0 - fx[k]) * v2[k] + fx[k] * v3[k]);
    if (kind != Interpolation::Bilateral) return;

    // Closeness weights by x parity for this row's y parity.
    alignas(16) double c0[kChunk], c1[kChunk], c2[kChunk], c3[kChunk];
    for (int k = 0; k < count; ++k) {
      const std::array<double, 4>& c = closeness[static_cast<std::size_t>(((y & 1) << 1) | ((x0 + k) & 1))];
      c0[k] = c[0];
      c1[k] = c[1];
      c2[k] = c[2];
      c3[k] = c[3];
    }
    // Branch-free from here, so that it vectorises. Scaled before squaring:
    // the scale may be tiny where a dark region was filled in from dark
    // coarse texels, and its square would underflow. It is 0 only when all
    // four are 0, and then any finite scale does.
    alignas(16) double inv_scale[kChunk];
    if (scale == RangeScale::LocalMax) {
      for (int k = 0; k < count; ++k)
        inv_scale[k] = 1.0 / max2(max2(max2(v0[k], v1[k]), max2(v2[k], v3[k])),
                                  std::numeric_limits<double>::min());
    } else {
      for (int k = 0; k < count; ++k) inv_scale[k] = 1.0 / max2(out[k], std::numeric_limits<double>::min());
    }
    for (int k = 0; k < count; ++k) {
      const double bilinear = out[k];
      const double inv_s = inv_scale[k];
      const double d0 = (v0[k] - bilinear) * inv_s, d1 = (v1[k] - bilinear) * inv_s;
      const double d2 = (v2[k] - bilinear) * inv_s, d3 = (v3[k] - bilinear) * inv_s;
      const double r0 = inv_two_sigma_r2 * d0 * d0, r1 = inv_two_sigma_r2 * d1 * d1;
      const double r2 = inv_two_sigma_r2 * d2 * d2, r3 = inv_two_sigma_r2 * d3 * d3;
      // Range weights relative to the largest (which is then 1), closeness
      // weights relative to the nearest centre's: nothing underflows for
      // sensible σ. The bilinear estimate enters with a negligible weight,
      // so that it stands where a tiny σ_d and σ_r leave no other.
      const double r_min = min2(min2(r0, r1), min2(r2, r3));
      const double w0 = c0[k] * exp_neg(r0 - r_min), w1 = c1[k] * exp_neg(r1 - r_min);
      const double w2 = c2[k] * exp_neg(r2 - r_min), w3 = c3[k] * exp_neg(r3 - r_min);
      constexpr double kTiny = 1e-300;
      const double sum_w = ((w0 + w1) + (w2 + w3)) + kTiny;
      const double sum_wv = ((w0 * v0[k] + w1 * v1[k]) + (w2 * v2[k] + w3 * v3[k])) + kTiny * bilinear;
      out[k] = sum_wv / sum_w;
    }
  }
};

}  // namespace

bool is_shadow_border(double photons, std::span<const double> neighbour_photons,
                      double threshold_photons) {
  int stable = 0;
  for (double n : neighbour_photons) stable += (photons + n >= 2.0 * threshold_photons) ? 1 : 0;
  return stable >= 3 && stable <= 6;
}

PreviewFilter::PreviewFilter(int face_size, const PreviewFilterParams& params)
    : PreviewFilter(face_size, params, {}) {}

PreviewFilter::PreviewFilter(int face_size, const PreviewFilterParams& params,
                             std::span<const double> face_solid_angle_sr)
    : n_(face_size),
      params_(params),
      pyramid_(face_solid_angle_sr.empty()
                   ? CubePyramid(face_size, CubePyramid::max_levels(face_size))
                   : CubePyramid(face_size, CubePyramid::max_levels(face_size),
                                 face_solid_angle_sr)) {
  check_params(params_);
  const int levels = pyramid_.levels();
  filtered_.resize(static_cast<std::size_t>(levels));
  counts_.resize(static_cast<std::size_t>(levels));
  contradictions_.resize(static_cast<std::size_t>(levels));
  halo_source_.resize(static_cast<std::size_t>(levels));
  for (int k = 0; k < levels; ++k) {
    const int m = pyramid_.face_size(k);
    if (k >= 1) filtered_[static_cast<std::size_t>(k)].assign(padded_size(m), 0.0);
    if (k >= 2) counts_[static_cast<std::size_t>(k)].assign(padded_size(m), 0.0);
    if (k + 1 < levels) contradictions_[static_cast<std::size_t>(k)].assign(padded_size(m), 0.0);
    const CubeNeighbours neighbours(m);
    const std::size_t mm = static_cast<std::size_t>(m), stride = mm + 2;
    std::vector<std::uint32_t>& source = halo_source_[static_cast<std::size_t>(k)];
    source.resize(static_cast<std::size_t>(kCubeFaces) * 4 * mm);
    for (int face = 0; face < kCubeFaces; ++face) {
      for (int edge = 0; edge < 4; ++edge) {
        for (int p = 0; p < m; ++p) {
          const std::size_t t = neighbours.across_edge(face, static_cast<FaceEdge>(edge), p);
          const std::size_t f = t / (mm * mm), x = t % mm, y = (t / mm) % mm;
          source[(static_cast<std::size_t>(face) * 4 + static_cast<std::size_t>(edge)) * mm +
                 static_cast<std::size_t>(p)] =
              static_cast<std::uint32_t>(f * stride * stride + (y + 1) * stride + (x + 1));
        }
      }
    }
  }
  output_.assign(pyramid_.texel_count(0), 0.0);
  estimates_.assign(pyramid_.texel_count(0), 0.0);
  row_flux_.assign(static_cast<std::size_t>(kCubeFaces) * static_cast<std::size_t>(n_), 0.0);
  row_stable_.assign(row_flux_.size(), 0);
}

void PreviewFilter::set_params(const PreviewFilterParams& params) {
  check_params(params);
  params_ = params;
}

int PreviewFilter::auto_levels(int face_size) {
  int levels = 1;
  for (int m = face_size; m > 16 && m % 2 == 0; m /= 2) ++levels;
  return std::min(std::max(levels, 2), CubePyramid::max_levels(face_size));
}

int PreviewFilter::levels_used() const {
  if (params_.interpolation == Interpolation::None) return 1;
  return std::min(params_.levels == 0 ? auto_levels(n_) : params_.levels, pyramid_.levels());
}

void PreviewFilter::fill_halo(int level, std::vector<double>& padded, bool corners) const {
  const std::size_t m = static_cast<std::size_t>(pyramid_.face_size(level)), stride = m + 2;
  const std::vector<std::uint32_t>& source = halo_source_[static_cast<std::size_t>(level)];
  for (std::size_t face = 0; face < static_cast<std::size_t>(kCubeFaces); ++face) {
    double* block = padded.data() + face * stride * stride;
    const std::uint32_t* src = source.data() + face * 4 * m;
    for (std::size_t p = 0; p < m; ++p) {
      block[(p + 1) * stride] = padded[src[p]];                   // left:   x = −1
      block[(p + 1) * stride + m + 1] = padded[src[m + p]];       // right:  x = M
      block[p + 1] = padded[src[2 * m + p]];                      // top:    y = −1
      block[(m + 1) * stride + p + 1] = padded[src[3 * m + p]];   // bottom: y = M
    }
    if (!corners) continue;
    // Past a cube corner: the mean of the three texels that meet there.
    auto corner = [&](std::size_t cx, std::size_t cy, std::size_t ix, std::size_t iy) {
      block[cy * stride + cx] =
          (block[iy * stride + ix] + block[iy * stride + cx] + block[cy * stride + ix]) / 3.0;
    };
    corner(0, 0, 1, 1);
    corner(m + 1, 0, m, 1);
    corner(0, m + 1, 1, m);
    corner(m + 1, m + 1, m, m);
  }
}

namespace {

// The 8 neighbours of texel (x, y) of an M × M face (`at`: its entry in a
// padded per-face array of row length `stride`, with the adjacent faces'
// texels as border); 7 at a cube corner, where none lies diagonally past it.
std::size_t neighbours(const double* at, std::size_t stride, std::size_t x, std::size_t y, std::size_t m,
                       std::array<double, 8>& out) {
  const bool edge_x = x == 0 || x + 1 == m, edge_y = y == 0 || y + 1 == m;
  std::size_t found = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      if (dx == 0 && dy == 0) continue;
      const bool out_x = edge_x && ((dx < 0 && x == 0) || (dx > 0 && x + 1 == m));
      const bool out_y = edge_y && ((dy < 0 && y == 0) || (dy > 0 && y + 1 == m));
      if (out_x && out_y) continue;  // past a cube corner
      out[found++] = at[static_cast<std::ptrdiff_t>(dy) * static_cast<std::ptrdiff_t>(stride) + dx];
    }
  }
  return found;
}

}  // namespace

void PreviewFilter::push_level(int level, int top, double photons_per_lm) {
  const int m = pyramid_.face_size(level);
  const std::size_t mm = static_cast<std::size_t>(m);
  const std::span<const double> flux = pyramid_.flux_lm(level);
  const std::span<const std::uint64_t> photons = pyramid_.photons(level);
  const std::span<const double> omega = pyramid_.face_solid_angle_sr(level);
  const double threshold = params_.threshold_photons;
  const bool adaptive = params_.adaptive;
  const double half_z = 0.5 * params_.adaptive_z;
  const bool borders = params_.shadow_borders && level >= 2 && level < top;
  const bool upsample = level < top;
  const Kernel kernel(params_);

  const std::size_t mc = mm / 2, coarse_stride = mc + 2;
  const double* coarse = upsample ? filtered_[static_cast<std::size_t>(level) + 1].data() : nullptr;
  const std::size_t stride = mm + 2;
  double* out = level == 0 ? output_.data() : filtered_[static_cast<std::size_t>(level)].data();
  const double* counts = borders ? counts_[static_cast<std::size_t>(level)].data() : nullptr;

  if (borders) {
    std::vector<double>& c = counts_[static_cast<std::size_t>(level)];
    for (std::size_t r = 0; r < 6 * mm; ++r) {
      const std::size_t face = r / mm, y = r % mm;
      for (std::size_t x = 0; x < mm; ++x)
        c[face * stride * stride + (y + 1) * stride + x + 1] =
            static_cast<double>(photons[r * mm + x]);
    }
    fill_halo(level, c, false);
  }

  // First pass: every texel's upsampled estimate and, with adaptive
  // stability, whether its photon count contradicts it (+1: more photons
  // than the estimate predicts, −1: fewer, 0: no), with a border of the
  // adjacent faces' texels.
  double* estimates = estimates_.data();
  double* contradicts = contradictions_[static_cast<std::size_t>(level)].data();
  if (upsample) {
    for_rows(6 * mm, mm, [&](std::size_t row_begin, std::size_t row_end) {
      for (std::size_t r = row_begin; r < row_end; ++r) {
        const std::size_t face = r / mm, y = r % mm;
        const double* coarse_face = coarse + face * coarse_stride * coarse_stride;
        double* contradicts_row = contradicts + face * stride * stride + (y + 1) * stride + 1;
        for (std::size_t x = 0; x < mm; x += kChunk) {
          const int count = static_cast<int>(std::min<std::size_t>(kChunk, mm - x));
          kernel(coarse_face, coarse_stride, static_cast<int>(x), static_cast<int>(y), count, estimates + r * mm + x);
        }
        if (!adaptive) continue;
        for (std::size_t x = 0; x < mm; ++x) {
          const std::size_t t = r * mm + x;
          const double n = static_cast<double>(photons[t]);
          const double expected = estimates[t] * omega[y * mm + x] * photons_per_lm;
          const double d = std::sqrt(n + 0.375) - std::sqrt(expected + 0.375);
          contradicts_row[x] = d > half_z ? 1.0 : d < -half_z ? -1.0 : 0.0;
        }
      }
    });
    if (adaptive) fill_halo(level, contradictions_[static_cast<std::size_t>(level)], false);
  }

  for_rows(6 * mm, mm, [&](std::size_t row_begin, std::size_t row_end) {
    std::array<double, 8> nb{};
    for (std::size_t r = row_begin; r < row_end; ++r) {
      const std::size_t face = r / mm, y = r % mm;
      double* out_row = level == 0 ? out + r * mm : out + face * stride * stride + (y + 1) * stride + 1;
      double row_flux = 0.0;
      std::uint32_t row_stable = 0;
      for (std::size_t x = 0; x < mm; ++x) {
        const std::size_t t = r * mm + x;
        const std::size_t padded = face * stride * stride + (y + 1) * stride + x + 1;
        const double n = static_cast<double>(photons[t]);
        const double w = omega[y * mm + x];
        bool keep = !upsample || n > threshold;
        if (!keep && adaptive) {
          // A contradiction is detail when a neighbour shows it too (a
          // cut-off, a shadow, a beam span texels); a lone one is noise (at
          // z = 3.5, ~5·10⁻⁴ of the texels where a few photons are expected:
          // dark specks in a bright region, sparks in a dim one).
          const double sign = contradicts[padded];
          if (sign != 0.0) {
            const std::size_t found = neighbours(contradicts + padded, stride, x, y, mm, nb);
            for (std::size_t i = 0; i < found && !keep; ++i) keep = nb[i] == sign;
          }
        }
        if (!keep && borders) {
          const std::size_t found = neighbours(counts + padded, stride, x, y, mm, nb);
          keep = is_shadow_border(n, std::span<const double>(nb.data(), found), threshold);
        }
        const double value = keep ? flux[t] / w : estimates[t];
        out_row[x] = value;
        if (level == 0) {
          row_flux += value * w;
          row_stable += keep ? 1u : 0u;
        }
      }
      if (level == 0) {
        row_flux_[r] = row_flux;
        row_stable_[r] = row_stable;
      }
    }
  });
  if (level > 0) fill_halo(level, filtered_[static_cast<std::size_t>(level)], true);
}

const PreviewStats& PreviewFilter::apply(const FarField& field) {
  GONIO_CHECK_MSG(field.face_size() == n_, "far field and preview filter differ in face size");
  const int top = levels_used() - 1;
  stats_ = PreviewStats{};
  stats_.levels_used = top + 1;
  if (top == 0) {
    for (std::size_t t = 0; t < output_.size(); ++t) output_[t] = field.flux_lm(t) / pyramid_.solid_angle_sr(0, t);
    stats_.raw_flux_lm = stats_.preview_flux_lm = field.total_flux_lm();
    stats_.stable_texels = output_.size();
    return stats_;
  }
  pyramid_.pull(field);
  const int coarsest = pyramid_.levels() - 1;
  const std::span<const double> top_flux = pyramid_.flux_lm(coarsest);
  const std::span<const std::uint64_t> top_photons = pyramid_.photons(coarsest);
  stats_.raw_flux_lm = std::accumulate(top_flux.begin(), top_flux.end(), 0.0);
  const double total_photons =
      static_cast<double>(std::accumulate(top_photons.begin(), top_photons.end(), std::uint64_t{0}));
  // Photons per lumen: what an intensity estimate predicts as a photon count.
  const double photons_per_lm = stats_.raw_flux_lm > 0.0 ? total_photons / stats_.raw_flux_lm : 0.0;

  for (int k = top; k >= 0; --k) push_level(k, top, photons_per_lm);

  stats_.preview_flux_lm = std::accumulate(row_flux_.begin(), row_flux_.end(), 0.0);
  stats_.stable_texels = std::accumulate(row_stable_.begin(), row_stable_.end(), std::size_t{0});
  stats_.upsampled_texels = output_.size() - stats_.stable_texels;
  return stats_;
}

}  // namespace gonio::sim
