// The material library: every preset is a valid material that states its
// values and source, surfaces reflect what their datasheet says, and each
// volume preset's stored medium, traced again through the sheet model with
// other random numbers, gives back the datasheet values it was fitted to (a
// stale or mistyped coefficient fails here).
#include "sim/bsdfs/library.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <set>

#include "sim/bsdfs/slab.h"
#include "sim/bsdfs/material.h"

namespace gonio::sim {
namespace {

TEST(Library, PresetsAreValidNamedAndSourced) {
  std::set<std::string> names;
  for (const MaterialPreset& p : material_library()) {
    EXPECT_TRUE(names.insert(p.name).second) << p.name;
    EXPECT_EQ(p.material.name, p.name);
    EXPECT_FALSE(p.datasheet.empty()) << p.name;
    EXPECT_FALSE(p.source.empty()) << p.name;
    EXPECT_TRUE(validate(p.material).ok()) << p.name;
    EXPECT_EQ(find_preset(p.name), &p);
  }
  for (const char* n : {"white powder coat", "anodised aluminium", "specular aluminium", "opal PC 3 mm",
                        "satin PC 3 mm", "opal PMMA 3 mm", "satin PMMA 3 mm", "clear PMMA", "clear PC", "black"})
    EXPECT_NE(find_preset(n), nullptr) << n;
  EXPECT_EQ(find_preset("Opal PC 3 mm"), nullptr);
  // Surfaces reflect their stated totals.
  EXPECT_NEAR(find_preset("white powder coat")->material.total(), 0.90, 1e-12);
  EXPECT_NEAR(find_preset("anodised aluminium")->material.total(), 0.85, 1e-12);
  EXPECT_NEAR(find_preset("specular aluminium")->material.total(), 0.95, 1e-12);
  EXPECT_NEAR(find_preset("black")->material.total(), 0.05, 1e-12);
  // Clear plastics: a lossless dielectric of the measured index.
  EXPECT_EQ(find_preset("clear PMMA")->material.dielectric, 1.0);
  EXPECT_EQ(find_preset("clear PMMA")->material.ior, 1.491);
  EXPECT_EQ(find_preset("clear PC")->material.ior, 1.585);
  EXPECT_EQ(find_preset("clear PC")->material.attenuation_per_m, 0.0);
}

TEST(Library, VolumePresetsGiveBackTheirDatasheetValues) {
  for (const MaterialPreset& p : material_library()) {
    if (p.thickness_m == 0.0) continue;
    SlabMedium m;
    m.scattering_per_m = p.material.scattering_per_m;
    m.absorption_per_m = p.material.attenuation_per_m;
    m.g = p.material.scattering_g;
    m.ior = p.material.ior;
    m.thickness_m = p.thickness_m;
    const SlabOptics o = slab_optics(m, 0.0, 100000, 12345);
    std::printf("  %s: T %.4f (%.2f), haze %.4f, half-value angle %.1f deg\n", p.name.c_str(), o.transmittance,
                p.transmittance, o.haze, o.half_value_deg);
    EXPECT_NEAR(o.transmittance, p.transmittance, 0.008) << p.name;
    if (p.haze > 0.0) {
      EXPECT_NEAR(o.haze, p.haze, 0.008) << p.name;
    }
    if (p.half_value_deg > 0.0) {
      EXPECT_NEAR(o.half_value_deg, p.half_value_deg, 2.0) << p.name;
    }
  }
}

}  // namespace
}  // namespace gonio::sim
