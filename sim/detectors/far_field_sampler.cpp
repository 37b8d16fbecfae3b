#include "sim/detectors/far_field_sampler.h"


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

FarFieldSampler::FarFieldSampler(std::span<const double> weights) : table_(weights) {}

void FarFieldSampler::add_photons(FarField& field, std::uint64_t photons, double flux_per_photon_lm,
                                  std::mt19937_64& rng) const {
  GONIO_CHECK(field.texel_count() == texel_count());
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (std::uint64_t i = 0; i < photons; ++i) field.add(sample(u(rng)), flux_per_photon_lm);
}

}  // namespace gonio::sim
