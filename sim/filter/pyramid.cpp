#include "sim/filter/pyramid.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "photometry/diagnostics.h"

namespace gonio::sim {
namespace {

std::vector<double> exact_face_solid_angles(int n) {
  const CubeMapGrid grid(n);
  std::vector<double> omega(static_cast<std::size_t>(n) * n);
  for (std::size_t t = 0; t < omega.size(); ++t) omega[t] = grid.texel_solid_angle(t);
  return omega;
}

}  // namespace

int CubePyramid::max_levels(int n) {
  GONIO_CHECK(n >= 1);
  int levels = 1;
  while (n % 2 == 0) {
    n /= 2;
    ++levels;
  }
  return levels;
}

CubePyramid::CubePyramid(int n, int levels)
    : CubePyramid(n, levels, exact_face_solid_angles(n)) {}

CubePyramid::CubePyramid(int n, int levels, std::span<const double> face_solid_angle_sr)
    : n0_(n), levels_(std::clamp(levels, 1, max_levels(n))) {
  GONIO_CHECK(face_solid_angle_sr.size() == static_cast<std::size_t>(n) * n);
  const std::size_t count = static_cast<std::size_t>(levels_);
  solid_angle_.resize(count);
  flux_.resize(count);
  photons_.resize(count);
  solid_angle_[0].assign(face_solid_angle_sr.begin(), face_solid_angle_sr.end());
  GONIO_CHECK_MSG(std::all_of(solid_angle_[0].begin(), solid_angle_[0].end(),
                              [](double w) { return w > 0.0; }),
                  "texel solid angles must be positive");
  for (int k = 1; k < levels_; ++k) {
    const std::size_t m = static_cast<std::size_t>(face_size(k)), fine = 2 * m;
    const std::vector<double>& below = solid_angle_[static_cast<std::size_t>(k) - 1];
    std::vector<double>& omega = solid_angle_[static_cast<std::size_t>(k)];
    omega.resize(m * m);
    for (std::size_t y = 0; y < m; ++y) {
      for (std::size_t x = 0; x < m; ++x) {
        const std::size_t c = 2 * y * fine + 2 * x;
        omega[y * m + x] = (below[c] + below[c + 1]) + (below[c + fine] + below[c + fine + 1]);
      }
    }
    flux_[static_cast<std::size_t>(k)].resize(texel_count(k));
    photons_[static_cast<std::size_t>(k)].resize(texel_count(k));
  }
}

void CubePyramid::pull(const FarField& field) {
  GONIO_CHECK_MSG(field.face_size() == n0_, "far field and pyramid differ in face size");
  base_flux_ = field.flux_lm();
  base_photons_ = field.photons();
  for (int k = 1; k < levels_; ++k) {
    const std::size_t m = static_cast<std::size_t>(face_size(k)), fine = 2 * m;
    const std::span<const double> flux_below = flux_lm(k - 1);
    const std::span<const std::uint64_t> photons_below = photons(k - 1);
    double* flux = flux_[static_cast<std::size_t>(k)].data();
    std::uint64_t* count = photons_[static_cast<std::size_t>(k)].data();
    // A coarse row of one face at a time: row r = face · M + y covers fine
    // rows 2r and 2r + 1 of the same face.
    auto rows = [&](std::size_t begin, std::size_t end) {
      for (std::size_t r = begin; r < end; ++r) {
        for (std::size_t x = 0; x < m; ++x) {
          const std::size_t c = 2 * r * fine + 2 * x;
          flux[r * m + x] =
              (flux_below[c] + flux_below[c + 1]) + (flux_below[c + fine] + flux_below[c + fine + 1]);
          count[r * m + x] = photons_below[c] + photons_below[c + 1] + photons_below[c + fine] +
                             photons_below[c + fine + 1];
        }
      }
    };
    const std::size_t row_count = 6 * m;
    if (m >= 64) {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, row_count, 16),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          rows(range.begin(), range.end());
                        });
    } else {
      rows(0, row_count);
    }
  }
}

std::span<const double> CubePyramid::flux_lm(int level) const {
  GONIO_CHECK(level >= 0 && level < levels_);
  return level == 0 ? base_flux_ : std::span<const double>(flux_[static_cast<std::size_t>(level)]);
}

std::span<const std::uint64_t> CubePyramid::photons(int level) const {
  GONIO_CHECK(level >= 0 && level < levels_);
  return level == 0 ? base_photons_
                    : std::span<const std::uint64_t>(photons_[static_cast<std::size_t>(level)]);
}

}  // namespace gonio::sim
