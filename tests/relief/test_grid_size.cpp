// SPDX-License-Identifier: MIT
// Occlusion ratio and automatic grid size on shapes whose answers are known.
#include <gtest/gtest.h>

#include <cellrelief/core/procedural.h>
#include <cellrelief/relief/grid_size.h>

namespace cellrelief::relief {
namespace {

TEST(Occlusion, AStarShapedSurfaceHasNoneFromItsCentre) {
  // A sphere seen from its centre (N = 1: one cell, case 6, perspective from the centre).
  const TriangleMesh sphere = makeIcosphere(4);
  const MeshRayQuery query(sphere);
  const cells::CellComplex one = cells::CellComplex::build(sphere, {.gridSize = 1});
  const OcclusionEstimate e = estimateOcclusion(sphere, one, {}, query);
  EXPECT_EQ(e.ratio, 0.0);
  EXPECT_NEAR(e.totalArea, surfaceArea(sphere) / (2.0 * 2.0), 0.01 * e.totalArea);  // sampled
  const GridSizeChoice choice = chooseGridSize(sphere, {});
  EXPECT_EQ(choice.gridSize, 1);
  EXPECT_TRUE(choice.metThreshold);
}

TEST(Occlusion, TorusNeedsFinerCellsAndTheRatioFalls) {
  // From the centre, rays through the hole's inner wall meet the tube twice: about half occluded.
  const TriangleMesh torus = makeTorus(1.0f, 0.35f, 96, 48);
  const MeshRayQuery query(torus);
  const OcclusionEstimate coarse =
      estimateOcclusion(torus, cells::CellComplex::build(torus, {.gridSize = 1}), {}, query);
  EXPECT_GT(coarse.ratio, 0.15);
  EXPECT_LT(coarse.ratio, 0.6);
  const OcclusionEstimate fine =
      estimateOcclusion(torus, cells::CellComplex::build(torus, {.gridSize = 32}), {}, query);
  EXPECT_LT(fine.ratio, 0.02);
  const GridSizeChoice choice = chooseGridSize(torus, {.threshold = 0.01, .maxGridSize = 64});
  ASSERT_GE(choice.trials.size(), 2u);
  EXPECT_GT(choice.gridSize, 1);
  // Every N tried is reported, doubling from 1; the last is the choice.
  for (std::size_t i = 0; i < choice.trials.size(); ++i)
    EXPECT_EQ(choice.trials[i].gridSize, 1 << i);
  EXPECT_EQ(choice.trials.back().gridSize, choice.gridSize);
  EXPECT_LT(choice.trials.back().occlusionRatio, 0.01);
  EXPECT_GT(choice.trials.front().occlusionRatio, choice.trials.back().occlusionRatio);
}

TEST(Occlusion, NMaxStopsTheSearch) {
  const TriangleMesh torus = makeTorus(1.0f, 0.35f, 48, 24);
  // N = 2 splits the torus into octants around the same centre: the ratio does not change yet.
  const GridSizeChoice choice = chooseGridSize(torus, {.threshold = 0.01, .maxGridSize = 2});
  EXPECT_EQ(choice.gridSize, 2);
  EXPECT_FALSE(choice.metThreshold);
  ASSERT_EQ(choice.trials.size(), 2u);  // 1, 2
  EXPECT_NEAR(choice.trials[0].occlusionRatio, choice.trials[1].occlusionRatio, 5e-3);
  EXPECT_THROW(chooseGridSize(torus, {.threshold = 0}), Error);
  EXPECT_THROW(chooseGridSize(torus, {.maxGridSize = 0}), Error);
}

TEST(Bvh, AgreesWithBruteForce) {
  const TriangleMesh torus = makeTorus(1.0f, 0.35f, 40, 20);
  const std::vector<Vec3d> p(torus.positions.begin(), torus.positions.end());
  const TriangleBvh<double> bvh(p, torus.triangles);
  std::uint32_t state = 99;
  auto rnd = [&] { return ((state = state * 1664525u + 1013904223u) >> 8) / double(1 << 24) * 4 - 2; };
  for (int i = 0; i < 2000; ++i) {
    const Rayd ray(Vec3d(rnd(), rnd(), rnd()), Vec3d(rnd(), rnd(), rnd()), 0.0, 1.0);
    Hitd brute;
    brute.t = 1.0;
    for (std::uint32_t f = 0; f < torus.triangles.size(); ++f) {
      const Vec3u& t = torus.triangles[f];
      intersectTriangle(ray.origin, ray.direction, 0.0, p[t[0]], p[t[1]], p[t[2]], f, 0u, brute);
    }
    const Hitd fast = bvh.closestHit(ray);
    ASSERT_EQ(fast.valid(), brute.valid()) << i;
    ASSERT_EQ(bvh.anyHit(ray), brute.valid()) << i;
    if (brute.valid()) {
      EXPECT_EQ(fast.primId, brute.primId);
      EXPECT_DOUBLE_EQ(fast.t, brute.t);
    }
  }
}

}  // namespace
}  // namespace cellrelief::relief
