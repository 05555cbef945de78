// SPDX-License-Identifier: MIT
// Ray casting of relief models against analytic answers: a finely tessellated sphere, rays that
// start inside, rays along cell faces, edges and corners, in float and double, with and without
// empty-space skipping.
#include <gtest/gtest.h>

#include <vector>

#include <cellrelief/core/procedural.h>
#include <cellrelief/io/mesh_io.h>
#include <cellrelief/relief/convert.h>
#include <cellrelief/render/camera.h>
#include <cellrelief/trace/relief_tracer.h>

#include "past_line_end.h"
#include "test_support.h"

namespace cellrelief::trace {
namespace {

/// Exact first intersection of a ray with the unit sphere (from outside), or infinity.
double raySphere(const Rayd& ray) {
  const double b = glm::dot(ray.origin, ray.direction), c = glm::dot(ray.origin, ray.origin) - 1.0;
  const double disc = b * b - c;
  if (disc < 0) return std::numeric_limits<double>::infinity();
  return -b - std::sqrt(disc);
}

struct SphereStats {
  int hits = 0, disagreements = 0, badNormals = 0;
  double worst = 0, mean = 0;  ///< |t - exact| over rays that meet the surface at 17+ degrees
  double worstSurface = 0;     ///< distance of the hit point from the sphere, over all hits
  int farHits = 0;             ///< hits more than a quarter of a sample spacing from the sphere
};

template <class Tracer>
SphereStats traceSphere(const Tracer& tracer, const relief::ReliefModel& model, int size) {
  using T = typename Tracer::Scalar;
  const render::Camera camera = render::Camera::framing(Vec3d(0), 1.0, 30, 20);
  const double quarterSample = 0.25 * model.sampleSpacingWS();
  SphereStats s;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const Rayd ray = camera.primaryRay(x, y, size, size);
      const double exact = raySphere(ray);
      const auto hit = tracer.intersect(Ray<T>(Vec3<T>(ray.origin), Vec3<T>(ray.direction)));
      // Rays that graze the silhouette within a sample spacing may go either way.
      const double b = glm::dot(ray.origin, ray.direction);
      const double missDistance = std::sqrt(std::max(0.0, glm::dot(ray.origin, ray.origin) - b * b));
      if (std::abs(missDistance - 1.0) < 2.0 / (model.gridSize * (model.texels - 1.0))) continue;
      if (std::isfinite(exact) != hit.valid()) {
        ++s.disagreements;
        continue;
      }
      if (!hit.valid()) continue;
      ++s.hits;
      // Along a grazing ray a small surface error is a long way in t: t is checked where the ray
      // meets the surface at 17 degrees or more, the hit point's distance from the surface always.
      const double error = std::abs(double(hit.t) - exact);
      const double cosine = std::abs(glm::dot(ray.direction, glm::normalize(ray.at(exact))));
      if (cosine >= 0.3) s.worst = std::max(s.worst, error);
      const double off = std::abs(glm::length(Vec3d(hit.position)) - 1.0);
      s.worstSurface = std::max(s.worstSurface, off);
      s.farHits += off > quarterSample;
      s.mean += error;
      s.badNormals += glm::dot(Vec3d(hit.normal), glm::normalize(Vec3d(hit.position))) < 0.95;
    }
  s.mean /= std::max(s.hits, 1);
  return s;
}

TEST(ReliefTracer, SphereDepthMatchesTheAnalyticIntersection) {
  TriangleMesh sphere = makeIcosphere(7);
  sphere.normals.clear();
  // Each size converts 327,680 triangles: the sanitizers' build leaves out the finest.
  const std::vector<int> sizes = test::kSlowBuild ? std::vector{1, 4, 16} : std::vector{1, 4, 16, 32};
  for (int n : sizes) {
    const relief::ReliefModel model = relief::convert(sphere, {.gridSize = n, .texels = 33});
    for (bool skip : {false, true}) {
      const TraceOptions options{.skipEmptySpace = skip};
      const SphereStats d = traceSphere(ReliefTracerd(model, options), model, 96);
      const SphereStats f = traceSphere(ReliefTracerf(model, options), model, 96);
      std::printf("N = %2d, skip %d: double %d hits, %d disagreements, depth error mean %.2e "
                  "max %.2e, surface %.2e, %d bad normals; float %d disagreements, max %.2e\n",
                  n, skip, d.hits, d.disagreements, d.mean, d.worst, d.worstSurface, d.badNormals,
                  f.disagreements, f.worst);
      EXPECT_GT(d.hits, 96 * 96 / 4);
      EXPECT_LE(d.badNormals, d.hits / 100);
      EXPECT_EQ(d.disagreements, 0) << "N = " << n << " skip " << skip;
      EXPECT_EQ(f.disagreements, 0) << "N = " << n << " skip " << skip;
      // Within the tessellation (1.5e-4 at 20 * 4^7 triangles) plus a fraction of a sample
      // spacing on average and one sample spacing (plus a quarter) at worst: where the surface
      // leaves a cell, the texel cells with an empty corner read as empty, and the crossing is
      // found at the rim or at the cell face instead. Float adds its rounding at a distance of 3.
      const double spacing = model.sampleSpacingWS();
      EXPECT_LT(d.mean, 2e-4 + 0.1 * spacing) << "N = " << n << " skip " << skip;
      // In t, that distance grows as 1 / cosine of the angle to the normal (>= 0.3 here).
      EXPECT_LT(d.worst, 2e-4 + 1.25 * spacing / 0.3) << "N = " << n << " skip " << skip;
      EXPECT_LT(f.worst, 2e-4 + 1.25 * spacing / 0.3 + 5e-6) << "N = " << n << " skip " << skip;
      EXPECT_LT(d.worstSurface, 2e-4 + 1.25 * spacing) << "N = " << n << " skip " << skip;
      EXPECT_LT(f.worstSurface, 2e-4 + 1.25 * spacing + 5e-6) << "N = " << n << " skip " << skip;
    }
  }
}

// The search ends with a secant step in the last bracket (ReliefTracer::secantCrossing): the
// field is nearly linear there, so two bisections place the hit about as well as ten. Without
// the step the hit sits at the bracket's far end, a quarter of a linear step out after two
// bisections: the mean error was 9.4x (N = 1) and 4.4x (N = 4) that of ten here.
TEST(ReliefTracer, TheSecantStepMakesFewBisectionsAsAccurateAsMany) {
  TriangleMesh sphere = makeIcosphere(5);
  sphere.normals.clear();
  for (int n : {1, 4}) {
    const relief::ReliefModel model = relief::convert(sphere, {.gridSize = n, .texels = 33});
    auto meanError = [&](int bisections) {
      const TraceOptions options{.binarySteps = bisections, .skipEmptySpace = false, .skipCentralCells = false};
      return traceSphere(ReliefTracerd(model, options), model, 64).mean;
    };
    const double few = meanError(2), many = meanError(10);
    std::printf("N = %d: mean depth error with 2 bisections %.3e, with 10 %.3e (sample spacing %.3e)\n", n,
                few, many, model.sampleSpacingWS());
    EXPECT_LT(few, 1.25 * many) << "N = " << n;
  }
}

// A parallel cell's lines end at the opposite face. Where the surface leaves the cell through
// it, a line just past the exit is empty, and the texel between it and a filled line read no
// surface: the ray went on into the neighbour, whose projection may see that piece edge-on or
// not at all. Those lines now keep the hit up to kPastLineEndSamples past the face (convert.h).
TEST(ReliefTracer, ParallelLinesLookPastTheOppositeFace) {
  TriangleMesh sphere = makeIcosphere(6);
  sphere.normals.clear();
  relief::ReliefModel model = relief::convert(sphere, {.gridSize = 8, .texels = 17});
  const SphereStats with = traceSphere(ReliefTracerd(model), model, 128);
  // The same model without the hits past the opposite face.
  const std::size_t removed = test::emptySamplesPastLineEnd(model, projection::ProjectionType::Parallel);
  const SphereStats without = traceSphere(ReliefTracerd(model), model, 128);
  const double spacing = model.sampleSpacingWS();
  std::printf("%zu samples past the opposite face; hits farther than a quarter sample from the sphere: %d of "
              "%d (%d of %d without them); worst %.2f samples (%.2f without)\n", removed, with.farHits, with.hits,
              without.farHits, without.hits, with.worstSurface / spacing, without.worstSurface / spacing);
  EXPECT_GT(removed, 0u);
  EXPECT_EQ(with.disagreements, 0);
  EXPECT_LT(4 * with.farHits, without.farHits);
}

TEST(ReliefTracer, RaysThatMissTheGridOrStartInsideAreHandled) {
  const relief::ReliefModel model = relief::convert(makeIcosphere(6), {.gridSize = 4, .texels = 17});
  for (bool skip : {false, true}) {
    const ReliefTracerd tracer(model, {.skipEmptySpace = skip});
    EXPECT_FALSE(tracer.intersect(Rayd(Vec3d(5, 5, 5), Vec3d(1, 0, 0))).valid());
    EXPECT_FALSE(tracer.intersect(Rayd(Vec3d(0, 3, 0), Vec3d(0, 1, 0))).valid());  // pointing away
    // tmax before the surface: no hit.
    EXPECT_FALSE(tracer.intersect(Rayd(Vec3d(0, 0, -3), Vec3d(0, 0, 1), 0.0, 1.9)).valid());
    // From the centre outwards: the ray starts inside the object and leaves through the surface.
    const auto out = tracer.intersect(Rayd(Vec3d(0.01, 0.02, 0.03), Vec3d(0, 0, 1)));
    ASSERT_TRUE(out.valid());
    EXPECT_NEAR(out.position.z, 1.0, 2e-3);
    // Starting inside a grey cell, just outside the surface.
    const auto near = tracer.intersect(Rayd(Vec3d(0, 0, 1.1), Vec3d(0, 0, -1)));
    ASSERT_TRUE(near.valid());
    EXPECT_NEAR(near.t, 0.1, 2e-3);
    // A direction that is not unit length: t is in its units.
    const auto scaled = tracer.intersect(Rayd(Vec3d(0, 0, -3), Vec3d(0, 0, 4)));
    ASSERT_TRUE(scaled.valid());
    EXPECT_NEAR(scaled.t, 0.5, 1e-3);
  }
}

TEST(ReliefTracer, RaysAlongCellFacesEdgesAndCornersFindTheSurface) {
  // N = 4 over the sphere's bounds: grid planes at -1, -0.5, 0, 0.5, 1 (plus the padding the
  // conversion adds); rays lying exactly in the planes x = 0, y = 0, along the edge x = y = 0 and
  // through the grid's corner points.
  const relief::ReliefModel model = relief::convert(makeIcosphere(7), {.gridSize = 4, .texels = 33});
  const Vec3d o = model.originWS;
  const double h = model.cellSizeWS;
  for (bool skip : {false, true}) {
    const ReliefTracerd tracer(model, {.skipEmptySpace = skip});
    int checked = 0;
    for (int i = 0; i <= 4; ++i)
      for (int j = 0; j <= 4; ++j) {
        // Along z through the grid line (x_i, y_j): an edge shared by up to four cells.
        const Vec3d start(o.x + i * h, o.y + j * h, -3);
        const Rayd ray(start, Vec3d(0, 0, 1));
        const double exact = raySphere(ray);
        const auto hit = tracer.intersect(ray);
        const double r = std::hypot(start.x, start.y);
        if (std::abs(r - 1.0) < 0.02) continue;  // silhouette
        ASSERT_EQ(std::isfinite(exact), hit.valid()) << i << " " << j << " skip " << skip;
        if (hit.valid()) EXPECT_NEAR(hit.t, exact, 2e-3);
        ++checked;
        // Diagonal rays through grid corners.
        const Vec3d corner(o.x + i * h, o.y + j * h, o.z + 2 * h);
        const Vec3d dir = glm::normalize(Vec3d(1, 1, 1));
        const Rayd diagonal(corner - 4.0 * dir, dir);
        const double exactDiagonal = raySphere(diagonal);
        const double b = glm::dot(diagonal.origin, dir);
        const double miss = std::sqrt(std::max(0.0, glm::dot(diagonal.origin, diagonal.origin) - b * b));
        if (std::abs(miss - 1.0) < 0.02) continue;
        const auto d = tracer.intersect(diagonal);
        ASSERT_EQ(std::isfinite(exactDiagonal), d.valid()) << "corner " << i << " " << j;
        if (d.valid()) EXPECT_NEAR(d.t, exactDiagonal, 2e-3);
      }
    EXPECT_GT(checked, 15);
  }
}

TEST(ReliefTracer, EmptySpaceSkippingTakesFewerSteps) {
  const relief::ReliefModel model = relief::convert(makeDisplacedSphere({.subdivisions = 6}), {.gridSize = 8, .texels = 33});
  const render::Camera camera = render::Camera::framing(Vec3d(0), 1.2, 30, 20);
  const ReliefTracerd plain(model, {.skipEmptySpace = false}), skipping(model);
  std::uint64_t plainSteps = 0, skipSteps = 0;
  int agree = 0, total = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const Rayd ray = camera.primaryRay(x, y, 64, 64);
      const auto a = plain.intersect(ray), b = skipping.intersect(ray);
      plainSteps += a.steps;
      skipSteps += b.steps;
      if (a.valid() && b.valid()) {
        ++total;
        agree += std::abs(a.t - b.t) < 0.01;
      }
    }
  std::printf("steps at hits: plain %llu, skipping %llu; %d of %d hits agree within 0.01\n",
              (unsigned long long)plainSteps, (unsigned long long)skipSteps, agree, total);
  EXPECT_LT(skipSteps, plainSteps);
  EXPECT_GE(agree, total * 99 / 100);
}

// The skip walk of perspective and axial cells against their sampled search, on a real mesh
// converted at N = 1 (one perspective cell, Igea's default) and at N = 8: fewer steps, the same
// hits. It may find a thin feature the sampled search steps over (the bound is exact, the
// samples are not), never lose one: each extra hit or miss is counted and kept rare.
TEST(ReliefTracer, CentralCellSkippingTakesFewerStepsAndFindsTheSameHits) {
  const auto path = test::dataDir() / "meshes" / "small" / "fertility_9k__libigl-tutorial-data.off";
  CELLRELIEF_REQUIRE_FILE(path);
  const TriangleMesh mesh = io::readMesh(path);
  const Aabbd bounds(Vec3d(mesh.bounds().min), Vec3d(mesh.bounds().max));
  const render::Camera camera = render::Camera::framing(bounds.center(), 0.5 * bounds.diagonal(), 35, 20);
  for (int n : {1, 8}) {
    const relief::ReliefModel model = relief::convert(mesh, {.gridSize = n, .texels = 33});
    const ReliefTracerf sampled(model, {.skipCentralCells = false}), skipping(model);
    std::uint64_t sampledSteps = 0, skipSteps = 0;
    int both = 0, agree = 0, onlySampled = 0, onlySkipping = 0;
    const double spacing = model.sampleSpacingWS();
    for (int y = 0; y < 96; ++y)
      for (int x = 0; x < 96; ++x) {
        const Rayd r = camera.primaryRay(x, y, 96, 96);
        const Rayf ray(Vec3f(r.origin), Vec3f(r.direction));
        const auto a = sampled.intersect(ray), b = skipping.intersect(ray);
        sampledSteps += a.steps;
        skipSteps += b.steps;
        onlySampled += a.valid() && !b.valid();
        onlySkipping += b.valid() && !a.valid();
        if (a.valid() && b.valid()) ++both, agree += std::abs(double(a.t) - double(b.t)) < spacing;
      }
    std::printf("N = %d: steps sampled %llu, skipping %llu; %d hits in both, %d within a sample spacing; "
                "hits only sampled %d, only skipping %d\n",
                n, (unsigned long long)sampledSteps, (unsigned long long)skipSteps, both, agree, onlySampled,
                onlySkipping);
    EXPECT_GT(both, 96 * 96 / 8);
    // Both walk only the surface's box (surface_bounds.h), which took from the sampled search the
    // empty space beside the mesh: at N = 1 it took 418 k steps to 122 k, skipping 143 k to 99 k.
    EXPECT_LT(double(skipSteps), 0.9 * double(sampledSteps)) << "N = " << n;
    EXPECT_GE(agree, both * 995 / 1000) << "N = " << n;
    EXPECT_LE(onlySampled, both / 1000) << "N = " << n;
    EXPECT_LE(onlySkipping, both / 200) << "N = " << n;
  }
}

}  // namespace
}  // namespace cellrelief::trace
