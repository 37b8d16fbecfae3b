// The measured-BSDF data type: the Klems bases against LBNL's published
// patch counts and projected solid angles, Shirley–Chiu's map against its
// inverse, row albedos against closed forms, the energy check on load and
// the reciprocity report.
#include "sim/bsdfs/tabulated_bsdf.h"

#include <gtest/gtest.h>

#include <cmath>

#include "tests/sim/bsdfs/lobe_checks.h"

namespace gonio::sim {
namespace {

using test::incident;
using test::kDeg;
using test::kPi;

TEST(PatchBasis, KlemsBasesMatchLbnlsDefinitions) {
  // LBNL's Klems bases: 145, 73 and 41 patches covering the hemisphere,
  // with the ring bounds and φ counts of Radiance's abase_list
  // (src/common/bsdf_m.c); projected solid angles ("Lambda") by Radiance's
  // io_getohm, π (cos² θlo − cos² θhi) / nφ: 0.0238639 for the first patch
  // (0–5°), 0.0233229 for each of the 8 of the second ring (5–15°),
  // 0.0175372 for each of the 12 of the last (75–90°).
  for (auto [name, count] : {std::pair{"LBNL/Klems Full", 145}, std::pair{"LBNL/Klems Half", 73},
                             std::pair{"LBNL/Klems Quarter", 41}}) {
    const PatchBasis b = PatchBasis::klems(name);
    ASSERT_EQ(b.size(), static_cast<std::size_t>(count)) << name;
    double sum = 0.0;
    for (std::size_t p = 0; p < b.size(); ++p) {
      sum += b.projected_solid_angle(p);
      EXPECT_EQ(b.patch_of(b.centre_of(p)), p) << name << " " << p;
      for (double u : {0.02, 0.5, 0.97}) EXPECT_EQ(b.patch_of(b.direction_in(p, u, 0.99 - u)), p) << name << " " << p;
    }
    EXPECT_NEAR(sum, kPi, 1e-12) << name;
  }
  const PatchBasis full = PatchBasis::klems("LBNL/Klems Full");
  EXPECT_NEAR(full.projected_solid_angle(0), 0.0238639, 5e-8);
  EXPECT_NEAR(full.projected_solid_angle(1), 0.0233229, 5e-8);
  EXPECT_NEAR(full.projected_solid_angle(144), 0.0175372, 5e-8);
  // Patch 1 is centred on φ = 0 in its ring (5–15°), patch 3 on 90°.
  EXPECT_EQ(full.patch_of(incident(10.0, 0.0)), 1u);
  EXPECT_EQ(full.patch_of(incident(10.0, 90.0)), 3u);
  EXPECT_EQ(full.patch_of(incident(10.0, -20.0)), 1u);
  EXPECT_EQ(full.patch_of(incident(89.9, 180.0)), 144u - 5u);
  EXPECT_EQ(PatchBasis::klems("LBNL/Klems Eighth").size(), 0u);
}

TEST(PatchBasis, ShirleyChiuSquareAndDiscAreInverse) {
  for (int i = 0; i < 50; ++i) {
    for (int j = 0; j < 50; ++j) {
      const double sx = (i + 0.37) / 50.0, sy = (j + 0.61) / 50.0;
      double dx, dy, bx, by;
      square_to_disc(sx, sy, &dx, &dy);
      ASSERT_LE(dx * dx + dy * dy, 1.0 + 1e-12);
      disc_to_square(dx, dy, &bx, &by);
      ASSERT_NEAR(bx, sx, 1e-12);
      ASSERT_NEAR(by, sy, 1e-12);
    }
  }
  PatchBasis sq;
  sq.kind = PatchBasis::Kind::Square;
  sq.square_n = 8;
  double sum = 0.0;
  for (std::size_t p = 0; p < sq.size(); ++p) {
    sum += sq.projected_solid_angle(p);
    EXPECT_EQ(sq.patch_of(sq.direction_in(p, 0.3, 0.8)), p);
  }
  EXPECT_NEAR(sum, kPi, 1e-12);
}

TabulatedBsdf lambertian(double reflect, double transmit) {
  TabulatedBsdf t;
  t.name = "lambertian";
  t.basis = PatchBasis::klems("LBNL/Klems Full");
  for (double theta : {0.0, 40.0, 82.5}) {
    TabulatedBsdf::Row r;
    r.theta_deg = theta;
    r.reflect.assign(t.basis.size(), static_cast<float>(reflect / kPi));
    r.transmit.assign(t.basis.size(), static_cast<float>(transmit / kPi));
    t.front.rows.push_back(r);
  }
  return t;
}

TEST(TabulatedBsdf, LambertianRowsReflectTheirAlbedo) {
  TabulatedBsdf t = lambertian(0.3, 0.5);
  std::vector<Finding> findings;
  ASSERT_TRUE(t.finish(findings).ok());
  EXPECT_TRUE(findings.empty());
  double r, tr;
  EXPECT_NEAR(t.albedo(true, incident(25.0, 70.0), &r, &tr), 0.8, 1e-6);
  EXPECT_NEAR(r, 0.3, 1e-6);
  EXPECT_NEAR(tr, 0.5, 1e-6);
  // The back uses the front where it has no data of its own.
  EXPECT_NEAR(t.albedo(false, incident(60.0)), 0.8, 1e-6);
  const Vec3 wo{0.6, 0.0, -0.8};
  EXPECT_NEAR(t.evaluate(true, incident(10.0), wo), 0.5 / kPi * 0.8, 1e-7);
  EXPECT_NEAR(t.reciprocity_error(false), 0.0, 1e-7);
  EXPECT_NEAR(t.reciprocity_error(true), -1.0, 0.0);  // one side only
}

TEST(TabulatedBsdf, RowsAboveOneAreScaledWithAFinding) {
  TabulatedBsdf t = lambertian(0.6, 0.5);
  std::vector<Finding> findings;
  ASSERT_TRUE(t.finish(findings).ok());
  ASSERT_EQ(findings.size(), 3u);
  EXPECT_EQ(findings[0].code, "bsdf-albedo-above-1");
  EXPECT_NE(findings[0].message.find("1.1"), std::string::npos) << findings[0].message;
  EXPECT_NEAR(t.albedo(true, incident(0.0)), 1.0, 1e-6);
}

TEST(TabulatedBsdf, BadShapesAreErrors) {
  std::vector<Finding> findings;
  TabulatedBsdf t = lambertian(0.3, 0.3);
  t.front.rows[1].reflect.pop_back();
  EXPECT_FALSE(t.finish(findings).ok());
  t = lambertian(0.3, 0.3);
  t.front.rows[1].theta_deg = 0.0;
  EXPECT_FALSE(t.finish(findings).ok());
  t = lambertian(0.3, 0.3);
  t.front.rows[2].transmit[7] = std::nanf("");
  EXPECT_FALSE(t.finish(findings).ok());
  t = lambertian(0.3, 0.3);
  t.basis.ring_phi_deg[3].pop_back();
  t.basis.ring_phi_deg[3].back() += 0.0;
  EXPECT_FALSE(t.finish(findings).ok());
  EXPECT_FALSE(TabulatedBsdf{}.finish(findings).ok());
}

TEST(TabulatedBsdf, ReciprocityReportSeesAnAsymmetricTable) {
  // Reflection that depends on the outgoing angle only (f ∝ cos θo) is not
  // reciprocal: f(a → b) ≠ f(b → a) unless θa = θb.
  TabulatedBsdf t;
  t.name = "asymmetric";
  t.basis = PatchBasis::klems("LBNL/Klems Full");
  for (double theta : {0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 82.5}) {
    TabulatedBsdf::Row r;
    r.theta_deg = theta;
    for (std::size_t p = 0; p < t.basis.size(); ++p)
      r.reflect.push_back(static_cast<float>(0.5 * t.basis.centre_of(p).z / kPi));
    t.front.rows.push_back(r);
  }
  std::vector<Finding> findings;
  ASSERT_TRUE(t.finish(findings).ok());
  EXPECT_GT(t.reciprocity_error(false), 0.2);
}

}  // namespace
}  // namespace gonio::sim
