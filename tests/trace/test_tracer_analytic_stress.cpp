// SPDX-License-Identifier: MIT
// The tracer against analytic answers, on many random rays: a sphere, a torus, a box with
// axis-aligned faces and a thin plate, each converted from a fine tessellation. Rays come from
// outside and from inside, aimed at random points, grazing the surface, and through the grid's
// cell edges and corners. Every hit must be finite and on the surface, and hit or miss must agree
// with the analytic shape wherever the ray clears or enters it by more than the model's tolerance
// (a few sample spacings; closer than that both answers are right). 3e6 rays per shape in the
// release build, 2e5 under the sanitizers; CELLRELIEF_STRESS_RAYS sets another count (the bounds
// below were measured at 1e7, which takes 6 minutes on 2 cores: run it after changing the tracer).
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdlib>
#include <functional>
#include <mutex>
#include <numbers>
#include <random>

#include <tbb/enumerable_thread_specific.h>

#include <cellrelief/core/parallel.h>
#include <cellrelief/core/procedural.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/trace/relief_tracer.h>

#include "test_support.h"

namespace cellrelief::trace {
namespace {

std::size_t raysPerShape() {
  if (const char* n = std::getenv("CELLRELIEF_STRESS_RAYS")) return std::size_t(std::atof(n));
  return test::kSlowBuild ? 200000 : 3000000;  // sanitizers and Debug: about 50 times slower
}

/// An analytic shape: signed distance (negative inside; exact or a lower bound near the surface)
/// and the exact hit/miss of a ray with the clearance that makes it robust.
struct Shape {
  std::string name;
  TriangleMesh mesh;
  std::function<double(const Vec3d&)> distance;
};

/// The signed distance of the nearest approach along the segment [t0, t1] of the ray: negative
/// when the ray enters the shape. Sampled densely and refined around the minimum (the shapes are
/// smooth or convex, so a fine sampling brackets it).
double nearestApproach(const Shape& s, const Rayd& ray, double t0, double t1) {
  constexpr int kSamples = 48;
  double best = std::numeric_limits<double>::infinity(), bestT = t0;
  for (int i = 0; i <= kSamples; ++i) {
    const double t = t0 + (t1 - t0) * i / kSamples;
    const double d = s.distance(ray.origin + t * ray.direction);
    if (d < best) best = d, bestT = t;
  }
  double lo = std::max(t0, bestT - (t1 - t0) / kSamples), hi = std::min(t1, bestT + (t1 - t0) / kSamples);
  for (int k = 0; k < 30; ++k) {  // golden-section refinement
    const double a = hi - 0.618034 * (hi - lo), b = lo + 0.618034 * (hi - lo);
    if (s.distance(ray.origin + a * ray.direction) < s.distance(ray.origin + b * ray.direction)) hi = b;
    else lo = a;
  }
  return std::min(best, s.distance(ray.origin + 0.5 * (lo + hi) * ray.direction));
}

TriangleMesh boxMesh(const Vec3f& lo, const Vec3f& hi, int subdivisions) {
  // Each face a grid of quads, so that the box has as many triangles as a real mesh.
  TriangleMesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
      const auto base = std::uint32_t(m.positions.size());
      for (int j = 0; j <= subdivisions; ++j)
        for (int i = 0; i <= subdivisions; ++i) {
          Vec3f p;
          p[axis] = side ? hi[axis] : lo[axis];
          p[ua] = lo[ua] + (hi[ua] - lo[ua]) * float(i) / float(subdivisions);
          p[va] = lo[va] + (hi[va] - lo[va]) * float(j) / float(subdivisions);
          m.positions.push_back(p);
        }
      const auto at = [&](int i, int j) { return base + std::uint32_t(j * (subdivisions + 1) + i); };
      for (int j = 0; j < subdivisions; ++j)
        for (int i = 0; i < subdivisions; ++i) {
          const std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
          if (side) m.triangles.push_back({a, b, c}), m.triangles.push_back({a, c, d});
          else m.triangles.push_back({a, c, b}), m.triangles.push_back({a, d, c});
        }
    }
  return m;
}

double boxDistance(const Vec3d& p, const Vec3d& lo, const Vec3d& hi) {
  const Vec3d c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  const Vec3d q = glm::abs(p - c) - h;
  return glm::length(glm::max(q, Vec3d(0))) + std::min(std::max({q.x, q.y, q.z}), 0.0);
}

std::vector<Shape> shapes() {
  std::vector<Shape> out;
  out.push_back({"sphere", makeIcosphere(6), [](const Vec3d& p) { return glm::length(p) - 1.0; }});
  out.push_back({"torus", makeTorus(1.0f, 0.35f, 384, 128), [](const Vec3d& p) {
                   return glm::length(Vec2d(std::hypot(p.x, p.y) - 1.0, p.z)) - 0.35;
                 }});
  // Faces a whole number of cells apart on the bounding cube at N = 16: the grid placement moves
  // them off the planes where projection lines end.
  out.push_back({"box", boxMesh({0, 0, 0}, {4, 4, 2}, 16),
                 [](const Vec3d& p) { return boxDistance(p, Vec3d(0, 0, 0), Vec3d(4, 4, 2)); }});
  out.push_back({"plate", boxMesh({-1, -1, -0.01f}, {1, 1, 0.01f}, 32),
                 [](const Vec3d& p) { return boxDistance(p, Vec3d(-1, -1, -0.01), Vec3d(1, 1, 0.01)); }});
  return out;
}

/// The rays of one shape: a mix of the kinds that break tracers.
Rayd randomRay(std::mt19937_64& rng, const Aabbd& bounds, const relief::ReliefModel& model, const Shape& shape,
               std::size_t i) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const Vec3d c = bounds.center();
  const double r = 0.5 * bounds.diagonal();
  auto inBox = [&] { return bounds.min + Vec3d(u(rng), u(rng), u(rng)) * bounds.extent(); };
  auto onSphere = [&](double radius) {
    const double z = 2 * u(rng) - 1, a = 2 * std::numbers::pi * u(rng), s = std::sqrt(1 - z * z);
    return c + radius * Vec3d(s * std::cos(a), s * std::sin(a), z);
  };
  Vec3d origin, target;
  switch (i % 4) {
    case 0:  // from outside at a random point of the bounds
      origin = onSphere(2.5 * r), target = inBox();
      break;
    case 1: {  // grazing: aimed at a point just off the surface, along its tangent plane
      Vec3d p = inBox();
      for (int k = 0; k < 8; ++k) {  // project onto the surface by the distance's gradient
        const double e = 1e-6 * r, d = shape.distance(p);
        const Vec3d g((shape.distance(p + Vec3d(e, 0, 0)) - d) / e, (shape.distance(p + Vec3d(0, e, 0)) - d) / e,
                      (shape.distance(p + Vec3d(0, 0, e)) - d) / e);
        if (glm::length(g) == 0) break;
        p -= d * glm::normalize(g);
      }
      const Vec3d tangent = glm::normalize(glm::cross(p - c + Vec3d(1e-3, 2e-3, 3e-3), onSphere(1.0) - c));
      origin = p - 2.5 * r * tangent, target = p;
      break;
    }
    case 2: {  // through a cell edge or corner of the model's lattice
      const int n = model.gridSize;
      Vec3d lattice(std::floor(u(rng) * (n + 1)), std::floor(u(rng) * (n + 1)), std::floor(u(rng) * (n + 1)));
      if (i % 8 == 2) lattice.z = u(rng) * n;  // an edge, not a corner
      target = model.originWS + lattice * model.cellSizeWS;
      origin = onSphere(2.5 * r);
      break;
    }
    default:  // from inside the bounds, often inside the shape, in a random direction
      origin = inBox(), target = onSphere(2.5 * r);
      break;
  }
  return Rayd(origin, glm::normalize(target - origin), 0.0, 6.0 * r);
}

class AnalyticStress : public testing::TestWithParam<int> {};

TEST_P(AnalyticStress, RandomRaysAgreeWithTheShape) {
  const Shape shape = std::move(shapes()[std::size_t(GetParam())]);
  // The plate needs samples finer than its thickness, so that rays through it are decided.
  const bool plate = shape.name == "plate";
  const relief::ReliefModel model = relief::convert(shape.mesh, {.gridSize = plate ? 32 : 16, .texels = 33});
  const ReliefTracerf tracer(model);
  const Aabbd bounds(model.originWS, model.originWS + Vec3d(model.cellSizeWS * model.gridSize));
  // The model's tolerance: a few sample spacings (and the tessellation's sagitta, far below it).
  const double spacing = model.sampleSpacingWS();
  const double tolerance = 3 * spacing;
  const std::size_t rays = raysPerShape();
  std::atomic<std::size_t> nonFinite{0}, offSurface{0}, decided{0}, falseHits{0}, falseMisses{0}, hits{0};
  std::mutex worstMutex;
  double worst = 0;  // the largest distance of a hit from the surface
  Vec3d worstAt(0);
  constexpr std::size_t kBatch = 4096;
  parallelFor(0, (rays + kBatch - 1) / kBatch, [&](std::size_t batch) {
    std::mt19937_64 rng(0x5eed + batch);
    std::size_t local[6] = {};
    double localWorst = 0;
    Vec3d localWorstAt(0);
    for (std::size_t i = batch * kBatch; i < std::min(rays, (batch + 1) * kBatch); ++i) {
      const Rayd ray = randomRay(rng, bounds, model, shape, i);
      const auto hit = tracer.intersect(Rayf(Vec3f(ray.origin), Vec3f(ray.direction), 0.0f, float(ray.tmax)));
      if (hit.valid()) {
        ++local[5];
        const bool finite = std::isfinite(hit.t) && std::isfinite(hit.position.x) && std::isfinite(hit.position.y) &&
                            std::isfinite(hit.position.z) && std::isfinite(hit.normal.x) &&
                            std::isfinite(hit.normal.y) && std::isfinite(hit.normal.z);
        local[0] += !finite;
        if (finite) {
          const double off = std::abs(shape.distance(Vec3d(hit.position)));
          local[1] += off > tolerance;
          if (off > localWorst) localWorst = off, localWorstAt = Vec3d(hit.position);
        }
      }
      // The analytic answer where it is robust: the ray enters by more than the tolerance, or
      // clears the shape by more than it. Rays starting inside the shape hit it from within.
      const double start = shape.distance(ray.origin);
      if (std::abs(start) <= tolerance) continue;
      const double approach = start < 0 ? -1.0 : nearestApproach(shape, ray, ray.tmin, ray.tmax);
      if (std::abs(approach) <= tolerance) continue;
      ++local[2];
      const bool truth = approach < 0;
      local[3] += hit.valid() && !truth;
      local[4] += !hit.valid() && truth;
    }
    {
      const std::lock_guard lock(worstMutex);
      if (localWorst > worst) worst = localWorst, worstAt = localWorstAt;
    }
    nonFinite += local[0], offSurface += local[1], decided += local[2];
    falseHits += local[3], falseMisses += local[4], hits += local[5];
  }, 1);
  std::printf("%-7s N = %d T = %d: %zu rays, %zu hits, %zu decided: %zu false hits, %zu false misses; "
              "%zu hits off the surface by more than %.2g (3 sample spacings), the farthest %.2f spacings at "
              "(%.3f, %.3f, %.3f)\n",
              shape.name.c_str(), model.gridSize, model.texels, rays, std::size_t(hits), std::size_t(decided),
              std::size_t(falseHits), std::size_t(falseMisses), std::size_t(offSurface), tolerance, worst / spacing,
              worstAt.x, worstAt.y, worstAt.z);
  EXPECT_EQ(nonFinite, 0u);
  EXPECT_GT(hits, rays / 10);
  EXPECT_GT(decided, rays / 2);
  // Bounds from the rates measured at 1e7 rays, with room for the small counts of a short run:
  // the torus gives 3 false hits, the plate 48 false misses (rays through a plate thinner than a
  // cell), the box 57 hits up to 21 spacings inside it near its corners (corner cells); these are
  // known defects of the tracer (issue 13), and the bounds tighten when they are fixed.
  EXPECT_LE(double(falseHits + falseMisses), 1e-5 * double(decided) + 5);
  EXPECT_LE(double(offSurface), 3e-5 * double(hits) + 5);
}

INSTANTIATE_TEST_SUITE_P(Shapes, AnalyticStress, testing::Range(0, 4), [](const auto& shapeInfo) {
  return std::string(std::array{"Sphere", "Torus", "Box", "Plate"}[std::size_t(shapeInfo.param)]);
});

}  // namespace
}  // namespace cellrelief::trace
