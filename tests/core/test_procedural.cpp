// SPDX-License-Identifier: MIT
// The built-in shapes: analytic properties of the sphere and torus, detail in the demo model.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/core/procedural.h>

namespace cellrelief {
namespace {

TEST(Procedural, IcosphereConvergesToTheSphere) {
  const TriangleMesh m = makeIcosphere(5, 2.0f);
  EXPECT_EQ(m.triangleCount(), 20u * 1024u);
  for (const Vec3f& p : m.positions) ASSERT_NEAR(glm::length(p), 2.0f, 1e-5f);
  const double exact = 4 * std::numbers::pi * 4;
  EXPECT_NEAR(surfaceArea(m) / exact, 1.0, 2e-3);  // inscribed: slightly less
  EXPECT_LT(surfaceArea(m), exact);
}

TEST(Procedural, TorusAreaAndGenus) {
  const TriangleMesh m = makeTorus(2.0f, 0.5f, 128, 64);
  const double exact = 4 * std::numbers::pi * std::numbers::pi * 2.0 * 0.5;
  EXPECT_NEAR(surfaceArea(m) / exact, 1.0, 2e-3);
  EXPECT_EQ(analyzeTopology(m).genus, 1);
  EXPECT_THROW(makeTorus(0.5f, 1.0f, 8, 8), Error);
}

TEST(Procedural, DisplacedSphereHasFineDetailAndStaysASphere) {
  DisplacedSphereOptions o;
  o.subdivisions = 6;
  const TriangleMesh m = makeDisplacedSphere(o);
  EXPECT_EQ(m.triangleCount(), 20u * 4096u);
  const MeshTopology t = analyzeTopology(m);
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(t.degenerateTriangles, 0u);
  float lo = 10, hi = 0;
  double roughness = 0;  // mean radius change across an edge: fine detail, not just a lumpy ball
  for (const Vec3f& p : m.positions) {
    lo = std::min(lo, glm::length(p));
    hi = std::max(hi, glm::length(p));
  }
  for (const Vec3u& tri : m.triangles)
    roughness += std::abs(glm::length(m.positions[tri[0]]) - glm::length(m.positions[tri[1]]));
  roughness /= double(m.triangleCount());
  EXPECT_GT(hi - lo, 0.05f);
  EXPECT_LT(hi - lo, 2 * o.amplitude);
  EXPECT_GT(roughness, 1e-3);
  ASSERT_TRUE(m.hasNormals() && m.hasColors());
  // Deterministic: the same seed gives the same model.
  EXPECT_EQ(makeDisplacedSphere(o).positions[1234], m.positions[1234]);
}

TEST(Procedural, DisplacedTorusIsTheDemoModel) {
  const TriangleMesh m = makeDisplacedTorus();
  EXPECT_EQ(m.triangleCount(), 327680u);
  const MeshTopology t = analyzeTopology(m);
  EXPECT_EQ(t.genus, 1);
  EXPECT_EQ(t.degenerateTriangles, 0u);
  ASSERT_TRUE(m.hasNormals() && m.hasColors());
}

}  // namespace
}  // namespace cellrelief
