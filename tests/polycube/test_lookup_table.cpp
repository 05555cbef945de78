// SPDX-License-Identifier: MIT
// The 3D look-up table and M: every vertex's case and transform reproduce its octants, every face
// owns four tiles and no tile is shared, points of the surface land in their own tile.
#include <random>
#include <set>

#include <gtest/gtest.h>

#include <cellrelief/polycube/lookup_table.h>

#include "random_polycubes.h"

namespace cellrelief::polycube {
namespace {

/// Manifold polycubes of every case: shapes drawn by hand and repaired random cube sets.
std::vector<Polycube> testPolycubes() {
  std::vector<Polycube> out = fixtures::shapedPolycubes();
  for (Polycube& p : fixtures::randomManifoldPolycubes(20)) out.push_back(std::move(p));
  return out;
}

/// The four squarelets of face `face` of cube `c`: (vertex, squarelet index), one per corner.
std::vector<std::pair<Vec3i, int>> faceSquarelets(const Vec3i& c, int face) {
  const int axis = face >> 1;
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  std::vector<std::pair<Vec3i, int>> out;
  for (int corner = 0; corner < 4; ++corner) {
    Vec3i v = c;
    if (face & 1) v[axis] += 1;
    const int da = corner & 1, db = (corner >> 1) & 1;
    v[a] += da;
    v[b] += db;
    // From that vertex the face lies towards the cube's side on a and b.
    int octant = 0;
    if (!da) octant |= 1 << a;
    if (!db) octant |= 1 << b;
    out.emplace_back(v, squareletIndex(octant, axis));
  }
  return out;
}

TEST(PolycubeLut, CaseAndTransformReproduceEveryVertexConfiguration) {
  std::array<int, kVertexCaseCount> seen{};
  for (const Polycube& p : testPolycubes()) {
    const PolycubeLut lut(p);
    for (const LutEntry& e : lut.entries()) {
      if (e.empty()) {
        EXPECT_TRUE(e.configuration == 0 || e.configuration == 255);
        continue;
      }
      ++seen[e.vertexCase];
      const std::uint8_t t = transformOctants(kCanonicalOctants[e.vertexCase], e.transform);
      EXPECT_EQ(e.complement ? std::uint8_t(~t) : t, e.configuration);
    }
  }
  // The test polycubes reach every case, 6a and 6b included.
  for (int c = 0; c < kVertexCaseCount; ++c) EXPECT_GT(seen[c], 0) << "case " << kVertexCaseNames[c];
}

TEST(PolycubeLut, EveryFaceOwnsFourTilesAndNoTileIsShared) {
  for (const Polycube& p : testPolycubes()) {
    const PolycubeLut lut(p);
    EXPECT_EQ(lut.tileCount(), 4 * p.surfaceStats().faces);
    std::set<std::uint32_t> tiles;
    for (const Vec3i& c : p.cubes())
      for (int face = 0; face < 6; ++face) {
        Vec3i n = c;
        n[face >> 1] += (face & 1) ? 1 : -1;
        if (p.contains(n)) continue;
        for (const auto& [vertex, squarelet] : faceSquarelets(c, face)) {
          const LutEntry& e = lut.at(vertex);
          ASSERT_FALSE(e.empty());
          ASSERT_TRUE(e.squarelets() & (1u << squarelet));
          EXPECT_TRUE(tiles.insert(e.tileOf(squarelet)).second) << "a tile used twice";
        }
      }
    EXPECT_EQ(tiles.size(), lut.tileCount());
    EXPECT_EQ(*tiles.rbegin() + 1, lut.tileCount());
  }
}

TEST(PolycubeLut, SurfacePointsLandInTheirFacesTilesAndOffSurfacePointsNowhere) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const Polycube& p : testPolycubes()) {
    const PolycubeLut lut(p);
    for (const Vec3i& c : p.cubes())
      for (int face = 0; face < 6; ++face) {
        Vec3i n = c;
        n[face >> 1] += (face & 1) ? 1 : -1;
        if (p.contains(n)) continue;
        std::set<std::uint32_t> faceTiles;
        for (const auto& [vertex, squarelet] : faceSquarelets(c, face)) faceTiles.insert(lut.at(vertex).tileOf(squarelet));
        for (int k = 0; k < 8; ++k) {
          const int axis = face >> 1;
          Vec3d q(c);
          q[axis] += (face & 1) ? 1.0 : 0.0;
          q[(axis + 1) % 3] += unit(random);
          q[(axis + 2) % 3] += unit(random);
          const std::optional<SquareletPoint> s = lut.locate(q);
          ASSERT_TRUE(s.has_value());
          EXPECT_TRUE(faceTiles.count(lut.at(s->vertex).tileOf(s->squarelet))) << "landed outside its face";
          EXPECT_GE(s->st.x, 0.0);
          EXPECT_LE(s->st.x, 1.0);
          EXPECT_GE(s->st.y, 0.0);
          EXPECT_LE(s->st.y, 1.0);
        }
      }
    // Half a cube off the surface, nothing is found.
    for (const Vec3i& c : p.cubes())
      if (p.contains(c + Vec3i(1, 0, 0)) && p.contains(c - Vec3i(1, 0, 0)) && p.contains(c + Vec3i(0, 1, 0)) &&
          p.contains(c - Vec3i(0, 1, 0)) && p.contains(c + Vec3i(0, 0, 1)) && p.contains(c - Vec3i(0, 0, 1))) {
        EXPECT_FALSE(lut.locate(Vec3d(c) + Vec3d(0.5)).has_value());
        break;
      }
  }
}

TEST(PolycubeLut, NonManifoldOrEmptyPolycubesAreRefused) {
  EXPECT_THROW(PolycubeLut(Polycube{}), Error);
  EXPECT_THROW(PolycubeLut(Polycube(std::vector<Vec3i>{{0, 0, 0}, {1, 1, 0}})), Error);
}

}  // namespace
}  // namespace cellrelief::polycube
