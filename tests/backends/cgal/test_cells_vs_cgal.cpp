// SPDX-License-Identifier: GPL-3.0-or-later
// Verification: on every closed real mesh at N = 8, 16, 32, 64, cellrelief's grey cells equal
// CGAL's exact triangle/box intersections, and black/white equal CGAL's Side_of_triangle_mesh at
// the centres of all non-grey cells. 100% agreement; the counts are printed.
#include <cstdio>

#include <gtest/gtest.h>

#include <cellrelief/cells/cell_complex.h>
#include <cellrelief/cgal/reference_cells.h>
#include <cellrelief/io/mesh_io.h>

#include "test_support.h"

namespace cellrelief {
namespace {

class CellsVersusCgal : public ::testing::TestWithParam<std::string> {};

TEST_P(CellsVersusCgal, FullAgreement) {
  const auto path = test::dataDir() / GetParam();
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh mesh = io::readMesh(path);
  for (int n : {8, 16, 32, 64}) {
    const cells::CellComplex c = cells::CellComplex::build(mesh, {.gridSize = n});
    const std::vector<char> grey =
        cgal::referenceGreyCells(c.snappedPositionsIS(), mesh.triangles, n);
    const cgal::ReferenceSide side(c.snappedPositionsIS(), mesh.triangles);
    ASSERT_TRUE(side.closed()) << GetParam();
    std::size_t greyMismatch = 0, sideMismatch = 0, cgalGrey = 0, cgalBlack = 0, cgalWhite = 0;
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const cells::CellColor ours = c.color(Vec3i(x, y, z));
          if (grey[cgal::cellId(n, x, y, z)]) {
            ++cgalGrey;
            greyMismatch += ours != cells::CellColor::Grey;
            continue;
          }
          if (ours == cells::CellColor::Grey) {
            ++greyMismatch;
            continue;
          }
          const bool inside = side.inside(Vec3d(x + 0.5, y + 0.5, z + 0.5));
          (inside ? cgalBlack : cgalWhite)++;
          sideMismatch += inside != (ours == cells::CellColor::Black);
        }
    std::printf("%-50s N=%3d  grey %7zu (CGAL %7zu)  black %8zu (CGAL %8zu)  white %8zu (CGAL %8zu)"
                "  mismatches: grey %zu, side %zu\n",
                GetParam().c_str(), n, c.stats().grey, cgalGrey, c.stats().black, cgalBlack,
                c.stats().white, cgalWhite, greyMismatch, sideMismatch);
    EXPECT_EQ(greyMismatch, 0u) << "N = " << n;
    EXPECT_EQ(sideMismatch, 0u) << "N = " << n;
  }
}

INSTANTIATE_TEST_SUITE_P(
    ClosedMeshes, CellsVersusCgal,
    ::testing::Values("meshes/small/cube__libigl-tutorial-data.obj",
                      "meshes/small/TinyTorus__libigl-tests-data.obj",
                      "meshes/small/bob_small__geometry-central.ply",
                      "meshes/small/decimated-knight__libigl-tutorial-data.off",
                      "meshes/small/bumpy__libigl-tutorial-data.off",
                      "meshes/small/3holes__cinolib.obj",
                      "meshes/small/spot__common-3d-test-models.obj",
                      "meshes/small/fertility_9k__libigl-tutorial-data.off",
                      "meshes/medium/fandisk__common-3d-test-models.obj",
                      "meshes/medium/egea__4AxisMilling.obj",
                      "meshes/medium/bumpy-cube__libigl-tutorial-data.obj",
                      "meshes/medium/pensatore__4AxisMilling.obj",
                      "meshes/medium/armadillo__libigl-tutorial-data.obj",
                      "meshes/large/igea__common-3d-test-models.ply"),
    [](const auto& param) {
      std::string name = std::filesystem::path(param.param).stem().string();
      name = name.substr(0, name.find("__"));
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

// The robustness meshes (open, non-manifold, degenerate, flat, self-intersecting): the grey cells
// are exactly those CGAL's do_intersect finds, at every N, whatever the mesh's defects (inside and
// outside are not compared: for open meshes they are undefined).
class RobustnessVersusCgal : public ::testing::TestWithParam<std::string> {};

TEST_P(RobustnessVersusCgal, GreyCellsAgree) {
  const auto path = test::dataDir() / "meshes/robustness" / GetParam();
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh mesh = io::readMesh(path);
  for (int n : {1, 7, 32}) {
    const cells::CellComplex c = cells::CellComplex::build(mesh, {.gridSize = n});
    const std::vector<char> grey = cgal::referenceGreyCells(c.snappedPositionsIS(), mesh.triangles, n);
    std::size_t cgalGrey = 0, mismatch = 0;
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const bool reference = grey[cgal::cellId(n, x, y, z)];
          cgalGrey += reference;
          mismatch += reference != (c.color(Vec3i(x, y, z)) == cells::CellColor::Grey);
        }
    EXPECT_GT(cgalGrey, 0u) << "N = " << n;
    EXPECT_EQ(c.stats().grey, cgalGrey) << "N = " << n;
    EXPECT_EQ(mismatch, 0u) << "N = " << n;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, RobustnessVersusCgal,
    ::testing::ValuesIn(test::robustnessMeshes()), test::meshTestName);

}  // namespace
}  // namespace cellrelief
