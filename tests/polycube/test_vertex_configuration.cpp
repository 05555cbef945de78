// SPDX-License-Identifier: MIT
// The 256 vertex configurations of a polycube: 126 manifold ones, 63 surfaces, six basic cases.
#include <bit>
#include <set>

#include <gtest/gtest.h>

#include <cellrelief/polycube/vertex_configuration.h>

namespace cellrelief::polycube {
namespace {

int determinant(int transform) {
  const Vec3i x = applyTransform(transform, {1, 0, 0}), y = applyTransform(transform, {0, 1, 0}),
              z = applyTransform(transform, {0, 0, 1});
  const Vec3i c(y.y * z.z - y.z * z.y, y.z * z.x - y.x * z.z, y.x * z.y - y.y * z.x);
  return x.x * c.x + x.y * c.y + x.z * c.z;
}

TEST(VertexTransforms, FortyEightDistinctSymmetriesHalfOfThemReflections) {
  std::set<std::array<int, 9>> seen;
  int reflections = 0;
  for (int s = 0; s < kTransformCount; ++s) {
    const Vec3i x = applyTransform(s, {1, 0, 0}), y = applyTransform(s, {0, 1, 0}), z = applyTransform(s, {0, 0, 1});
    seen.insert({x.x, x.y, x.z, y.x, y.y, y.z, z.x, z.y, z.z});
    EXPECT_EQ(std::abs(determinant(s)), 1);
    reflections += determinant(s) < 0;
    EXPECT_EQ(determinant(s) < 0, s >= 24);
    // Octants map one to one.
    std::set<int> images;
    for (int o = 0; o < 8; ++o) images.insert(octantOf(applyTransform(s, octantDirection(o))));
    EXPECT_EQ(images.size(), 8u);
  }
  EXPECT_EQ(seen.size(), 48u);
  EXPECT_EQ(reflections, 24);
}

TEST(VertexConfigurations, ManifoldCountsPerCaseAndSixtyThreeSurfaces) {
  // Configurations per case (complements counted apart): corners 8 + 8, flat 3 + 3, edges 12 +
  // 12, L's 24 + 24, tetrapods 4 + 4, skew paths 12 + 12.
  const std::array<int, kVertexCaseCount> expected{16, 6, 24, 48, 8, 24};
  std::array<int, kVertexCaseCount> count{};
  std::set<std::uint16_t> surfaces;
  int manifold = 0;
  for (int c = 1; c < 255; ++c) {
    const VertexConfigurationInfo& info = kVertexConfigurations[c];
    ASSERT_TRUE(info.surface);
    if (!info.manifold) continue;
    ++manifold;
    ++count[static_cast<int>(info.vertexCase)];
    surfaces.insert(info.squarelets);
  }
  EXPECT_EQ(manifold, 126);
  EXPECT_EQ(surfaces.size(), 63u);
  EXPECT_EQ(count, expected);
  EXPECT_FALSE(kVertexConfigurations[0].surface);
  EXPECT_FALSE(kVertexConfigurations[255].surface);
}

TEST(VertexConfigurations, EachIsItsCaseTransformedAndHasTheCaseSquareletCount) {
  const std::array<int, kVertexCaseCount> squarelets{3, 4, 4, 5, 6, 6};
  for (int c = 1; c < 255; ++c) {
    const VertexConfigurationInfo& info = kVertexConfigurations[c];
    if (!info.manifold) continue;
    const std::uint8_t canonical = kCanonicalOctants[static_cast<int>(info.vertexCase)];
    const std::uint8_t t = transformOctants(canonical, info.transform);
    EXPECT_EQ(info.complement ? std::uint8_t(~t) : t, std::uint8_t(c)) << "configuration " << c;
    EXPECT_EQ(std::popcount(unsigned(info.squarelets)), squarelets[static_cast<int>(info.vertexCase)]);
    // The squarelets themselves transform: those of the canonical case, moved, are the configuration's.
    EXPECT_EQ(squareletMask(t), info.squarelets);
    // A configuration and its complement are one surface.
    EXPECT_EQ(squareletMask(std::uint8_t(~c)), info.squarelets);
  }
}

TEST(VertexConfigurations, OnlyTheSkewPathNeedsAReflection) {
  std::array<int, kVertexCaseCount> mirrored{};
  for (int c = 1; c < 255; ++c)
    if (kVertexConfigurations[c].manifold && kVertexConfigurations[c].transform >= 24)
      ++mirrored[static_cast<int>(kVertexConfigurations[c].vertexCase)];
  EXPECT_EQ(mirrored, (std::array<int, kVertexCaseCount>{0, 0, 0, 0, 0, 12}));
}

TEST(VertexConfigurations, CubesMeetingAlongAnEdgeOrAtACornerAreNotManifold) {
  EXPECT_FALSE(isManifold(0b00001001));  // octants 0 and 3: an edge
  EXPECT_FALSE(isManifold(0b10000001));  // octants 0 and 7: a corner
  EXPECT_FALSE(isManifold(std::uint8_t(~0b10000001)));
  EXPECT_TRUE(isManifold(0b00000011));
  EXPECT_TRUE(isManifold(0));
  EXPECT_TRUE(isManifold(255));
}

}  // namespace
}  // namespace cellrelief::polycube
