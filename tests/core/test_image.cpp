// SPDX-License-Identifier: MIT
// Images and array textures: GPU-style sampling, wrap modes, mip chains, memory layout.
#include <cmath>
#include <limits>
#include <numeric>

#include <gtest/gtest.h>

#include <cellrelief/core/image.h>

namespace cellrelief {
namespace {

Image<float> ramp(int w, int h) {
  Image<float> im(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) im.at(x, y, 0) = float(x + 10 * y);
  return im;
}

TEST(Image, BilinearAtTexelCentresReturnsTheTexel) {
  const Image<float> im = ramp(4, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x)
      EXPECT_FLOAT_EQ(im.sample(Vec2f((x + 0.5f) / 4, (y + 0.5f) / 3)).r, float(x + 10 * y));
}

TEST(Image, BilinearBetweenCentresIsLinear) {
  const Image<float> im = ramp(4, 3);
  // Halfway between texels (1,1) and (2,1), and a quarter of the way down towards row 2.
  EXPECT_FLOAT_EQ(im.sample(Vec2f(2.0f / 4, 1.5f / 3)).r, 11.5f);
  EXPECT_FLOAT_EQ(im.sample(Vec2f(2.0f / 4, 1.75f / 3)).r, 11.5f + 2.5f);
}

TEST(Image, ClampAndRepeatAtTheBorder) {
  const Image<float> im = ramp(4, 1);
  const Sampler clamp{Filter::Bilinear, Wrap::Clamp};
  const Sampler repeat{Filter::Bilinear, Wrap::Repeat};
  EXPECT_FLOAT_EQ(im.sample(Vec2f(0.0f, 0.5f), clamp).r, 0.0f);
  EXPECT_FLOAT_EQ(im.sample(Vec2f(1.0f, 0.5f), clamp).r, 3.0f);
  // Repeat: u = 0 lies halfway between the last texel (3) and the first (0).
  EXPECT_FLOAT_EQ(im.sample(Vec2f(0.0f, 0.5f), repeat).r, 1.5f);
  EXPECT_FLOAT_EQ(im.sample(Vec2f(1.25f + 0.5f / 4, 0.5f), repeat).r, 1.0f);
  EXPECT_FLOAT_EQ(im.sample(Vec2f(-0.75f + 0.5f / 4, 0.5f), repeat).r, 1.0f);
  const Sampler nearest{Filter::Nearest, Wrap::Repeat};
  EXPECT_FLOAT_EQ(im.sample(Vec2f(-0.1f, 0.5f), nearest).r, 3.0f);
}

TEST(Image, IntegerTexelsReadAsUnorm) {
  Image<std::uint8_t> im(2, 1, 2);
  im.at(0, 0, 0) = 255;
  im.at(0, 0, 1) = 51;
  const Vec4f t = im.fetch(0, 0);
  EXPECT_FLOAT_EQ(t.r, 1.0f);
  EXPECT_FLOAT_EQ(t.g, 0.2f);
  EXPECT_FLOAT_EQ(t.b, 0.0f);  // missing channels read as (0, 0, 0, 1)
  EXPECT_FLOAT_EQ(t.a, 1.0f);
}

TEST(Image, MipChainOfOddSizesKeepsTheMean) {
  Image<float> im(5, 3, 1);
  float sum = 0;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) sum += (im.at(x, y, 0) = float((x * 7 + y * 3) % 5));
  im.generateMips();
  ASSERT_EQ(im.levelCount(), 3);  // 5x3, 2x1, 1x1
  EXPECT_EQ(im.width(1), 2);
  EXPECT_EQ(im.height(1), 1);
  EXPECT_EQ(im.width(2), 1);
  // Area-weighted box filter: every level has the same mean as the base.
  EXPECT_NEAR(im.at(0, 0, 0, 2), sum / 15, 1e-5);
  EXPECT_NEAR((im.at(0, 0, 0, 1) + im.at(1, 0, 0, 1)) / 2, sum / 15, 1e-5);
}

TEST(Image, MipChainOfAwkwardOddSizesStaysInside) {
  // Sizes whose footprint products round up past the last texel (27, 29, 55, ...).
  for (int w : {27, 29, 31, 47, 55}) {
    Image<float> im(w, 3, 1, 1.0f);
    im.generateMips();
    for (int level = 0; level < im.levelCount(); ++level)
      for (int x = 0; x < im.width(level); ++x) ASSERT_NEAR(im.at(x, 0, 0, level), 1.0f, 1e-6f) << w;
  }
}

TEST(Image, NonFiniteAndHugeCoordinatesAreSafe) {
  const Image<float> im = ramp(4, 4);
  const float inf = std::numeric_limits<float>::infinity();
  for (const Sampler s : {Sampler{Filter::Bilinear, Wrap::Repeat}, Sampler{Filter::Nearest, Wrap::Clamp}}) {
    EXPECT_TRUE(std::isfinite(im.sample(Vec2f(std::nanf(""), 0.5f), s).r));
    EXPECT_TRUE(std::isfinite(im.sample(Vec2f(inf, -inf), s).r));
    EXPECT_TRUE(std::isfinite(im.sample(Vec2f(3e9f, -7e12f), s).r));
  }
}

TEST(ImageArray, LevelMemoryIsLayerRowColumnChannel) {
  ImageArray<std::uint16_t> arr(3, 2, 4, 2);
  arr.at(2, 1, 3, 1) = 777;
  const auto data = arr.levelData(0);
  ASSERT_EQ(data.size(), std::size_t(3 * 2 * 4 * 2));
  EXPECT_EQ(data[((3 * 2 + 1) * 3 + 2) * 2 + 1], 777);
  EXPECT_EQ(arr.byteSize(), data.size() * sizeof(std::uint16_t));
  arr.generateMips();
  EXPECT_EQ(arr.levelCount(), 2);  // 3x2 -> 1x1
  EXPECT_EQ(arr.levelData(1).size(), std::size_t(1 * 1 * 4 * 2));
}

TEST(ImageArray, LayersAreSampledIndependently) {
  ImageArray<float> arr(2, 2, 3, 1);
  for (int layer = 0; layer < 3; ++layer)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) arr.at(x, y, layer, 0) = float(layer * 100 + x + 2 * y);
  EXPECT_FLOAT_EQ(arr.sample(Vec2f(0.5f), 2).r, 201.5f);
  EXPECT_FLOAT_EQ(arr.sample(Vec2f(0.5f), 0).r, 1.5f);
}

TEST(Image, InvalidSizesAreRejected) {
  EXPECT_THROW(Image<float>(0, 4, 1), Error);
  EXPECT_THROW(Image<float>(4, -1, 1), Error);
  EXPECT_THROW(Image<float>(4, 4, 5), Error);
  EXPECT_THROW(ImageArray<float>(1 << 20, 1, 1, 1), Error);
}

}  // namespace
}  // namespace cellrelief
