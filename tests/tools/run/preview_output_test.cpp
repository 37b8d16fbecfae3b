#include "tools/cli/input_options.h"
#include "tools/run/preview_output.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "io/outputs/cube_cross.h"
#include "io/outputs/exr.h"
#include "io/outputs/image.h"
#include "tests/support/test_support.h"

namespace gonio::cli {
namespace {

sim::FarField sample_field(int n) {
  sim::FarField field(n);
  std::mt19937_64 rng(2);
  std::poisson_distribution<int> photons(3.0);
  for (std::size_t t = 0; t < field.texel_count(); ++t) {
    const int k = photons(rng);
    field.add(t, 0.01 * k, static_cast<std::uint64_t>(k));
  }
  return field;
}

TEST(PreviewOutput, WritesTheFilteredCubeAsExrAndTheCrossAsPng) {
  test::TempDir dir;
  const int n = 16;
  const sim::FarField field = sample_field(n);
  PreviewOutput out(dir.path().string(), n, sim::PreviewFilterParams{});
  ASSERT_TRUE(out.write(field).ok());
  ASSERT_TRUE(out.write(field).ok());  // replaced, nothing else left behind
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator()),
            2);

  const Result<io::ExrImage> exr = io::read_exr(out.exr_path());
  ASSERT_TRUE(exr.ok()) << exr.error().message;
  EXPECT_EQ(exr->envmap, io::Envmap::Cube);
  EXPECT_EQ(exr->width, n);
  EXPECT_EQ(exr->height, 6 * n);
  const io::ExrImage::FloatChannel* y = exr->find_float("Y");
  ASSERT_NE(y, nullptr);
  for (std::size_t t = 0; t < field.texel_count(); ++t)
    ASSERT_EQ(y->values[t], static_cast<float>(out.intensity_cd()[t]));
  ASSERT_NE(exr->find_attribute("gonio:filter"), nullptr);
  EXPECT_NE(exr->find_attribute("gonio:filter")->find("adaptive"), std::string::npos);

  const Result<io::Image8> png = io::read_png(out.png_path());
  ASSERT_TRUE(png.ok()) << png.error().message;
  EXPECT_EQ(png->width, 4 * n);
  EXPECT_EQ(png->height, 3 * n);
  EXPECT_EQ(png->pixels, io::cube_cross_preview(sim::CubeMapGrid(n), out.intensity_cd()).pixels);
}

TEST(PreviewOutput, AnUnwritableDirectoryIsAnErrorNamingThePath) {
  test::TempDir dir;
  PreviewOutput out((dir / "missing").string(), 8, sim::PreviewFilterParams{});
  const Status s = out.write(sim::FarField(8));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(to_string(s.error()).find("missing"), std::string::npos);
}

TEST(PreviewOptions, MapToTheFilterParameters) {
  const auto parse = [](const std::vector<std::string>& args) {
    PreviewOptions o;
    ArgParser parser("simulate", "", "");
    add_preview_options(parser, &o);
    EXPECT_EQ(parser.parse(args), ArgParser::Outcome::Run);
    return std::pair{o, preview_params(o, parser)};
  };
  {
    const auto [o, p] = parse({"--preview"});
    EXPECT_TRUE(o.enabled);
    ASSERT_TRUE(p.ok());
    const sim::PreviewFilterParams defaults;
    EXPECT_EQ(p->interpolation, defaults.interpolation);
    EXPECT_EQ(p->adaptive, defaults.adaptive);
    EXPECT_EQ(p->threshold_photons, defaults.threshold_photons);
    EXPECT_EQ(p->levels, 0);
  }
  {
    const auto [o, p] = parse({"--preview", "--no-adaptive", "--filter", "bilinear", "--levels", "3"});
    ASSERT_TRUE(p.ok());
    EXPECT_FALSE(p->adaptive);
    EXPECT_EQ(p->threshold_photons, sim::PreviewFilterParams::kFixedThreshold);
    EXPECT_EQ(p->interpolation, sim::Interpolation::Bilinear);
    EXPECT_EQ(p->levels, 3);
  }
  {
    const auto [o, p] = parse({"--preview", "--threshold=250", "--sigma-d", "0.7", "--sigma-r", "0.3",
                               "--filter=none"});
    ASSERT_TRUE(p.ok());
    EXPECT_TRUE(p->adaptive);
    EXPECT_EQ(p->threshold_photons, 250.0);
    EXPECT_EQ(p->sigma_d, 0.7);
    EXPECT_EQ(p->sigma_r, 0.3);
    EXPECT_EQ(p->interpolation, sim::Interpolation::None);
  }
  {
    const auto [o, p] = parse({"--adaptive", "--no-adaptive"});
    EXPECT_FALSE(p.ok());
  }
}

}  // namespace
}  // namespace gonio::cli
