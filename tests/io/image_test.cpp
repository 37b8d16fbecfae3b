#include "io/image.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "tests/support/test_support.h"

namespace gonio::io {
namespace {

TEST(Png, WritesAtomicallyAndReadsBackTheSamePixels) {
  test::TempDir dir;
  Rgba8Image img;
  img.width = 5;
  img.height = 3;
  for (int i = 0; i < 15; ++i)
    for (int c = 0; c < 4; ++c) img.rgba.push_back(static_cast<std::uint8_t>(17 * i + 60 * c));
  const std::string path = (dir / "preview.png").string();
  ASSERT_TRUE(write_png(path, img).ok());
  // Overwrites in place and leaves nothing else behind.
  img.rgba[0] = 1;
  ASSERT_TRUE(write_png(path, img).ok());
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), std::filesystem::directory_iterator()),
            1);
  const Result<Rgba8Image> back = read_png(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->width, 5);
  EXPECT_EQ(back->height, 3);
  EXPECT_EQ(back->rgba, img.rgba);
}

TEST(Png, ErrorsNameThePath) {
  test::TempDir dir;
  const Rgba8Image img{1, 1, {0, 0, 0, 255}};
  const Status s = write_png((dir / "missing" / "x.png").string(), img);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(to_string(s.error()).find("missing"), std::string::npos);
  test::write_file(dir / "bad.png", "not a png");
  const Result<Rgba8Image> r = read_png((dir / "bad.png").string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(to_string(r.error()).find("bad.png"), std::string::npos);
}

}  // namespace
}  // namespace gonio::io
