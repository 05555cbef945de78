// SPDX-License-Identifier: MIT
// Topology report on hand-made meshes whose answers are known exactly.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/core/procedural.h>

namespace cellrelief {
namespace {

TriangleMesh soup(std::vector<Vec3f> p, std::vector<Vec3u> t) {
  TriangleMesh m;
  m.positions = std::move(p);
  m.triangles = std::move(t);
  return m;
}

TEST(MeshTopology, ClosedSurfacesHaveTheirGenus) {
  const MeshTopology sphere = analyzeTopology(makeIcosphere(3));
  EXPECT_TRUE(sphere.closed() && sphere.manifold() && sphere.oriented());
  EXPECT_EQ(sphere.eulerCharacteristic, 2);
  EXPECT_EQ(sphere.genus, 0);
  const MeshTopology torus = analyzeTopology(makeTorus(2, 0.5f, 24, 12));
  EXPECT_EQ(torus.eulerCharacteristic, 0);
  EXPECT_EQ(torus.genus, 1);
  EXPECT_EQ(torus.components, 1u);
}

TEST(MeshTopology, OpenTriangle) {
  const MeshTopology t = analyzeTopology(soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}));
  EXPECT_EQ(t.boundaryEdges, 3u);
  EXPECT_EQ(t.boundaryLoops, 1u);
  EXPECT_FALSE(t.genus.has_value());
}

TEST(MeshTopology, BowtieVertexIsNonManifold) {
  const MeshTopology t = analyzeTopology(
      soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}}, {{0, 1, 2}, {0, 3, 4}}));
  EXPECT_EQ(t.nonManifoldVertices, 1u);
  EXPECT_EQ(t.nonManifoldEdges, 0u);
  EXPECT_EQ(t.components, 1u);
}

TEST(MeshTopology, ThreeTrianglesOnOneEdge) {
  const MeshTopology t = analyzeTopology(soup(
      {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}}, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}));
  EXPECT_EQ(t.nonManifoldEdges, 1u);
  EXPECT_EQ(t.nonManifoldVertices, 0u);  // counted under the edge only
}

// The boundary count alone (countBoundaryEdges) is the full analysis's, on every mesh here: closed,
// open, a hole cut, an edge of three triangles, a repeated index.
TEST(MeshTopology, TheBoundaryCountAloneIsTheAnalysisOne) {
  TriangleMesh holed = makeIcosphere(2);
  holed.triangles.erase(holed.triangles.begin() + 3, holed.triangles.begin() + 9);
  const std::vector<TriangleMesh> meshes = {
      makeIcosphere(3), makeTorus(2, 0.5f, 24, 12), holed,
      soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}),
      soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}}, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}),
      soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 0, 1}})};
  // By hand (the hole's count only by the analysis): the repeated index's edge {0, 1} is used three
  // times, so only the first triangle's other two edges are boundary.
  constexpr std::size_t kByAnalysis = ~std::size_t(0);
  const std::size_t expected[] = {0, 0, kByAnalysis, 3, 6, 2};
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    EXPECT_EQ(countBoundaryEdges(meshes[i]), analyzeTopology(meshes[i]).boundaryEdges) << "mesh " << i;
    if (expected[i] != kByAnalysis) EXPECT_EQ(countBoundaryEdges(meshes[i]), expected[i]) << "mesh " << i;
  }
  EXPECT_GT(countBoundaryEdges(holed), 0u);
}

TEST(MeshTopology, FlippedTriangleIsMisoriented) {
  TriangleMesh m = makeIcosphere(1);
  std::swap(m.triangles[0][0], m.triangles[0][1]);
  const MeshTopology t = analyzeTopology(m);
  EXPECT_EQ(t.misorientedEdges, 3u);
  EXPECT_FALSE(t.genus.has_value());
}

TEST(MeshTopology, DegenerateUnreferencedAndDuplicates) {
  const MeshTopology t = analyzeTopology(soup(
      {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {5, 5, 5}, {0, 1, 0}},
      {{0, 1, 2}, {0, 1, 3}, {1, 1, 3}, {0, 5, 1}}));
  EXPECT_EQ(t.degenerateTriangles, 2u);  // collinear, and a repeated index
  EXPECT_EQ(t.unreferencedVertices, 1u);
  EXPECT_EQ(t.duplicatePositions, 1u);  // vertices 3 and 5
}

TEST(MeshTopology, ComponentsAreCounted) {
  TriangleMesh a = makeIcosphere(1), b = makeIcosphere(1);
  const auto offset = static_cast<unsigned>(a.positions.size());
  for (Vec3f p : b.positions) a.positions.push_back(p + Vec3f(3, 0, 0));
  for (Vec3u t : b.triangles) a.triangles.push_back(t + Vec3u(offset));
  a.normals.clear();
  const MeshTopology t = analyzeTopology(a);
  EXPECT_EQ(t.components, 2u);
  EXPECT_EQ(t.eulerCharacteristic, 4);
  EXPECT_FALSE(t.genus.has_value());
}

TEST(TriangleMesh, ValidateNamesTheProblem) {
  TriangleMesh m = soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 3}});
  try {
    m.validate("model.obj");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::InvalidInput);
    EXPECT_NE(std::string(e.what()).find("model.obj"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("vertex 3"), std::string::npos);
  }
  m.triangles[0][2] = 2;
  m.positions[1].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(m.validate(), Error);
  m.positions[1].y = 0;
  EXPECT_NO_THROW(m.validate());
  m.normals.resize(2);
  EXPECT_THROW(m.validate(), Error);
}

}  // namespace
}  // namespace cellrelief
