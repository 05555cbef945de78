// SPDX-License-Identifier: MIT
// Polycubes: surface counts, genus, manifold repair, cavities, the surface mesh and the cube file.
#include <gtest/gtest.h>

#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/polycube/polycube.h>
#include <cellrelief/polycube/polycube_file.h>

#include "random_polycubes.h"
#include "test_support.h"

namespace cellrelief::polycube {
namespace {

/// A box of a x b x c cubes.
std::vector<Vec3i> box(int a, int b, int c, Vec3i at = Vec3i(0)) {
  std::vector<Vec3i> cubes;
  for (int z = 0; z < c; ++z)
    for (int y = 0; y < b; ++y)
      for (int x = 0; x < a; ++x) cubes.push_back(at + Vec3i(x, y, z));
  return cubes;
}

TEST(Polycube, OneCubeIsASphereOfSixFacesAndEightCorners) {
  const Polycube cube(std::vector<Vec3i>{{3, -2, 5}});
  const SurfaceStats s = cube.surfaceStats();
  EXPECT_EQ(s.faces, 6u);
  EXPECT_EQ(s.vertices, 8u);
  EXPECT_EQ(s.edges, 12u);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.perCase[static_cast<int>(VertexCase::k3)], 8u);
  EXPECT_EQ(s.genus(), 0);
}

TEST(Polycube, BoxVerticesAreCornersEdgesAndFlats) {
  const Polycube b(box(3, 3, 3));
  const SurfaceStats s = b.surfaceStats();
  EXPECT_EQ(s.faces, 54u);
  EXPECT_EQ(s.perCase[static_cast<int>(VertexCase::k3)], 8u);
  EXPECT_EQ(s.perCase[static_cast<int>(VertexCase::k4b)], 12u * 2u);
  EXPECT_EQ(s.perCase[static_cast<int>(VertexCase::k4a)], 6u * 4u);
  EXPECT_EQ(s.genus(), 0);
}

TEST(Polycube, RingHasGenusOneAndTwoRingsGenusTwo) {
  std::vector<Vec3i> ring = box(3, 3, 1);
  std::erase(ring, Vec3i(1, 1, 0));
  EXPECT_EQ(Polycube(ring).surfaceStats().genus(), 1);
  std::vector<Vec3i> two = box(5, 3, 1);
  std::erase(two, Vec3i(1, 1, 0));
  std::erase(two, Vec3i(3, 1, 0));
  const SurfaceStats s = Polycube(two).surfaceStats();
  EXPECT_EQ(s.genus(), 2);
  // A genus-2 surface has saddles: cases 5 and 6 appear.
  EXPECT_GT(s.perCase[static_cast<int>(VertexCase::k5)], 0u);
}

TEST(Polycube, SurfaceMeshIsClosedManifoldOutwardWithTheSameGenus) {
  std::vector<Vec3i> cubes = box(4, 3, 2);
  std::erase(cubes, Vec3i(1, 1, 0));
  std::erase(cubes, Vec3i(1, 1, 1));
  cubes.push_back({0, 0, 2});
  const Polycube p(cubes);
  const TriangleMesh mesh = p.surfaceMesh({Vec3d(1, 2, 3), 0.5});
  const MeshTopology t = analyzeTopology(mesh);
  EXPECT_TRUE(t.closed());
  EXPECT_TRUE(t.manifold());
  EXPECT_TRUE(t.oriented());
  EXPECT_EQ(t.genus, p.surfaceStats().genus());
  EXPECT_EQ(t.genus, 1);
  // Outward: the signed volume is the cubes' volume times the cube size cubed.
  double volume = 0;
  for (const Vec3u& tri : mesh.triangles)
    volume += glm::dot(Vec3d(mesh.positions[tri[0]]),
                       glm::cross(Vec3d(mesh.positions[tri[1]]), Vec3d(mesh.positions[tri[2]]))) / 6.0;
  EXPECT_NEAR(volume, double(p.size()) * 0.125, 1e-4);
}

TEST(Polycube, CubesMeetingAtAnEdgeAreRepairedWithOneCube) {
  Polycube p(std::vector<Vec3i>{{0, 0, 0}, {1, 1, 0}});
  EXPECT_FALSE(p.nonManifoldVertices().empty());
  EXPECT_FALSE(p.surfaceStats().genus().has_value());
  const std::size_t added = makeManifold(p);
  EXPECT_EQ(added, 1u);
  EXPECT_TRUE(p.nonManifoldVertices().empty());
  EXPECT_EQ(p.surfaceStats().genus(), 0);
  EXPECT_TRUE(p.contains({0, 0, 0}) && p.contains({1, 1, 0}));
}

TEST(Polycube, CubesMeetingAtACornerAreRepairedAndThePreferenceChoosesWhere) {
  Polycube p(std::vector<Vec3i>{{0, 0, 0}, {1, 1, 1}});
  // Two cubes join a corner pair; prefer the path through x first.
  const std::size_t added = makeManifold(p, [](const Vec3i& c) { return c == Vec3i(1, 0, 0) || c == Vec3i(1, 1, 0) ? 1.0 : 0.0; });
  EXPECT_EQ(added, 2u);
  EXPECT_TRUE(p.contains({1, 0, 0}));
  EXPECT_TRUE(p.contains({1, 1, 0}));
  EXPECT_EQ(p.surfaceStats().genus(), 0);
}

TEST(Polycube, RandomCubeSetsBecomeManifoldAndOneClosedShell) {
  std::mt19937 random(7);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Vec3i> cubes;
    std::uniform_int_distribution<int> coordinate(0, 5);
    for (int i = 0; i < 40; ++i) cubes.push_back({coordinate(random), coordinate(random), coordinate(random)});
    Polycube p = keepLargestAndFill(Polycube(cubes));
    makeManifold(p);
    p = keepLargestAndFill(p);
    makeManifold(p);
    EXPECT_TRUE(p.nonManifoldVertices().empty()) << "trial " << trial;
    const SurfaceStats s = p.surfaceStats();
    EXPECT_EQ(s.components, 1u) << "trial " << trial;
    ASSERT_TRUE(s.genus().has_value()) << "trial " << trial;
    const MeshTopology t = analyzeTopology(p.surfaceMesh());
    EXPECT_TRUE(t.closed() && t.manifold() && t.oriented()) << "trial " << trial;
    EXPECT_EQ(t.genus, s.genus());
  }
}

TEST(Polycube, VerticesOfACaseAreRemovedKeepingGenusAndManifoldness) {
  std::size_t before = 0, after = 0;
  int trial = 0;
  for (Polycube& p : fixtures::randomManifoldPolycubes(20)) {
    ++trial;
    const SurfaceStats start = p.surfaceStats();
    const std::size_t saddles = verticesOfCase(p, VertexCase::k6b).size();
    removeVerticesOfCase(p, VertexCase::k6b, [](const Vec3i&) { return 0.5; });
    const SurfaceStats end = p.surfaceStats();
    EXPECT_TRUE(p.nonManifoldVertices().empty()) << "trial " << trial;
    EXPECT_EQ(end.components, 1u) << "trial " << trial;
    EXPECT_EQ(end.genus(), start.genus()) << "trial " << trial;
    EXPECT_EQ(end.perCase[static_cast<int>(VertexCase::k6b)], verticesOfCase(p, VertexCase::k6b).size());
    before += saddles;
    after += verticesOfCase(p, VertexCase::k6b).size();
  }
  EXPECT_GT(before, 0u);  // the random sets do have such vertices
  EXPECT_EQ(after, 0u);
  std::printf("case-6b vertices in 20 random polycubes: %zu before, %zu after\n", before, after);
}

TEST(Polycube, CavitiesAreFilledAndOnlyTheLargestPieceKept) {
  std::vector<Vec3i> cubes = box(3, 3, 3);
  std::erase(cubes, Vec3i(1, 1, 1));  // a cavity: a second, inner surface
  cubes.push_back({10, 10, 10});      // a stray cube
  const Polycube p(cubes);
  EXPECT_EQ(p.surfaceStats().components, 3u);
  const Polycube filled = keepLargestAndFill(p);
  EXPECT_EQ(filled.size(), 27u);
  EXPECT_EQ(filled.surfaceStats().components, 1u);
}

TEST(PolycubeFile, RoundTripIsExact) {
  test::TempDir dir;
  const Polycube p(box(2, 3, 1, {-4, 7, 100}));
  const PolycubeFrame frame{Vec3d(0.1, -0.2, 1.0 / 3.0), 0.0625};
  writePolycube(p, frame, dir / "p.txt");
  const PolycubeFile file = readPolycube(dir / "p.txt");
  EXPECT_TRUE(file.hasFrame);
  EXPECT_EQ(file.frame.origin, frame.origin);
  EXPECT_EQ(file.frame.cubeSize, frame.cubeSize);
  ASSERT_EQ(file.polycube.size(), p.size());
  EXPECT_TRUE(std::equal(p.cubes().begin(), p.cubes().end(), file.polycube.cubes().begin()));
}

TEST(PolycubeFile, BadFilesAreRefusedNamingFileAndLine) {
  test::TempDir dir;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"0 0 0\n1 0\n", "line 2"},
      {"0 0 0\n1 0 x\n", "line 2"},
      {"0 0 0.5\n", "line 1"},
      {"# nothing\n\n", "no cubes"},
      {"frame 0 0 0 -1\n0 0 0\n", "positive"},
      {"frame 0 0 0 1\nframe 0 0 0 1\n0 0 0\n", "second frame"},
      {"0 0 99999999\n", "out of range"},
      {"frame 0 0 nan 1\n0 0 0\n", "finite"},
  };
  for (const auto& [text, words] : cases) {
    const std::filesystem::path path = dir / "bad.txt";
    test::writeBytes(path, text);
    try {
      readPolycube(path);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("bad.txt"), std::string::npos) << what;
      EXPECT_NE(what.find(words), std::string::npos) << what;
    }
  }
  EXPECT_THROW(readPolycube(dir / "missing.txt"), Error);
}

TEST(PolycubeFile, TexturedMeshesRoundTripAndBadOnesAreRefusedNamingFileAndLine) {
  test::TempDir dir;
  TriangleMesh surface = Polycube(box(2, 1, 1, {0, 0, 0})).surfaceMesh();
  surface.positions.push_back(Vec3f(5.0f));  // a vertex no triangle uses keeps its texture position
  std::vector<Vec3d> texture;
  for (const Vec3f& p : surface.positions) texture.push_back(Vec3d(p) + Vec3d(0.0, 0.0, 1.0 / 3.0));
  writeTexturedMesh(surface, texture, dir / "m.obj");
  const TexturedMeshFile file = readTexturedMesh(dir / "m.obj");
  ASSERT_EQ(file.mesh.positions.size(), surface.positions.size());
  EXPECT_EQ(file.mesh.triangles, surface.triangles);
  for (std::size_t v = 0; v < texture.size(); ++v) EXPECT_LT(glm::length(file.texture[v] - texture[v]), 1e-11);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nf 1/1 2/1 3\n", "line 5"},                 // a corner without vt
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nf 1/1 2/1 4/1\n", "out of range"},         // vertex 4
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nf 1/1 2/1 3/2\n", "out of range"},         // vt 2
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n", "line 4"},                                 // vt of two numbers
      {"v 0 0 nan\n", "finite"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nvt 1 0 0\nf 1/1 2/1 3/1\nf 1/2 2/1 3/1\n", "two texture positions"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nf 1/1 2/1 3/1 3/1\n", "triangle"},
      {"v 0 0 0\nvn 0 0 1\n", "expected v, vt or f"},
      {"v 0 0 0\n", "no triangles"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\nvt 0 0 0\nf 1/1 2/1 3/1\n", "in no triangle"},  // and no vt 4
  };
  for (const auto& [text, words] : cases) {
    const std::filesystem::path path = dir / "bad.obj";
    test::writeBytes(path, text);
    try {
      readTexturedMesh(path);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const Error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("bad.obj"), std::string::npos) << what;
      EXPECT_NE(what.find(words), std::string::npos) << what;
    }
  }
  EXPECT_THROW(readTexturedMesh(dir / "missing.obj"), Error);
}

}  // namespace
}  // namespace cellrelief::polycube
