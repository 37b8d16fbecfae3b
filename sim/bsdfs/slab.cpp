#include "sim/bsdfs/slab.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "photometry/format.h"
#include "sim/bsdfs/tabulated_bsdf.h"
#include "sim/bsdfs/volume.h"
#include "sim/bsdfs/material.h"
#include "sim/samplers/random.h"

namespace gonio::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr int kMaxEvents = 1000000;
constexpr double kBinDeg = 2.5;
constexpr int kBins = 36;

// One photon's end: which face it left (+1 far, −1 near, 0 lost), the
// cosine of its direction outside with the normal, its path inside.
struct Exit {
  int side = 0;
  double cos_out = 0.0;
  double path_m = 0.0;
  bool scattered = false;
};

// Traces photons without absorption (μa enters as exp(−μa L) afterwards).
std::vector<Exit> trace_slab(const SlabMedium& m, double incidence_deg, std::uint64_t photons, std::uint64_t seed) {
  std::vector<Exit> out(photons);
  const double mu0 = std::cos(incidence_deg * kDeg);
  const double sin_t = std::sin(incidence_deg * kDeg) / m.ior;
  const double mu_in = std::sqrt(std::max(0.0, 1.0 - sin_t * sin_t));
  const double r0 = fresnel_dielectric(mu0, 1.0, m.ior);
  const double d = m.thickness_m, mus = m.scattering_per_m;
  for (std::uint64_t i = 0; i < photons; ++i) {
    PhotonRandom rng(seed, i);
    Exit& e = out[i];
    if (rng.uniform() < r0) {
      e.side = -1;
      e.cos_out = mu0;
      continue;
    }
    double z = 0.0, mu = mu_in;  // depth from the near face, direction cosine (> 0: inwards)
    for (int events = 0; events < kMaxEvents; ++events) {
      const double s = mus > 0.0 ? -std::log(rng.uniform_open0()) / mus : 1e300;
      const double to_face = mu > 0.0 ? (d - z) / mu : (mu < 0.0 ? -z / mu : 1e300);
      if (s < to_face) {
        z += s * mu;
        e.path_m += s;
        e.scattered = true;
        const double c = sample_henyey_greenstein_cos(m.g, rng.uniform());
        const double phi = 2.0 * kPi * rng.uniform();
        const double st = std::sqrt(std::max(0.0, 1.0 - c * c)), sm = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        mu = std::clamp(mu * c + sm * st * std::cos(phi), -1.0, 1.0);
        continue;
      }
      e.path_m += to_face;
      z = mu > 0.0 ? d : 0.0;
      const double a = std::abs(mu);
      if (rng.uniform() < fresnel_dielectric(a, m.ior, 1.0)) {
        mu = -mu;
        continue;
      }
      const double so = m.ior * std::sqrt(std::max(0.0, 1.0 - a * a));
      e.side = mu > 0.0 ? 1 : -1;
      e.cos_out = std::sqrt(std::max(0.0, 1.0 - so * so));
      break;
    }
  }
  return out;
}

SlabOptics optics_of(const std::vector<Exit>& exits, double absorption_per_m, bool normal) {
  SlabOptics o;
  std::vector<double> bins(kBins, 0.0);
  const double n = static_cast<double>(exits.size());
  const double cos_haze = std::cos(2.5 * kDeg);
  double hazy = 0.0;
  for (const Exit& e : exits) {
    const double w = std::exp(-absorption_per_m * e.path_m);
    if (e.side > 0) {
      o.transmittance += w;
      if (!e.scattered) o.unscattered += w;
      if (e.cos_out < cos_haze) hazy += w;
      const double theta = std::acos(std::clamp(e.cos_out, 0.0, 1.0)) / kDeg;
      bins[static_cast<std::size_t>(std::min(kBins - 1, static_cast<int>(theta / kBinDeg)))] += w;
    } else if (e.side < 0) {
      o.reflectance += w;
    }
  }
  if (!normal) {
    o.transmittance /= n;
    o.reflectance /= n;
    o.unscattered /= n;
    return o;
  }
  o.haze = o.transmittance > 0.0 ? hazy / o.transmittance : 0.0;
  // Intensity per bin: flux over the bin's solid angle, without the
  // unscattered beam (a delta along the normal, which a goniophotometer's
  // half-value angle leaves out too).
  for (const Exit& e : exits)
    if (e.side > 0 && !e.scattered) bins[0] -= std::exp(-absorption_per_m * e.path_m);
  o.relative_intensity.resize(kBins);
  for (int k = 0; k < kBins; ++k) {
    const double omega = 2.0 * kPi * (std::cos(k * kBinDeg * kDeg) - std::cos((k + 1) * kBinDeg * kDeg));
    o.relative_intensity[static_cast<std::size_t>(k)] = bins[static_cast<std::size_t>(k)] / omega;
  }
  // The intensity as a polynomial of degree 4 in cos θ, fitted by least
  // squares to the bins (weighted by their solid angle: noise per bin falls
  // with it), so that the value along the normal and the half-value angle
  // do not hang on the few photons of the innermost bins.
  constexpr int kDegree = 4;
  double a[kDegree + 1][kDegree + 2] = {};
  for (int k = 0; k < kBins; ++k) {
    const double mu = std::cos((k + 0.5) * kBinDeg * kDeg);
    const double w = 2.0 * kPi * (std::cos(k * kBinDeg * kDeg) - std::cos((k + 1) * kBinDeg * kDeg));
    double pw[kDegree + 1];
    pw[0] = 1.0;
    for (int i = 1; i <= kDegree; ++i) pw[i] = pw[i - 1] * mu;
    for (int i = 0; i <= kDegree; ++i) {
      for (int j = 0; j <= kDegree; ++j) a[i][j] += w * pw[i] * pw[j];
      a[i][kDegree + 1] += w * pw[i] * o.relative_intensity[static_cast<std::size_t>(k)];
    }
  }
  for (int c = 0; c <= kDegree; ++c) {  // Gauss–Jordan with partial pivoting
    int pivot = c;
    for (int r = c + 1; r <= kDegree; ++r)
      if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
    for (int j = 0; j <= kDegree + 1; ++j) std::swap(a[c][j], a[pivot][j]);
    if (!(std::abs(a[c][c]) > 0.0)) continue;
    for (int r = 0; r <= kDegree; ++r) {
      if (r == c) continue;
      const double f = a[r][c] / a[c][c];
      for (int j = c; j <= kDegree + 1; ++j) a[r][j] -= f * a[c][j];
    }
  }
  const auto fitted = [&](double mu) {
    double v = 0.0, p = 1.0;
    for (int i = 0; i <= kDegree; ++i, p *= mu) v += (a[i][i] != 0.0 ? a[i][kDegree + 1] / a[i][i] : 0.0) * p;
    return v;
  };
  const double i0 = fitted(1.0);
  for (double& v : o.relative_intensity) v = i0 > 0.0 ? v / i0 : 0.0;
  o.half_value_deg = 90.0;
  if (i0 > 0.0 && fitted(0.0) < 0.5 * i0) {
    double lo = 0.0, hi = 90.0;  // the first angle where the fit falls to half
    for (int step = 1; step <= 900; ++step)
      if (fitted(std::cos(step * 0.1 * kDeg)) <= 0.5 * i0) {
        hi = step * 0.1;
        lo = hi - 0.1;
        break;
      }
    for (int k = 0; k < 40; ++k) {
      const double mid = 0.5 * (lo + hi);
      (fitted(std::cos(mid * kDeg)) > 0.5 * i0 ? lo : hi) = mid;
    }
    o.half_value_deg = 0.5 * (lo + hi);
  }
  o.transmittance /= n;
  o.reflectance /= n;
  o.unscattered /= n;
  return o;
}

}  // namespace

SlabOptics slab_optics(const SlabMedium& medium, double incidence_deg, std::uint64_t photons, std::uint64_t seed) {
  SlabMedium clear = medium;
  clear.absorption_per_m = 0.0;
  return optics_of(trace_slab(clear, incidence_deg, photons, seed), medium.absorption_per_m, incidence_deg == 0.0);
}

TabulatedBsdf sheet_bsdf(const SlabMedium& m, std::uint64_t photons, std::uint64_t seed) {
  TabulatedBsdf t;
  t.name = "sheet of " + format_number(m.thickness_m * 1e3) + " mm (volume model)";
  for (int r = 0; r <= 18; ++r) t.basis.ring_theta_deg.push_back(5.0 * r);
  for (int r = 0; r < 18; ++r) {
    const double mid = (r + 0.5) * 5.0 * kDeg;
    const int count = r == 0 ? 1 : std::max(4, static_cast<int>(std::lround(2.0 * kPi * std::sin(mid) / (5.0 * kDeg))));
    std::vector<double> bounds;
    for (int k = 0; k <= count; ++k) bounds.push_back((k - 0.5) * 360.0 / count);
    t.basis.ring_phi_deg.push_back(std::move(bounds));
  }
  const std::size_t n = t.basis.size();
  std::vector<double> omega(n);
  for (std::size_t p = 0; p < n; ++p) omega[p] = t.basis.projected_solid_angle(p);
  const double d = m.thickness_m, mus = m.scattering_per_m;
  for (double theta : {0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 89.0}) {
    std::vector<double> reflect(n, 0.0), transmit(n, 0.0);
    const double st = std::sin(theta * kDeg), ct = std::cos(theta * kDeg);
    const double r0 = fresnel_dielectric(ct, 1.0, m.ior);
    for (std::uint64_t i = 0; i < photons; ++i) {
      PhotonRandom rng(seed, i + static_cast<std::uint64_t>(theta * 1000.0) * photons);
      // Light travels along +x and down (−z) onto the face z = 0; the sheet
      // fills −d < z < 0.
      if (rng.uniform() < r0) {
        reflect[t.basis.patch_of(Vec3{st, 0.0, ct})] += 1.0;
        continue;
      }
      const double s_in = st / m.ior;
      Vec3 dir{s_in, 0.0, -std::sqrt(std::max(0.0, 1.0 - s_in * s_in))};
      double z = 0.0, path = 0.0;
      for (int events = 0; events < kMaxEvents; ++events) {
        const double s = mus > 0.0 ? -std::log(rng.uniform_open0()) / mus : 1e300;
        const double to_face = dir.z < 0.0 ? (z + d) / -dir.z : (dir.z > 0.0 ? -z / dir.z : 1e300);
        if (s < to_face) {
          z += s * dir.z;
          path += s;
          dir = sample_henyey_greenstein(dir, m.g, rng);
          continue;
        }
        path += to_face;
        z = dir.z < 0.0 ? -d : 0.0;
        if (rng.uniform() < fresnel_dielectric(std::abs(dir.z), m.ior, 1.0)) {
          dir.z = -dir.z;
          continue;
        }
        const double tx = dir.x * m.ior, ty = dir.y * m.ior;
        const double tz = std::sqrt(std::max(0.0, 1.0 - tx * tx - ty * ty));
        const Vec3 out{tx, ty, dir.z > 0.0 ? tz : -tz};
        const double w = std::exp(-m.absorption_per_m * path);
        const std::size_t p = t.basis.patch_of(Vec3{out.x, out.y, std::abs(out.z)});
        if (p < n) (out.z > 0.0 ? reflect : transmit)[p] += w;
        break;
      }
    }
    TabulatedBsdf::Row row;
    row.theta_deg = theta;
    for (std::size_t p = 0; p < n; ++p) {
      row.reflect.push_back(static_cast<float>(reflect[p] / (static_cast<double>(photons) * omega[p])));
      row.transmit.push_back(static_cast<float>(transmit[p] / (static_cast<double>(photons) * omega[p])));
    }
    t.front.rows.push_back(std::move(row));
  }
  std::vector<Finding> findings;
  const Status s = t.finish(findings);
  GONIO_CHECK(s.ok());
  return t;
}

Result<SlabMedium> fit_volume(const VolumeDatasheet& s, std::uint64_t photons, std::uint64_t seed) {
  const bool by_haze = s.haze >= 0.0;
  if (by_haze == (s.half_value_deg >= 0.0))
    return make_error("volume fit: give exactly one of haze and half-value angle");
  if (!(s.transmittance > 0.0 && s.transmittance < 1.0)) return make_error("volume fit: transmittance must lie in (0, 1)");
  if (by_haze && !(s.haze > 0.0 && s.haze < 1.0)) return make_error("volume fit: haze must lie in (0, 1)");
  if (!by_haze && !(s.half_value_deg > 0.0 && s.half_value_deg < 90.0))
    return make_error("volume fit: the half-value angle must lie in (0, 90) degrees");
  if (!(s.thickness_m > 0.0 && std::isfinite(s.thickness_m))) return make_error("volume fit: thickness must be > 0");
  if (!(s.ior >= 1.0 && s.ior < 4.0)) return make_error("volume fit: ior must lie in [1, 4)");
  if (!(s.g > -1.0 && s.g < 1.0)) return make_error("volume fit: g must lie in (-1, 1)");
  SlabMedium m;
  m.g = s.g;
  m.ior = s.ior;
  m.thickness_m = s.thickness_m;
  // For a trial μs: μa from the transmittance, then the haze or
  // half-value angle it gives (negative: the transmittance is out of reach).
  const auto measure = [&](double mus, double* mua) {
    m.scattering_per_m = mus;
    m.absorption_per_m = 0.0;
    const std::vector<Exit> exits = trace_slab(m, 0.0, photons, seed);
    if (optics_of(exits, 0.0, true).transmittance < s.transmittance) return -1.0;
    double lo = 0.0, hi = 1.0 / s.thickness_m;
    while (optics_of(exits, hi, true).transmittance > s.transmittance) hi *= 4.0;
    for (int k = 0; k < 50; ++k) {
      const double mid = 0.5 * (lo + hi);
      (optics_of(exits, mid, true).transmittance > s.transmittance ? lo : hi) = mid;
    }
    *mua = 0.5 * (lo + hi);
    const SlabOptics o = optics_of(exits, *mua, true);
    return by_haze ? o.haze : o.half_value_deg;
  };
  const double target = by_haze ? s.haze : s.half_value_deg;
  const auto unreachable = [&] {
    return make_error("volume fit: no sheet with g = " + format_number(s.g) + " and thickness " +
                      format_number(s.thickness_m * 1e3) + " mm has transmittance " + format_number(s.transmittance) +
                      " and " +
                      (by_haze ? "haze " + format_number(s.haze) : "half-value angle " + format_number(s.half_value_deg) + " degrees"));
  };
  // Both the haze and the half-value angle grow with μs. Bracket from
  // optical thickness 1 in steps of 4, then bisect log μs.
  double mua = 0.0;
  double lo = 1.0 / s.thickness_m, hi = lo;
  double v = measure(lo, &mua);
  if (v >= 0.0 && v < target) {
    // Up until the angle or haze is reached or the transmittance is lost.
    while (true) {
      hi *= 4.0;
      if (hi > 1e4 / s.thickness_m) return unreachable();
      v = measure(hi, &mua);
      if (v < 0.0 || v >= target) break;
      lo = hi;
    }
  } else {
    while (true) {
      lo /= 4.0;
      if (lo < 1e-4 / s.thickness_m) return unreachable();
      v = measure(lo, &mua);
      if (v >= 0.0 && v < target) break;
      hi = lo;
    }
  }
  for (int k = 0; k < 14; ++k) {
    const double mid = std::sqrt(lo * hi);
    const double vm = measure(mid, &mua);
    ((vm >= 0.0 && vm < target) ? lo : hi) = mid;
  }
  const double mus = std::sqrt(lo * hi);
  const double reached = measure(mus, &mua);
  // Where the transmittance runs out before the angle or haze is reached,
  // the bisection ends at the last μs that keeps it, short of the target.
  if (reached < 0.0 || std::abs(reached - target) > (by_haze ? 0.02 : 2.0)) return unreachable();
  m.scattering_per_m = mus;
  m.absorption_per_m = mua;
  return m;
}

}  // namespace gonio::sim
