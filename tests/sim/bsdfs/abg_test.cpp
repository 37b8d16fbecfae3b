// The ABg model against its closed forms: the integrals I0 that turn A into
// a total integrated scatter (g = 0, 1, 2 integrate in closed form), the
// albedo falling towards grazing incidence, and the peak at the specular
// direction with the kernel's own value.
#include "sim/bsdfs/abg.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/sim/bsdfs/lobe_checks.h"

namespace gonio::sim {
namespace {

using test::incident;
using test::kPi;

TEST(Abg, TotalIntegratedScatterClosedForms) {
  // I0 = 2π ∫_0^1 r dr / (B + r^g):
  //   g = 0: π / (B + 1);   g = 1: 2π (1 − B ln((1 + B)/B));   g = 2: π ln((B + 1)/B).
  for (double b : {1e-5, 1e-3, 0.05, 1.0}) {
    EXPECT_NEAR(abg_table(b, 0.0)->i0, kPi / (b + 1.0), 1e-9 * kPi / (b + 1.0)) << b;
    const double g1 = 2.0 * kPi * (1.0 - b * std::log((1.0 + b) / b));
    EXPECT_NEAR(abg_table(b, 1.0)->i0, g1, 1e-7 * g1) << b;
    const double g2 = kPi * std::log((b + 1.0) / b);
    EXPECT_NEAR(abg_table(b, 2.0)->i0, g2, 1e-7 * g2) << b;
    EXPECT_NEAR(abg_tis_from_a(abg_a_from_tis(0.3, b, 2.0), b, 2.0), 0.3, 1e-15);
  }
}

TEST(Abg, AlbedoIsTheTisAtNormalIncidenceAndFallsTowardsGrazing) {
  const auto t = abg_table(1e-3, 2.0);
  EXPECT_NEAR(abg_albedo(*t, incident(0.0)), 1.0, 1e-9);
  // g = 0: the kernel is constant over the unit disc of β (a Lambertian
  // lobe), so every incidence reflects all of the TIS.
  const auto flat = abg_table(0.5, 0.0);
  double last = 2.0;
  for (double ti : {0.0, 20.0, 40.0, 60.0, 80.0}) {
    const double a = abg_albedo(*t, incident(ti, 33.0));
    EXPECT_LT(a, last + 1e-12) << ti;
    last = a;
    EXPECT_NEAR(abg_albedo(*flat, incident(ti)), 1.0, 1e-6) << ti;
  }
  EXPECT_LT(abg_albedo(*t, incident(85.0)), 0.8);
}

TEST(Abg, EvaluatePeaksAtTheSpecularDirection) {
  const double b = 0.01, g = 2.0, tis = 0.6;
  const auto t = abg_table(b, g);
  const double a = abg_a_from_tis(tis, b, g);
  for (double ti : {0.0, 30.0, 70.0}) {
    const Vec3 wi = incident(ti, 15.0);
    const Vec3 spec{-wi.x, -wi.y, wi.z};
    // BSDF = A / (B + 0) at the specular direction; evaluate is per unit TIS.
    EXPECT_NEAR(tis * abg_evaluate(*t, false, wi, spec) / spec.z, a / b, 1e-9 * a / b) << ti;
    const Vec3 through{-wi.x, -wi.y, -wi.z};
    EXPECT_NEAR(tis * abg_evaluate(*t, true, wi, through) / wi.z, a / b, 1e-9 * a / b) << ti;
    EXPECT_EQ(abg_evaluate(*t, true, wi, spec), 0.0);  // transmission only below
  }
}

}  // namespace
}  // namespace gonio::sim
