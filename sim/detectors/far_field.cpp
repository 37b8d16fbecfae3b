#include "sim/detectors/far_field.h"

#include <algorithm>
#include <numeric>

#include "photometry/diagnostics.h"

namespace gonio::sim {

FarField::FarField(int face_size)
    : grid_(face_size), flux_lm_(grid_.texel_count(), 0.0), photons_(grid_.texel_count(), 0) {}

FarField::FarField(int face_size, std::vector<double> flux_lm, std::vector<std::uint64_t> photons)
    : grid_(face_size), flux_lm_(std::move(flux_lm)), photons_(std::move(photons)) {
  GONIO_CHECK(flux_lm_.size() == grid_.texel_count());
  GONIO_CHECK(photons_.size() == grid_.texel_count());
}

double FarField::total_flux_lm() const {
  return std::accumulate(flux_lm_.begin(), flux_lm_.end(), 0.0);
}

std::uint64_t FarField::total_photons() const {
  return std::accumulate(photons_.begin(), photons_.end(), std::uint64_t{0});
}

void FarField::add(const FarField& other) {
  GONIO_CHECK(other.face_size() == face_size());
  for (std::size_t i = 0; i < flux_lm_.size(); ++i) {
    flux_lm_[i] += other.flux_lm_[i];
    photons_[i] += other.photons_[i];
  }
}

void FarField::clear() {
  std::fill(flux_lm_.begin(), flux_lm_.end(), 0.0);
  std::fill(photons_.begin(), photons_.end(), 0);
}

}  // namespace gonio::sim
