// The ABg kernel's integral over the unit disc, I0(B, g) = 2π ∫_0^1 r dr /
// (B + r^g): TIS = A · I0 (sim/bsdfs/abg.h). Plain arithmetic, so that a
// reader converting a TracePro-style A into Gonio's TIS computes it the
// same way as the tracer's tables.
#pragma once

namespace gonio::sim {

// B > 0 and g in [0, 6]; relative error below 10⁻¹⁰.
double abg_i0(double b, double g);

}  // namespace gonio::sim
