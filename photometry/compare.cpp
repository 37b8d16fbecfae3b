#include "photometry/compare.h"

#include <cmath>
#include <numbers>

#include "photometry/beam.h"
#include "photometry/flux.h"
#include "photometry/resample.h"

namespace gonio::photometry {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Solid angle [sr] each node of a full Type C grid (C 0…360 inclusive) stands
// for: the trapezoid share of C times the γ band between midpoints. The
// planes C = 0 and C = 360 are one direction and share their weight.
std::vector<double> solid_angle_weights(const Distribution& g) {
  const auto& c = g.horizontal_deg;
  const auto& v = g.vertical_deg;
  std::vector<double> band(v.size());
  for (std::size_t j = 0; j < v.size(); ++j) {
    const double lo = j == 0 ? v.front() : 0.5 * (v[j - 1] + v[j]);
    const double hi = j + 1 == v.size() ? v.back() : 0.5 * (v[j] + v[j + 1]);
    band[j] = std::cos(lo * kDeg) - std::cos(hi * kDeg);
  }
  std::vector<double> w(c.size() * v.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    const double left = i == 0 ? 0.0 : c[i] - c[i - 1];
    const double right = i + 1 == c.size() ? 0.0 : c[i + 1] - c[i];
    const double share = 0.5 * (left + right) * kDeg;
    for (std::size_t j = 0; j < v.size(); ++j) w[i * v.size() + j] = share * band[j];
  }
  return w;
}

double difference(const BeamSpread& a, const BeamSpread& b) { return b.angle_deg - a.angle_deg; }

}  // namespace

bool same_angles(const Distribution& a, const Distribution& b) {
  if (a.type != b.type) return false;
  const auto same = [](const std::vector<double>& x, const std::vector<double>& y) {
    if (x.size() != y.size()) return false;
    for (std::size_t k = 0; k < x.size(); ++k)
      if (std::abs(x[k] - y[k]) > 1e-6) return false;
    return true;
  };
  if (!same(a.vertical_deg, b.vertical_deg)) return false;
  if (a.symmetry == b.symmetry && same(a.horizontal_deg, b.horizontal_deg)) return true;
  return same(expand_symmetry(a).horizontal_deg, expand_symmetry(b).horizontal_deg);
}

Result<Comparison> compare(const Distribution& a, const Distribution& b,
                           const CompareOptions& options) {
  TypeCGrid grid;
  grid.c_step_deg = options.c_step_deg;
  grid.gamma_step_deg = options.gamma_step_deg;
  grid.symmetry = Symmetry::None;
  grid.whole_sphere = true;
  Result<Distribution> ga = to_type_c(a, grid);
  if (!ga.ok()) return ga.error();
  Result<Distribution> gb = to_type_c(b, grid);
  if (!gb.ok()) return gb.error();

  Comparison r;
  r.flux_a_lm = total_flux_lm(a);
  r.flux_b_lm = total_flux_lm(b);
  if (r.flux_a_lm != 0.0) r.flux_ratio = r.flux_b_lm / r.flux_a_lm;
  if (options.normalize_flux && r.flux_a_lm != 0.0 && r.flux_b_lm != 0.0)
    r.scale = r.flux_a_lm / r.flux_b_lm;

  const std::vector<double>& ia = ga->candela;
  const std::vector<double>& ib = gb->candela;
  for (double v : ia) r.reference_cd = std::max(r.reference_cd, v);
  if (r.reference_cd <= 0.0)
    for (double v : ib) r.reference_cd = std::max(r.reference_cd, r.scale * v);
  if (r.reference_cd > 0.0) {
    const std::vector<double> w = solid_angle_weights(*ga);
    const std::size_t nv = ga->vertical_count();
    double sum = 0.0, weight = 0.0;
    for (std::size_t k = 0; k < ia.size(); ++k) {
      const double e = (r.scale * ib[k] - ia[k]) / r.reference_cd;
      sum += w[k] * e * e;
      weight += w[k];
      if (std::abs(e) > r.max_relative) {
        r.max_relative = std::abs(e);
        r.max_at_c_deg = ga->horizontal_deg[k / nv];
        r.max_at_gamma_deg = ga->vertical_deg[k % nv];
      }
    }
    r.rms_relative = std::sqrt(sum / weight);
  }

  r.beam_difference_c0_c180_deg = difference(beam_angle(a, 0.0), beam_angle(b, 0.0));
  r.beam_difference_c90_c270_deg = difference(beam_angle(a, 90.0), beam_angle(b, 90.0));
  r.field_difference_c0_c180_deg = difference(field_angle(a, 0.0), field_angle(b, 0.0));
  r.field_difference_c90_c270_deg = difference(field_angle(a, 90.0), field_angle(b, 90.0));
  return r;
}

}  // namespace gonio::photometry
