#include "photometry/hermite.h"

#include <algorithm>
#include <cmath>

namespace gonio::photometry {
namespace {

// Clamps a slope estimate so that the cubic stays monotone: zero unless it
// has the sign of both secants, at most three times the smaller of them.
double limit(double d, double s1, double s2) {
  if (!(s1 * s2 > 0.0) || !(d * s1 > 0.0)) return 0.0;
  const double bound = 3.0 * std::min(std::abs(s1), std::abs(s2));
  return std::abs(d) <= bound ? d : std::copysign(bound, s1);
}

// Slope at the end node of two consecutive segments of lengths h0 (the one
// touching the node) and h1, with secant slopes s0 and s1: the derivative
// there of the parabola through the three nodes.
double end_slope(double h0, double h1, double s0, double s1) {
  return ((2.0 * h0 + h1) * s0 - h0 * s1) / (h0 + h1);
}

}  // namespace

void monotone_hermite_slopes(std::size_t n, const double* h, const double* inv_h,
                             const double* left_weight, const double* f, double* s, double* left,
                             double* right) {
  double scale = 0.0;
  for (std::size_t k = 0; k < n; ++k) scale = std::max(scale, std::abs(f[k]));
  // Differences at rounding level are flat: a computed cos 90° must not
  // pass for a slope.
  const double tiny = 1e-12 * scale;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double df = f[k + 1] - f[k];
    s[k] = std::abs(df) <= tiny ? 0.0 : df * inv_h[k];
  }
  // Boundary nodes: the parabola through the first (last) three nodes.
  right[0] = n > 2 ? limit(end_slope(h[0], h[1], s[0], s[1]), s[0], s[0]) : s[0];
  left[n - 1] =
      n > 2 ? limit(end_slope(h[n - 2], h[n - 3], s[n - 2], s[n - 3]), s[n - 2], s[n - 2])
            : s[n - 2];
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double l = s[k - 1], r = s[k];
    // Three-point slope, limited to three times the smaller secant; it has
    // the sign of both secants where they agree (a convex combination),
    // and is zero at extrema and flat runs.
    const double d = l + left_weight[k] * (r - l);
    const double limited =
        std::copysign(std::min(std::abs(d), 3.0 * std::min(std::abs(l), std::abs(r))), l);
    left[k] = right[k] = l * r > 0.0 ? limited : 0.0;
    if (l * r <= 0.0 && std::abs(f[k]) <= tiny && ((l == 0.0) != (r == 0.0))) {
      // Edge of a dark run: the lit side keeps the slope of its own
      // parabola if it is monotone over two segments (a smooth flank, not
      // an under-resolved step).
      left[k] = l != 0.0 && k >= 2 ? limit(end_slope(h[k - 1], h[k - 2], l, s[k - 2]), l, s[k - 2])
                                   : 0.0;
      right[k] = r != 0.0 && k + 2 < n
                     ? limit(end_slope(h[k], h[k + 1], r, s[k + 1]), r, s[k + 1])
                     : 0.0;
    }
  }
}

}  // namespace gonio::photometry
