// The chi-square distribution's upper tail, for the statistical tests the
// simulation makes about its own noise (sim/detectors/symmetry.h).
#pragma once

namespace gonio::sim {

// P(X ≥ x) for X ~ χ² with `dof` > 0 degrees of freedom: the regularised
// upper incomplete gamma function Q(dof/2, x/2). 1 for x ≤ 0. Accurate to
// about 1e-12 absolute for dof up to 10⁷.
double chi_square_upper_tail(double x, double dof);

}  // namespace gonio::sim
