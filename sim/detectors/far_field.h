// The far field: a histogram of escaped flux over directions, binned on a
// direction cube map (the infinite-distance limit IES and LDT files describe).
//
// Per texel it holds the accumulated flux [lm] and the number of photons.
// Intensity is flux divided by the texel's exact solid angle [cd]. Only the
// photon tracer adds to it; the preview filter, the resampler and the writers
// read it and never write back.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "sim/detectors/cube_map.h"

namespace gonio::sim {

class FarField {
 public:
  explicit FarField(int face_size);
  // A far field from existing data (file readers, tests): sizes must equal
  // the grid's texel count.
  FarField(int face_size, std::vector<double> flux_lm, std::vector<std::uint64_t> photons);

  const CubeMapGrid& grid() const { return grid_; }
  int face_size() const { return grid_.face_size(); }
  std::size_t texel_count() const { return flux_lm_.size(); }

  std::span<const double> flux_lm() const { return flux_lm_; }            // per texel [lm]
  std::span<const std::uint64_t> photons() const { return photons_; }    // per texel

  double flux_lm(std::size_t texel) const { return flux_lm_[texel]; }
  std::uint64_t photons(std::size_t texel) const { return photons_[texel]; }
  // Mean intensity over the texel [cd].
  double intensity_cd(std::size_t texel) const {
    return flux_lm_[texel] / grid_.texel_solid_angle(texel);
  }

  double total_flux_lm() const;          // sum over all texels [lm]
  std::uint64_t total_photons() const;   // sum over all texels

  // The tracer's writes: add photons carrying `flux_lm` in total to a texel.
  void add(std::size_t texel, double flux_lm, std::uint64_t photons = 1) {
    flux_lm_[texel] += flux_lm;
    photons_[texel] += photons;
  }
  // Adds another far field on the same grid, texel by texel.
  void add(const FarField& other);
  // Forgets everything accumulated.
  void clear();

 private:
  CubeMapGrid grid_;
  std::vector<double> flux_lm_;
  std::vector<std::uint64_t> photons_;
};

// What a spectral run's far field adds beside Y (sim/tracer/spectral.h): the CIE
// tristimulus values X and Z per texel, in the units of the far field's flux
// (Y is the luminous flux [lm]), on the same grid. Empty for a grey run.
struct ColourFarField {
  std::vector<double> x_lm;
  std::vector<double> z_lm;
  bool empty() const { return x_lm.empty(); }
};

}  // namespace gonio::sim
