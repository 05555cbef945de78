// SPDX-License-Identifier: MIT
// The closed reconstruction's lattice (relief/closed_lattice.h): handles that one lattice point
// makes are removed, and nothing else. Shapes one lattice point thick, whose surfaces' topology is
// known, polygonized by marching tetrahedra and welded by lattice edge as the reconstruction does.
#include <functional>
#include <unordered_map>

#include <gtest/gtest.h>

#include <cellrelief/core/marching_tetrahedra.h>
#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/relief/closed_lattice.h>

namespace cellrelief::relief {
namespace {

constexpr int kCubes = 12;  // one cell of 12^3 cubes

/// One cell whose lattice points are inside (+1/2) where `inside` says so, else outside (-1/2).
detail::LatticeBlocks makeLattice(const std::function<bool(const Vec3i&)>& inside) {
  detail::LatticeBlocks lattice({Vec3i(0)}, kCubes, 1);
  for (int z = 0; z <= kCubes; ++z)
    for (int y = 0; y <= kCubes; ++y)
      for (int x = 0; x <= kCubes; ++x)
        lattice.block(0)[lattice.index(0, {x, y, z})] = inside({x, y, z}) ? 0.5f : -0.5f;
  return lattice;
}

MeshTopology topologyOf(const detail::LatticeBlocks& lattice) {
  TriangleMesh mesh;
  std::unordered_map<std::uint64_t, std::uint32_t> vertexOf;
  const float* values = lattice.block(0);
  for (int z = 0; z < kCubes; ++z)
    for (int y = 0; y < kCubes; ++y)
      for (int x = 0; x < kCubes; ++x) {
        const Vec3i cube(x, y, z);
        std::array<float, 8> corner;
        for (int k = 0; k < 8; ++k)
          corner[std::size_t(k)] = values[lattice.index(0, cube + cubeCorner(k))];
        const CubeTriangles& triangles = kMarchingTetrahedraTable[std::size_t(insideMask(corner))];
        for (int t = 0; t < triangles.count; ++t) {
          Vec3u tri;
          for (int k = 0; k < 3; ++k) {
            const CubeEdge& e = triangles.triangles[std::size_t(t)][std::size_t(k)];
            const auto [it, added] = vertexOf.try_emplace(latticeEdgeKey(cube, e.inside, e.outside),
                                                          std::uint32_t(mesh.positions.size()));
            if (added)
              mesh.positions.push_back(
                  0.5f * Vec3f(cube + cubeCorner(e.inside) + cube + cubeCorner(e.outside)));
            tri[k] = it->second;
          }
          mesh.triangles.push_back(tri);
        }
      }
  return analyzeTopology(mesh);
}

bool inPlate(const Vec3i& p) {
  return p.z == 6 && p.x >= 2 && p.x <= 10 && p.y >= 2 && p.y <= 10;
}
bool onBoxShell(const Vec3i& p) {
  const Vec3i d = glm::abs(p - Vec3i(6));
  return std::max({d.x, d.y, d.z}) == 3;
}

TEST(ClosedLattice, APoreThroughAOnePointPlateIsClosed) {
  detail::LatticeBlocks lattice =
      makeLattice([](const Vec3i& p) { return inPlate(p) && p != Vec3i(6, 6, 6); });
  const MeshTopology before = topologyOf(lattice);
  ASSERT_TRUE(before.closed() && before.manifold());
  ASSERT_EQ(before.genus, 1);  // the plate with its pore is a ring
  EXPECT_EQ(detail::removeSinglePointHandles(lattice, 1, 1.0f / kCubes), 1);
  const MeshTopology after = topologyOf(lattice);
  EXPECT_TRUE(after.closed() && after.manifold());
  EXPECT_EQ(after.genus, 0);
  EXPECT_EQ(after.components, 1u);
  EXPECT_GT(lattice.block(0)[lattice.index(0, {6, 6, 6})], 0.0f);  // the pore's point moved inside
}

TEST(ClosedLattice, AOnePointRingIsCutOnce) {
  // A square loop of points, one point thick: a torus, cut at one point into an arc.
  auto onLoop = [](const Vec3i& p) {
    const Vec3i d = glm::abs(p - Vec3i(6));
    return p.z == 6 && std::max(d.x, d.y) == 3;
  };
  detail::LatticeBlocks lattice = makeLattice(onLoop);
  ASSERT_EQ(topologyOf(lattice).genus, 1);
  EXPECT_EQ(detail::removeSinglePointHandles(lattice, 1, 1.0f / kCubes), 1);
  const MeshTopology after = topologyOf(lattice);
  EXPECT_EQ(after.genus, 0);
  EXPECT_EQ(after.components, 1u);  // not cut again into two pieces
}

TEST(ClosedLattice, APinholeIntoACavityIsKept) {
  // A hollow box one point thick with one point missing: the pinhole is the only way between the
  // cavity and the outside, so closing it would make a second surface, not remove a handle.
  const Vec3i pinhole(9, 6, 6);
  detail::LatticeBlocks lattice =
      makeLattice([&](const Vec3i& p) { return onBoxShell(p) && p != pinhole; });
  const MeshTopology before = topologyOf(lattice);
  ASSERT_EQ(before.genus, 0);
  ASSERT_EQ(before.components, 1u);
  EXPECT_EQ(detail::removeSinglePointHandles(lattice, 1, 1.0f / kCubes), 0);
  EXPECT_LT(lattice.block(0)[lattice.index(0, pinhole)], 0.0f);
  const MeshTopology after = topologyOf(lattice);
  EXPECT_EQ(after.genus, 0);
  EXPECT_EQ(after.components, 1u);
}

TEST(ClosedLattice, HandlesWiderThanAPointAreKept) {
  // The plate with a pore of 2 x 2 points: a real hole at this lattice's resolution.
  detail::LatticeBlocks lattice = makeLattice(
      [](const Vec3i& p) { return inPlate(p) && !(p.x >= 6 && p.x <= 7 && p.y >= 6 && p.y <= 7); });
  ASSERT_EQ(topologyOf(lattice).genus, 1);
  EXPECT_EQ(detail::removeSinglePointHandles(lattice, 1, 1.0f / kCubes), 0);
  EXPECT_EQ(topologyOf(lattice).genus, 1);
}

}  // namespace
}  // namespace cellrelief::relief
