// SPDX-License-Identifier: MIT
// Automatic polycubes of the real meshes: closed manifold shells of the mesh's genus, near it.
#include <gtest/gtest.h>

#include <cellrelief/core/bvh.h>
#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/polycube/from_mesh.h>
#include <cellrelief/polycube/projection.h>

#include "test_support.h"

namespace cellrelief::polycube {
namespace {

struct MeshCase {
  std::string path;
  int genus;  ///< with the holes capped
};

class PolycubeOfRealMesh : public testing::TestWithParam<MeshCase> {};

TEST_P(PolycubeOfRealMesh, IsAClosedManifoldShellOfTheMeshGenusNearTheMesh) {
  const std::filesystem::path path = test::dataDir() / GetParam().path;
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh mesh = io::readMesh(path);
  const PolycubeResult result = polycubeOfMesh(mesh);
  EXPECT_EQ(result.meshGenus, GetParam().genus);
  const Polycube& p = result.polycube;
  EXPECT_TRUE(p.nonManifoldVertices().empty());
  const SurfaceStats s = p.surfaceStats();
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.genus(), GetParam().genus);
  const TriangleMesh surface = p.surfaceMesh(result.frame);
  const MeshTopology t = analyzeTopology(surface);
  EXPECT_TRUE(t.closed() && t.manifold() && t.oriented());
  // Near the mesh, both ways (a coarse Hausdorff bound): a cube is a cell the surface passes
  // through or one beside it that repair added, so two cube diagonals.
  const double reach = 2 * std::sqrt(3.0) * result.frame.cubeSize;
  const MeshBvh meshBvh(mesh), cubeBvh(surface);
  for (const Vec3f& v : surface.positions)
    EXPECT_LE(std::sqrt(meshBvh.bvh.closestPoint(Vec3d(v)).first), reach);
  for (std::size_t i = 0; i < mesh.positions.size(); i += 17)
    EXPECT_LE(std::sqrt(cubeBvh.bvh.closestPoint(Vec3d(mesh.positions[i])).first), reach);
  // Few cubes per feature: the coarsest size that keeps the genus.
  EXPECT_EQ(result.trials.back().cubesPerSide, result.cubesPerSide);
  // Case 6b vertices are kept (removeCase6b is off) and counted.
  EXPECT_EQ(result.trials.back().case6bToggled, 0u);
  EXPECT_EQ(s.perCase[static_cast<int>(VertexCase::k6b)], result.trials.back().case6bLeft);
  for (const Vec3i& v : p.surfaceVertices()) EXPECT_NO_THROW(project(p.vertexConfiguration(v), Vec3d(0.05, -0.03, 0.02)));
  std::printf("%s: N = %d, %zu cubes (%zu added for manifoldness, %zu toggled to remove 6b), %zu faces, "
              "cases 3/4a/4b/5/6a/6b = %zu/%zu/%zu/%zu/%zu/%zu, %.2f s\n",
              GetParam().path.c_str(), result.cubesPerSide, p.size(), result.trials.back().addedForManifold,
              result.trials.back().case6bToggled, s.faces, s.perCase[0], s.perCase[1], s.perCase[2], s.perCase[3],
              s.perCase[4], s.perCase[5], result.seconds);
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, PolycubeOfRealMesh,
    testing::Values(MeshCase{"meshes/small/fertility_9k__libigl-tutorial-data.off", 4},
                    MeshCase{"meshes/small/3holes__cinolib.obj", 3},
                    MeshCase{"meshes/medium/stanford-bunny__common-3d-test-models.obj", 0},
                    MeshCase{"meshes/medium/laurana__cinolib.obj", 0},
                    MeshCase{"meshes/medium/bumpy-cube__libigl-tutorial-data.obj", 0},
                    MeshCase{"meshes/medium/armadillo__libigl-tutorial-data.obj", 0},
                    MeshCase{"meshes/small/spot__common-3d-test-models.obj", 0}),
    [](const testing::TestParamInfo<MeshCase>& param) { return test::testNameOfPath(param.param.path); });

TEST(PolycubeOfMesh, EmptyMeshAndBadSizesAreRefused) {
  EXPECT_THROW(polycubeOfMesh(TriangleMesh{}), Error);
  const std::filesystem::path path = test::dataDir() / "meshes/small/fertility_9k__libigl-tutorial-data.off";
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh mesh = io::readMesh(path);
  EXPECT_THROW(polycubeOfMesh(mesh, {.cubesPerSide = 1}), Error);
  // Fertility's four handles cannot survive a 2-cube lattice: a clear error, with the genus.
  try {
    polycubeOfMesh(mesh, {.cubesPerSide = 2});
    ADD_FAILURE() << "accepted a polycube of the wrong genus";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("genus 4"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cellrelief::polycube
