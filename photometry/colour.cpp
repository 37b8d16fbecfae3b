#include "photometry/colour.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "gonio/cie1931_cmf.inc"

namespace gonio::photometry {
namespace {

static_assert(kCie1931Count == kCmfCount, "the generated CMF table has the expected size");


struct Uv {
  double u, v;  // CIE 1960
};

Uv uv1960(const Tristimulus& t) {
  const double d = t.X + 15.0 * t.Y + 3.0 * t.Z;
  if (!(d > 0.0)) return {kNaN, kNaN};
  return {4.0 * t.X / d, 6.0 * t.Y / d};
}

Tristimulus planck_tristimulus(double temperature_k) {
  Tristimulus t;
  for (int i = 0; i < kCmfCount; ++i) {
    const double l = planck_radiance(kCmfFirstNm + kCmfStepNm * i, temperature_k);
    t.X += l * kCie1931xbar[i];
    t.Y += l * kCie1931ybar[i];
    t.Z += l * kCie1931zbar[i];
  }
  return t;
}

// Ohno's Planckian table: temperatures in geometric steps with their (u, v).
struct PlanckEntry {
  double t_k;
  Uv uv;
};

constexpr double kTableFirstK = 1000.0;
constexpr double kTableLastK = 1e6;
constexpr double kTableRatio = 1.001;

const std::vector<PlanckEntry>& planck_table() {
  static const std::vector<PlanckEntry> table = [] {
    std::vector<PlanckEntry> t;
    for (double k = kTableFirstK; k <= kTableLastK * (1.0 + 1e-12); k *= kTableRatio)
      t.push_back({k, uv1960(planck_tristimulus(k))});
    return t;
  }();
  return table;
}

}  // namespace

CmfValue cie1931_cmf_sample(int index) {
  if (index < 0 || index >= kCmfCount) return {};
  return {kCie1931xbar[index], kCie1931ybar[index], kCie1931zbar[index]};
}

CmfValue cie1931_cmf(double wavelength_nm) {
  const double f = (wavelength_nm - kCmfFirstNm) / kCmfStepNm;
  if (!(f >= 0.0) || !(f <= kCmfCount - 1)) return {};
  const int i = std::min(static_cast<int>(f), kCmfCount - 2);
  const double t = f - i;
  return {kCie1931xbar[i] + t * (kCie1931xbar[i + 1] - kCie1931xbar[i]),
          kCie1931ybar[i] + t * (kCie1931ybar[i + 1] - kCie1931ybar[i]),
          kCie1931zbar[i] + t * (kCie1931zbar[i + 1] - kCie1931zbar[i])};
}

Tristimulus tristimulus(const SampledSpectrum& s) {
  Tristimulus t;
  for (int i = 0; i < kCmfCount; ++i) {
    const double v = s.at(kCmfFirstNm + kCmfStepNm * i);
    if (v == 0.0) continue;
    t.X += v * kCie1931xbar[i];
    t.Y += v * kCie1931ybar[i];
    t.Z += v * kCie1931zbar[i];
  }
  t.X *= kCmfStepNm;
  t.Y *= kCmfStepNm;
  t.Z *= kCmfStepNm;
  return t;
}

Chromaticity chromaticity(const Tristimulus& t) {
  const double sum = t.X + t.Y + t.Z;
  if (!(sum > 0.0)) return {kNaN, kNaN};
  return {t.X / sum, t.Y / sum};
}

UvPrime uv_prime(const Tristimulus& t) {
  const double d = t.X + 15.0 * t.Y + 3.0 * t.Z;
  if (!(d > 0.0)) return {kNaN, kNaN};
  return {4.0 * t.X / d, 9.0 * t.Y / d};
}

UvPrime uv_prime(const Chromaticity& c) {
  const double d = -2.0 * c.x + 12.0 * c.y + 3.0;
  return {4.0 * c.x / d, 9.0 * c.y / d};
}

Chromaticity chromaticity(const UvPrime& uv) {
  const double d = 6.0 * uv.u_prime - 16.0 * uv.v_prime + 12.0;
  return {9.0 * uv.u_prime / d, 4.0 * uv.v_prime / d};
}

double delta_uv_prime(const UvPrime& a, const UvPrime& b) {
  return std::hypot(a.u_prime - b.u_prime, a.v_prime - b.v_prime);
}

UvPrime planckian_uv_prime(double temperature_k) { return uv_prime(planck_tristimulus(temperature_k)); }

CctDuv cct_duv(const UvPrime& uvp) {
  const Uv p{uvp.u_prime, uvp.v_prime * (2.0 / 3.0)};
  if (!std::isfinite(p.u) || !std::isfinite(p.v)) return {kNaN, kNaN};
  const std::vector<PlanckEntry>& table = planck_table();
  const auto dist = [&p](const PlanckEntry& e) { return std::hypot(p.u - e.uv.u, p.v - e.uv.v); };
  std::size_t best = 0;
  double best_d = dist(table[0]);
  for (std::size_t i = 1; i < table.size(); ++i) {
    const double d = dist(table[i]);
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  // The nearest entry at either end of the table: outside its range.
  if (best == 0 || best + 1 >= table.size()) return {kNaN, kNaN};
  const PlanckEntry& ep = table[best - 1];
  const PlanckEntry& en = table[best + 1];
  const double dp = dist(ep), di = best_d, dn = dist(en);

  // Triangular solution (Ohno 2014, eqs. 4-7).
  const double l = std::hypot(en.uv.u - ep.uv.u, en.uv.v - ep.uv.v);
  const double x = (dp * dp - dn * dn + l * l) / (2.0 * l);
  const double t_tri = ep.t_k + (en.t_k - ep.t_k) * (x / l);
  const double v_tx = ep.uv.v + (en.uv.v - ep.uv.v) * (x / l);
  const double sign = p.v - v_tx >= 0.0 ? 1.0 : -1.0;
  const double duv_tri = std::sqrt(std::max(0.0, dp * dp - x * x)) * sign;
  if (std::abs(duv_tri) < 0.002) return {t_tri, duv_tri};

  // Parabolic solution (eqs. 8-11): d(T) through the three entries, here in
  // t = T − T_i to keep the coefficients well conditioned.
  const double tp = ep.t_k - table[best].t_k, tn = en.t_k - table[best].t_k;
  // d(t) = a t² + b t + c with d(0) = di.
  const double c = di;
  const double sp = (dp - di) / tp, sn = (dn - di) / tn;  // a t + b at t = tp, tn
  const double a = (sn - sp) / (tn - tp);
  const double b = sp - a * tp;
  if (!(a > 0.0)) return {t_tri, duv_tri};
  const double t_min = -b / (2.0 * a);
  const double d_min = a * t_min * t_min + b * t_min + c;
  return {table[best].t_k + t_min, d_min * sign};
}

}  // namespace gonio::photometry
