#include "sim/detectors/colour_over_angle.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gonio::sim {

ColourOverAngle colour_over_angle(const Resampler& resampler, const FarField& y,
                                  const ColourFarField& colour, double threshold_fraction) {
  GONIO_CHECK(colour.x_lm.size() == y.texel_count() && colour.z_lm.size() == y.texel_count());
  ColourOverAngle out;
  out.threshold_fraction = threshold_fraction;
  const std::vector<std::uint64_t> none(y.texel_count(), 0);
  const BinnedField by = resampler.bin(y);
  const BinnedField bx = resampler.bin(FarField(y.face_size(), colour.x_lm, none));
  const BinnedField bz = resampler.bin(FarField(y.face_size(), colour.z_lm, none));
  const CGammaGrid& grid = resampler.grid();
  const std::size_t bins = grid.bin_count();
  const auto tri = [&](std::size_t b) { return photometry::Tristimulus{bx.flux_lm[b], by.flux_lm[b], bz.flux_lm[b]}; };
  for (std::size_t b = 0; b < bins; ++b) {
    out.total.X += bx.flux_lm[b];
    out.total.Y += by.flux_lm[b];
    out.total.Z += bz.flux_lm[b];
  }
  out.uv = photometry::uv_prime(out.total);
  out.cct = photometry::cct_duv(out.uv);

  for (double c : {0.0, 90.0, 180.0, 270.0}) {
    const int i = grid.c_index_of(c);
    if (i < 0) continue;
    ColourPlane plane;
    plane.c_deg = c;
    for (int j = 0; j < grid.gamma_count(); ++j) {
      const std::size_t b = grid.bin(i, j);
      ColourAtGamma p;
      p.gamma_deg = grid.gamma_deg(j);
      p.intensity_cd = by.intensity_cd(b);
      p.uv = photometry::uv_prime(tri(b));
      p.cct = photometry::cct_duv(p.uv);
      plane.points.push_back(p);
    }
    out.planes.push_back(std::move(plane));
  }

  double peak = 0.0;
  for (std::size_t b = 0; b < bins; ++b) peak = std::max(peak, by.intensity_cd(b));
  const double floor_cd = threshold_fraction * peak;
  double weight = 0.0, su = 0.0, sv = 0.0;
  std::vector<std::size_t> counted;
  for (std::size_t b = 0; b < bins; ++b) {
    if (!(peak > 0.0) || by.intensity_cd(b) < floor_cd) continue;
    const photometry::UvPrime uv = photometry::uv_prime(tri(b));
    if (!std::isfinite(uv.u_prime)) continue;
    counted.push_back(b);
    weight += by.flux_lm[b];
    su += by.flux_lm[b] * uv.u_prime;
    sv += by.flux_lm[b] * uv.v_prime;
  }
  out.bins_counted = counted.size();
  if (weight > 0.0) {
    out.mean_uv = {su / weight, sv / weight};
    for (std::size_t b : counted)
      out.delta_uv_max = std::max(out.delta_uv_max, photometry::delta_uv_prime(photometry::uv_prime(tri(b)), out.mean_uv));
  } else {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    out.mean_uv = {nan, nan};
    out.delta_uv_max = nan;
  }
  return out;
}

}  // namespace gonio::sim
