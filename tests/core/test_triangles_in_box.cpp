// SPDX-License-Identifier: MIT
// TrianglesInBox (the triangles of one cell, for its projection lines) against the whole mesh's
// TriangleBvh: on segments inside grid cells of a real mesh and a procedural one, on segments
// lying in the planes of an axis-aligned cube's faces (where a plane test with too little slack
// would drop the face), and on segments that leave the box, both queries give the same nearest
// hit, the same any-hit answer, and the same answer when the nearest triangle is skipped. The
// one-descent query of the conversion (closestHitAndNext: the nearest hit and whether the ray
// crosses again past it) gives what the two separate queries give.
#include <random>
#include <string>

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

/// Where a second hit may start past a first at t (the conversion's rule, pastFirstHit).
double pastFirst(double t) { return t * (1 + 1e-9) + 1e-9; }

/// What closestHitAndNext answers, from the two queries it replaces: the nearest hit, then any
/// hit in [pastFirst(t), within).
template <class Surface>
FirstAndNextHit<double> twoQueries(const Surface& surface, const Rayd& ray, double within) {
  FirstAndNextHit<double> out{surface.closestHit(ray), false};
  if (!out.first.valid()) return out;
  Rayd rest = ray;
  rest.tmin = pastFirst(out.first.t);
  rest.tmax = within;
  out.next = rest.tmin < rest.tmax && surface.anyHit(rest);
  return out;
}

template <class Surface>
void expectSameFirstAndNext(const Surface& surface, const Rayd& ray, double within, const std::string& where) {
  const FirstAndNextHit<double> expected = twoQueries(surface, ray, within);
  const FirstAndNextHit<double> got = surface.closestHitAndNext(ray, within, pastFirst);
  ASSERT_EQ(got.first.valid(), expected.first.valid()) << where;
  EXPECT_EQ(got.first.t, expected.first.t) << where;
  EXPECT_EQ(got.next, expected.next) << where;
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
          // The one-descent query, as the conversion asks it: a line's first hit, past its end too.
          const double within = s % 2 ? 1.0 : 0.6;
          expectSameFirstAndNext(whole, ray, within, "whole tree, segment " + std::to_string(s));
          expectSameFirstAndNext(inBox, ray, within, "in the box, segment " + std::to_string(s));
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

/// More hits on one ray than closestHitAndNext records: 24 copies of one square at z = 0.5 (a
/// mesh with duplicated faces), with and without another square at z = 0.8. Rays through them meet
/// the copies first; whether they cross again is then answered by the separate query, exactly.
TEST(ClosestHitAndNext, AgreesWithTwoQueriesWhenARayMeetsMoreHitsThanItRecords) {
  for (const bool secondSheet : {false, true}) {
    TriangleMesh m;
    const auto square = [&](float z) {
      const auto first = std::uint32_t(m.positions.size());
      m.positions.insert(m.positions.end(), {{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 1, z}});
      m.triangles.emplace_back(first, first + 1, first + 2);
      m.triangles.emplace_back(first, first + 2, first + 3);
    };
    for (int copy = 0; copy < 24; ++copy) square(0.5f);
    if (secondSheet) square(0.8f);
    std::vector<Vec3d> positions(m.positions.begin(), m.positions.end());
    const TriangleBvh<double> whole(positions, m.triangles);
    const TrianglesInBox<double> inBox(whole, Aabbd(Vec3d(0), Vec3d(1)));
    ASSERT_LE(inBox.triangleCount(), TrianglesInBox<double>::kMaxTriangles);
    std::mt19937 random(5);
    std::uniform_real_distribution<double> u(0.05, 0.95);
    int crossingAgain = 0;
    for (int s = 0; s < 500; ++s) {
      const Vec3d from(u(random), u(random), 0.01), to(u(random), u(random), 0.99);
      const Rayd ray(from, to - from, 0.0, 1.0);
      const std::string where = "second sheet " + std::to_string(secondSheet) + ", ray " + std::to_string(s);
      expectSameFirstAndNext(whole, ray, 1.0, where);
      expectSameFirstAndNext(inBox, ray, 1.0, where);
      crossingAgain += whole.closestHitAndNext(ray, 1.0, pastFirst).next;
    }
    EXPECT_EQ(crossingAgain, secondSheet ? 500 : 0);
  }
}

}  // namespace
}  // namespace cellrelief
