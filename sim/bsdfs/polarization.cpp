#include "sim/bsdfs/polarization.h"

#include <algorithm>
#include <cmath>

#include "sim/samplers/sampling.h"

namespace gonio::sim {
namespace {

using C = std::complex<double>;

C dot(const C e[3], const Vec3& v) { return e[0] * v.x + e[1] * v.y + e[2] * v.z; }

// Complex product without the C99 Annex G NaN recovery for which GCC calls
// __muldc3 (the operands here are always finite).
C mul(const C& a, const C& b) {
  return {a.real() * b.real() - a.imag() * b.imag(), a.real() * b.imag() + a.imag() * b.real()};
}

// s axis for direction k onto normal n; any perpendicular of k at normal
// incidence, where s and p are interchangeable.
Vec3 s_axis(const Vec3& k, const Vec3& n) {
  const Vec3 s = cross(k, n);
  const double len = length(s);
  if (len > 1e-12) return s / len;
  return basis_from_normal(k).t;
}

}  // namespace

void polarize_randomly(Polarization& p, const Vec3& direction, PhotonRandom& rng) {
  if (p.polarized) return;
  const Basis b = basis_from_normal(direction);
  double c, s;
  sample_unit_circle(rng, &c, &s);
  const Vec3 e = c * b.t + s * b.b;
  p.e[0] = e.x;
  p.e[1] = e.y;
  p.e[2] = e.z;
  p.polarized = true;
}

void reflect_field(Polarization& p, const Vec3& n) {
  if (!p.polarized) return;
  const C en = dot(p.e, n);
  p.e[0] = -p.e[0] + 2.0 * en * n.x;
  p.e[1] = -p.e[1] + 2.0 * en * n.y;
  p.e[2] = -p.e[2] + 2.0 * en * n.z;
}

FresnelAmplitudes fresnel_amplitudes(double cos_i, double eta_i, double eta_t) {
  FresnelAmplitudes a;
  cos_i = std::clamp(cos_i, 0.0, 1.0);
  const double sin_t = eta_i / eta_t * std::sqrt(std::max(0.0, 1.0 - cos_i * cos_i));
  if (sin_t >= 1.0) {
    // cos t = i·k: r = (x − i·y)/(x + i·y) = ((x² − y²) − 2i·x·y)/(x² + y²),
    // of unit modulus (real arithmetic: no complex division).
    a.total_internal_reflection = true;
    const double k = std::sqrt(sin_t * sin_t - 1.0);
    auto unit = [](double x, double y) {
      const double d = x * x + y * y;
      return d > 0.0 ? C((x * x - y * y) / d, -2.0 * x * y / d) : C(1.0, 0.0);
    };
    a.rs = unit(eta_i * cos_i, eta_t * k);
    a.rp = unit(eta_t * cos_i, eta_i * k);
    a.ts = a.tp = 0.0;
    return a;
  }
  const double cos_t = std::sqrt(1.0 - sin_t * sin_t);
  a.cos_t = cos_t;
  const double n1ci = eta_i * cos_i, n2ct = eta_t * cos_t, n2ci = eta_t * cos_i, n1ct = eta_i * cos_t;
  a.rs = (n1ci - n2ct) / (n1ci + n2ct);
  a.rp = (n2ci - n1ct) / (n2ci + n1ct);
  a.ts = 2.0 * n1ci / (n1ci + n2ct);
  a.tp = 2.0 * n1ci / (n2ci + n1ct);
  return a;
}

InterfaceOutcome interface_event(const Polarization& state, const Vec3& k, const Vec3& n,
                                 double eta_i, double eta_t, double u) {
  const double cos_i = -::gonio::dot(k, n);
  const FresnelAmplitudes a = fresnel_amplitudes(cos_i, eta_i, eta_t);
  const Vec3 s = s_axis(k, n);
  const Vec3 p_in = cross(k, s);
  const C es = dot(state.e, s), ep = dot(state.e, p_in);
  const double rs2 = std::norm(a.rs), rp2 = std::norm(a.rp);
  const double es2 = std::norm(es), ep2 = std::norm(ep);
  const double r = a.total_internal_reflection ? 1.0 : std::clamp((rs2 * es2 + rp2 * ep2) / (es2 + ep2), 0.0, 1.0);

  InterfaceOutcome out;
  out.reflectance = r;
  out.state.polarized = true;
  C fs, fp;
  Vec3 p_out;
  if (u < r) {
    out.reflected = true;
    out.direction = k + 2.0 * cos_i * n;
    fs = mul(a.rs, es);
    fp = mul(a.rp, ep);
  } else {
    out.reflected = false;
    const double eta = eta_i / eta_t;
    out.direction = eta * k + (eta * cos_i - a.cos_t) * n;
    fs = mul(a.ts, es);
    fp = mul(a.tp, ep);
  }
  out.direction = normalize(out.direction);
  p_out = cross(out.direction, s);
  const double norm = std::sqrt(std::norm(fs) + std::norm(fp));
  if (norm > 0.0) {
    fs /= norm;
    fp /= norm;
  } else {
    fs = 1.0;  // no field left in either beam (cannot happen for chosen beams)
    fp = 0.0;
  }
  out.state.e[0] = fs * s.x + fp * p_out.x;
  out.state.e[1] = fs * s.y + fp * p_out.y;
  out.state.e[2] = fs * s.z + fp * p_out.z;
  return out;
}

}  // namespace gonio::sim
