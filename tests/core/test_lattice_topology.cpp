// SPDX-License-Identifier: MIT
// The link of a lattice point in the Kuhn triangulation (core/lattice_topology.h): its shape, and
// the circle test that decides whether moving the point removes a handle.
#include <algorithm>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include <cellrelief/core/lattice_topology.h>

namespace cellrelief {
namespace {

TEST(KuhnLink, IsATriangulatedSphereOfTheFourteenNeighbours) {
  // The triangulation's edges: the 7 monotone steps of a cube's tetrahedra, both ways.
  std::set<std::tuple<int, int, int>> expected;
  for (int k = 1; k < 8; ++k) {
    expected.emplace(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    expected.emplace(-(k & 1), -((k >> 1) & 1), -((k >> 2) & 1));
  }
  std::set<std::tuple<int, int, int>> found;
  for (const Vec3i& d : KuhnLink::offsets()) found.emplace(d.x, d.y, d.z);
  EXPECT_EQ(found.size(), 14u);
  EXPECT_EQ(found, expected);
  EXPECT_EQ(KuhnLink::eulerCharacteristic(KuhnLink::kAll), 2);  // a sphere
  EXPECT_EQ(KuhnLink::components(KuhnLink::kAll, nullptr), 1);
  EXPECT_FALSE(KuhnLink::isCircle(KuhnLink::kAll));
}

TEST(KuhnLink, OneVertexAndItsComplementAreDiscs) {
  for (int v = 0; v < KuhnLink::kSize; ++v) {
    const auto one = KuhnLink::Mask(1u << v);
    EXPECT_EQ(KuhnLink::eulerCharacteristic(one), 1);
    EXPECT_EQ(KuhnLink::eulerCharacteristic(KuhnLink::Mask(KuhnLink::kAll & ~one)), 1);
    EXPECT_FALSE(KuhnLink::isCircle(one));
  }
}

/// The ring of a vertex's neighbours within the link is a circle, and what is left when the
/// vertex and its ring are taken away is a disc: the ring separates the vertex from the rest.
TEST(KuhnLink, TheRingAroundAVertexIsACircleThatSplitsTheRest) {
  for (int v = 0; v < KuhnLink::kSize; ++v) {
    KuhnLink::Mask ring = 0;
    for (int w = 0; w < KuhnLink::kSize; ++w) {
      if (w == v) continue;
      // w neighbours v in the link when the mask {v, w} spans an edge (Euler characteristic 1).
      if (KuhnLink::eulerCharacteristic(KuhnLink::Mask((1u << v) | (1u << w))) == 1)
        ring |= KuhnLink::Mask(1u << w);
    }
    EXPECT_GE(__builtin_popcount(ring), 4) << v;  // 4 or 6 neighbours
    EXPECT_TRUE(KuhnLink::isCircle(ring)) << v;
    std::array<std::int8_t, KuhnLink::kSize> label;
    const auto rest = KuhnLink::Mask(KuhnLink::kAll & ~ring);
    ASSERT_EQ(KuhnLink::components(rest, &label), 2) << v;
    EXPECT_EQ(std::count(label.begin(), label.end(), label[std::size_t(v)]), 1) << v;  // v alone
  }
}

TEST(KuhnLink, TwoPolesLeaveAnAnnulus) {
  // A line of points along x through the point: the rest of its link is a circle round the line.
  int plus = -1, minus = -1;
  for (int v = 0; v < KuhnLink::kSize; ++v) {
    if (KuhnLink::offsets()[std::size_t(v)] == Vec3i(1, 0, 0)) plus = v;
    if (KuhnLink::offsets()[std::size_t(v)] == Vec3i(-1, 0, 0)) minus = v;
  }
  ASSERT_GE(plus, 0);
  ASSERT_GE(minus, 0);
  const auto poles = KuhnLink::Mask((1u << plus) | (1u << minus));
  EXPECT_EQ(KuhnLink::components(poles, nullptr), 2);
  EXPECT_TRUE(KuhnLink::isCircle(KuhnLink::Mask(KuhnLink::kAll & ~poles)));
}

}  // namespace
}  // namespace cellrelief
