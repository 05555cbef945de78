// SPDX-License-Identifier: MIT
// TrianglesInBox (the triangles of one cell, for its projection lines) against the whole mesh's
// TriangleBvh: on segments inside grid cells of a real mesh and a procedural one, on segments
// lying in the planes of an axis-aligned cube's faces (where a plane test with too little slack
// would drop the face), and on segments that leave the box, both queries give the same nearest
// hit, the same any-hit answer, and the same answer when the nearest triangle is skipped.
#include <random>

#include <gtest/gtest.h>

#include <cellrelief/core/bvh.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/io/mesh_io.h>

#include "test_support.h"

namespace cellrelief {
namespace {

/// The unit cube [0, 1]^3 as 12 triangles.
TriangleMesh unitCube() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.positions.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  const unsigned quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.emplace_back(q[0], q[1], q[2]);
    m.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

struct Agreement {
  int segments = 0, hits = 0;             ///< segments tried, of them hitting
  int cellsWithTriangles = 0, local = 0;  ///< and of them, those answered from their own triangles
};

/// Compares the two queries on `perBox` random segments in each cell of an n^3 grid over the mesh
/// that holds triangles (every tenth leaves its cell, every tenth lies on one of its faces), one in
/// each other cell.
Agreement compare(const TriangleMesh& mesh, int n, int perBox, std::uint32_t seed) {
  std::vector<Vec3d> positions(mesh.positions.begin(), mesh.positions.end());
  const TriangleBvh<double> whole(positions, mesh.triangles);
  const Aabbd bounds = Aabbd(Vec3d(mesh.bounds().min), Vec3d(mesh.bounds().max)).boundingCube(0.01);
  const double h = bounds.extent().x / n;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::uniform_int_distribution<int> face(0, 5);
  Agreement got;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3d lo = bounds.min + Vec3d(i, j, k) * h;
        const Aabbd cell(lo, lo + Vec3d(h));
        const TrianglesInBox<double> inBox(whole, cell);
        got.cellsWithTriangles += inBox.triangleCount() > 0;
        got.local += inBox.triangleCount() > 0 &&
                     inBox.triangleCount() <= TrianglesInBox<double>::kMaxTriangles;
        // Cells without triangles: one segment is enough.
        const int segments = inBox.triangleCount() == 0 ? 1 : perBox;
        for (int s = 0; s < segments; ++s) {
          const auto point = [&] { return lo + h * Vec3d(u(random), u(random), u(random)); };
          Vec3d from = point(), to = point();
          if (s % 10 == 9) to = from + 3.0 * (to - from);  // leaves the cell
          if (s % 10 == 8) {
            // Both ends on one of the cell's faces: a grid plane, where the cube's faces lie.
            const int f = face(random), axis = f / 2;
            from[axis] = to[axis] = lo[axis] + (f % 2) * h;
          }
          if (from == to) continue;
          const Rayd ray(from, to - from, 0.0, 1.0);
          const Hitd expected = whole.closestHit(ray), hit = inBox.closestHit(ray);
          ++got.segments;
          got.hits += expected.valid();
          EXPECT_EQ(hit.valid(), expected.valid())
              << "cell " << i << " " << j << " " << k << ", segment " << s;
          EXPECT_EQ(inBox.anyHit(ray), whole.anyHit(ray));
          if (!expected.valid() || !hit.valid()) continue;
          EXPECT_EQ(hit.t, expected.t);
          EXPECT_EQ(inBox.anyHit(ray, expected.primId), whole.anyHit(ray, expected.primId));
        }
      }
  return got;
}

TEST(TrianglesInBox, AgreesWithTheWholeTreeInTheCellsOfARealMesh) {
  const auto path = test::dataDir() / "meshes/medium/stanford-bunny__common-3d-test-models.obj";
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh bunny = io::readMesh(path);
  for (const int n : {4, 16, 48}) {
    const Agreement got = compare(bunny, n, n >= 48 ? 3 : 60, 11 + n);
    std::printf(
        "bunny, N = %d: %d segments, %d hit; %d of the %d cells with triangles answered from "
        "them\n",
        n, got.segments, got.hits, got.local, got.cellsWithTriangles);
    EXPECT_GT(got.hits, got.segments / 50);
    if (n == 48)
      EXPECT_GT(got.local, got.cellsWithTriangles / 2);  // the local path is what is tested
  }
}

TEST(TrianglesInBox, AgreesOnSegmentsInTheFacePlanesOfACube) {
  // The box is the cube itself: its faces and the cube's coincide.
  const TriangleMesh cube = unitCube();
  std::vector<Vec3d> positions(cube.positions.begin(), cube.positions.end());
  const TriangleBvh<double> whole(positions, cube.triangles);
  const TrianglesInBox<double> inBox(whole, Aabbd(Vec3d(0), Vec3d(1)));
  std::mt19937 random(3);
  std::uniform_real_distribution<double> inside(0, 1), around(-0.2, 1.2);
  int hits = 0;
  for (int s = 0; s < 20000; ++s) {
    auto& u = s % 5 == 4 ? around : inside;  // a fifth may leave the box
    Vec3d from(u(random), u(random), u(random)), to(u(random), u(random), u(random));
    const int axis = s % 3;
    from[axis] = to[axis] = (s / 3) % 2;  // in the plane of a face: grazing every triangle there
    if (s % 7 == 0) to[axis] = 0.5;       // from the face plane inwards
    const Rayd ray(from, to - from, 0.0, 1.0);
    const Hitd expected = whole.closestHit(ray), hit = inBox.closestHit(ray);
    hits += expected.valid();
    EXPECT_EQ(hit.valid(), expected.valid()) << s;
    EXPECT_EQ(inBox.anyHit(ray), whole.anyHit(ray)) << s;
    if (expected.valid() && hit.valid()) EXPECT_EQ(hit.t, expected.t) << s;
  }
  EXPECT_GT(hits, 1000);
}

TEST(TrianglesInBox, AgreesFarFromTheOriginAndAtTinyScales) {
  // A displaced torus moved to 1e5 and shrunk to 1e-4: the plane test's slack scales with the
  // coordinates, the cells with the mesh.
  for (const auto& [scale, offset] :
       {std::pair{1e-4, 0.0}, std::pair{1.0, 1e5}, std::pair{1e-3, 1e2}}) {
    TriangleMesh torus = makeDisplacedTorus({.ringSegments = 96, .tubeSegments = 48});
    for (Vec3f& p : torus.positions)
      p = Vec3f(Vec3d(p) * scale + Vec3d(offset, -offset, 0.5 * offset));
    const Agreement got = compare(torus, 16, 20, 5);
    EXPECT_GT(got.hits, got.segments / 20) << scale << " " << offset;
    EXPECT_GT(got.local, got.cellsWithTriangles / 2);
  }
}

}  // namespace
}  // namespace cellrelief
