// SPDX-License-Identifier: MIT
// Relief maps: bilinear evaluation and gradient against analytic surfaces, borders, every height-map
// format of the shared data, and the errors for maps that cannot be relief.
#include <gtest/gtest.h>

#include <cellrelief/indirection/relief_map.h>

#include "indirection/test_support_indirection.h"

namespace cellrelief {
namespace {

using indirection::ReliefMap;

TEST(ReliefMap, BilinearReproducesALinearFunctionAndItsGradient) {
  // H = 0.25 + 0.5 u - 0.2 v is reproduced exactly by bilinear interpolation between texel centres.
  const float s = 0.3f;
  const ReliefMap map =
      test::analyticRelief(64, s, [](float u, float v) { return 0.25f + 0.5f * u - 0.2f * v; });
  for (float u = 0.02f; u < 0.98f; u += 0.037f)
    for (float v = 0.02f; v < 0.98f; v += 0.041f) {
      EXPECT_NEAR(map.heightAt(u, v), s * (0.25f + 0.5f * u - 0.2f * v), 2e-6f);
      const Vec2f grad = map.gradientAt(u, v);
      EXPECT_NEAR(grad.x, s * 0.5f, 2e-4f);
      EXPECT_NEAR(grad.y, -s * 0.2f, 2e-4f);
    }
}

TEST(ReliefMap, GradientMatchesFiniteDifferencesOfACurvedSurface) {
  const ReliefMap map = test::analyticRelief(128, 0.2f, [](float u, float v) {
    return 0.5f + 0.5f * std::sin(6.0f * u) * std::cos(5.0f * v);
  });
  const float h = 1e-3f / 128;  // well inside one texel
  for (float u = 0.05f; u < 0.95f; u += 0.0731f)
    for (float v = 0.05f; v < 0.95f; v += 0.0677f) {
      const Vec2f grad = map.gradientAt(u, v);
      const float du = (map.heightAt(u + h, v) - map.heightAt(u - h, v)) / (2 * h);
      const float dv = (map.heightAt(u, v + h) - map.heightAt(u, v - h)) / (2 * h);
      EXPECT_NEAR(grad.x, du, 2e-2f * (1 + std::abs(du)));
      EXPECT_NEAR(grad.y, dv, 2e-2f * (1 + std::abs(dv)));
      // and the analytic derivative of the smooth function it samples
      EXPECT_NEAR(grad.x, 0.2f * 0.5f * 6 * std::cos(6 * u) * std::cos(5 * v), 2e-2f);
    }
}

TEST(ReliefMap, ClampAndRepeatBorders) {
  const std::vector<float> h = {0.0f, 1.0f, 0.5f, 0.25f};  // 2x2
  const ReliefMap clamp(2, 2, h, 1.0f, Wrap::Clamp);
  EXPECT_FLOAT_EQ(clamp.heightAt(0.0f, 0.0f), 0.0f);  // beyond the outer centre: constant
  EXPECT_FLOAT_EQ(clamp.heightAt(0.1f, 0.1f), 0.0f);
  EXPECT_EQ(clamp.gradientAt(0.1f, 0.1f), Vec2f(0.0f));
  EXPECT_FLOAT_EQ(clamp.heightAt(-3.0f, 7.0f), 0.5f);
  const ReliefMap repeat(2, 2, h, 1.0f, Wrap::Repeat);
  EXPECT_FLOAT_EQ(repeat.heightAt(0.0f, 0.25f), 0.5f);  // halfway between texel 1 and texel 0
  EXPECT_NEAR(repeat.heightAt(1.3f, 0.6f), repeat.heightAt(0.3f, -0.4f), 1e-5f);
  EXPECT_NEAR(repeat.gradientAt(0.0f, 0.25f).x, -2.0f, 1e-5f);  // (0 - 1) / half a tile
  EXPECT_TRUE(std::isfinite(repeat.heightAt(NAN, 1e30f)));
}

// Far from the map (a grazing ray's end, a large UV scale) the repeat's reduction x - size floor(x /
// size) can come out negative or at size where the compiler fuses the multiply and the subtraction
// (aarch64, GPU compilers): whatever the platform, an index must never leave the map.
TEST(ReliefMap, RepeatFarFromTheMapStaysInsideIt) {
  for (const int size : {3, 5, 7, 1000, 1023}) {
    int outside = 0;
    for (double t = 1e3; t < 1e12; t *= 1.0007) {
      for (const float sign : {1.0f, -1.0f}) {
        int i0 = -1, i1 = -1;
        float fraction = -1, slope = 0;
        indirection::bilinearAxis(sign * float(t), size, true, i0, i1, fraction, slope);
        outside += i0 < 0 || i0 >= size || i1 < 0 || i1 >= size || !(fraction >= 0 && fraction <= 1);
      }
    }
    EXPECT_EQ(outside, 0) << "size " << size;
  }
  const std::vector<float> h(3 * 5, 0.5f);
  const ReliefMap repeat(3, 5, h, 1.0f, Wrap::Repeat);
  EXPECT_FLOAT_EQ(repeat.heightAt(16777217.5f / 3.0f, -16777217.0f), 0.5f);  // in the map's memory
}

TEST(ReliefMap, ReadsEveryHeightMapFormat) {
  struct Case {
    const char* file;
    int size;
  };
  for (const Case& c : {Case{"sponza/lion_bump.png", 1024}, Case{"learnopengl/bricks2_disp.jpg", 512},
                        Case{"learnopengl/toy_box_disp.png", 256},
                        Case{"pom_dxsdk/rocks_NM_height.tga", 256},
                        Case{"irrlicht/rockwall_height.bmp", 256},
                        Case{"irrlicht/terrain-heightmap.bmp", 256}}) {
    const auto path = test::heightmap(c.file);
    CELLRELIEF_REQUIRE_FILE(path);
    const ReliefMap map = indirection::loadReliefMap(path, {0.1f});
    EXPECT_EQ(map.width(), c.size) << c.file;
    EXPECT_FALSE(map.isFlat()) << c.file;
    float lo = 1, hi = 0;
    for (int y = 0; y < map.height(); ++y)
      for (int x = 0; x < map.width(); ++x) {
        lo = std::min(lo, map.texel(x, y));
        hi = std::max(hi, map.texel(x, y));
      }
    EXPECT_GE(lo, 0.0f);
    EXPECT_LE(hi, 0.1f + 1e-6f);
    EXPECT_GT(hi - lo, 0.02f) << c.file;
  }
  // The TGA's height is its alpha channel (SOURCES.md: A min=0 max=253), not its blue-ish RGB.
  const auto tga = test::heightmap("pom_dxsdk/rocks_NM_height.tga");
  const ReliefMap alpha = indirection::loadReliefMap(tga, {1.0f});
  float hi = 0, lo = 1;
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x) hi = std::max(hi, alpha.texel(x, y)), lo = std::min(lo, alpha.texel(x, y));
  EXPECT_NEAR(hi, 253.0f / 255.0f, 1e-6f);
  EXPECT_EQ(lo, 0.0f);
}

TEST(ReliefMap, SixteenBitHeightMapsKeepTheirPrecision) {
  test::TempDir dir;
  Image<std::uint16_t> im(8, 8, 1);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) im.at(x, y, 0) = std::uint16_t(1000 + x * 7 + y);
  io::writePng(im, dir / "h16.png");
  const ReliefMap map = indirection::loadReliefMap(dir / "h16.png", {1.0f});
  EXPECT_NEAR(map.texel(3, 2), (1000 + 21 + 2) / 65535.0f, 1e-7f);
  EXPECT_NE(map.texel(1, 0), map.texel(0, 0));  // one 16-bit step apart, lost in 8 bits
}

TEST(ReliefMap, MapsThatCannotBeReliefAreClearErrors) {
  test::TempDir dir;
  io::writePng(Image<std::uint8_t>(16, 16, 1, 77), dir / "constant.png");
  io::writePng(Image<std::uint8_t>(1, 9, 1, 7), dir / "thin.png");
  auto message = [](const std::filesystem::path& p) {
    try {
      indirection::loadReliefMap(p);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(dir / "constant.png").find("constant"), std::string::npos);
  EXPECT_NE(message(dir / "constant.png").find("constant.png"), std::string::npos);
  EXPECT_NE(message(dir / "thin.png").find("too small"), std::string::npos);
  EXPECT_NE(message(dir / "absent.png").find("no such file"), std::string::npos);
  EXPECT_THROW(ReliefMap(1, 1, {0.5f}, 1.0f), Error);
  EXPECT_THROW(ReliefMap(2, 2, {0, 0, 0, NAN}, 1.0f), Error);
  EXPECT_THROW(ReliefMap(2, 2, {0, 0, 0, 1}, -1.0f), Error);
}

}  // namespace
}  // namespace cellrelief
