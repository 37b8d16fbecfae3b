#include "io/outputs/luminance_images.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "io/outputs/exr.h"
#include "io/outputs/image.h"
#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

// A 0.1 m square panel seen straight below (201 pixels of 1 mm): uniform
// `face_cd_m2`, with one 3 × 3 mm spot of `spot_cd_m2` in the middle.
sim::LuminanceImage panel(double spot_cd_m2, double face_cd_m2 = 2000.0) {
  sim::LuminanceImage img;
  img.plane.view = {0.0, 0.0};
  img.plane.pixel_m = 0.001;
  img.plane.pixels = 201;
  img.cd_m2.assign(201 * 201, 0.0);
  for (int y = 50; y < 150; ++y)
    for (int x = 50; x < 150; ++x) img.cd_m2[static_cast<std::size_t>(y) * 201 + x] = face_cd_m2;
  for (int y = 99; y < 102; ++y)
    for (int x = 99; x < 102; ++x) img.cd_m2[static_cast<std::size_t>(y) * 201 + x] = spot_cd_m2;
  for (double l : img.cd_m2) {
    img.intensity_cd += l * 1e-6;
    img.max_cd_m2 = std::max(img.max_cd_m2, l);
  }
  return img;
}

TEST(LuminanceImages, WritesTheExrAndReportsCie232PerView) {
  test::TempDir dir;
  photometry::LuminousOpening opening;
  opening.shape = photometry::OpeningShape::Rectangular;
  opening.length_m = opening.width_m = 0.1;
  sim::LuminanceImage bright = panel(2.0e6, 200.0), second = panel(2000.0);
  second.plane.view = {90.0, 0.0};
  const LuminanceOutputs out = write_luminance_images(dir.path().string(), "lamp", {bright, second}, opening, 2.5);
  EXPECT_EQ(luminance_image_name("lamp", {90.0, 65.0}), "lamp.luminance-C90-G65.exr");
  ASSERT_EQ(out.images.size(), 2u);
  const auto exr = read_exr((dir / "lamp.luminance-C0-G0.exr").string());
  ASSERT_TRUE(exr.ok()) << exr.error().message;
  const ExrImage::FloatChannel* l = exr->find_float("L");
  ASSERT_NE(l, nullptr);
  EXPECT_EQ(exr->width, 201);
  EXPECT_FLOAT_EQ(l->values[100 * 201 + 100], 2.0e6f);
  EXPECT_FLOAT_EQ(l->values[60 * 201 + 60], 200.0f);
  EXPECT_EQ(exr->find_float("x"), nullptr);  // grey run: no chromaticity
  // A dim face (200 cd/m², under the threshold) with the spot: the spot's
  // blur is the glare source; k² far above 1 (it holds 18 cd of the 20 cd
  // on ~9 cm² of 100 cm²). A face above the threshold would be part of the
  // glare source itself: CIE 232 sees non-uniformity only through it.
  const nlohmann::json& a = out.images[0]["cie232"];
  ASSERT_TRUE(a["defined"].get<bool>());
  EXPECT_NEAR(a["projected_area_m2"].get<double>(), 0.01, 1e-12);
  EXPECT_NEAR(a["intensity_cd"].get<double>(), bright.intensity_cd, 1e-9);
  EXPECT_GT(a["k2"].get<double>(), 5.0);
  EXPECT_NEAR(a["delta_ugr"].get<double>(), 8.0 * std::log10(a["k2"].get<double>()), 1e-9);
  EXPECT_TRUE(a["resolution_ok"].get<bool>());
  // The uniform panel (2000 cd/m² ≥ 500): k² ≈ A/A_eff, a small rebate.
  const nlohmann::json& b = out.images[1]["cie232"];
  ASSERT_TRUE(b["defined"].get<bool>());
  EXPECT_LT(b["delta_ugr"].get<double>(), 0.0);
  EXPECT_GT(b["delta_ugr"].get<double>(), -2.0);
  // The largest ΔUGR and its view.
  EXPECT_DOUBLE_EQ(out.cie232["delta_ugr"].get<double>(), a["delta_ugr"].get<double>());
  EXPECT_EQ(out.cie232["c_deg"].get<double>(), 0.0);
  EXPECT_EQ(out.cie232["threshold_cd_m2"].get<double>(), 500.0);
  // io::largest_delta_ugr (gonio tolerance's dugr): the same largest, in
  // either order of the views, and its image.
  const LargestDeltaUgr largest = largest_delta_ugr({second, bright}, opening);
  EXPECT_EQ(largest.delta_ugr, out.cie232["delta_ugr"].get<double>());
  EXPECT_EQ(largest.image, 1u);
  EXPECT_EQ(largest.glare.k2, a["k2"].get<double>());
  EXPECT_TRUE(std::isnan(largest_delta_ugr({bright}, {}).delta_ugr));  // a point opening: none defined
  // The thumbnail covers the lit part (the panel plus a margin), ≤ 48 a side.
  const nlohmann::json& t = out.images[0]["thumbnail"];
  EXPECT_EQ(t["size"].get<int>(), 48);
  EXPECT_EQ(t["cd_m2"].size(), 48u * 48u);
  EXPECT_NEAR(t["cd_m2"][0].get<double>(), 0.0, 1e-9);
  EXPECT_NEAR(t["cd_m2"][10 * 48 + 10].get<double>(), 200.0, 1e-6);
  // No luminous area (a point opening): CIE 232 is not defined, and says so.
  const LuminanceOutputs point = write_luminance_images(dir.path().string(), "pt", {bright}, {}, 2.5);
  EXPECT_FALSE(point.images[0]["cie232"]["defined"].get<bool>());
  EXPECT_TRUE(point.cie232["delta_ugr"].is_null());
}

TEST(LuminanceImages, SpectralImagesCarryChromaticity) {
  test::TempDir dir;
  sim::LuminanceImage img = panel(2000.0);
  img.cie_x.assign(img.cd_m2.size(), 0.3127);
  img.cie_y.assign(img.cd_m2.size(), 0.3290);
  const LuminanceOutputs out = write_luminance_images(dir.path().string(), "c", {img}, {}, 2.5);
  const auto exr = read_exr((dir / "c.luminance-C0-G0.exr").string());
  ASSERT_TRUE(exr.ok());
  ASSERT_NE(exr->find_float("x"), nullptr);
  EXPECT_FLOAT_EQ(exr->find_float("y")->values[5], 0.3290f);
}

TEST(LuminanceImages, UnwritableFolderIsAFailureNotACrash) {
  const LuminanceOutputs out =
      write_luminance_images("/nonexistent/gonio/dir", "x", {panel(2000.0)}, {}, 2.5);
  EXPECT_FALSE(out.failures.empty());
  EXPECT_TRUE(out.written.empty());
  EXPECT_EQ(out.images.size(), 1u);
}

}  // namespace
}  // namespace gonio::io
