// Far fields with known contents for the resampling and symmetry tests:
// texel fluxes integrated from an analytic intensity, or photons drawn from
// it at random.
#pragma once

#include <cstdint>
#include <functional>
#include <random>
#include <vector>

#include "photometry/vec3.h"
#include "sim/detectors/far_field.h"

namespace gonio::sim::test {

// Intensity [cd] of a unit world direction.
using IntensityFn = std::function<double(const Vec3&)>;

// Texel flux = ∫ I dΩ over each texel by 4-point Gauss-Legendre on
// `split` × `split` sub-squares of face coordinates, with the cube's
// Jacobian dΩ = da db / (1 + a² + b²)^{3/2}. No photons are counted.
inline FarField integrate_far_field(int face_size, const IntensityFn& intensity, int split = 1) {
  static constexpr double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                  0.8611363115940526};
  static constexpr double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                  0.3478548451374538};
  const CubeMapGrid grid(face_size);
  std::vector<double> flux(grid.texel_count(), 0.0);
  const double step = 2.0 / face_size, sub = step / split, half = 0.5 * sub;
  for (int f = 0; f < 6; ++f) {
    for (int ty = 0; ty < face_size; ++ty) {
      for (int tx = 0; tx < face_size; ++tx) {
        double sum = 0.0;
        for (int sy = 0; sy < split; ++sy) {
          for (int sx = 0; sx < split; ++sx) {
            const double a0 = -1.0 + tx * step + sx * sub + half;
            const double b0 = -1.0 + ty * step + sy * sub + half;
            for (int i = 0; i < 4; ++i) {
              for (int j = 0; j < 4; ++j) {
                const double a = a0 + half * x[i], b = b0 + half * x[j];
                const double r2 = 1.0 + a * a + b * b;
                const double jac = 1.0 / (r2 * std::sqrt(r2));
                sum += w[i] * w[j] * half * half * jac *
                       intensity(normalize(CubeMapGrid::direction(f, a, b)));
              }
            }
          }
        }
        flux[grid.index(f, tx, ty)] = sum;
      }
    }
  }
  return FarField(face_size, std::move(flux), std::vector<std::uint64_t>(grid.texel_count(), 0));
}

// `photons` photons of equal flux (total `flux_lm`) with directions drawn
// from the density ∝ intensity by rejection from the uniform sphere;
// `max_intensity` must bound the intensity.
inline FarField sample_far_field(int face_size, const IntensityFn& intensity,
                                 double max_intensity, std::uint64_t photons, double flux_lm,
                                 std::uint64_t seed) {
  FarField field(face_size);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double per_photon = flux_lm / static_cast<double>(photons);
  for (std::uint64_t n = 0; n < photons;) {
    const Vec3 d{normal(rng), normal(rng), normal(rng)};
    const double len = length(d);
    if (len < 1e-12) continue;
    const Vec3 u = d / len;
    if (uniform(rng) * max_intensity >= intensity(u)) continue;
    field.add(field.grid().texel_of(u), per_photon);
    ++n;
  }
  return field;
}

}  // namespace gonio::sim::test
