// SPDX-License-Identifier: MIT
// Property tests of the four projections for every configuration: points of the cell project onto
// a domain face, never onto an internal one, and unproject(project(p)) == p; degenerate loci
// behave as documented.
#include <random>

#include <gtest/gtest.h>

#include <cellrelief/projection/choice.h>

namespace cellrelief::projection {
namespace {

template <class T>
class ProjectionTest : public ::testing::Test {};
using Scalars = ::testing::Types<float, double>;
TYPED_TEST_SUITE(ProjectionTest, Scalars);

template <class T>
T roundTripTolerance() {
  return std::is_same_v<T, float> ? T(1e-5) : T(1e-12);
}

template <class T>
void checkPoint(const CellProjection<T>& proj, const Vec3<T>& p, std::uint8_t config) {
  const FacePoint<T> fp = proj.project(p);
  ASSERT_GE(fp.face, 0);
  ASSERT_TRUE(proj.domainFaces() & (1u << fp.face))
      << "config " << int(config) << " projects onto non-domain face " << fp.face;
  if (config != 0) ASSERT_TRUE(config & (1u << fp.face)) << "onto an internal face";
  ASSERT_GE(fp.uv.x, T(0));
  ASSERT_LE(fp.uv.x, T(1));
  ASSERT_GE(fp.uv.y, T(0));
  ASSERT_LE(fp.uv.y, T(1));
  ASSERT_GE(fp.distance, T(0));
  ASSERT_LE(fp.distance, std::sqrt(T(3)) + roundTripTolerance<T>());
  const Vec3<T> back = proj.unproject(fp.face, fp.uv, fp.distance);
  ASSERT_LE(glm::length(back - p), roundTripTolerance<T>())
      << "config " << int(config) << " type " << toString(proj.type) << " p (" << p.x << ", "
      << p.y << ", " << p.z << ")";
}

TYPED_TEST(ProjectionTest, EveryConfigurationRoundTripsOntoDomainFaces) {
  using T = TypeParam;
  std::mt19937 rng(7);
  std::uniform_real_distribution<T> u(T(0), T(1));
  for (int config = 0; config < 64; ++config) {
    const CellProjection<T> proj = chooseProjection<T>(std::uint8_t(config));
    EXPECT_EQ(proj.domainFaces(), cells::domainFacesOf(std::uint8_t(config)));
    for (int i = 0; i < 4000; ++i) checkPoint(proj, Vec3<T>(u(rng), u(rng), u(rng)), std::uint8_t(config));
    // Points on the cell's boundary, edges and corners too.
    for (int i = 0; i < 500; ++i) {
      Vec3<T> p(u(rng), u(rng), u(rng));
      p[i % 3] = T(i % 2);
      if (i % 5 == 0) p[(i + 1) % 3] = T((i / 2) % 2);
      checkPoint(proj, p, std::uint8_t(config));
    }
    for (int corner = 0; corner < 8; ++corner)
      checkPoint(proj, Vec3<T>(T(corner & 1), T((corner >> 1) & 1), T((corner >> 2) & 1)),
                 std::uint8_t(config));
  }
}

TYPED_TEST(ProjectionTest, CentroidOptionKeepsRaysOffInternalFaces) {
  using T = TypeParam;
  std::mt19937 rng(11);
  std::uniform_real_distribution<T> u(T(0), T(1));
  for (int config = 0; config < 64; ++config)
    for (int trial = 0; trial < 20; ++trial) {
      const Vec3<T> centroid(u(rng), u(rng), u(rng));
      const CellProjection<T> proj = chooseProjection<T>(
          std::uint8_t(config), CentreOfProjection::SurfaceCentroid, centroid);
      for (int i = 0; i < 200; ++i)
        checkPoint(proj, Vec3<T>(u(rng), u(rng), u(rng)), std::uint8_t(config));
    }
}

TEST(Projections, ParametersFollowTheBaseCaseTable) {
  // Rotated canonical parameters equal the direct rule: perspective centres and axis points are
  // the cell centre moved half a cell towards each internal face.
  for (int config = 1; config < 64; ++config) {
    const CellProjection<double> proj = chooseProjection<double>(std::uint8_t(config));
    Vec3d expected(0.5);
    for (int f = 0; f < 6; ++f)
      if (!(config & (1 << f))) expected += 0.5 * Vec3d(cells::faceNormal(f));
    if (proj.type == ProjectionType::Perspective) {
      EXPECT_EQ(proj.point, expected) << config;
    }
    if (proj.type == ProjectionType::Axial) {
      // The axis runs between the two internal faces it pierces; compare across it.
      for (int a = 0; a < 3; ++a)
        if (a != proj.faceOrAxis) EXPECT_EQ(proj.point[a], expected[a]) << config;
    }
  }
  const auto typeOf = [](cells::BaseCase c) {
    return chooseProjection<float>(cells::kCanonicalConfiguration[int(c)]).type;
  };
  EXPECT_EQ(typeOf(cells::BaseCase::k1), ProjectionType::Parallel);
  EXPECT_EQ(typeOf(cells::BaseCase::k2a), ProjectionType::Planar);
  EXPECT_EQ(typeOf(cells::BaseCase::k2b), ProjectionType::Axial);
  EXPECT_EQ(typeOf(cells::BaseCase::k3a), ProjectionType::Axial);
  EXPECT_EQ(typeOf(cells::BaseCase::k4b), ProjectionType::Axial);
  EXPECT_EQ(typeOf(cells::BaseCase::k3b), ProjectionType::Perspective);
  EXPECT_EQ(typeOf(cells::BaseCase::k4a), ProjectionType::Perspective);
  EXPECT_EQ(typeOf(cells::BaseCase::k5), ProjectionType::Perspective);
}

TEST(Projections, DegenerateLociBehaveAsDocumented) {
  // Planar: a point on the mid-plane goes to the + face, half a cell away.
  const PlanarProjection<double> planar{2};
  const FacePoint<double> onPlane = planar.project(Vec3d(0.3, 0.6, 0.5));
  EXPECT_EQ(onPlane.face, 5);
  EXPECT_DOUBLE_EQ(onPlane.distance, 0.5);
  // Perspective: the centre goes to the centre of the first domain face.
  const PerspectiveProjection<double> persp{Vec3d(0.5, 0.5, 0.0), 0b101111};
  const FacePoint<double> atCentre = persp.project(Vec3d(0.5, 0.5, 0.0));
  EXPECT_EQ(atCentre.face, 0);
  EXPECT_EQ(atCentre.uv, Vec2d(0.5, 0.5));
  EXPECT_EQ(persp.unproject(atCentre.face, atCentre.uv, atCentre.distance), Vec3d(0.5, 0.5, 0.0));
  // Axial: a point on the axis goes along the first domain face's normal.
  const AxialProjection<double> axial{2, Vec3d(0.5, 0.5, 0.5), 0b001111};
  const FacePoint<double> onAxis = axial.project(Vec3d(0.5, 0.5, 0.8));
  EXPECT_EQ(onAxis.face, 0);
  EXPECT_DOUBLE_EQ(onAxis.distance, 0.5);
  EXPECT_EQ(onAxis.uv, Vec2d(0.5, 0.8));
  // Axial projection maps a straight segment to a curve on the face: three points of a segment
  // that crosses the radial direction project to non-collinear face points.
  const Vec3d p0(0.9, 0.4, 0.1), p1(0.8, 0.6, 0.9);
  const FacePoint<double> f0 = axial.project(p0), fm = axial.project(0.5 * (p0 + p1)),
                          f1 = axial.project(p1);
  ASSERT_EQ(f0.face, 1);
  ASSERT_EQ(fm.face, 1);
  ASSERT_EQ(f1.face, 1);
  const Vec2d d1 = fm.uv - f0.uv, d2 = f1.uv - f0.uv;
  EXPECT_GT(std::abs(d1.x * d2.y - d1.y * d2.x), 1e-3);
  // A parallel projection keeps them collinear.
  const ParallelProjection<double> parallel{1};
  const Vec2d e1 = parallel.project(0.5 * (p0 + p1)).uv - parallel.project(p0).uv,
              e2 = parallel.project(p1).uv - parallel.project(p0).uv;
  EXPECT_NEAR(e1.x * e2.y - e1.y * e2.x, 0.0, 1e-12);
}

}  // namespace
}  // namespace cellrelief::projection
