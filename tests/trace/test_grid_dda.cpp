// SPDX-License-Identifier: MIT
// The grid walk against brute force: every cell a random segment passes through, in order.
#include <gtest/gtest.h>

#include <random>
#include <set>
#include <tuple>

#include <cellrelief/core/aabb.h>
#include <cellrelief/trace/grid_dda.h>

namespace cellrelief::trace {
namespace {

TEST(GridDda, VisitsEveryCellTheSegmentCrossesInOrder) {
  const Vec3d origin(-1.5, 0.25, 2.0);
  const double h = 0.375;
  const int n = 8;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(-0.5, 1.5);  // in grid units: inside and around it
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3d a(u(random), u(random), u(random)), b(u(random), u(random), u(random));
    // Axis-aligned directions now and then: a zero component must not stall the walk.
    Vec3d d = b - a;
    if (trial % 7 == 0) d.y = 0;
    if (trial % 11 == 0) d.x = d.z = 0;
    if (d == Vec3d(0)) continue;
    const Rayd ray(origin + h * n * a, h * n * d, 0.0, 1.0);
    // The segment's part inside the grid.
    const Aabbd box(origin, origin + Vec3d(h * n));
    const RayInterval<double> span = intersect(ray, box);
    if (!span.hit) continue;
    GridDda<double> walk(ray, origin, h, n, span.t0, span.t1);
    std::set<std::tuple<int, int, int>> visited;
    Vec3i previous = walk.cell();
    double tPrevious = walk.tEntry();
    int cells = 0;
    do {
      const Vec3i c = walk.cell();
      ASSERT_TRUE(glm::all(glm::greaterThanEqual(c, Vec3i(0))) && glm::all(glm::lessThan(c, Vec3i(n))));
      if (cells > 0) {  // face neighbours, entered in order
        const Vec3i step = glm::abs(c - previous);
        ASSERT_EQ(step.x + step.y + step.z, 1) << trial;
        ASSERT_GE(walk.tEntry(), tPrevious) << trial;
      }
      ASSERT_LE(walk.tEntry(), walk.tExit() + 1e-12) << trial;
      visited.insert({c.x, c.y, c.z});
      previous = c;
      tPrevious = walk.tEntry();
      ++cells;
      ASSERT_LT(cells, 3 * n + 2) << trial;  // a segment crosses at most 3n cells
    } while (walk.next());
    // Brute force: the cells that hold points of the segment, away from cell boundaries.
    for (int k = 0; k <= 4000; ++k) {
      const double t = span.t0 + (span.t1 - span.t0) * (k + 0.5) / 4001;
      const Vec3d p = (ray.at(t) - origin) / h;
      const Vec3d f = p - glm::floor(p);
      if (glm::any(glm::lessThan(f, Vec3d(1e-6))) || glm::any(glm::greaterThan(f, Vec3d(1 - 1e-6)))) continue;
      const Vec3i c = glm::clamp(Vec3i(glm::floor(p)), Vec3i(0), Vec3i(n - 1));
      ASSERT_TRUE(visited.count({c.x, c.y, c.z})) << trial << " misses cell " << c.x << "," << c.y << "," << c.z;
    }
  }
}

}  // namespace
}  // namespace cellrelief::trace
