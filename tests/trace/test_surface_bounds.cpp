// SPDX-License-Identifier: MIT
// The surface's box (relief/surface_bounds.h), which every tracer clips rays to in place of the
// grid's cube: on real meshes and every projection type it hugs the mesh, and nowhere between it
// and the cube does the relief's field read "inside", so clipping loses no crossing.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <utility>
#include <string>
#include <vector>

#include <cellrelief/core/procedural.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/relief/surface_bounds.h>
#include <cellrelief/trace/relief_tracer.h>

#include "test_support.h"

namespace cellrelief::trace {
namespace {

struct Case {
  std::string file;
  int gridSize, texels;
};

// Fertility at N = 1 is one perspective cell; at N = 8, and the bunny (open) at 16, parallel,
// planar and axial cells too; the armadillo at 32 has interior cells (case 0).
const Case kCases[] = {{"meshes/small/fertility_9k__libigl-tutorial-data.off", 1, 33},
                       {"meshes/small/fertility_9k__libigl-tutorial-data.off", 8, 9},
                       {"meshes/medium/stanford-bunny__common-3d-test-models.obj", 16, 9},
                       {"meshes/medium/armadillo__libigl-tutorial-data.obj", 32, 5}};

/// The case's mesh and its model, converted once for all the tests of this file.
struct Loaded {
  TriangleMesh mesh;
  relief::ReliefModel model;
};
const Loaded& load(const Case& c) {
  static std::map<std::pair<std::string, int>, Loaded> cache;
  auto [it, inserted] = cache.try_emplace({c.file, c.gridSize});
  if (inserted) {
    it->second.mesh = io::readMesh(test::dataDir() / c.file);
    it->second.model = relief::convert(it->second.mesh, {.gridSize = c.gridSize, .texels = c.texels});
  }
  return it->second;
}

Aabbd cubeOf(const relief::ReliefModel& model) {
  return Aabbd(model.originWS, model.originWS + Vec3d(model.cellSizeWS * model.gridSize));
}

TEST(SurfaceBounds, HugTheMeshInsideTheCube) {
  for (const Case& c : kCases) {
    CELLRELIEF_REQUIRE_FILE(test::dataDir() / c.file);
    const auto& [mesh, model] = load(c);
    const Aabbd box = relief::surfaceBoundsWS(model), cube = cubeOf(model);
    const Aabbd meshBox(Vec3d(mesh.bounds().min), Vec3d(mesh.bounds().max));
    const double spacing = model.sampleSpacingWS();
    SCOPED_TRACE(c.file + " N = " + std::to_string(model.gridSize));
    const double margin = relief::kSurfaceBoundsMarginSamples * spacing;
    for (int a = 0; a < 3; ++a) {
      EXPECT_GE(box.min[a], cube.min[a]);
      EXPECT_LE(box.max[a], cube.max[a]);
      // The samples lie on the mesh (centring moves them by hundredths of a spacing) and reach
      // its extremes within a spacing; the box adds its margin.
      const double lo = std::max(cube.min[a], meshBox.min[a] - margin);
      const double hi = std::min(cube.max[a], meshBox.max[a] + margin);
      EXPECT_GE(box.min[a], lo - 0.05 * spacing);
      EXPECT_LE(box.min[a], lo + spacing);
      EXPECT_LE(box.max[a], hi + 0.05 * spacing);
      EXPECT_GE(box.max[a], hi - spacing);
    }
    // The cube is the longest side on every axis: the box is smaller on the other two.
    EXPECT_LT(box.extent().x * box.extent().y * box.extent().z,
              0.9 * cube.extent().x * cube.extent().y * cube.extent().z);
  }
}

TEST(SurfaceBounds, TheFieldReadsOutsideEverywhereBetweenTheBoxAndTheCube) {
  std::mt19937 random(7);
  for (const Case& c : kCases) {
    CELLRELIEF_REQUIRE_FILE(test::dataDir() / c.file);
    const relief::ReliefModel& model = load(c).model;
    const ReliefTracerd tracer(model);
    const Aabbd box = relief::surfaceBoundsWS(model), cube = cubeOf(model);
    // Probes in the grey cells the box cuts, in their part outside it.
    std::uniform_real_distribution<double> along(0, 1);
    int cut = 0, probed = 0, inside = 0;
    const int tries = std::max<int>(200, 20000 / int(model.cells.size()));
    for (const relief::CellRecord& r : model.cells) {
      const Vec3d lo = model.toWorld(r.ijk(), Vec3d(0)), hi = model.toWorld(r.ijk(), Vec3d(1));
      if (box.contains(lo) && box.contains(hi)) continue;
      ++cut;
      for (int k = 0; k < tries; ++k) {
        const Vec3d p = lo + Vec3d(along(random), along(random), along(random)) * (hi - lo);
        if (box.contains(p) || !cube.contains(p)) continue;
        const std::optional<double> f = tracer.fieldAt(p);
        if (!f) continue;
        ++probed;
        inside += *f > 0;
      }
    }
    SCOPED_TRACE(c.file + " N = " + std::to_string(model.gridSize));
    EXPECT_GT(cut, 0);
    EXPECT_GT(probed, 20 * cut);  // most of a cut cell lies outside the box
    std::printf("%s N = %d: %d grey cells cut by the box, %d probes outside it\n", c.file.c_str(),
                model.gridSize, cut, probed);
    EXPECT_EQ(inside, 0);
  }
}

// The per-cell reach (relief::CellReach): a segment inside a grey cell that misses its box reads
// one side of the surface all along, as the tracers assume when they take two steps there. A
// planar cell's halves read their own faces (no crossing at the mid-plane), and in a cell with a
// hole's rim an empty line beside one with surface is no crossing: segments there stay in one
// half, and steps to or from an empty line are not counted.
TEST(SurfaceBounds, ASegmentThatMissesItsCellsReachReadsOneSide) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> along(0, 1);
  for (const Case& c : kCases) {
    CELLRELIEF_REQUIRE_FILE(test::dataDir() / c.file);
    const relief::ReliefModel& model = load(c).model;
    const ReliefTracerd tracer(model);
    const std::vector<relief::CellReach> reaches = relief::cellReaches(model);
    const int segmentsPerCell = std::max(20, 4000 / int(model.cells.size()));
    constexpr int kSamples = 96;
    int missed = 0, reached = 0, flips = 0;
    for (std::size_t i = 0; i < model.cells.size(); ++i) {
      const relief::CellRecord& r = model.cells[i];
      const bool planar = r.projectionType == std::uint8_t(projection::ProjectionType::Planar);
      for (int k = 0; k < segmentsPerCell; ++k) {
        Vec3d a(along(random), along(random), along(random)), b(along(random), along(random), along(random));
        if (planar) b[r.faceOrAxis] = a[r.faceOrAxis] < 0.5 ? 0.5 * b[r.faceOrAxis] : 0.5 + 0.5 * b[r.faceOrAxis];
        if (reaches[i].reaches(a, b - a, 0.0, 1.0)) {
          ++reached;
          continue;
        }
        ++missed;
        std::optional<double> previous;
        for (int s = 0; s <= kSamples; ++s) {
          const Vec3d unit = a + (b - a) * (double(s) / kSamples);
          const std::optional<double> f = tracer.fieldAt(model.toWorld(r.ijk(), glm::clamp(unit, 0.001, 0.999)));
          if (!f) continue;
          const bool emptyStep = previous && (std::abs(*f) >= constants::kEmptyField ||
                                              std::abs(*previous) >= constants::kEmptyField);
          if (previous && (*previous > 0) != (*f > 0) && !(r.openSurface() && emptyStep)) ++flips;
          previous = f;
        }
      }
    }
    SCOPED_TRACE(c.file + " N = " + std::to_string(model.gridSize));
    std::printf("%s N = %d: %d segments miss their cell's reach, %d reach it\n", c.file.c_str(), model.gridSize,
                missed, reached);
    EXPECT_GT(missed, c.gridSize == 1 ? 0 : reached / 10);  // the boxes are tighter than their cells
    EXPECT_EQ(flips, 0);
  }
}

TEST(SurfaceBounds, RaysBesideTheBoxMissWithoutAStep) {
  TriangleMesh ellipsoid = makeIcosphere(5);  // the unit sphere flattened to half its height
  for (Vec3f& p : ellipsoid.positions) p.z *= 0.5f;
  const relief::ReliefModel model = relief::convert(ellipsoid, {.gridSize = 1, .texels = 33});
  const ReliefTracerf tracer(model);
  const Aabbd box = relief::surfaceBoundsWS(model);
  EXPECT_EQ(Vec3d(tracer.boundsWS().min), Vec3d(Vec3f(box.min)));
  EXPECT_EQ(Vec3d(tracer.boundsWS().max), Vec3d(Vec3f(box.max)));
  const double spacing = model.sampleSpacingWS();
  EXPECT_NEAR(box.max.z, 0.5 + relief::kSurfaceBoundsMarginSamples * spacing, 0.1 * spacing);
  // Through the cube above the box: no search at all.
  const float above = float(0.5 * (box.max.z + cubeOf(model).max.z));
  const auto miss = tracer.intersect(Rayf(Vec3f(-5, 0, above), Vec3f(1, 0, 0)));
  EXPECT_FALSE(miss.valid());
  EXPECT_EQ(miss.steps, 0u);
  // Through the middle, the ellipsoid is found.
  const auto hit = tracer.intersect(Rayf(Vec3f(0.01f, 0.02f, -5), Vec3f(0, 0, 1)));
  ASSERT_TRUE(hit.valid());
  EXPECT_NEAR(hit.t, 4.5, 5e-3);
  const auto side = tracer.intersect(Rayf(Vec3f(-5, 0.01f, 0.02f), Vec3f(1, 0, 0)));
  ASSERT_TRUE(side.valid());
  EXPECT_NEAR(side.t, 4.0, 5e-3);
}

}  // namespace
}  // namespace cellrelief::trace
