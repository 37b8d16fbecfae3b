#include "sim/far_field_sampler.h"

#include <algorithm>
#include <numeric>

#include "photometry/diagnostics.h"

namespace gonio::sim {

std::vector<double> expected_texel_flux(const CubeMapGrid& grid,
                                        const std::function<double(const Vec3&)>& intensity_cd,
                                        int q) {
  GONIO_CHECK(q >= 1);
  const int n = grid.face_size();
  const double texel = 2.0 / n, sub = texel / q;
  // Sub-texel solid angles of one texel depend on where the texel is, so
  // they are computed exactly for each.
  std::vector<double> flux(grid.texel_count(), 0.0);
  for (int face = 0; face < kCubeFaces; ++face) {
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        double sum = 0.0;
        for (int j = 0; j < q; ++j) {
          const double b0 = -1.0 + y * texel + j * sub;
          for (int i = 0; i < q; ++i) {
            const double a0 = -1.0 + x * texel + i * sub;
            const Vec3 d = normalize(CubeMapGrid::direction(face, a0 + 0.5 * sub, b0 + 0.5 * sub));
            sum += intensity_cd(d) * CubeMapGrid::solid_angle(a0, b0, a0 + sub, b0 + sub);
          }
        }
        flux[grid.index(face, x, y)] = sum;
      }
    }
  }
  return flux;
}

FarFieldSampler::FarFieldSampler(std::span<const double> weights) {
  GONIO_CHECK(!weights.empty() && weights.size() < (std::size_t{1} << 32));
  const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
  GONIO_CHECK_MSG(total > 0.0 && std::all_of(weights.begin(), weights.end(),
                                             [](double w) { return w >= 0.0; }),
                  "sampler weights must be ≥ 0 with a positive sum");
  const std::size_t n = weights.size();
  probability_.resize(n);
  accept_.resize(n);
  alias_.resize(n);
  // Vose's construction of Walker's alias table.
  std::vector<double> scaled(n);
  std::vector<std::uint32_t> small, large;
  for (std::size_t i = 0; i < n; ++i) {
    probability_[i] = weights[i] / total;
    scaled[i] = probability_[i] * static_cast<double>(n);
    (scaled[i] < 1.0 ? small : large).push_back(static_cast<std::uint32_t>(i));
  }
  while (!small.empty() && !large.empty()) {
    const std::uint32_t s = small.back(), l = large.back();
    small.pop_back();
    accept_[s] = scaled[s];
    alias_[s] = l;
    scaled[l] = (scaled[l] + scaled[s]) - 1.0;
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  // What is left is 1 up to rounding.
  for (const std::vector<std::uint32_t>* rest : {&large, &small}) {
    for (std::uint32_t i : *rest) {
      accept_[i] = 1.0;
      alias_[i] = i;
    }
  }
}

std::size_t FarFieldSampler::sample(double u1, double u2) const {
  const std::size_t n = accept_.size();
  const std::size_t column = std::min(n - 1, static_cast<std::size_t>(u1 * static_cast<double>(n)));
  return u2 < accept_[column] ? column : alias_[column];
}

void FarFieldSampler::add_photons(FarField& field, std::uint64_t photons, double flux_per_photon_lm,
                                  std::mt19937_64& rng) const {
  GONIO_CHECK(field.texel_count() == texel_count());
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::uint64_t i = 0; i < photons; ++i) {
    const double u1 = u(rng), u2 = u(rng);
    field.add(sample(u1, u2), flux_per_photon_lm);
  }
}

}  // namespace gonio::sim
