// SPDX-License-Identifier: MIT
// The nearest point of a triangle, as barycentric weights, against dense sampling of the
// triangle, including degenerate triangles, and the BVH's nearest triangle against all of them.
#include <random>

#include <gtest/gtest.h>

#include <cellrelief/core/bvh.h>
#include <cellrelief/core/procedural.h>

namespace cellrelief {
namespace {

double sampledDistance2(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  double best = std::numeric_limits<double>::infinity();
  constexpr int kSteps = 200;
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; i + j <= kSteps; ++j) {
      const double u = double(i) / kSteps, v = double(j) / kSteps;
      const Vec3d q = (1 - u - v) * a + u * b + v * c;
      best = std::min(best, glm::dot(p - q, p - q));
    }
  return best;
}

TEST(ClosestPoint, WeightsAreAPointOfTheTriangleNoFartherThanAnySample) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  const auto random = [&] { return Vec3d(coordinate(rng), coordinate(rng), coordinate(rng)); };
  for (int trial = 0; trial < 300; ++trial) {
    Vec3d a = random(), b = random(), c = random();
    if (trial % 10 == 1) c = a + 0.3 * (b - a);  // collinear: a degenerate triangle
    if (trial % 10 == 2) b = c = a;              // a point
    const Vec3d p = 2.0 * random();
    const Vec3d w = closestPointBarycentrics(p, a, b, c);
    EXPECT_GE(glm::min(w.x, glm::min(w.y, w.z)), -1e-12);
    EXPECT_NEAR(w.x + w.y + w.z, 1.0, 1e-12);
    const Vec3d q = w.x * a + w.y * b + w.z * c;
    const double d2 = glm::dot(p - q, p - q);
    EXPECT_LE(d2, sampledDistance2(p, a, b, c) + 1e-12) << trial;
    EXPECT_NEAR(pointTriangleDistance2(p, a, b, c), d2, 1e-12);
  }
}

TEST(ClosestPoint, TheBvhFindsTheNearestTriangle) {
  const TriangleMesh sphere = makeIcosphere(3, 1.0f);
  const std::vector<Vec3d> positions(sphere.positions.begin(), sphere.positions.end());
  const TriangleBvh<double> bvh(positions, sphere.triangles);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> coordinate(-1.5, 1.5);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3d p(coordinate(rng), coordinate(rng), coordinate(rng));
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3u& t : sphere.triangles)
      best = std::min(best, pointTriangleDistance2(p, positions[t[0]], positions[t[1]], positions[t[2]]));
    const auto [d2, id] = bvh.closestPoint(p);
    EXPECT_DOUBLE_EQ(d2, best);
    const Vec3u& t = sphere.triangles[id];
    EXPECT_DOUBLE_EQ(pointTriangleDistance2(p, positions[t[0]], positions[t[1]], positions[t[2]]), best);
  }
}

}  // namespace
}  // namespace cellrelief
