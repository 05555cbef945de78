// SPDX-License-Identifier: MIT
// Surfaces the relief maps cannot see as they are: flat meshes (modelled as a closed slab) and
// triangles lying in the planes where projection lines end (kept off them by the grid placement).
#include <gtest/gtest.h>

#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/metrics/geometric_error.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/relief/flat_mesh.h>
#include <cellrelief/relief/reconstruct.h>

namespace cellrelief::relief {
namespace {

/// A square sheet of n x n quads in the plane z = 0.3, [0, 2] x [0, 1], split into triangles
/// whose diagonals alternate, with every vertex but one copied (as meshes split for attributes are).
TriangleMesh sheet(int n, bool splitVertices) {
  TriangleMesh m;
  auto vertex = [&](int i, int j) {
    m.positions.push_back(Vec3f(2.0f * float(i) / float(n), float(j) / float(n), 0.3f));
    return std::uint32_t(m.positions.size() - 1);
  };
  std::vector<std::uint32_t> grid;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) grid.push_back(vertex(i, j));
  auto at = [&](int i, int j) { return splitVertices ? vertex(i, j) : grid[std::size_t(j) * (n + 1) + i]; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if ((i + j) % 2) {
        m.triangles.push_back({a, b, c});
        m.triangles.push_back({a, c, d});
      } else {  // the other diagonal, and the other winding: orientation must not matter
        m.triangles.push_back({a, d, b});
        m.triangles.push_back({b, d, c});
      }
    }
  return m;
}

TEST(FlatMesh, TheAxisOfAFlatMeshIsFound) {
  EXPECT_EQ(flatAxis(sheet(3, false)), 2);
  EXPECT_FALSE(flatAxis(makeIcosphere(1)).has_value());
  TriangleMesh line;
  line.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  line.triangles = {{0, 1, 2}};
  EXPECT_FALSE(flatAxis(line).has_value()) << "a line is flat in two axes: no surface";
}

TEST(FlatMesh, TheSlabIsClosedManifoldAndAsThickAsAsked) {
  for (const bool split : {false, true}) {
    const TriangleMesh slab = slabOfFlatMesh(sheet(4, split), 2, 0.01f);
    // Top, bottom, and two wall triangles on each of the 16 edges of the sheet's rim only: the
    // copies of a vertex are one vertex there, so no wall stands inside the slab.
    EXPECT_EQ(slab.triangles.size(), 2u * 32u + 2u * 16u) << "split " << split;
    if (!split) {  // shared vertices: the slab is a closed, consistently oriented surface
      const MeshTopology t = analyzeTopology(slab);
      EXPECT_EQ(t.boundaryEdges, 0u);
      EXPECT_EQ(t.misorientedEdges, 0u);
      EXPECT_EQ(t.genus, 0);
    }
    const Aabbf box = slab.surfaceBounds();
    EXPECT_FLOAT_EQ(box.min.z, 0.29f);
    EXPECT_FLOAT_EQ(box.max.z, 0.31f);
    // Every triangle faces out of the slab: its normal points away from the slab's centre line.
    for (const Vec3u& tri : slab.triangles) {
      const Vec3f a = slab.positions[tri[0]], b = slab.positions[tri[1]], c = slab.positions[tri[2]];
      const Vec3f normal = glm::cross(b - a, c - a);
      const Vec3f centroid = (a + b + c) / 3.0f;
      const Vec3f outward = centroid - Vec3f(1.0f, 0.5f, 0.3f);
      EXPECT_GT(glm::dot(normal, outward), 0.0f);
    }
  }
  TriangleMesh degenerate;
  degenerate.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  degenerate.triangles = {{0, 1, 2}};
  EXPECT_THROW(slabOfFlatMesh(degenerate, 2, 0.01f), Error);
}

TEST(FlatMesh, ASheetConvertsAndItsModelReproducesIt) {
  const TriangleMesh flat = sheet(8, false);
  ConvertReport report;
  const ReliefModel model = convert(flat, {}, &report);
  EXPECT_GT(report.slabThicknessWS, 0.0);
  EXPECT_LE(report.slabThicknessWS, kFlatSlabThickness * 2.0 + 1e-9);
  ASSERT_FALSE(report.gridTrials.empty());
  EXPECT_GE(report.gridTrials.front().gridSize, 2);  // N = 1 has no grid plane through the slab
  EXPECT_GE(report.gridTrials.back().hausdorff, 0.0);
  const metrics::SurfaceError e =
      metrics::surfaceError(flat, metrics::DistanceField(flat), reconstruct(model), 50000);
  const double diagonal = flat.surfaceBounds().diagonal();
  EXPECT_LT(e.rms() / diagonal, 0.002);
  EXPECT_LT(e.hausdorff() / diagonal, detail::kFlatHausdorff);
}

/// A box of whole cells: its faces lie in grid planes of the bounding cube at N = 4, and a cube
/// rotated by a quarter turn in one axis puts a face on the cells' middle planes at N = 2.
TEST(GridPlacement, TrianglesInProjectionPlanesAreMovedOffThem) {
  TriangleMesh box;
  box.positions = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {4, 4, 0}, {0, 0, 2}, {4, 0, 2}, {0, 4, 2}, {4, 4, 2}};
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    box.triangles.push_back({q[0], q[1], q[2]});
    box.triangles.push_back({q[0], q[2], q[3]});
  }
  for (const int n : {2, 4, 8, 16}) {
    const cells::CellComplex c = cells::CellComplex::build(box, {.gridSize = n});
    // The lattice covers the mesh, with at most half a cell more than the cube.
    EXPECT_LE(c.boundsWS().min.x, 0.0);
    EXPECT_GE(c.boundsWS().max.x, 4.0);
    EXPECT_GE(c.cellSizeWS(), 4.0 / n);
    EXPECT_LE(c.cellSizeWS(), 4.0 / (n - 0.5) + 1e-12);
    // No face plane (x, y in {0, 4}, z in {0, 2}) is on a grid plane or a cell's middle plane.
    for (const auto& [axis, value] : std::vector<std::pair<int, double>>{{0, 0}, {0, 4}, {1, 0}, {1, 4}, {2, 0}, {2, 2}}) {
      const double u = (value - c.boundsWS().min[axis]) / c.cellSizeWS();
      const double offHalf = std::abs(2 * u - std::round(2 * u)) / 2;
      EXPECT_GT(offHalf, 0.1) << "N " << n << " axis " << axis << " plane " << value << " at u = " << u;
    }
    // And the box converts with every face stored: its model is as accurate as a generic shape's.
    const ReliefModel model = convert(box, {.gridSize = n});
    // The samples joined per face: what the maps store (the closed method is tested on its own).
    const metrics::SurfaceError e =
        metrics::surfaceError(box, metrics::DistanceField(box), reconstructPerFace(model), 50000);
    EXPECT_LT(e.rms() / box.surfaceBounds().diagonal(), 0.01) << "N " << n;
  }
}

}  // namespace
}  // namespace cellrelief::relief
