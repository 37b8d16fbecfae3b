#include "sim/bsdfs/abg_integral.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gonio::sim {

double abg_i0(double b, double g) {
  // ∫_0^1 r / (B + r^g) dr in u = ln r (the core, ~B^(1/g) wide, may be
  // tiny): ∫ e^{2u} / (B + e^{gu}) du from ln(r0) to 0 by Simpson, plus
  // the part below r0, where the kernel is its value at r0: r0² / (2 (B + r0^g)).
  const double core = g > 0.0 ? std::pow(b, 1.0 / g) : 1.0;
  const double r0 = std::clamp(1e-6 * core, 1e-300, 1e-6);
  const double u0 = std::log(r0);
  const int n = 20000;  // even
  const double h = -u0 / n;
  const auto f = [&](double u) { return std::exp(2.0 * u) / (b + std::exp(g * u)); };
  double sum = f(u0) + f(0.0);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(u0 + i * h);
  return 2.0 * std::numbers::pi * (sum * h / 3.0 + r0 * r0 / (2.0 * (b + std::pow(r0, g))));
}

}  // namespace gonio::sim
