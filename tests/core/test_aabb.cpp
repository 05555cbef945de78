// SPDX-License-Identifier: MIT
// Ray/box slab test: exact answers on hand-made cases and a property test for shared faces.
#include <random>

#include <gtest/gtest.h>

#include <cellrelief/core/aabb.h>
#include <cellrelief/core/hit.h>

namespace cellrelief {
namespace {

template <class T>
class AabbTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(AabbTest, Scalars);

TYPED_TEST(AabbTest, HitsThroughTheMiddle) {
  using T = TypeParam;
  const Aabb<T> box(Vec3<T>(0), Vec3<T>(1));
  const auto r = intersect(Ray<T>(Vec3<T>(-1, T(0.5), T(0.5)), Vec3<T>(1, 0, 0)), box);
  ASSERT_TRUE(r.hit);
  EXPECT_NEAR(r.t0, 1, 1e-6);
  EXPECT_NEAR(r.t1, 2, 1e-6);
}

TYPED_TEST(AabbTest, MissesBesideTheBox) {
  using T = TypeParam;
  const Aabb<T> box(Vec3<T>(0), Vec3<T>(1));
  EXPECT_FALSE(intersect(Ray<T>(Vec3<T>(-1, T(1.5), T(0.5)), Vec3<T>(1, 0, 0)), box).hit);
  EXPECT_FALSE(intersect(Ray<T>(Vec3<T>(-1, T(0.5), T(0.5)), Vec3<T>(-1, 0, 0)), box).hit);
}

TYPED_TEST(AabbTest, ParallelToASlabIsDecidedByTheOrigin) {
  using T = TypeParam;
  const Aabb<T> box(Vec3<T>(0), Vec3<T>(1));
  // Direction y = z = 0 exactly: 0 * inf would be NaN in a naive test.
  EXPECT_TRUE(intersect(Ray<T>(Vec3<T>(-1, T(0.3), T(0.7)), Vec3<T>(1, 0, 0)), box).hit);
  EXPECT_FALSE(intersect(Ray<T>(Vec3<T>(-1, T(-0.1), T(0.7)), Vec3<T>(1, 0, 0)), box).hit);
  // Negative zero components behave like positive zero.
  EXPECT_TRUE(intersect(Ray<T>(Vec3<T>(-1, T(0.3), T(0.7)), Vec3<T>(1, T(-0.0), T(-0.0))), box).hit);
}

TYPED_TEST(AabbTest, GrazingAFaceAnEdgeOrACornerHits) {
  using T = TypeParam;
  const Aabb<T> box(Vec3<T>(0), Vec3<T>(1));
  // Along the face y = 1, along the edge y = 1, z = 1, and through the corner (1, 1, 1) only.
  EXPECT_TRUE(intersect(Ray<T>(Vec3<T>(-1, 1, T(0.5)), Vec3<T>(1, 0, 0)), box).hit);
  EXPECT_TRUE(intersect(Ray<T>(Vec3<T>(-1, 1, 1), Vec3<T>(1, 0, 0)), box).hit);
  const auto corner = intersect(Ray<T>(Vec3<T>(2, 2, 0), Vec3<T>(-1, -1, 1)), box);
  ASSERT_TRUE(corner.hit);
  EXPECT_NEAR(corner.t0, 1, 1e-6);
}

TYPED_TEST(AabbTest, RayStartingOnOrInsideTheBox) {
  using T = TypeParam;
  const Aabb<T> box(Vec3<T>(0), Vec3<T>(1));
  const auto onFace = intersect(Ray<T>(Vec3<T>(0, T(0.5), T(0.5)), Vec3<T>(1, 0, 0)), box);
  ASSERT_TRUE(onFace.hit);
  EXPECT_EQ(onFace.t0, T(0));
  const auto leaving = intersect(Ray<T>(Vec3<T>(0, T(0.5), T(0.5)), Vec3<T>(-1, 0, 0)), box);
  ASSERT_TRUE(leaving.hit);  // touches the face at t = 0 and leaves
  EXPECT_EQ(leaving.t0, T(0));
  EXPECT_EQ(leaving.t1, T(0));
  const auto inside = intersect(Ray<T>(Vec3<T>(T(0.5)), Vec3<T>(0, 0, 1)), box);
  ASSERT_TRUE(inside.hit);
  EXPECT_EQ(inside.t0, T(0));
  EXPECT_NEAR(inside.t1, 0.5, 1e-6);
}

TYPED_TEST(AabbTest, IntervalIsClippedToTheRay) {
  using T = TypeParam;
  const Aabb<T> box(Vec3<T>(0), Vec3<T>(1));
  EXPECT_FALSE(intersect(Ray<T>(Vec3<T>(-1, T(0.5), T(0.5)), Vec3<T>(1, 0, 0), 0, T(0.9)), box).hit);
  const auto r = intersect(Ray<T>(Vec3<T>(-1, T(0.5), T(0.5)), Vec3<T>(1, 0, 0), T(1.5), 10), box);
  ASSERT_TRUE(r.hit);
  EXPECT_EQ(r.t0, T(1.5));
}

// Neighbouring cells of a grid share faces: a ray that leaves one cell must enter the next without
// a gap, whatever rounding does. This is what lets a traversal step from cell to cell.
TYPED_TEST(AabbTest, NoGapBetweenBoxesSharingAFace) {
  using T = TypeParam;
  std::mt19937 rng(42);
  std::uniform_real_distribution<T> u(T(-1), T(1));
  const T split = T(0.1);  // not a power of two: the shared face is not exactly representable
  const Aabb<T> left(Vec3<T>(-1), Vec3<T>(split, 1, 1));
  const Aabb<T> right(Vec3<T>(split, -1, -1), Vec3<T>(1));
  int crossings = 0;
  for (int i = 0; i < 100000; ++i) {
    const Vec3<T> a(-1, u(rng), u(rng)), b(1, u(rng), u(rng));
    const Ray<T> ray(a + (b - a) * T(-0.5), b - a);
    const auto l = intersect(ray, left), r = intersect(ray, right);
    if (!l.hit || !r.hit) continue;
    ++crossings;
    ASSERT_GE(l.t1, r.t0) << "gap between cells for ray " << i;
  }
  EXPECT_GT(crossings, 50000);
}

TEST(Boxes, BoundingCubeIsACubeAroundTheBox) {
  const Aabbf box(Vec3f(0, 0, 0), Vec3f(2, 1, 0.5f));
  const Aabbf cube = box.boundingCube(0.0f);
  const Vec3f e = cube.extent();
  EXPECT_FLOAT_EQ(e.x, 2);
  EXPECT_FLOAT_EQ(e.y, 2);
  EXPECT_FLOAT_EQ(e.z, 2);
  EXPECT_TRUE(cube.contains(box.min) && cube.contains(box.max));
  EXPECT_TRUE(Aabbf().isEmpty());
  EXPECT_EQ(Aabbf().diagonal(), 0.0f);
}

TEST(Triangles, MollerTrumboreMatchesThePlaneIntersection) {
  Hitd hit;
  const Vec3d p0(0, 0, 2), p1(2, 0, 2), p2(0, 2, 2);
  ASSERT_TRUE(intersectTriangle(Vec3d(0.5, 0.5, 0), Vec3d(0, 0, 1), 0.0, p0, p1, p2, 7, 3, hit));
  EXPECT_DOUBLE_EQ(hit.t, 2.0);
  EXPECT_DOUBLE_EQ(hit.u, 0.25);
  EXPECT_DOUBLE_EQ(hit.v, 0.25);
  EXPECT_EQ(hit.primId, 7u);
  EXPECT_TRUE(hit.valid());
  EXPECT_GT(hit.geometricNormal.z, 0);
  Hitd miss;
  EXPECT_FALSE(intersectTriangle(Vec3d(1.5, 1.5, 0), Vec3d(0, 0, 1), 0.0, p0, p1, p2, 0, 0, miss));
  EXPECT_FALSE(miss.valid());
}

}  // namespace
}  // namespace cellrelief
