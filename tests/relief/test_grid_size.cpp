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

/// An icosphere without the triangles whose centroid lies above z = 0: a hemisphere, whose rim is
/// the equator (2 pi long, zig-zagging along the triangles' edges).
TriangleMesh hemisphere() {
  const TriangleMesh sphere = makeIcosphere(4);
  TriangleMesh open = sphere;
  open.normals.clear();
  open.triangles.clear();
  for (const Vec3u& t : sphere.triangles)
    if (sphere.positions[t[0]].z + sphere.positions[t[1]].z + sphere.positions[t[2]].z < 0) open.triangles.push_back(t);
  return open;
}

TEST(RimBand, AnOpenMeshRefinesUntilTheBandAlongItsRimIsSmall) {
  // Seen from the centre, the hemisphere has no occlusion: by the occlusion ratio alone, N = 1.
  const TriangleMesh open = hemisphere();
  const double rim = boundaryLength(open), area = surfaceArea(open);
  EXPECT_GT(rim, 2 * 3.14159);
  EXPECT_LT(rim, 1.3 * 2 * 3.14159);
  EXPECT_EQ(boundaryLength(makeIcosphere(4)), 0.0);
  // With T fixed at 65, each doubling of N halves the sample spacing.
  const GridSizeChoice choice = chooseGridSize(open, {.threshold = 0.01, .maxGridSize = 64, .texels = 65});
  ASSERT_GE(choice.trials.size(), 2u);
  EXPECT_LT(choice.trials.front().occlusionRatio, 0.01);
  // At N = 1 the cube's side (2) holds 64 sample spacings: a band 2 spacings wide along the rim.
  EXPECT_NEAR(choice.trials.front().rimBandRatio, rim * 2 * (2.0 / 64) / area, 1e-6);  // (float bounds)
  for (std::size_t i = 1; i < choice.trials.size(); ++i)  // the band halves
    EXPECT_NEAR(choice.trials[i].rimBandRatio, choice.trials[i - 1].rimBandRatio / 2, 1e-9);
  EXPECT_TRUE(choice.metThreshold);
  EXPECT_LT(choice.trials.back().rimBandRatio, 0.01);
  EXPECT_GE(choice.trials[choice.trials.size() - 2].rimBandRatio, 0.01);
  // A closed mesh has no band.
  for (const GridSizeTrial& t : chooseGridSize(makeIcosphere(4), {}).trials) EXPECT_EQ(t.rimBandRatio, 0.0);
}

TEST(RimBand, TheSearchStopsWhereAFinerGridWouldNotSampleFiner) {
  // Disjoint small triangles in one plane: all boundary, no occlusion. The band stays at its cap;
  // the default T keeps 512 sample spacings across the cube for every N up to 64, so no doubling
  // samples finer and the search stops at N = 1.
  TriangleMesh confetti;
  for (int j = 0; j < 20; ++j)
    for (int i = 0; i < 20; ++i) {
      const auto base = std::uint32_t(confetti.positions.size());
      const float x = i * 0.1f, y = j * 0.1f;
      confetti.positions.push_back(Vec3f(x, y, 0.2f * x));
      confetti.positions.push_back(Vec3f(x + 0.05f, y, 0.2f * (x + 0.05f)));
      confetti.positions.push_back(Vec3f(x, y + 0.05f, 0.2f * x));
      confetti.triangles.push_back({base, base + 1, base + 2});
    }
  const GridSizeChoice byDefault = chooseGridSize(confetti, {.threshold = 0.01, .maxGridSize = 64});
  EXPECT_EQ(byDefault.gridSize, 1);
  EXPECT_EQ(byDefault.trials.size(), 1u);
  EXPECT_FALSE(byDefault.metThreshold);
  EXPECT_GT(byDefault.trials.back().rimBandRatio, 0.01);
  // With T fixed, every doubling samples finer: the search goes on to N_max.
  const GridSizeChoice fixedT = chooseGridSize(confetti, {.threshold = 0.01, .maxGridSize = 32, .texels = 17});
  EXPECT_EQ(fixedT.gridSize, 32);
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
