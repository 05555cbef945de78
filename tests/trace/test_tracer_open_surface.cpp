// SPDX-License-Identifier: MIT
// Open surfaces: a sphere with a hole cut in it, seen through the hole. Inside and outside are
// undefined near the hole's rim; the cells that hold it are marked (CellRecord::kOpenSurface) and
// the tracer reads no side from an empty projection line there. Rays through the hole must meet
// the inner wall where the exact mesh does, and rays around it the outer surface, with no false
// hit on the cone of lines that pass the rim.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include <cellrelief/core/bvh.h>
#include <cellrelief/core/mesh_topology.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/trace/relief_tracer.h>

#include "past_line_end.h"

namespace cellrelief::trace {
namespace {

/// An icosphere without the triangles whose centroid lies above z = cut: a hole of radius
/// sqrt(1 - cut^2) at the top.
TriangleMesh sphereWithHole(float cut) {
  const TriangleMesh sphere = makeIcosphere(5);
  TriangleMesh open = sphere;
  open.normals.clear();
  open.triangles.clear();
  for (const Vec3u& t : sphere.triangles)
    if ((sphere.positions[t[0]].z + sphere.positions[t[1]].z + sphere.positions[t[2]].z) / 3 < cut)
      open.triangles.push_back(t);
  return open;
}

struct Agreement {
  int rays = 0, agree = 0;  ///< same hit or miss as the mesh, and within `tolerance` in depth
};

/// 4000 rays from above, each aimed at a random point (x, y, z) with |x|, |y| < reach, from
/// directions up to atan(tilt) off the vertical: the exact hit on the mesh against the tracer's.
Agreement raysFromAbove(const TriangleMesh& mesh, const relief::ReliefModel& model, double tolerance,
                        double reach, double z, double tilt, unsigned seed) {
  const MeshBvh exact(mesh);
  const ReliefTracerd tracer(model);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Agreement a;
  for (int i = 0; i < 4000; ++i) {
    const Vec3d target(reach * u(random), reach * u(random), z);
    const Vec3d from = target + glm::normalize(Vec3d(tilt * u(random), tilt * u(random), 1.0)) * 3.0;
    const Rayd ray(from, glm::normalize(target - from));
    const Hitd truth = exact.bvh.closestHit(ray);
    const auto hit = tracer.intersect(ray);
    ++a.rays;
    a.agree += truth.valid() == hit.valid() && (!truth.valid() || std::abs(truth.t - hit.t) < tolerance);
  }
  return a;
}

/// Rays at points of the hole's disc and a little beyond its rim, from above at up to 45 degrees.
Agreement traceThroughTheHole(const TriangleMesh& mesh, const relief::ReliefModel& model, double tolerance) {
  return raysFromAbove(mesh, model, tolerance, 0.8, 0.8, 0.7, 5);
}

TEST(OpenSurface, RaysThroughAHoleMeetTheInnerWallAndNoConeAroundTheRim) {
  const TriangleMesh mesh = sphereWithHole(0.6f);
  ASSERT_GT(analyzeTopology(mesh).boundaryEdges, 0u);
  relief::ReliefModel model = relief::convert(mesh, {.gridSize = 8, .texels = 17});
  std::size_t open = 0;
  for (const relief::CellRecord& r : model.cells) open += r.openSurface();
  // The rim (radius 0.8 at z = 0.6) crosses a ring of cells, not the whole grid.
  EXPECT_GT(open, 4u);
  EXPECT_LT(open, model.cells.size() / 3);
  const double spacing = model.sampleSpacingWS();
  const Agreement marked = traceThroughTheHole(mesh, model, 2 * spacing);
  // The same model with the marks taken off: the side is read from empty lines at the rim too,
  // and carried across every cell face as in a closed model.
  for (relief::CellRecord& r : model.cells) r.packedIjk &= ~relief::CellRecord::kOpenSurface;
  const Agreement unmarked = traceThroughTheHole(mesh, model, 2 * spacing);
  std::printf("open cells %zu of %zu; rays agreeing with the mesh: %d of %d marked, %d unmarked\n", open,
              model.cells.size(), marked.agree, marked.rays, unmarked.agree);
  // Measured: 96.8% marked, 74.5% unmarked. The rest are rays that graze the sheet near the rim
  // or meet the inner wall at a cell whose projection sees it edge-on.
  EXPECT_GE(marked.agree, int(0.95 * marked.rays));
  EXPECT_GT(marked.agree, unmarked.agree + marked.rays / 10);
}

/// A tilted square sheet, z = 0.23 x + 0.11 y over [-1, 1]^2: open, with white space on both
/// sides, so the cells it crosses face it from above and below (planar projections) and it
/// crosses their mid-planes.
TriangleMesh tiltedSheet(int quads) {
  TriangleMesh sheet;
  for (int j = 0; j <= quads; ++j)
    for (int i = 0; i <= quads; ++i) {
      const float x = -1 + 2.0f * i / quads, y = -1 + 2.0f * j / quads;
      sheet.positions.push_back(Vec3f(x, y, 0.23f * x + 0.11f * y));
    }
  for (int j = 0; j < quads; ++j)
    for (int i = 0; i < quads; ++i) {
      const auto v = std::uint32_t(j * (quads + 1) + i), w = v + std::uint32_t(quads + 1);
      sheet.triangles.push_back({v, v + 1, w + 1});
      sheet.triangles.push_back({v, w + 1, w});
    }
  return sheet;
}

/// Rays from above at points of the sheet away from the cells that hold its border (|x|, |y| <
/// 0.7; at N = 8 the border cells begin at 0.75): how many miss it or meet it farther than
/// `tolerance` from the exact hit.
int raysThatMissTheSheet(const TriangleMesh& sheet, const relief::ReliefModel& model, double tolerance) {
  const Agreement a = raysFromAbove(sheet, model, tolerance, 0.7, 0.0, 0.1, 11);
  return a.rays - a.agree;  // every ray meets the sheet
}

TEST(OpenSurface, HitsPastAPlanarMidPlaneCloseTheGapThere) {
  const TriangleMesh sheet = tiltedSheet(40);
  relief::ReliefModel model = relief::convert(sheet, {.gridSize = 8, .texels = 17});
  int planar = 0;
  for (const relief::CellRecord& r : model.cells)
    planar += r.projection<double>().type == projection::ProjectionType::Planar;
  ASSERT_GT(planar, 20);
  const double spacing = model.sampleSpacingWS();
  const int wrong = raysThatMissTheSheet(sheet, model, 2 * spacing);
  // The same model without the hits past the mid-plane (convert.h, kPastLineEndSamples): the
  // texels next to where the sheet crosses it read no surface.
  const std::size_t removed = test::emptySamplesPastLineEnd(model, projection::ProjectionType::Planar);
  const int wrongWithout = raysThatMissTheSheet(sheet, model, 2 * spacing);
  std::printf("planar cells %d; rays missing the sheet: %d of 4000 (%d without the %zu samples past the "
              "mid-plane)\n", planar, wrong, wrongWithout, removed);
  // Measured: 22 of 4000 with, 121 without; 0 and 99 on 2026-12-07, after centred samples and
  // parallel lines past the far face (convert.h). What the 22 were: where the sheet lies in a face
  // shared by two cells (no side is carried across faces in an open model), and where it lies so
  // near the mid-plane that the band between them, the only stretch of the line that reads "beyond
  // the surface" when white space borders both sides of one sheet, is thinner than a search step.
  EXPECT_GT(removed, 0u);
  EXPECT_LE(wrong, 40);
  EXPECT_GT(wrongWithout, 3 * wrong);
}

TEST(OpenSurface, ClosedMeshesMarkNoCell) {
  const relief::ReliefModel model = relief::convert(makeIcosphere(4), {.gridSize = 8, .texels = 17});
  for (const relief::CellRecord& r : model.cells) ASSERT_FALSE(r.openSurface());
  // A soup (every triangle with its own corners, as STL files are) is closed all the same.
  const TriangleMesh sphere = makeIcosphere(3);
  TriangleMesh soup;
  for (const Vec3u& t : sphere.triangles) {
    const auto base = std::uint32_t(soup.positions.size());
    for (int k = 0; k < 3; ++k) soup.positions.push_back(sphere.positions[t[k]]);
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  EXPECT_TRUE(boundaryEdges(soup).empty());
  EXPECT_EQ(boundaryEdges(sphereWithHole(0.6f)).size(), analyzeTopology(sphereWithHole(0.6f)).boundaryEdges);
}

}  // namespace
}  // namespace cellrelief::trace
