// SPDX-License-Identifier: MIT
// The Ceres optimizer: the flat map is the identity, it lowers distortion on real height maps below
// the springs' without flipped cells, steps and noise stay finite and flip-free, and a reused
// solver gives what the function gives and refines a warm start.
#include <gtest/gtest.h>

#include <cellrelief/indirection/ceres_optimizer.h>
#include <cellrelief/indirection/distortion.h>
#include <cellrelief/indirection/springs.h>

#include "indirection/test_support_indirection.h"
#include "test_support.h"

namespace cellrelief {
namespace {

using namespace indirection;

TEST(Ceres, FlatMapGivesTheIdentity) {
  const ReliefMap flat = test::analyticRelief(64, 0.2f, [](float, float) { return 0.5f; });
  CeresOptions o;
  o.gridSize = 32;
  const Grid grid = optimizeCeres(flat, o);
  const Grid id(32);
  for (std::size_t k = 0; k < grid.vertexCount(); ++k) {
    EXPECT_NEAR(grid.u()[k], id.u()[k], 1e-6f);
    EXPECT_NEAR(grid.v()[k], id.v()[k], 1e-6f);
  }
}

TEST(Ceres, LowerDistortionThanTheSpringsOnRealHeightMaps) {
  for (const char* name : {"sponza/lion_bump.png", "sponza/spnza_bricks_a_bump.png"}) {
    const auto path = test::heightmap(name);
    CELLRELIEF_REQUIRE_FILE(path);
    const ReliefMap relief = downsample(loadReliefMap(path, {0.1f}), 128);
    CeresOptions co;
    co.gridSize = 32;
    CeresReport report;
    const Grid c = optimizeCeres(relief, co, {}, &report);
    SpringOptions so;
    so.gridSize = 32;
    const Grid s = relaxSprings(relief, so);
    const Distortion dc = measureDistortion(c, relief), ds = measureDistortion(s, relief);
    const Distortion d0 = measureDistortion(Grid(32), relief);
    std::printf("%s g=32: L2 identity %.4f springs %.4f ceres %.4f (%d iterations)\n", name,
                d0.l2Stretch, ds.l2Stretch, dc.l2Stretch, report.iterations);
    EXPECT_EQ(dc.flippedCells, 0u);
    EXPECT_TRUE(c.isFinite());
    EXPECT_LT(dc.l2Stretch, ds.l2Stretch) << name;
    EXPECT_LT(dc.l2Stretch, d0.l2Stretch) << name;
  }
}

TEST(Ceres, StepsAndNoiseStayFiniteAndFlipFree) {
  for (const auto& [relief, what] :
       {std::pair{test::boxRelief(128, 0.3f), "box"}, std::pair{test::boxRelief(128, 0.3f, true), "well"},
        std::pair{test::noiseRelief(128, 0.3f, 50, 5), "noise"}}) {
    CeresOptions o;
    o.gridSize = test::kSlowBuild ? 32 : 64;  // the sanitizers' build: the same steps on a coarser grid
    const Grid grid = optimizeCeres(relief, o);
    ASSERT_TRUE(grid.isFinite()) << what;
    const Distortion d = measureDistortion(grid, relief);
    EXPECT_EQ(d.flippedCells, 0u) << what;
    EXPECT_LT(d.l2Stretch, measureDistortion(Grid(o.gridSize), relief).l2Stretch) << what;
  }
}

TEST(Ceres, AReusedSolverGivesWhatTheFunctionGives) {
  const ReliefMap relief = test::noiseRelief(64, 0.2f, 6, 11), other = test::noiseRelief(64, 0.3f, 5, 3);
  CeresOptions o;
  o.gridSize = 32;
  o.threads = 1;  // one thread: Ceres' sums in one order, so results compare bitwise
  CeresSolver solver(o);
  const Grid first = solver.solve(relief);
  const std::size_t built = solver.builtLevels();
  const Grid between = solver.solve(other);  // the problems now hold another map's relief
  const Grid again = solver.solve(relief);
  EXPECT_EQ(solver.builtLevels(), built);  // no problem built twice
  const Grid once = optimizeCeres(relief, o);
  EXPECT_EQ(first.u(), once.u());
  EXPECT_EQ(first.v(), once.v());
  EXPECT_EQ(again.u(), once.u());
  EXPECT_EQ(again.v(), once.v());
  EXPECT_NE(between.u(), once.u());
}

TEST(Ceres, AWarmStartRefinesFromItsOwnLevel) {
  const ReliefMap relief = test::noiseRelief(64, 0.25f, 6, 7);
  CeresOptions o;
  o.gridSize = 32;
  o.threads = 1;
  o.maxFinalIterations = 30;  // stop early, so that a second run has something left to do
  CeresSolver solver(o);
  CeresReport cold, warm;
  const Grid first = solver.solve(relief, {}, &cold);
  const Grid refined = solver.solve(relief, first, {}, &warm);
  // Only the last level runs, from where the first solve stopped.
  EXPECT_EQ(warm.iterations, warm.finalIterations);
  EXPECT_NEAR(warm.initialCost, cold.finalCost, 1e-4 * cold.finalCost);  // the grid holds floats
  EXPECT_LE(warm.finalCost, cold.finalCost);
  const Distortion d1 = measureDistortion(first, relief), d2 = measureDistortion(refined, relief);
  EXPECT_EQ(d2.flippedCells, 0u);
  EXPECT_LE(d2.l2Stretch, d1.l2Stretch * (1 + 1e-6));
  // A coarser start is resampled to its level and solved up from there.
  CeresReport fromCoarse;
  const Grid up = solver.solve(relief, Grid(16), {}, &fromCoarse);
  EXPECT_EQ(up.g(), 32);
  EXPECT_GT(fromCoarse.iterations, fromCoarse.finalIterations);
  EXPECT_THROW(solver.solve(relief, Grid(64)), Error);  // finer than the grid
}

TEST(Ceres, BadOptionsAreClearErrors) {
  const ReliefMap relief = test::noiseRelief(16, 0.1f, 3, 1);
  CeresOptions o;
  o.gridSize = 1;
  EXPECT_THROW(optimizeCeres(relief, o), Error);
  o = {};
  o.maxIterations = 0;
  EXPECT_THROW(optimizeCeres(relief, o), Error);
  EXPECT_THROW(CeresSolver{o}, Error);
}

}  // namespace
}  // namespace cellrelief
