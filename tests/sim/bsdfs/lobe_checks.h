// What the lobe suites share: quadrature over the sphere, a chi-square
// test of sampled directions against a density, and a measured sheet.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <vector>

#include "photometry/diagnostics.h"
#include "photometry/vec3.h"
#include "sim/bsdfs/tabulated_bsdf.h"
#include "sim/detectors/chi_square.h"

namespace gonio::sim::test {

// A Klems sheet that is not Lambertian: reflection 0.25 and transmission 0.5
// with a brighter patch on each side (reflect[3] ×4, transmit[10] ×3), at
// θ 0°, 45° and 82.5°.
inline std::shared_ptr<TabulatedBsdf> non_lambertian_klems_sheet() {
  auto table = std::make_shared<TabulatedBsdf>();
  table->name = "sheet";
  table->basis = PatchBasis::klems("LBNL/Klems Full");
  for (double theta : {0.0, 45.0, 82.5}) {
    TabulatedBsdf::Row r;
    r.theta_deg = theta;
    r.reflect.assign(table->basis.size(), static_cast<float>(0.25 / std::numbers::pi));
    r.transmit.assign(table->basis.size(), static_cast<float>(0.5 / std::numbers::pi));
    r.reflect[3] *= 4.0f;
    r.transmit[10] *= 3.0f;
    table->front.rows.push_back(r);
  }
  std::vector<Finding> findings;
  EXPECT_TRUE(table->finish(findings).ok());
  return table;
}

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDeg = kPi / 180.0;

inline Vec3 incident(double theta_deg, double phi_deg = 0.0) {
  const double t = theta_deg * kDeg, p = phi_deg * kDeg;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// ∫ f dω over the whole sphere by the midpoint rule in (z, φ): nz × np cells
// of equal solid angle.
inline double integrate_sphere(const std::function<double(const Vec3&)>& f, int nz = 1200, int np = 600) {
  double sum = 0.0;
  for (int i = 0; i < nz; ++i) {
    const double z = -1.0 + (i + 0.5) * 2.0 / nz;
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    for (int j = 0; j < np; ++j) {
      const double p = (j + 0.5) * 2.0 * kPi / np;
      sum += f(Vec3{s * std::cos(p), s * std::sin(p), z});
    }
  }
  return sum * (2.0 / nz) * (2.0 * kPi / np);
}

// Directions binned on an nz × np grid of equal solid angle (z, φ) against
// `expected_per_sr` (the expected count per steradian, integrated over each
// bin by sub × sub midpoints). Bins expecting fewer than 5 are pooled into
// one. Returns the chi-square p-value; `dof` receives the degrees of freedom.
struct ChiSquare {
  double p_value = 0.0;
  int dof = 0;
  double chi2 = 0.0;
};
inline ChiSquare chi_square_sphere(const std::vector<Vec3>& directions,
                                   const std::function<double(const Vec3&)>& expected_per_sr, int nz = 40,
                                   int np = 40, int sub = 12) {
  std::vector<double> obs(static_cast<std::size_t>(nz * np), 0.0), exp(obs.size(), 0.0);
  for (const Vec3& d : directions) {
    const int i = std::clamp(static_cast<int>((d.z + 1.0) * 0.5 * nz), 0, nz - 1);
    double p = std::atan2(d.y, d.x);
    if (p < 0) p += 2 * kPi;
    const int j = std::clamp(static_cast<int>(p / (2 * kPi) * np), 0, np - 1);
    obs[static_cast<std::size_t>(i * np + j)] += 1.0;
  }
  const double cell = (2.0 / (nz * sub)) * (2.0 * kPi / (np * sub));
  for (int i = 0; i < nz * sub; ++i) {
    const double z = -1.0 + (i + 0.5) * 2.0 / (nz * sub);
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    for (int j = 0; j < np * sub; ++j) {
      const double p = (j + 0.5) * 2.0 * kPi / (np * sub);
      exp[static_cast<std::size_t>((i / sub) * np + j / sub)] +=
          expected_per_sr(Vec3{s * std::cos(p), s * std::sin(p), z}) * cell;
    }
  }
  ChiSquare r;
  double pooled_obs = 0.0, pooled_exp = 0.0;
  for (std::size_t b = 0; b < obs.size(); ++b) {
    if (exp[b] < 5.0) {
      pooled_obs += obs[b];
      pooled_exp += exp[b];
      continue;
    }
    r.chi2 += (obs[b] - exp[b]) * (obs[b] - exp[b]) / exp[b];
    ++r.dof;
  }
  if (pooled_exp >= 5.0) {
    r.chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++r.dof;
  } else if (pooled_obs > pooled_exp + 10.0 * std::sqrt(pooled_exp + 1.0)) {
    r.chi2 += 1e9;  // samples where the density says (almost) none belong
  }
  r.dof -= 1;
  r.p_value = chi_square_upper_tail(r.chi2, r.dof);
  return r;
}

}  // namespace gonio::sim::test
