// The monotone piecewise-cubic Hermite model of intensities along one grid
// axis (photometry/flux.h describes it): node slopes from three-point
// parabolas, limited so that the curve never leaves the range of its two end
// values on any interval, with the one-sided slopes kept at the edge of a dark
// run. flux.cpp integrates this model; resample.cpp evaluates it, so that a
// resampled distribution carries the flux its source has.
#pragma once

#include <cstddef>

namespace gonio::photometry {

// Node slopes of the model through f[0..n) at nodes with spacings
// h[k] = x[k+1] − x[k] (n − 1 of them, positive), inv_h[k] = 1 / h[k] and
// left_weight[k] = h[k] / (h[k−1] + h[k]) for interior k (entries 0 and n − 1
// unused). Writes the secant slopes s[0..n−1) and the slope at node k used by
// the segment left of it, left[k], and right of it, right[k] (equal except at
// the edge of a dark run). Requires n ≥ 2.
void monotone_hermite_slopes(std::size_t n, const double* h, const double* inv_h,
                             const double* left_weight, const double* f, double* s, double* left,
                             double* right);

// The cubic of one segment of length h with values f0, f1 and slopes d0, d1
// at its ends, at t = (x − x0) / h in [0, 1].
inline double hermite_value(double h, double f0, double f1, double d0, double d1, double t) {
  const double t2 = t * t, t3 = t2 * t;
  return f0 * (2.0 * t3 - 3.0 * t2 + 1.0) + f1 * (-2.0 * t3 + 3.0 * t2) +
         h * (d0 * (t3 - 2.0 * t2 + t) + d1 * (t3 - t2));
}

}  // namespace gonio::photometry
