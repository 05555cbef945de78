// SPDX-License-Identifier: MIT
// P over the whole lattice, the surface's normals, and the distortion measures on maps whose
// distortion is known in closed form.
#include <map>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include <cellrelief/core/procedural.h>
#include <cellrelief/polycube/parameterization.h>

#include "random_polycubes.h"

namespace cellrelief::polycube {
namespace {

/// The surface of a polycube as a mesh (lattice units), each face split into 2 x 2 quads so that
/// vertices lie inside faces, on edges and at corners.
TriangleMesh refinedSurface(const Polycube& p) {
  const TriangleMesh coarse = p.surfaceMesh();
  TriangleMesh out;
  std::map<std::array<int, 3>, std::uint32_t> index;  // doubled coordinates: exact
  const auto vertex = [&](const Vec3d& x) {
    const std::array<int, 3> key{int(std::lround(2 * x.x)), int(std::lround(2 * x.y)), int(std::lround(2 * x.z))};
    const auto [it, added] = index.emplace(key, std::uint32_t(out.positions.size()));
    if (added) out.positions.push_back(Vec3f(x));
    return it->second;
  };
  for (const Vec3u& t : coarse.triangles) {
    // Midpoint subdivision of each triangle: 4 triangles, same orientation.
    const Vec3d a(coarse.positions[t[0]]), b(coarse.positions[t[1]]), c(coarse.positions[t[2]]);
    const std::uint32_t A = vertex(a), B = vertex(b), C = vertex(c);
    const std::uint32_t ab = vertex(0.5 * (a + b)), bc = vertex(0.5 * (b + c)), ca = vertex(0.5 * (c + a));
    for (const Vec3u& s : {Vec3u(A, ab, ca), Vec3u(ab, B, bc), Vec3u(ca, bc, C), Vec3u(ab, bc, ca)})
      out.triangles.push_back(s);
  }
  out.sourcePolygons = out.triangles.size();
  return out;
}

Distortion distortionOf(const TriangleMesh& mesh, std::span<const Vec3d> texture, const PolycubeSurface& surface) {
  std::vector<TriangleFrame> frames;
  for (const Vec3u& t : mesh.triangles)
    frames.emplace_back(Vec3d(mesh.positions[t[0]]), Vec3d(mesh.positions[t[1]]), Vec3d(mesh.positions[t[2]]));
  return measureDistortion(frames, mesh.triangles, texture, [&](std::size_t i) {
    const Vec3u& t = mesh.triangles[i];
    return surface.normal(texture[t[0]]) + surface.normal(texture[t[1]]) + surface.normal(texture[t[2]]);
  });
}

TEST(PolycubeSurface, ProjectsPointsNearTheSurfaceOntoItAndLeavesItsPointsAlone) {
  const Polycube ell(std::vector<Vec3i>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const PolycubeSurface surface(ell);
  EXPECT_EQ(surface.area(), 14.0);
  const TriangleMesh mesh = refinedSurface(ell);
  for (const Vec3f& x : mesh.positions) {
    const std::optional<Vec3d> q = surface.project(Vec3d(x));
    ASSERT_TRUE(q);
    EXPECT_LT(glm::length(*q - Vec3d(x)), 1e-12);
    EXPECT_TRUE(surface.lut().locate(*q));
  }
  EXPECT_EQ(surface.normal(Vec3d(1.5, 0.5, 0.0)), Vec3d(0, 0, -1));
  EXPECT_EQ(surface.normal(Vec3d(1.5, 1.0, 0.5)), Vec3d(0, 1, 0));  // the L's inner wall
  EXPECT_EQ(surface.normal(Vec3d(0.3, 0.6, 1.0)), Vec3d(0, 0, 1));
  // Where the surface is flat around a vertex (case 4a) P is orthogonal: a point pushed off along
  // the normal comes back to where it was. Elsewhere P is central, and only lands on the surface.
  const PolycubeSurface slab(Polycube(std::vector<Vec3i>{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0},
                                                         {2, 1, 0}, {0, 2, 0}, {1, 2, 0}, {2, 2, 0}}));
  const Vec3d top(1.4, 1.6, 1.0);
  ASSERT_EQ(slab.normal(top), Vec3d(0, 0, 1));
  for (double h : {-0.3, -0.1, 0.1, 0.3}) {
    const std::optional<Vec3d> q = slab.project(top + h * slab.normal(top));
    ASSERT_TRUE(q);
    EXPECT_LT(glm::length(*q - top), 1e-12) << h;
  }
  for (double h : {-0.3, 0.3}) {
    const std::optional<Vec3d> q = surface.project(Vec3d(0.3, 0.6, 1.0 + h));
    ASSERT_TRUE(q);
    EXPECT_TRUE(surface.lut().locate(*q));
  }
  // Far from the surface there is nothing to project onto.
  EXPECT_FALSE(surface.project(Vec3d(5, 5, 5)));
  EXPECT_FALSE(surface.project(Vec3d(std::nan(""), 0, 0)));
}

TEST(PolycubeSurface, AcceptsEveryManifoldPolycubeAndProjectsOntoItAtCase6bVertices) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> along(0.0, 1.0), off(-0.3, 0.3);
  int with6b = 0, projected = 0;
  for (Polycube& p : fixtures::randomManifoldPolycubes(40)) {
    const std::vector<Vec3i> saddles = verticesOfCase(p, VertexCase::k6b);
    std::unique_ptr<PolycubeSurface> surface;
    ASSERT_NO_THROW(surface = std::make_unique<PolycubeSurface>(p));
    if (saddles.empty()) continue;
    ++with6b;
    // Points pushed off the squarelets around each saddle vertex come back onto the surface.
    for (const Vec3i& vertex : saddles) {
      const std::uint16_t squarelets = surface->lut().at(vertex).squarelets();
      for (int i = 0; i < 12; ++i) {
        if (!(squarelets & (1u << i))) continue;
        const SquareletBounds box = squareletBounds(i);
        for (int k = 0; k < 20; ++k) {
          Vec3d d(0.0);
          for (int a = 0; a < 3; ++a) d[a] = box.min[a] + (box.max[a] - box.min[a]) * along(random);
          d[box.axis] = off(random);
          const std::optional<Vec3d> q = surface->project(Vec3d(vertex) + d);
          ASSERT_TRUE(q);
          EXPECT_TRUE(surface->lut().locate(*q)) << "vertex " << vertex.x << " " << vertex.y << " " << vertex.z;
          ++projected;
        }
      }
    }
  }
  EXPECT_GT(with6b, 0);
  EXPECT_GT(projected, 100);
}

TEST(Distortion, IsOneForAnIsometryAtAnyScale) {
  const Polycube box(std::vector<Vec3i>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}});
  const PolycubeSurface surface(box);
  TriangleMesh mesh = refinedSurface(box);
  const std::vector<Vec3d> texture(mesh.positions.begin(), mesh.positions.end());
  for (float scale : {1.0f, 3.5f, 1e-3f}) {
    TriangleMesh scaled = mesh;
    for (Vec3f& x : scaled.positions) x *= scale;
    const Distortion d = distortionOf(scaled, texture, surface);
    EXPECT_NEAR(d.area, 1.0, 1e-6) << scale;
    EXPECT_NEAR(d.angle, 1.0, 1e-6) << scale;
    EXPECT_NEAR(d.stretchEfficiency, 1.0, 1e-6) << scale;
    EXPECT_EQ(d.flipped, 0u);
  }
}

TEST(Distortion, MatchesTheClosedFormOfAStretchedCube) {
  // The mesh is the unit cube stretched twice along x, the texture the cube itself. Faces normal
  // to x keep their shape (area 1 each); the other four are 2 x 1 rectangles mapped to squares.
  // Texture area per mesh area: 6 / 10. After scaling by it, s1 s2 is 1 / 0.6 on the x faces
  // and 0.5 / 0.6 on the others; angle distortion (1/2 + 2) / 2 = 1.25 on the others.
  const Polycube cube(std::vector<Vec3i>{{0, 0, 0}});
  const PolycubeSurface surface(cube);
  TriangleMesh mesh = refinedSurface(cube);
  const std::vector<Vec3d> texture(mesh.positions.begin(), mesh.positions.end());
  for (Vec3f& x : mesh.positions) x.x *= 2;
  const Distortion d = distortionOf(mesh, texture, surface);
  const double xFaces = 1 / 0.6, others = 0.5 / 0.6;
  const double area = (2 * 0.5 * (xFaces + 1 / xFaces) + 8 * 0.5 * (others + 1 / others)) / 10;
  EXPECT_NEAR(d.area, area, 1e-9);
  EXPECT_NEAR(d.angle, (2 * 1.0 + 8 * 1.25) / 10, 1e-9);
  // Inverse singular values squared: 0.6 and 0.6 on the x faces, 0.6 * (4, 1) on the others.
  const double l2 = (2 * 0.6 + 8 * 0.5 * (2.4 + 0.6)) / 10;
  EXPECT_NEAR(d.stretchEfficiency, 1 / l2, 1e-9);
  EXPECT_EQ(d.flipped, 0u);
}

TEST(Distortion, CountsFlippedAndFlatTrianglesAndLeavesThemOutOfTheMeans) {
  const Polycube cube(std::vector<Vec3i>{{0, 0, 0}});
  const PolycubeSurface surface(cube);
  const TriangleMesh mesh = refinedSurface(cube);
  std::vector<Vec3d> texture(mesh.positions.begin(), mesh.positions.end());
  // Swapping two corners' texture positions turns their triangle over.
  std::swap(texture[mesh.triangles[0][0]], texture[mesh.triangles[0][1]]);
  Distortion d = distortionOf(mesh, texture, surface);
  EXPECT_GT(d.flipped, 0u);
  EXPECT_TRUE(std::isfinite(d.area) && std::isfinite(d.angle) && std::isfinite(d.stretchEfficiency));
  // Every triangle flat: nothing to average, and no infinity either.
  std::vector<Vec3d> flat(texture.size(), Vec3d(0.5, 0.5, 1));
  d = distortionOf(mesh, flat, surface);
  EXPECT_EQ(d.flipped, mesh.triangles.size());
  EXPECT_EQ(d.area, 0.0);
  EXPECT_EQ(d.angle, 0.0);
}

TEST(Distortion, CountsATriangleBelowItsFlatShareAsFlatThoughItsAreaIsPositive) {
  const Polycube cube(std::vector<Vec3i>{{0, 0, 0}});
  const PolycubeSurface surface(cube);
  const TriangleMesh mesh = refinedSurface(cube);
  std::vector<Vec3d> texture(mesh.positions.begin(), mesh.positions.end());
  ASSERT_EQ(distortionOf(mesh, texture, surface).flipped, 0u);
  // One corner moved almost onto the next: the triangle keeps its orientation and 1e-11 of its
  // area. Its area distortion alone would be about 5e10, so it is flat, not a term of the means.
  const Vec3u t = mesh.triangles[0];
  texture[t[0]] = texture[t[1]] + 1e-11 * (texture[t[0]] - texture[t[1]]);
  const Distortion d = distortionOf(mesh, texture, surface);
  EXPECT_GE(d.flipped, 1u);
  EXPECT_LT(d.area, 10.0);
}

TEST(PolycubeParameterization, KeepsAMeshThatIsThePolycubesOwnSurface) {
  const Polycube ell(std::vector<Vec3i>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}});
  const PolycubeSurface surface(ell);
  const TriangleMesh mesh = refinedSurface(ell);
  for (PolycubeEnergy energy : {PolycubeEnergy::ExtendedMips, PolycubeEnergy::Mips}) {
    const PolycubeParameterization p = parameterize(mesh, surface, {}, {.energy = energy});
    EXPECT_NEAR(p.initial.area, 1.0, 1e-9);
    EXPECT_NEAR(p.initial.angle, 1.0, 1e-9);
    EXPECT_EQ(p.final.flipped, 0u);
    EXPECT_LT(p.final.area, 1.0 + 1e-6);
    EXPECT_LT(p.final.angle, 1.0 + 1e-6);
    for (const Vec3d& u : p.texture) EXPECT_TRUE(surface.lut().locate(u, 1e-9));
  }
}

TEST(PolycubeParameterization, MapsAWarpedSkewPathThroughItsCase6bVertexWithoutFlips) {
  // Four cubes in a skew path: the vertex (1, 1, 1) is of case 6b. The mesh is their surface,
  // refined and warped smoothly, so the optimization moves vertices off the surface around that
  // vertex and case 6b's P brings them back.
  const Polycube path(std::vector<Vec3i>{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}});
  ASSERT_EQ(verticesOfCase(path, VertexCase::k6b), std::vector<Vec3i>{Vec3i(1, 1, 1)});
  const PolycubeSurface surface(path);
  TriangleMesh mesh = refinedSurface(path);
  for (Vec3f& x : mesh.positions)
    x += 0.1f * Vec3f(std::sin(2.3f * x.y + 0.4f), std::sin(1.9f * x.z + 1.1f), std::sin(2.7f * x.x + 2.0f));
  const PolycubeParameterization p = parameterize(mesh, surface, {});
  EXPECT_EQ(p.final.flipped, 0u);
  EXPECT_LT(p.final.area, p.initial.area);
  EXPECT_LT(p.final.area, 1.01);  // measured 1.0004
  EXPECT_LT(p.final.angle, 1.02);  // measured 1.0036
  for (const Vec3d& u : p.texture) EXPECT_TRUE(surface.lut().locate(u, 1e-9));
  std::printf("warped skew path (case 6b at (1, 1, 1)): area %.4f -> %.4f, angle %.4f -> %.4f, %d sweeps\n",
              p.initial.area, p.final.area, p.initial.angle, p.final.angle, p.sweeps);
}

TEST(PolycubeParameterization, MapsASphereOntoACubeWithoutFlipsAndLowersItsDistortion) {
  const TriangleMesh sphere = makeIcosphere(4, 0.45f);
  const PolycubeSurface surface(Polycube(std::vector<Vec3i>{{0, 0, 0}}));
  const PolycubeFrame frame{Vec3d(-0.5), 1.0};  // the cube around the sphere
  for (PolycubeEnergy energy : {PolycubeEnergy::ExtendedMips, PolycubeEnergy::Mips, PolycubeEnergy::MeanValue}) {
    const PolycubeParameterization p = parameterize(sphere, surface, frame, {.energy = energy});
    EXPECT_EQ(p.final.flipped, 0u) << toString(energy);
    EXPECT_LT(p.final.angle, p.initial.angle) << toString(energy);
    for (const Vec3d& u : p.texture) EXPECT_TRUE(surface.lut().locate(u, 1e-9));
    std::printf("sphere on a cube, %s: area %.4f -> %.4f, angle %.4f -> %.4f, stretch efficiency %.3f -> %.3f, "
                "%d sweeps\n", std::string(toString(energy)).c_str(), p.initial.area, p.final.area, p.initial.angle,
                p.final.angle, p.initial.stretchEfficiency, p.final.stretchEfficiency, p.sweeps);
  }
}

TEST(PolycubeParameterization, SeparatesVerticesThatStartOnOnePoint) {
  // The cube's own surface, refined, with one vertex started on its neighbour: their triangles
  // are flat, and a step sized by the distance to the nearest neighbour would be zero for both.
  const Polycube cube(std::vector<Vec3i>{{0, 0, 0}});
  const PolycubeSurface surface(cube);
  const TriangleMesh mesh = refinedSurface(cube);
  const std::vector<Vec3d> lattice(mesh.positions.begin(), mesh.positions.end());
  std::vector<Vec3d> texture = lattice;
  const Vec3u t = mesh.triangles[mesh.triangles.size() / 2];
  texture[t[0]] = texture[t[1]];
  PolycubeParameterizer parameterizer(mesh.triangles, lattice, surface, texture);
  ASSERT_GT(parameterizer.distortion().flipped, 0u);
  parameterizer.optimize({});
  EXPECT_EQ(parameterizer.distortion().flipped, 0u);
  EXPECT_GT(glm::length(parameterizer.texture()[t[0]] - parameterizer.texture()[t[1]]), 0.01);
  EXPECT_LT(parameterizer.distortion().area, 1.01);
}

TEST(PolycubeParameterization, DoesNotDependOnTheThreadCount) {
  const TriangleMesh sphere = makeIcosphere(3, 0.45f);
  const PolycubeSurface surface(Polycube(std::vector<Vec3i>{{0, 0, 0}}));
  const PolycubeFrame frame{Vec3d(-0.5), 1.0};
  std::vector<Vec3d> texture[2];
  for (std::size_t threads : {1u, 2u}) {
    const ThreadLimit limit(threads);
    texture[threads - 1] = parameterize(sphere, surface, frame).texture;
  }
  EXPECT_EQ(texture[0], texture[1]);
}

TEST(PolycubeParameterization, RefusesBadInput) {
  const PolycubeSurface surface(Polycube(std::vector<Vec3i>{{0, 0, 0}}));
  EXPECT_THROW(parameterize(TriangleMesh{}, surface, {}), Error);
  TriangleMesh broken = makeIcosphere(1, 0.4f);
  broken.triangles.push_back({0, 1, std::uint32_t(broken.positions.size())});
  EXPECT_THROW(parameterize(broken, surface, {}), Error);
  EXPECT_THROW(parameterize(makeIcosphere(1, 0.4f), surface, {Vec3d(0.0), 0.0}), Error);
  EXPECT_FALSE(parsePolycubeEnergy("tutte"));
  EXPECT_EQ(parsePolycubeEnergy("extended-mips"), PolycubeEnergy::ExtendedMips);
}

}  // namespace
}  // namespace cellrelief::polycube
