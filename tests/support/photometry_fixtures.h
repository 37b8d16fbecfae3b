// Distributions with known closed-form properties, built in the tests.
#pragma once

#include <functional>
#include <vector>

#include "photometry/distribution.h"
#include "photometry/vec3.h"

namespace gonio::test {

// from, from + step, …, to (the last one exactly `to`).
std::vector<double> angles(double from, double to, double step);

// A relative-photometry distribution of `type` whose intensity at each grid
// point is f(direction) [cd] of that point's local direction.
photometry::Distribution sample_direction(photometry::PhotometricType type,
                                          photometry::Symmetry symmetry,
                                          std::vector<double> horizontal_deg,
                                          std::vector<double> vertical_deg,
                                          const std::function<double(const Vec3&)>& f);

// A Type C distribution with intensity f(C, γ) [cd], angles in degrees.
photometry::Distribution sample_c(photometry::Symmetry symmetry, std::vector<double> c_deg,
                                  std::vector<double> gamma_deg,
                                  const std::function<double(double, double)>& f);

// I₀ cosⁿγ below the horizontal, 0 above (f of a local direction).
std::function<double(const Vec3&)> cos_lobe(double i0_cd, double n);

}  // namespace gonio::test
