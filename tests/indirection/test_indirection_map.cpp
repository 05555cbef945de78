// SPDX-License-Identifier: MIT
// The indirection map: inversion of the relaxed grid by rasterization (M(M^-1(x)) = x), packing
// round trips at 8 and 16 bits, and the pre-warp of structured textures.
#include <gtest/gtest.h>

#include <cellrelief/indirection/indirection_map.h>
#include <cellrelief/indirection/springs.h>

#include "indirection/test_support_indirection.h"

namespace cellrelief {
namespace {

using namespace indirection;

Grid relaxedNoiseGrid() {
  const ReliefMap relief = test::noiseRelief(128, 0.25f, 5, 3);
  SpringOptions o;
  o.gridSize = 32;
  return relaxSprings(relief, o);
}

TEST(IndirectionMap, IdentityGridGivesZero) {
  const Image<float> I = indirectionMap(Grid(16), 64, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      EXPECT_NEAR(I.at(x, y, 0), 0.0f, 1e-6f);
      EXPECT_NEAR(I.at(x, y, 1), 0.0f, 1e-6f);
    }
}

TEST(IndirectionMap, InversionRoundTrip) {
  const Grid grid = relaxedNoiseGrid();
  const int n = 200;
  const Image<float> I = indirectionMap(grid, n, n);
  float worst = 0, largest = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const Vec2f uv((x + 0.5f) / n, (y + 0.5f) / n);
      const Vec2f st = uv + Vec2f(I.at(x, y, 0), I.at(x, y, 1));  // M^-1(uv)
      worst = std::max(worst, glm::length(grid.map(st) - uv));    // M(M^-1(uv)) = uv
      largest = std::max(largest, glm::length(st - uv));
    }
  EXPECT_LT(worst, 1e-5f);
  EXPECT_GT(largest, 0.005f);  // the map is not the identity: the test tests something
}

TEST(IndirectionMap, PackingRoundTrips) {
  const Image<float> I = indirectionMap(relaxedNoiseGrid(), 96, 96);
  const auto p8 = packIndirection<std::uint8_t>(I);
  const auto p16 = packIndirection<std::uint16_t>(I, 3);
  EXPECT_EQ(p8.texels.channels(), 2);
  EXPECT_EQ(p16.texels.channels(), 3);
  for (int c = 0; c < 2; ++c) EXPECT_GT(p8.scale[c], 0.0f);
  float worst8 = 0, worst16 = 0;
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      const Vec2f truth(I.at(x, y, 0), I.at(x, y, 1));
      worst8 = std::max(worst8, glm::length(p8.decode(x, y) - truth));
      worst16 = std::max(worst16, glm::length(p16.decode(x, y) - truth));
    }
  // Half a quantization step of the per-channel range, in each of the two channels.
  const float range = std::max(p8.scale.x, p8.scale.y);
  EXPECT_LE(worst8, range * 0.5f / 255 * 1.5f);
  EXPECT_LE(worst16, range * 0.5f / 65535 * 1.5f);
  EXPECT_LT(worst16, worst8 / 100);
  // Extremes are exactly representable: min and max normalization.
  const auto p = packIndirection<std::uint8_t>(I);
  bool sawZero = false, sawFull = false;
  for (int y = 0; y < 96; ++y)
    for (int x = 0; x < 96; ++x) {
      sawZero |= p.texels.at(x, y, 0) == 0;
      sawFull |= p.texels.at(x, y, 0) == 255;
    }
  EXPECT_TRUE(sawZero && sawFull);
}

TEST(IndirectionMap, PrewarpUndoesTheIndirection) {
  // C'(M^-1(x)) = C(x): fetch the pre-warped texture through the indirection and compare.
  const Grid grid = relaxedNoiseGrid();
  const int n = 128;
  Image<float> texture(n, n, 1);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      texture.at(x, y, 0) = 0.5f + 0.5f * std::sin(0.2f * x) * std::cos(0.15f * y);  // smooth
  const Image<float> warped = prewarp(texture, grid);
  const Image<float> I = indirectionMap(grid, n, n);
  double err = 0;
  for (int y = 4; y < n - 4; ++y)
    for (int x = 4; x < n - 4; ++x) {
      const Vec2f uv((x + 0.5f) / n, (y + 0.5f) / n);
      const Vec2f st = uv + Vec2f(I.at(x, y, 0), I.at(x, y, 1));
      err = std::max<double>(err, std::abs(warped.sample(st).x - texture.at(x, y, 0)));
    }
  EXPECT_LT(err, 0.03);  // bilinear resampling twice on a smooth signal
}

}  // namespace
}  // namespace cellrelief
