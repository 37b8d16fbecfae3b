#include "io/outputs/image.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

TEST(Png, WritesAtomicallyAndReadsBackTheSamePixels) {
  test::TempDir dir;
  for (int channels = 1; channels <= 4; ++channels) {
    Image8 img;
    img.width = 5;
    img.height = 3;
    img.channels = channels;
    for (int i = 0; i < 15; ++i)
      for (int c = 0; c < channels; ++c) img.pixels.push_back(static_cast<std::uint8_t>(17 * i + 60 * c));
    const std::string path = (dir / "preview.png").string();
    ASSERT_TRUE(write_png(path, img).ok());
    // Overwrites in place and leaves nothing else behind.
    img.pixels[0] = 1;
    ASSERT_TRUE(write_png(path, img).ok());
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator()),
              1);
    const Result<Image8> back = read_png(path);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back->width, 5);
    EXPECT_EQ(back->height, 3);
    EXPECT_EQ(back->channels, channels);
    EXPECT_EQ(back->pixels, img.pixels) << channels << " channels";
  }
}

TEST(Png, ErrorsNameThePath) {
  test::TempDir dir;
  const Image8 img{1, 1, 2, {0, 255}};
  const Status s = write_png((dir / "missing" / "x.png").string(), img);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(to_string(s.error()).find("missing"), std::string::npos);
  test::write_file(dir / "bad.png", "not a png");
  const Result<Image8> r = read_png((dir / "bad.png").string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(to_string(r.error()).find("bad.png"), std::string::npos);
}

TEST(Png, AMissingOrForeignModuleIsAClearError) {
  test::TempDir dir;
  const std::string missing = (dir / "gonio_png.so").string();
  const Status none = load_png_module({missing});
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("gonio_png.so (OpenImageIO) is missing"), std::string::npos)
      << none.error().message;
  EXPECT_NE(none.error().message.find(missing), std::string::npos) << none.error().message;
  test::write_file(dir / "gonio_png.so", "not a shared object");
  const Status foreign = load_png_module({missing});
  ASSERT_FALSE(foreign.ok());
  EXPECT_NE(foreign.error().message.find("cannot load the PNG module " + missing),
            std::string::npos)
      << foreign.error().message;
}

}  // namespace
}  // namespace gonio::io
