#include "sim/emitters/emission_guide.h"

#include <algorithm>
#include <cmath>

#include "photometry/diagnostics.h"
#include "sim/filter/cube_neighbours.h"
#include "sim/ledger.h"
#include "sim/filter/preview_filter.h"

namespace gonio::sim {

void GuideTally::add(const GuideTally& o) {
  GONIO_CHECK(o.importance_sum.size() == importance_sum.size() && o.extra_units.size() == extra_units.size());
  for (std::size_t e = 0; e < importance_sum.size(); ++e) {
    importance_sum[e] += o.importance_sum[e];
    traced[e] += o.traced[e];
  }
  for (std::size_t t = 0; t < extra_units.size(); ++t) extra_units[t] += o.extra_units[t];
  dropped += o.dropped;
}

void GuideTally::clear() {
  std::fill(importance_sum.begin(), importance_sum.end(), 0);
  std::fill(traced.begin(), traced.end(), 0);
  std::fill(extra_units.begin(), extra_units.end(), 0);
  dropped = 0;
}

namespace {

int checked_face_size(int n) {
  GONIO_CHECK(n >= 1 && n <= 1024);
  return n;
}

}  // namespace

EmissionGuide::EmissionGuide(const ImportanceSettings& settings, int far_field_face_size)
    : settings_(settings),
      emission_grid_(checked_face_size(settings.emission_face_size)),
      far_face_size_(far_field_face_size),
      power_units_(emission_grid_.texel_count(), kPowerUnits),
      importance_(CubeMapGrid(far_field_face_size).texel_count(), 0) {
  GONIO_CHECK(settings.min_acceptance > 0.0 && settings.min_acceptance <= 1.0);
}

GuideTally EmissionGuide::make_tally() const {
  GuideTally t;
  t.importance_sum.assign(emission_grid_.texel_count(), 0);
  t.traced.assign(emission_grid_.texel_count(), 0);
  t.extra_units.assign(importance_.size(), 0);
  return t;
}

double EmissionGuide::acceptance(std::uint32_t e) const {
  return static_cast<double>(kPowerUnits) / static_cast<double>(power_units_[e]);
}

bool EmissionGuide::accept(std::uint32_t e, PhotonRandom& rng) const {
  const std::uint64_t u = power_units_[e];
  if (u == kPowerUnits) return true;
  // A uniform integer in [0, u) as the high word of x·u (Lemire): < K with
  // probability K/u to within 2⁻⁶⁴.
  __extension__ using Wide = unsigned __int128;
  const Wide product = static_cast<Wide>(rng.next_u64()) * u;
  return static_cast<std::uint64_t>(product >> 64) < kPowerUnits;
}

void EmissionGuide::update(const GuideTally& iteration, const FarField& field) {
  GONIO_CHECK(field.face_size() == far_face_size_);
  GONIO_CHECK(iteration.traced.size() == power_units_.size());

  // Acceptance from the mean importance per emission texel, smoothed.
  const std::size_t emission_texels = emission_grid_.texel_count();
  std::vector<double> flux(emission_texels, 0.0);
  std::vector<std::uint64_t> photons(emission_texels, 0);
  for (std::size_t e = 0; e < emission_texels; ++e) {
    if (iteration.traced[e] == 0) continue;
    const double mean = static_cast<double>(iteration.importance_sum[e]) / kImportanceScale /
                        static_cast<double>(iteration.traced[e]);
    // The filter interpolates flux / solid angle: store mean × Ω so that it
    // interpolates the mean.
    flux[e] = mean * emission_grid_.texel_solid_angle(e);
    photons[e] = iteration.traced[e];
  }
  PreviewFilterParams params;
  params.adaptive = false;  // its photon statistics assume flux ∝ photons
  params.threshold_photons = PreviewFilterParams::kFixedThreshold;
  PreviewFilter filter(emission_grid_.face_size(), params);
  const FarField means(emission_grid_.face_size(), std::move(flux), std::move(photons));
  filter.apply(means);
  smoothed_.assign(filter.intensity_cd().begin(), filter.intensity_cd().end());
  double g_max = 0.0;
  for (double g : smoothed_)
    if (std::isfinite(g)) g_max = std::max(g_max, g);
  for (std::size_t e = 0; e < emission_texels; ++e) {
    double a = 1.0;
    if (g_max > 0.0) {
      const double g = smoothed_[e];
      a = std::clamp(std::isfinite(g) ? g / g_max : 1.0, settings_.min_acceptance, 1.0);
    }
    power_units_[e] = static_cast<std::uint64_t>(std::llround(static_cast<double>(kPowerUnits) / a));
  }

  // imp(T) on the far field so far.
  const int n = field.face_size();
  const CubeNeighbours neighbours(n);
  const CubeMapGrid& grid = field.grid();
  for (int face = 0; face < kCubeFaces; ++face) {
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        const std::size_t t = grid.index(face, x, y);
        const double centre = field.intensity_cd(t);
        double imp = 0.0;
        if (centre > 0.0) {
          double laplacian = -4.0 * centre;
          laplacian += field.intensity_cd(neighbours.neighbour(face, x, y, -1, 0));
          laplacian += field.intensity_cd(neighbours.neighbour(face, x, y, 1, 0));
          laplacian += field.intensity_cd(neighbours.neighbour(face, x, y, 0, -1));
          laplacian += field.intensity_cd(neighbours.neighbour(face, x, y, 0, 1));
          imp = std::min(std::abs(laplacian) / centre, kMaxImportance);
        }
        importance_[t] = static_cast<std::uint32_t>(std::llround(imp * kImportanceScale));
      }
    }
  }
}

}  // namespace gonio::sim
