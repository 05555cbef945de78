// SPDX-License-Identifier: MIT
// Numerical stress for the tracer: degenerate, non-finite and extreme rays never crash, hang or
// report a hit that is not on the model; huge and tiny models behave like the unit one.
#include <gtest/gtest.h>

#include <random>

#include <cellrelief/core/procedural.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/render/camera.h>
#include <cellrelief/trace/relief_tracer.h>

namespace cellrelief::trace {
namespace {

const relief::ReliefModel& sphereModel() {
  static const relief::ReliefModel model = relief::convert(makeIcosphere(5), {.gridSize = 8, .texels = 17});
  return model;
}

template <class Tracer>
void expectOnModelOrMiss(const Tracer& tracer, const typename Tracer::Hit& hit) {
  if (!hit.valid()) return;
  EXPECT_TRUE(std::isfinite(hit.t));
  // Inside the model's grid, up to the rounding of t in float.
  using S = typename Tracer::Scalar;
  Aabb<S> grown = tracer.boundsWS();
  const S margin = S(1e-5) * grown.diagonal();
  grown.min -= Vec3<S>(margin);
  grown.max += Vec3<S>(margin);
  EXPECT_TRUE(grown.contains(Vec3<S>(hit.position)))
      << "t " << hit.t << " at " << hit.position.x << " " << hit.position.y << " " << hit.position.z;
}

TEST(ReliefTracerStress, DegenerateAndNonFiniteRaysMissCleanly) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (bool skip : {false, true}) {
    const ReliefTracerf tracer(sphereModel(), {.skipEmptySpace = skip});
    const Rayf rays[] = {
        Rayf(Vec3f(0, 0, -3), Vec3f(0)),                 // no direction
        Rayf(Vec3f(nan, 0, -3), Vec3f(0, 0, 1)),         // NaN origin
        Rayf(Vec3f(0, 0, -3), Vec3f(0, nan, 1)),         // NaN direction
        Rayf(Vec3f(0, 0, -inf), Vec3f(0, 0, 1)),         // infinitely far
        Rayf(Vec3f(0, 0, -3), Vec3f(0, 0, inf)),         // infinite direction
        Rayf(Vec3f(0, 0, -3), Vec3f(0, 0, 1), 5, 4),     // empty interval
        Rayf(Vec3f(0, 0, -3), Vec3f(0, 0, 1), nan, nan)};
    // None of them names a point of the model's surface: every one misses.
    for (std::size_t i = 0; i < std::size(rays); ++i)
      EXPECT_FALSE(tracer.intersect(rays[i]).valid()) << "ray " << i << " skip " << skip;
  }
}

TEST(ReliefTracerStress, DenormalDirectionsAndCameraAlongUpDoNotStall) {
  const ReliefTracerf tracer(sphereModel());
  // Origin on a grid plane, a denormal component: its inverse overflows, and must count as zero.
  const Vec3f o = Vec3f(sphereModel().originWS) + Vec3f(float(sphereModel().cellSizeWS) * 4);
  const auto hit = tracer.intersect(Rayf(Vec3f(-3, o.y, o.z), Vec3f(1, -1e-40f, 0)));
  expectOnModelOrMiss(tracer, hit);
  // A ray whose stored inverse disagrees with its direction is traced by its direction.
  Rayf stale(Vec3f(0.1f, 0.2f, -3), Vec3f(0, 0, 1));
  stale.direction = Vec3f(0, 0, -1);  // set directly, without setDirection()
  EXPECT_FALSE(tracer.intersect(stale).valid());
  const render::Camera up{Vec3d(0, 10, 0), Vec3d(0), Vec3d(0, 1, 0), 40};
  const Rayd centre = up.primaryRay(16, 16, 32, 32);
  EXPECT_TRUE(std::isfinite(centre.direction.x) && std::isfinite(centre.direction.y));
  EXPECT_TRUE(tracer.intersect(Rayf(Vec3f(centre.origin), Vec3f(centre.direction))).valid());
}

TEST(ReliefTracerStress, TinyAndHugeDirectionsAndFarOriginsGiveTheSameHits) {
  const ReliefTracerd tracer(sphereModel());
  const auto reference = tracer.intersect(Rayd(Vec3d(0.1, 0.2, -3), Vec3d(0, 0, 1)));
  ASSERT_TRUE(reference.valid());
  for (double scale : {1e-30, 1e-8, 1e8, 1e30}) {
    const auto hit = tracer.intersect(Rayd(Vec3d(0.1, 0.2, -3), Vec3d(0, 0, scale)));
    ASSERT_TRUE(hit.valid()) << scale;
    EXPECT_NEAR(hit.t * scale, reference.t, 1e-9 * reference.t) << scale;
  }
  const auto far = tracer.intersect(Rayd(Vec3d(0.1, 0.2, -1e12), Vec3d(0, 0, 1)));
  ASSERT_TRUE(far.valid());
  EXPECT_NEAR(far.position.z, reference.position.z, 1e-3);  // 1e12 in double keeps ~1e-4
}

TEST(ReliefTracerStress, ScaledModelsTraceLikeTheUnitOne) {
  const relief::ReliefModel unit = relief::convert(makeIcosphere(5), {.gridSize = 8, .texels = 17});
  const ReliefTracerf unitTracer(unit);
  for (float scale : {1e-4f, 1e4f}) {
    const relief::ReliefModel model =
        relief::convert(makeIcosphere(5, scale), {.gridSize = 8, .texels = 17});
    const ReliefTracerf tracer(model);
    std::mt19937 random(3);
    std::uniform_real_distribution<float> u(-0.7f, 0.7f);
    int agree = 0;
    for (int i = 0; i < 500; ++i) {
      const Vec3f origin(u(random), u(random), -3);
      const auto expected = unitTracer.intersect(Rayf(origin, Vec3f(0, 0, 1)));
      const auto hit = tracer.intersect(Rayf(origin * scale, Vec3f(0, 0, 1)));
      ASSERT_TRUE(expected.valid() && hit.valid()) << scale << " " << i;
      // On the sphere within a sample, and where the unit model's hit is, up to float rounding.
      EXPECT_NEAR(glm::length(hit.position) / scale, 1.0f, 0.03f) << scale << " " << i;
      agree += std::abs(hit.position.z / scale - expected.position.z) < 1e-4f;
    }
    EXPECT_GE(agree, 495) << scale;
  }
}

TEST(ReliefTracerStress, RandomRaysFromEverywhereNeverHitOffTheModel) {
  for (bool skip : {false, true}) {
    const ReliefTracerf tracer(sphereModel(), {.skipEmptySpace = skip});
    std::mt19937 random(11);
    std::normal_distribution<float> g;
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
      const Vec3f origin = Vec3f(g(random), g(random), g(random)) * 1.5f;
      const Vec3f direction(g(random), g(random), g(random));
      const auto hit = tracer.intersect(Rayf(origin, direction));
      expectOnModelOrMiss(tracer, hit);
      if (!hit.valid()) continue;
      ++hits;
      // On the sphere within the representation's error (a sample at N = 8, T = 17 is 0.018).
      EXPECT_NEAR(glm::length(hit.position), 1.0f, 0.03f) << i;
    }
    EXPECT_GT(hits, 2000);
  }
}

}  // namespace
}  // namespace cellrelief::trace
