// SPDX-License-Identifier: MIT
// The cell complex on bad input (clear errors) and on every robustness mesh (a result or a clear
// error, never a crash or a hang).
#include <gtest/gtest.h>

#include <cellrelief/cells/cell_complex.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/io/mesh_io.h>

#include "test_support.h"

namespace cellrelief::cells {
namespace {

TEST(CellComplexBadInput, ClearErrors) {
  const TriangleMesh sphere = makeIcosphere(2);
  auto expectKind = [&](const TriangleMesh& m, ComplexOptions o, ErrorKind kind,
                        const std::string& words) {
    try {
      CellComplex::build(m, o);
      FAIL() << "no error for " << words;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), kind) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  expectKind(sphere, {.gridSize = 0}, ErrorKind::InvalidArgument, "N = 0");
  expectKind(sphere, {.gridSize = 5000}, ErrorKind::InvalidArgument, "out of range");
  expectKind(TriangleMesh{}, {.gridSize = 8}, ErrorKind::InvalidInput, "no triangles");
  TriangleMesh nan = sphere;
  nan.positions[3].x = std::nanf("");
  expectKind(nan, {.gridSize = 8}, ErrorKind::InvalidInput, "non-finite");
  expectKind(sphere, {.gridSize = 512, .memoryLimitBytes = 64u << 20}, ErrorKind::ResourceLimit,
             "over the limit");
  TriangleMesh point = sphere;
  for (Vec3f& p : point.positions) p = Vec3f(1, 2, 3);
  expectKind(point, {.gridSize = 8}, ErrorKind::InvalidInput, "zero extent");
}

// Every robustness mesh builds (never a crash or a hang), and its grid covers the whole mesh.
// The grey cells are compared with CGAL's exact test in cgal_verify_tests (RobustnessVersusCgal).
class RobustnessCells : public ::testing::TestWithParam<std::string> {};

TEST_P(RobustnessCells, ResultOrClearError) {
  const auto path = test::dataDir() / "meshes/robustness" / GetParam();
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh m = io::readMesh(path);
  for (int n : {1, 7, 32}) {
    const CellComplex c = CellComplex::build(m, {.gridSize = n});
    EXPECT_GT(c.stats().grey, 0u);
    const Aabbf box = m.surfaceBounds();
    EXPECT_TRUE(c.boundsWS().contains(Vec3d(box.min)) && c.boundsWS().contains(Vec3d(box.max))) << "N " << n;
    // Every triangle's cells are grey: the cell of each vertex (clamped into the grid) is grey.
    std::size_t notGrey = 0;
    for (const Vec3u& t : m.triangles)
      for (int k = 0; k < 3; ++k) {
        const Vec3i ijk = glm::clamp(Vec3i(glm::floor(c.worldToIndex(Vec3d(m.positions[t[k]])))), Vec3i(0), Vec3i(n - 1));
        notGrey += c.color(ijk) != CellColor::Grey;
      }
    EXPECT_EQ(notGrey, 0u) << "N " << n;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, RobustnessCells,
    ::testing::ValuesIn(test::robustnessMeshes()), test::meshTestName);

}  // namespace
}  // namespace cellrelief::cells
