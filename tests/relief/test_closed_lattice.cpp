// SPDX-License-Identifier: MIT
// The closed reconstruction's lattice (relief/closed_lattice.h): handles that one lattice point
// makes are removed, and nothing else. Shapes one lattice point thick, whose surfaces' topology is
// known, polygonized by marching tetrahedra and welded by lattice edge as the reconstruction does.
// Each runs twice: deciding by the local search, and by the sides' components (a search budget of
// 0), which larger lattices fall back on.
#include <array>
#include <functional>
#include <unordered_map>

#include <gtest/gtest.h>

#include <cellrelief/core/marching_tetrahedra.h>
#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/relief/closed_lattice.h>

namespace cellrelief::relief {
namespace {

// A 2 x 2 x 2 grid of cells of 6^3 cubes: lattice points 0..12 a side, the centre (6, 6, 6) held
// by all 8 cells, so the shapes below cross cell faces, edges and corners.
constexpr int kCubes = 6;
constexpr int kGrid = 2;

/// Lattice points inside (+1/2) where `inside` says so, else outside (-1/2).
detail::LatticeBlocks makeLattice(const std::function<bool(const Vec3i&)>& inside) {
  std::vector<Vec3i> cells;
  for (int k = 0; k < kGrid; ++k)
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i) cells.emplace_back(i, j, k);
  detail::LatticeBlocks lattice(cells, kCubes, kGrid);
  for (std::size_t b = 0; b < lattice.blockCount(); ++b)
    for (int z = 0; z <= kCubes; ++z)
      for (int y = 0; y <= kCubes; ++y)
        for (int x = 0; x <= kCubes; ++x) {
          const Vec3i global = lattice.cell(b) * kCubes + Vec3i(x, y, z);
          lattice.block(b)[lattice.offset({x, y, z})] = inside(global) ? 0.5f : -0.5f;
        }
  return lattice;
}

/// The surface of every block, welded by global lattice edge.
MeshTopology topologyOf(const detail::LatticeBlocks& lattice) {
  TriangleMesh mesh;
  std::unordered_map<std::uint64_t, std::uint32_t> vertexOf;
  for (std::size_t b = 0; b < lattice.blockCount(); ++b) {
    const float* values = lattice.block(b);
    for (int z = 0; z < kCubes; ++z)
      for (int y = 0; y < kCubes; ++y)
        for (int x = 0; x < kCubes; ++x) {
          const Vec3i cube(x, y, z), global = lattice.cell(b) * kCubes + cube;
          std::array<float, 8> corner;
          for (int k = 0; k < 8; ++k)
            corner[std::size_t(k)] = values[lattice.offset(cube + cubeCorner(k))];
          const CubeTriangles& triangles =
              kMarchingTetrahedraTable[std::size_t(insideMask(corner))];
          for (int t = 0; t < triangles.count; ++t) {
            Vec3u tri;
            for (int k = 0; k < 3; ++k) {
              const CubeEdge& e = triangles.triangles[std::size_t(t)][std::size_t(k)];
              const auto [it, added] =
                  vertexOf.try_emplace(latticeEdgeKey(global, e.inside, e.outside),
                                       std::uint32_t(mesh.positions.size()));
              if (added)
                mesh.positions.push_back(
                    0.5f * Vec3f(global + cubeCorner(e.inside) + global + cubeCorner(e.outside)));
              tri[k] = it->second;
            }
            mesh.triangles.push_back(tri);
          }
        }
  }
  return analyzeTopology(mesh);
}

/// A point's value, read from the copy in the cell it is the low corner of (or the last cell).
float valueAt(const detail::LatticeBlocks& lattice, const Vec3i& global) {
  return lattice.value(*lattice.find(global));
}

/// The budgets of the two ways a handle point's sides are found joined or apart.
constexpr std::array<std::size_t, 2> kBudgets{detail::kSideSearchBudget, 0};

bool inPlate(const Vec3i& p) {
  return p.z == 6 && p.x >= 2 && p.x <= 10 && p.y >= 2 && p.y <= 10;
}
bool onBoxShell(const Vec3i& p) {
  const Vec3i d = glm::abs(p - Vec3i(6));
  return std::max({d.x, d.y, d.z}) == 3;
}

TEST(ClosedLattice, APoreThroughAOnePointPlateIsClosed) {
  for (const std::size_t budget : kBudgets) {
    SCOPED_TRACE(budget);
    detail::LatticeBlocks lattice =
        makeLattice([](const Vec3i& p) { return inPlate(p) && p != Vec3i(6, 6, 6); });
    const MeshTopology before = topologyOf(lattice);
    ASSERT_TRUE(before.closed() && before.manifold());
    ASSERT_EQ(before.genus, 1);  // the plate with its pore is a ring
    EXPECT_EQ(detail::removeSinglePointHandles(lattice, kGrid, 1.0f / kCubes, budget), 1);
    const MeshTopology after = topologyOf(lattice);
    EXPECT_TRUE(after.closed() && after.manifold());
    EXPECT_EQ(after.genus, 0);
    EXPECT_EQ(after.components, 1u);
    // The pore's point moved inside, in each of the 8 cells that hold it.
    int copiesInside = 0;
    lattice.forEachCopy(Vec3i(6), [&](std::size_t i) { copiesInside += lattice.value(i) > 0; });
    EXPECT_EQ(copiesInside, 8);
  }
}

TEST(ClosedLattice, AOnePointRingIsCutOnce) {
  for (const std::size_t budget : kBudgets) {
    SCOPED_TRACE(budget);
    // A square loop of points, one point thick: a torus, cut at one point into an arc.
    auto onLoop = [](const Vec3i& p) {
      const Vec3i d = glm::abs(p - Vec3i(6));
      return p.z == 6 && std::max(d.x, d.y) == 3;
    };
    detail::LatticeBlocks lattice = makeLattice(onLoop);
    ASSERT_EQ(topologyOf(lattice).genus, 1);
    EXPECT_EQ(detail::removeSinglePointHandles(lattice, kGrid, 1.0f / kCubes, budget), 1);
    const MeshTopology after = topologyOf(lattice);
    EXPECT_EQ(after.genus, 0);
    EXPECT_EQ(after.components, 1u);  // not cut again into two pieces
  }
}

TEST(ClosedLattice, APinholeIntoACavityIsKept) {
  for (const std::size_t budget : kBudgets) {
    SCOPED_TRACE(budget);
    // A hollow box one point thick with one point missing: the pinhole is the only way between the
    // cavity and the outside, so closing it would make a second surface, not remove a handle.
    const Vec3i pinhole(9, 6, 6);
    detail::LatticeBlocks lattice =
        makeLattice([&](const Vec3i& p) { return onBoxShell(p) && p != pinhole; });
    const MeshTopology before = topologyOf(lattice);
    ASSERT_EQ(before.genus, 0);
    ASSERT_EQ(before.components, 1u);
    EXPECT_EQ(detail::removeSinglePointHandles(lattice, kGrid, 1.0f / kCubes, budget), 0);
    EXPECT_LT(valueAt(lattice, pinhole), 0.0f);
    const MeshTopology after = topologyOf(lattice);
    EXPECT_EQ(after.genus, 0);
    EXPECT_EQ(after.components, 1u);
  }
}

TEST(ClosedLattice, HandlesWiderThanAPointAreKept) {
  for (const std::size_t budget : kBudgets) {
    SCOPED_TRACE(budget);
    // The plate with a pore of 2 x 2 points: a real hole at this lattice's resolution.
    detail::LatticeBlocks lattice = makeLattice([](const Vec3i& p) {
      return inPlate(p) && !(p.x >= 6 && p.x <= 7 && p.y >= 6 && p.y <= 7);
    });
    ASSERT_EQ(topologyOf(lattice).genus, 1);
    EXPECT_EQ(detail::removeSinglePointHandles(lattice, kGrid, 1.0f / kCubes, budget), 0);
    EXPECT_EQ(topologyOf(lattice).genus, 1);
  }
}

}  // namespace
}  // namespace cellrelief::relief
