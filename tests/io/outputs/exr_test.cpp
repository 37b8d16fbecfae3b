#include "io/outputs/exr.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

sim::FarField sample_far_field(int n) {
  sim::FarField f(n);
  for (std::size_t t = 0; t < f.texel_count(); ++t)
    f.add(t, 0.001 * static_cast<double>(t % 97) + 1e-4, t % 13 + (t == 5 ? 4000000000ull : 0ull));
  return f;
}

TEST(Exr, FarFieldRoundTrip) {
  test::TempDir dir;
  const sim::FarField f = sample_far_field(8);
  auto image = far_field_image(f);
  ASSERT_TRUE(image.ok()) << image.error().message;
  EXPECT_EQ(image->width, 8);
  EXPECT_EQ(image->height, 48);
  const std::string path = (dir / "farfield.exr").string();
  ASSERT_TRUE(write_exr(path, *image).ok());

  auto back = read_exr(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->envmap, Envmap::Cube);
  ASSERT_NE(back->find_attribute("gonio:units"), nullptr);
  const auto* y = back->find_float("Y");
  const auto* photons = back->find_uint("photons");
  ASSERT_NE(y, nullptr);
  ASSERT_NE(photons, nullptr);
  for (std::size_t t = 0; t < f.texel_count(); ++t) {
    // Texel t is pixel (x, face·N + y): row-major order of the image.
    EXPECT_EQ(photons->values[t], f.photons(t));  // exact, even above 2^31
    EXPECT_FLOAT_EQ(y->values[t], static_cast<float>(f.intensity_cd(t)));
  }
  auto g = far_field_from_image(*back, path);
  ASSERT_TRUE(g.ok());
  EXPECT_EQ(g->total_photons(), f.total_photons());
  EXPECT_NEAR(g->total_flux_lm(), f.total_flux_lm(), 1e-6 * f.total_flux_lm());
}

// A spectral run's X and Z ride beside Y, in Y's units (per steradian), so
// a texel's chromaticity reads straight off the file; a grey run has none.
TEST(Exr, SpectralFarFieldCarriesXAndZ) {
  test::TempDir dir;
  const sim::FarField f = sample_far_field(4);
  sim::ColourFarField c;
  for (std::size_t t = 0; t < f.texel_count(); ++t) {
    c.x_lm.push_back(0.9 * f.flux_lm(t));
    c.z_lm.push_back(0.4 * f.flux_lm(t));
  }
  auto image = far_field_image(f, &c);
  ASSERT_TRUE(image.ok()) << image.error().message;
  const std::string path = (dir / "farfield.exr").string();
  ASSERT_TRUE(write_exr(path, *image).ok());
  auto back = read_exr(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  const auto *x = back->find_float("X"), *y = back->find_float("Y"), *z = back->find_float("Z");
  ASSERT_TRUE(x && y && z);
  for (std::size_t t = 0; t < f.texel_count(); ++t) {
    EXPECT_FLOAT_EQ(x->values[t], static_cast<float>(0.9 * f.intensity_cd(t)));
    EXPECT_FLOAT_EQ(z->values[t], static_cast<float>(0.4 * f.intensity_cd(t)));
  }
  EXPECT_EQ(far_field_image(f)->find_float("X"), nullptr);
  c.z_lm.pop_back();
  EXPECT_FALSE(far_field_image(f, &c).ok());
}

TEST(Exr, GenericImagesWithAnyChannels) {
  test::TempDir dir;
  ExrImage image;
  image.width = 5;
  image.height = 3;
  image.envmap = Envmap::LatLong;
  image.float_channels = {{"R", std::vector<float>(15, 0.5f)}, {"G", std::vector<float>(15)}};
  for (int i = 0; i < 15; ++i) image.float_channels[1].values[i] = static_cast<float>(i) * 1.5f;
  image.uint_channels = {{"id", std::vector<std::uint32_t>(15, 7u)}};
  image.attributes = {{"note", "ünïcode ok"}};
  const std::string path = (dir / "latlong.exr").string();
  ASSERT_TRUE(write_exr(path, image).ok());
  auto back = read_exr(path);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->envmap, Envmap::LatLong);
  EXPECT_EQ(back->width, 5);
  EXPECT_EQ(back->height, 3);
  EXPECT_EQ(back->find_float("G")->values, image.float_channels[1].values);
  EXPECT_EQ(back->find_uint("id")->values, image.uint_channels[0].values);
  EXPECT_EQ(*back->find_attribute("note"), "ünïcode ok");
}

TEST(Exr, WriterRejectsInconsistentImages) {
  test::TempDir dir;
  const std::string path = (dir / "bad.exr").string();
  ExrImage image = cube_image(4);
  EXPECT_FALSE(write_exr(path, image).ok());  // no channels
  image.float_channels = {{"Y", std::vector<float>(10)}};
  EXPECT_FALSE(write_exr(path, image).ok());  // wrong size
  image.float_channels = {{"Y", std::vector<float>(96)}, {"Y", std::vector<float>(96)}};
  EXPECT_FALSE(write_exr(path, image).ok());  // repeated name
  image.float_channels.pop_back();
  image.height = 20;
  image.float_channels[0].values.resize(80);
  EXPECT_FALSE(write_exr(path, image).ok());  // a cube must be N × 6N
  EXPECT_FALSE(std::filesystem::exists(path));
  // A directory that does not exist: an error, nothing written.
  image = cube_image(4);
  image.float_channels = {{"Y", std::vector<float>(96)}};
  const Status s = write_exr((dir / "missing" / "x.exr").string(), image);
  EXPECT_FALSE(s.ok());
}

TEST(Exr, ReaderRejectsHostileFiles) {
  test::TempDir dir;
  const std::string missing = (dir / "none.exr").string();
  auto r = read_exr(missing);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().where.file, missing);

  const std::string text = (dir / "text.exr").string();
  test::write_file(text, "this is not an image\n");
  r = read_exr(text);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("not an OpenEXR"), std::string::npos);

  // A valid file cut short, and one with flipped bytes in its pixel data.
  auto image = far_field_image(sample_far_field(16));
  ASSERT_TRUE(image.ok());
  const std::string good = (dir / "good.exr").string();
  ASSERT_TRUE(write_exr(good, *image).ok());
  const std::string bytes = test::read_file(good);
  for (std::size_t keep : {std::size_t{8}, std::size_t{100}, bytes.size() / 2, bytes.size() - 10}) {
    const std::string cut = (dir / "cut.exr").string();
    test::write_file(cut, bytes.substr(0, keep));
    r = read_exr(cut);
    EXPECT_FALSE(r.ok()) << "kept " << keep << " bytes";
    if (!r.ok()) {
      EXPECT_EQ(r.error().where.file, cut);
    }
  }
  // A header claiming an absurd image size is refused before allocating.
  std::string huge = bytes;
  const std::string key = std::string("dataWindow") + '\0' + "box2i" + '\0';
  const std::size_t at = huge.find(key);
  ASSERT_NE(at, std::string::npos);
  const std::size_t value = at + key.size() + 4;  // after the attribute size
  const std::int32_t big = 20000;  // 20001² pixels: beyond the reader's limit, not OpenEXR's
  std::memcpy(&huge[value + 8], &big, 4);   // xMax
  std::memcpy(&huge[value + 12], &big, 4);  // yMax
  const std::string absurd = (dir / "absurd.exr").string();
  test::write_file(absurd, huge);
  r = read_exr(absurd);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("out of range"), std::string::npos) << r.error().message;

  // Far fields need a cube map with the flux and photons channels.
  ExrImage plain;
  plain.width = 2;
  plain.height = 2;
  EXPECT_FALSE(far_field_from_image(plain, "x").ok());
  ExrImage cube = cube_image(2);
  cube.float_channels = {{"Y", std::vector<float>(24)}};
  EXPECT_FALSE(far_field_from_image(cube, "x").ok());
}

}  // namespace
}  // namespace gonio::io

namespace gonio::io {
namespace {

TEST(LatLong, PixelCentresFollowOpenExrsConventionAndSolidAnglesTileTheSphere) {
  const int w = 9, h = 5;  // 45° per pixel
  // Top row: the +Y pole; bottom row: −Y; middle row: longitude +180° at the
  // left, 0° (+Z) in the middle, +90° (+X) a quarter from the left edge
  // of the middle… i.e. longitude = 180° − x·45°.
  const Vec3 top = latlong_direction(w, h, 3, 0);
  EXPECT_NEAR(top.y, 1.0, 1e-6);
  EXPECT_NEAR(latlong_direction(w, h, 0, h - 1).y, -1.0, 1e-6);
  for (int x = 0; x < w; ++x) {
    const double lon = (180.0 - 45.0 * x) * M_PI / 180.0;
    const Vec3 d = latlong_direction(w, h, x, 2);
    EXPECT_NEAR(d.x, std::sin(lon), 1e-6) << x;
    EXPECT_NEAR(d.y, 0.0, 1e-6) << x;
    EXPECT_NEAR(d.z, std::cos(lon), 1e-6) << x;
  }
  const Vec3 d = latlong_direction(w, h, 2, 1);  // latitude 45°, longitude 90°
  EXPECT_NEAR(d.x, std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(d.y, std::sqrt(0.5), 1e-6);

  double total = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) total += latlong_pixel_solid_angle(w, h, x, y);
  EXPECT_NEAR(total, 4.0 * M_PI, 1e-12);
  // A polar cap of half a row: 2π(1 − cos 22.5°), shared by 8 columns.
  EXPECT_NEAR(latlong_pixel_solid_angle(w, h, 3, 0), 2.0 * M_PI * (1.0 - std::cos(M_PI / 8)) / 8.0, 1e-15);
  EXPECT_NEAR(latlong_pixel_solid_angle(w, h, 0, 0), 0.5 * latlong_pixel_solid_angle(w, h, 3, 0), 1e-15);
}

TEST(LatLong, FluxOfAnIsotropicMapIsFourPiTimesItsIntensityAndSurvivesTheFile) {
  test::TempDir dir;
  ExrImage image = latlong_image(65, 33);
  image.float_channels.push_back({"Y", std::vector<float>(65 * 33, 250.0f)});
  const std::string path = (dir / "latlong.exr").string();
  ASSERT_TRUE(write_exr(path, image).ok());
  auto back = read_exr(path);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->envmap, Envmap::LatLong);
  auto flux = latlong_flux_lm(*back, path);
  ASSERT_TRUE(flux.ok());
  EXPECT_NEAR(*flux, 4.0 * M_PI * 250.0, 1e-9);

  back->float_channels[0].values[100] = -1.0f;
  auto bad = latlong_flux_lm(*back, path);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("pixel (35, 1)"), std::string::npos) << bad.error().message;
  EXPECT_FALSE(latlong_flux_lm(cube_image(4), "cube").ok());
}

}  // namespace
}  // namespace gonio::io
