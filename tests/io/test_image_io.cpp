// SPDX-License-Identifier: MIT
// Image I/O on the real height maps and textures, and bit-exact PNG round trips (8 and 16 bit).
#include <regex>
#include <set>

#include <gtest/gtest.h>

#include <cellrelief/io/image_io.h>

#include "test_support.h"

namespace cellrelief {
namespace {

using test::dataDir;

TEST(ImageIO, EveryImageLoadsWithTheSizeInSources) {
  const std::filesystem::path sources = dataDir() / "SOURCES.md";
  CELLRELIEF_REQUIRE_FILE(sources);
  const std::regex sizeRe(R"((\d+) ?x ?(\d+))");
  int checked = 0;
  for (const test::SourceRow& row : test::readSources()) {
    if (!io::isImageFile(row.path)) continue;
    const auto path = dataDir() / row.path;
    CELLRELIEF_REQUIRE_FILE(path);
    SCOPED_TRACE(row.path);
    const io::ImageFile im = io::readImage(path);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(row.contents, m, sizeRe)) << row.contents;
    EXPECT_EQ(im.width(), std::stoi(m[1]));
    EXPECT_EQ(im.height(), std::stoi(m[2]));
    EXPECT_EQ(im.bitDepth(), 8);
    ++checked;
  }
  EXPECT_GE(checked, 25);
}

TEST(ImageIO, ChannelsOfTheHeightMapFormats) {
  const auto tga = dataDir() / "heightmaps/pom_dxsdk/rocks_NM_height.tga";
  const auto gray = dataDir() / "heightmaps/sponza/lion_bump.png";
  CELLRELIEF_REQUIRE_FILE(tga);
  CELLRELIEF_REQUIRE_FILE(gray);
  const io::ImageFile t = io::readImage(tga);
  EXPECT_EQ(t.channels(), 4);  // normal in RGB, height in alpha
  const io::ImageFile g = io::readImage(gray);
  EXPECT_EQ(g.channels(), 1);
  // SOURCES.md: A[min=0 max=253] for rocks, gray[min=0 max=255 mean=120.8] for the lion.
  float lo = 1, hi = 0;
  double mean = 0;
  for (int y = 0; y < g.height(); ++y)
    for (int x = 0; x < g.width(); ++x) {
      mean += g.fetch(x, y).r;
      hi = std::max(hi, t.fetch(x % t.width(), y % t.height()).a);
      lo = std::min(lo, t.fetch(x % t.width(), y % t.height()).a);
    }
  EXPECT_NEAR(mean / (g.width() * g.height()) * 255, 120.8, 0.05);
  EXPECT_FLOAT_EQ(lo * 255, 0);
  EXPECT_FLOAT_EQ(hi * 255, 253);
}

TEST(ImageIO, RunLengthEncodedBmpDecodes) {
  const auto path = dataDir() / "heightmaps/irrlicht/terrain-heightmap.bmp";
  CELLRELIEF_REQUIRE_FILE(path);
  const io::ImageFile im = io::readImage(path);
  ASSERT_EQ(im.width(), 256);
  ASSERT_EQ(im.height(), 256);
  std::set<int> values;
  double step = 0;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) {
      const Vec4f t = im.fetch(x, y);
      ASSERT_EQ(t.r, t.g);  // a gray palette
      values.insert(int(t.r * 255 + 0.5f));
      if (x > 0) step += std::abs(t.r - im.fetch(x - 1, y).r);
    }
  EXPECT_GT(values.size(), 64u);             // a real height field, not a constant
  EXPECT_LT(step / (255.0 * 256), 0.03);     // and a smooth one: decoding errors show as noise
}

template <class T>
Image<T> pattern(int w, int h, int channels) {
  Image<T> im(w, h, channels);
  auto data = im.levelData(0);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = T((i * 2654435761u) >> 7);
  return im;
}

template <class T>
void expectPngRoundTrip(int channels) {
  test::TempDir dir;
  const Image<T> im = pattern<T>(37, 23, channels);
  io::writePng(im, dir / "x.png");
  const io::ImageFile back = io::readImage(dir / "x.png");
  ASSERT_EQ(back.bitDepth(), int(8 * sizeof(T)));
  ASSERT_EQ(back.channels(), channels);
  const auto& pixels = std::get<Image<T>>(back.pixels);
  ASSERT_TRUE(std::equal(im.levelData(0).begin(), im.levelData(0).end(),
                         pixels.levelData(0).begin()));
}

TEST(ImageIO, Png8BitRoundTripIsBitExact) {
  for (int c = 1; c <= 4; ++c) expectPngRoundTrip<std::uint8_t>(c);
}
TEST(ImageIO, Png16BitRoundTripIsBitExact) {
  for (int c = 1; c <= 4; ++c) expectPngRoundTrip<std::uint16_t>(c);
}

}  // namespace
}  // namespace cellrelief
