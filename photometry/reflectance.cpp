#include "photometry/reflectance.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "gonio/cie1931_cmf.inc"

namespace gonio::photometry {
namespace {

using Vec = std::array<double, 3>;

double sigmoid(double x) { return 0.5 + x / (2.0 * std::sqrt(1.0 + x * x)); }

double d65_y_sum() {
  double s = 0.0;
  for (int i = 0; i < kCmfCount; ++i) s += kCieD65[i] * kCie1931ybar[i];
  return s;
}

Vec xyz_of(const SigmoidReflectance& c) {
  static const double norm = d65_y_sum();
  Vec v{0.0, 0.0, 0.0};
  for (int i = 0; i < kCmfCount; ++i) {
    const double r = c.at(kCmfFirstNm + kCmfStepNm * i) * kCieD65[i];
    v[0] += r * kCie1931xbar[i];
    v[1] += r * kCie1931ybar[i];
    v[2] += r * kCie1931zbar[i];
  }
  for (double& x : v) x /= norm;
  return v;
}

Vec white() {
  static const Vec w = [] {
    double x = 0.0, z = 0.0;
    for (int i = 0; i < kCmfCount; ++i) {
      x += kCieD65[i] * kCie1931xbar[i];
      z += kCieD65[i] * kCie1931zbar[i];
    }
    const double n = d65_y_sum();
    return Vec{x / n, 1.0, z / n};
  }();
  return w;
}

Vec lab(const Vec& xyz) {
  const Vec w = white();
  const auto f = [](double t) {
    constexpr double d = 6.0 / 29.0;
    return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
  };
  const double fx = f(xyz[0] / w[0]), fy = f(xyz[1] / w[1]), fz = f(xyz[2] / w[2]);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

Vec srgb_to_xyz(double r, double g, double b) {  // IEC 61966-2-1, linear components
  return {0.4124 * r + 0.3576 * g + 0.1805 * b, 0.2126 * r + 0.7152 * g + 0.0722 * b,
          0.0193 * r + 0.1192 * g + 0.9505 * b};
}

// Solves A x = y (3×3) by Cramer's rule; false if singular.
bool solve3(const std::array<Vec, 3>& a, const Vec& y, Vec* x) {
  const auto det = [](const std::array<Vec, 3>& m) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double d = det(a);
  if (!(std::abs(d) > 1e-300)) return false;
  for (int c = 0; c < 3; ++c) {
    std::array<Vec, 3> m = a;
    for (int r = 0; r < 3; ++r) m[r][c] = y[r];
    (*x)[c] = det(m) / d;
  }
  return true;
}

double norm2(const Vec& v) { return v[0] * v[0] + v[1] * v[1] + v[2] * v[2]; }

}  // namespace

double SigmoidReflectance::at(double wavelength_nm) const {
  const double t = (wavelength_nm - 360.0) / (830.0 - 360.0);
  return sigmoid((c0 * t + c1) * t + c2);
}

ReflectanceFit fit_reflectance(double r, double g, double b) {
  r = std::clamp(r, 0.0, 1.0);
  g = std::clamp(g, 0.0, 1.0);
  b = std::clamp(b, 0.0, 1.0);
  SigmoidReflectance c;  // mid grey: r(λ) = 1/2
  const auto residual = [](const SigmoidReflectance& s, const Vec& target) {
    const Vec l = lab(xyz_of(s));
    return Vec{l[0] - target[0], l[1] - target[1], l[2] - target[2]};
  };
  constexpr int kSteps = 16;
  Vec res{};
  for (int step = 1; step <= kSteps; ++step) {
    const double f = static_cast<double>(step) / kSteps;
    const Vec target = lab(srgb_to_xyz(0.5 + (r - 0.5) * f, 0.5 + (g - 0.5) * f, 0.5 + (b - 0.5) * f));
    double mu = 1e-3;
    res = residual(c, target);
    for (int it = 0; it < 40 && norm2(res) > 1e-10; ++it) {
      std::array<Vec, 3> jac{};  // jac[row = Lab component][column = coefficient]
      for (int k = 0; k < 3; ++k) {
        SigmoidReflectance p = c;
        double* coef[] = {&p.c0, &p.c1, &p.c2};
        const double h = 1e-5 * std::max(1.0, std::abs(*coef[k]));
        *coef[k] += h;
        const Vec rp = residual(p, target);
        for (int row = 0; row < 3; ++row) jac[row][k] = (rp[row] - res[row]) / h;
      }
      // Levenberg–Marquardt: (JᵀJ + μ diag) δ = −Jᵀr.
      std::array<Vec, 3> a{};
      Vec rhs{};
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
          for (int row = 0; row < 3; ++row) a[i][j] += jac[row][i] * jac[row][j];
        for (int row = 0; row < 3; ++row) rhs[i] -= jac[row][i] * res[row];
      }
      bool improved = false;
      for (int tries = 0; tries < 12 && !improved; ++tries) {
        std::array<Vec, 3> damped = a;
        for (int i = 0; i < 3; ++i) damped[i][i] *= 1.0 + mu;
        Vec delta{};
        if (!solve3(damped, rhs, &delta)) break;
        SigmoidReflectance next{c.c0 + delta[0], c.c1 + delta[1], c.c2 + delta[2]};
        const Vec next_res = residual(next, target);
        if (norm2(next_res) < norm2(res)) {
          c = next;
          res = next_res;
          mu = std::max(mu * 0.3, 1e-9);
          improved = true;
        } else {
          mu *= 10.0;
        }
      }
      if (!improved) break;
    }
  }
  return {c, std::sqrt(norm2(res))};
}

SampledSpectrum sampled(const SigmoidReflectance& s) {
  SampledSpectrum out;
  for (int i = 0; i < kCmfCount; ++i) {
    const double nm = kCmfFirstNm + kCmfStepNm * i;
    out.wavelengths_nm.push_back(nm);
    out.values.push_back(s.at(nm));
  }
  return out;
}

Tristimulus tristimulus_under_d65(const SampledSpectrum& reflectance) {
  static const double norm = d65_y_sum();
  Tristimulus t;
  for (int i = 0; i < kCmfCount; ++i) {
    const double r = reflectance.at(kCmfFirstNm + kCmfStepNm * i) * kCieD65[i];
    t.X += r * kCie1931xbar[i];
    t.Y += r * kCie1931ybar[i];
    t.Z += r * kCie1931zbar[i];
  }
  t.X /= norm;
  t.Y /= norm;
  t.Z /= norm;
  return t;
}

}  // namespace gonio::photometry
