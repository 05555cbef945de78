// SPDX-License-Identifier: MIT
// The cell complex on analytic shapes with exact answers, the tie rule, and the documented
// degradation on open meshes.
#include <gtest/gtest.h>

#include <cellrelief/cells/cell_complex.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/io/mesh_io.h>

#include "test_support.h"

namespace cellrelief::cells {
namespace {

TEST(CellComplex, SphereHasAGreyShellAroundABlackCore) {
  const TriangleMesh sphere = makeIcosphere(5);
  const CellComplex c = CellComplex::build(sphere, {.gridSize = 16});
  const ComplexStats& s = c.stats();
  EXPECT_EQ(s.white + s.black + s.grey, 16u * 16u * 16u);
  EXPECT_GT(s.black, 0u);
  EXPECT_EQ(c.color(Vec3i(8, 8, 8)), CellColor::Black);
  EXPECT_EQ(c.color(Vec3i(7, 7, 7)), CellColor::Black);
  EXPECT_EQ(c.color(Vec3i(-1, 0, 0)), CellColor::White);  // outside the grid
  EXPECT_EQ(c.stats().enclosedComponents, 1u);
  std::size_t perCase = 0;
  for (std::size_t k : s.perCase) perCase += k;
  EXPECT_EQ(perCase, s.grey);
  EXPECT_EQ(std::size_t(c.grid().activeVoxelCount()), s.grey);
  // Every grey cell really is near the unit sphere: its closed box reaches radius 1.
  for (const GreyCell& g : c.greyCells()) {
    const Aabbd box = c.cellBoxWS(g.ijk);
    const Vec3d nearest = glm::clamp(Vec3d(0), box.min, box.max);
    Vec3d farthest;
    for (int a = 0; a < 3; ++a) farthest[a] = std::abs(box.min[a]) > std::abs(box.max[a]) ? box.min[a] : box.max[a];
    EXPECT_LE(glm::length(nearest), 1.0 + 1e-6);
    EXPECT_GE(glm::length(farthest), 0.99);  // the icosphere is inscribed in the unit sphere
    EXPECT_EQ(c.color(g.ijk), CellColor::Grey);
    EXPECT_EQ(c.greyIndex(g.ijk), &g - c.greyCells().data());
    EXPECT_GT(g.triangleCount, 0u);
  }
  // Most grey cells see white (BG); where the shell is two cells thick some see only grey and
  // black neighbours (IG, case 0).
  EXPECT_EQ(s.borderGrey + s.interiorGrey, s.grey);
  EXPECT_EQ(s.interiorGrey, s.perCase[0]);
  EXPECT_GT(s.borderGrey, s.interiorGrey);
  // Black space is stored as tiles: far fewer leaf voxels than black cells.
  EXPECT_LT(c.grid().tree().leafCount() * 512, s.grey * 512 + s.black);
}

TEST(CellComplex, TrianglesInGridPlanesMakeBothSidesGrey) {
  // A unit cube whose faces lie exactly on the grid planes 1 and 2 of a 4^3 grid over [0, 4]^3.
  TriangleMesh m;
  const Vec3f corners[8] = {{1, 1, 1}, {2, 1, 1}, {1, 2, 1}, {2, 2, 1},
                            {1, 1, 2}, {2, 1, 2}, {1, 2, 2}, {2, 2, 2}};
  m.positions.assign(corners, corners + 8);
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  // Two tiny triangles stretch the bounds to [0, 4]^3; each lies in one corner cell.
  const auto base = std::uint32_t(m.positions.size());
  m.positions.insert(m.positions.end(),
                     {{0, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0}, {4, 4, 4}, {3.9f, 4, 4}, {4, 3.9f, 4}});
  m.triangles.push_back({base, base + 1, base + 2});
  m.triangles.push_back({base + 3, base + 4, base + 5});
  const CellComplex c = CellComplex::build(m, {.gridSize = 4, .offProjectionPlanes = false});
  EXPECT_DOUBLE_EQ(c.cellSizeWS(), 1.0);
  std::size_t grey = 0;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) {
        // Closed cells: every cell in {0,1,2}^3 touches the cube's surface (faces, edges, corners).
        const bool touches = x <= 2 && y <= 2 && z <= 2;
        const bool corner = x == 3 && y == 3 && z == 3;
        const bool isGrey = c.color(Vec3i(x, y, z)) == CellColor::Grey;
        EXPECT_EQ(isGrey, touches || corner) << x << " " << y << " " << z;
        grey += isGrey;
      }
  EXPECT_EQ(grey, 28u);
  // The cube's inside, cell (1,1,1), is grey (its faces carry the surface): no black cell remains.
  EXPECT_EQ(c.stats().black, 0u);
}

TEST(CellComplex, OpenMeshesDegradeAsDocumented) {
  TriangleMesh sphere = makeIcosphere(5);
  // A small hole (one triangle) is sealed by the grey cells at a coarse grid.
  TriangleMesh pinhole = sphere;
  pinhole.triangles.erase(pinhole.triangles.begin());
  EXPECT_GT(CellComplex::build(pinhole, {.gridSize = 8}).stats().black, 0u);
  // A hole wider than a cell (a polar cap) lets the outside in: no black cells, grey shell intact.
  TriangleMesh capped = sphere;
  std::erase_if(capped.triangles, [&](const Vec3u& t) {
    return capped.positions[t[0]].z > 0.7f && capped.positions[t[1]].z > 0.7f &&
           capped.positions[t[2]].z > 0.7f;
  });
  const CellComplex leaky = CellComplex::build(capped, {.gridSize = 32});
  EXPECT_EQ(leaky.stats().black, 0u);
  EXPECT_GT(leaky.stats().grey, 1000u);
  // Two overlapping shells (self-intersection): inside where either shell is.
  TriangleMesh two = sphere;
  const auto offset = std::uint32_t(two.positions.size());
  for (Vec3f p : sphere.positions) two.positions.push_back(p + Vec3f(0.5f, 0, 0));
  for (Vec3u t : sphere.triangles) two.triangles.push_back(t + Vec3u(offset));
  two.normals.clear();
  const CellComplex both = CellComplex::build(two, {.gridSize = 24});
  EXPECT_GT(both.stats().enclosedComponents, 1u);
  EXPECT_GT(both.stats().black, 0u);
}

TEST(CellComplex, WindingNumberOfAClosedSphere) {
  const TriangleMesh s = makeIcosphere(4);
  std::vector<Vec3d> p(s.positions.begin(), s.positions.end());
  EXPECT_NEAR(windingNumber(p, s.triangles, Vec3d(0.1, 0.2, -0.3)), 1.0, 1e-9);
  EXPECT_NEAR(windingNumber(p, s.triangles, Vec3d(1.5, 0.2, -0.3)), 0.0, 1e-9);
}

}  // namespace
}  // namespace cellrelief::cells
