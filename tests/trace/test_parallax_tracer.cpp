// SPDX-License-Identifier: MIT
// Parallax occlusion mapping of relief surfaces against analytic answers: a flat relief and a
// ramp on a rotated, scaled square (the bilinear interpolant of a linear function is that
// function, so the hit is a ray-plane intersection), the walls of the slab, thin bumps at grazing
// angles, and the indirection map's shift of the colour fetch. On a base mesh with UVs: a flat
// mesh at the top of a square's slab traces as that square, rays see front faces only, a ramp
// shadows itself where the light is lower than its slope, and on a sphere every hit lies within
// the relief's depth below the mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include <cellrelief/trace/parallax_tracer.h>

#include "test_support.h"

namespace cellrelief::trace::parallax_tracer_tests {
namespace {

using indirection::ReliefMap;
using indirection::ReliefSurface;

/// A square of side 2 centred near (1, -2, 3), turned about an oblique axis.
ReliefSurface placed(ReliefMap relief) {
  ReliefSurface s;
  s.relief = std::move(relief);
  const Vec3f u = glm::normalize(Vec3f(1, 1, 0)) * 2.0f;
  const Vec3f v = glm::normalize(glm::cross(Vec3f(0.2f, -0.3f, 1.0f), u)) * 2.0f;
  s.uAxisWS = u;
  s.vAxisWS = v;
  s.originWS = Vec3f(1, -2, 3) - 0.5f * (u + v);
  return s;
}

/// H(u, v) = u sampled at texel centres: the interpolant is s * u between the outer centres.
ReliefMap ramp(int size, float scale) {
  std::vector<float> h(std::size_t(size) * size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) h[std::size_t(y) * size + x] = (x + 0.5f) / float(size);
  return ReliefMap(size, size, std::move(h), scale);
}

TEST(ParallaxTracer, AFlatReliefIsAPlaneAtItsHeight) {
  const ReliefSurface s = placed(ReliefMap(8, 8, std::vector<float>(64, 0.5f), 0.2f));
  const ParallaxTracer tracer(s);
  const Vec3f n = s.normalWS();
  const float side = s.sideWS();
  const Vec3f centre = s.originWS + 0.5f * (s.uAxisWS + s.vAxisWS);
  const Vec3f planePoint = centre + n * (0.1f * side);  // height 0.5 * 0.2 tile widths
  int hits = 0;
  for (int i = 0; i < 50; ++i) {
    const Vec3f eye = centre + n * 3.0f + s.uAxisWS * (0.3f * std::sin(float(i))) + s.vAxisWS * (0.02f * float(i) - 0.5f);
    const Vec3f target = centre + s.uAxisWS * (0.4f * std::cos(0.7f * float(i))) + s.vAxisWS * (0.008f * float(i) - 0.2f);
    const Rayf ray(eye, glm::normalize(target - eye));
    const ParallaxHit h = tracer.intersect(ray);
    ASSERT_TRUE(h.valid()) << i;
    EXPECT_EQ(h.face, kReliefFace);
    const float exact = glm::dot(planePoint - eye, n) / glm::dot(ray.direction, n);
    EXPECT_NEAR(h.t, exact, 1e-5f * exact) << i;
    EXPECT_LT(glm::length(tracer.normalAt(h) - n), 1e-5f);
    ++hits;
  }
  EXPECT_EQ(hits, 50);
}

TEST(ParallaxTracer, ARampIsHitWhereTheRayMeetsItsPlane) {
  const int size = 64;
  const float scale = 0.3f;
  const ReliefSurface s = placed(ramp(size, scale));
  const ParallaxTracer tracer(s);
  const float side = s.sideWS();
  const Vec3f U = s.uAxisWS / side, V = s.vAxisWS / side, N = s.normalWS();
  // The plane w = scale * u in the square's frame, in world space: through the origin, with normal
  // N - scale * U (per unit of u and w alike, as the frame is a similarity).
  const Vec3f planeNormal = glm::normalize(N - scale * U);
  double worst = 0;
  for (int i = 0; i < 200; ++i) {
    const float u = 0.1f + 0.8f * float(i % 20) / 19.0f, v = 0.1f + 0.8f * float(i / 20) / 9.0f;
    const float w = scale * u;
    const Vec3f onSurface = s.originWS + side * (u * U + v * V + w * N);
    // From several directions, all from above the ramp's plane (and not grazing it).
    const Vec3f from = onSurface + side * (1.5f * N + (0.6f * std::sin(float(i)) * U) + (0.6f * std::cos(1.3f * float(i)) * V));
    const Rayf ray(from, glm::normalize(onSurface - from));
    const ParallaxHit h = tracer.intersect(ray);
    ASSERT_TRUE(h.valid()) << i;
    const float exact = glm::dot(s.originWS - from, planeNormal) / glm::dot(ray.direction, planeNormal);
    worst = std::max(worst, double(std::abs(h.t - exact)) / side);
    // The shading normal is the plane's.
    EXPECT_LT(glm::length(tracer.normalAt(h) - planeNormal), 1e-4f) << i;
  }
  EXPECT_LT(worst, 2e-5);
}

TEST(ParallaxTracer, TheSlabIsClosedByWallsBelowTheRelief) {
  const ReliefSurface s = placed(ReliefMap(16, 16, std::vector<float>(256, 1.0f), 0.25f));
  const ParallaxTracer tracer(s);
  const float side = s.sideWS();
  const Vec3f U = s.uAxisWS / side, V = s.vAxisWS / side, N = s.normalWS();
  // Level with the middle of the wall at u = 0, heading +u: it meets the wall at distance 1.
  const Vec3f start = s.originWS + side * (-0.5f * U + 0.5f * V + 0.1f * N);
  const ParallaxHit h = tracer.intersect(Rayf(start, U));
  ASSERT_TRUE(h.valid());
  EXPECT_EQ(h.face, kFaceU0);
  EXPECT_NEAR(h.t, 0.5f * side, 1e-5f);
  EXPECT_LT(glm::length(tracer.normalAt(h) + U), 1e-6f);
  // From below, through the bottom.
  const ParallaxHit below = tracer.intersect(Rayf(s.originWS + side * (0.5f * U + 0.5f * V - N), N));
  ASSERT_TRUE(below.valid());
  EXPECT_EQ(below.face, kFaceBottom);
  EXPECT_NEAR(below.t, side, 1e-5f);
  // Above the slab, parallel to it: a miss; and a ray limited before the surface: a miss.
  EXPECT_FALSE(tracer.intersect(Rayf(s.originWS + side * (-0.5f * U + 0.5f * V + 0.3f * N), U)).valid());
  const Vec3f above = s.originWS + side * (0.5f * U + 0.5f * V + 2.0f * N);
  EXPECT_TRUE(tracer.occluded(Rayf(above, -N)));
  EXPECT_FALSE(tracer.occluded(Rayf(above, -N, 0.0f, 1.0f * side)));
}

TEST(ParallaxTracer, TheFloorIsSolidWhereTheReliefIsAtZero) {
  // Heights 0 but for one texel: rays onto the flat part end on the slab's floor, where rounding
  // can put the last linear sample a hair above height 0 (483 of these 4000 rays fell through
  // before the floor counted as solid).
  const int size = 64;
  std::vector<float> h(std::size_t(size) * size, 0.0f);
  h[std::size_t(32) * size + 32] = 1.0f;
  ReliefSurface s;
  s.relief = ReliefMap(size, size, std::move(h), 0.1f);
  s.uAxisWS = Vec3f(0.7f, 0.7f, 0.1f);
  s.vAxisWS = glm::normalize(glm::cross(Vec3f(0.1f, -0.2f, 1.0f), s.uAxisWS)) * glm::length(s.uAxisWS);
  s.originWS = Vec3f(0.3f, -1.7f, 2.1f);
  const ParallaxTracer tracer(s);
  int misses = 0;
  for (int i = 0; i < 4000; ++i) {
    const float u = 0.05f + 0.2f * float((i * 37) % 100) / 100.0f, v = 0.05f + 0.9f * float((i * 53) % 97) / 97.0f;
    const Vec3f target = s.originWS + u * s.uAxisWS + v * s.vAxisWS;
    const Vec3f eye = target + Vec3f(0.3f * std::sin(0.1f * float(i)), 0.5f, 1.0f + 0.3f * std::cos(0.7f * float(i)));
    misses += !tracer.intersect(Rayf(eye, glm::normalize(target - eye))).valid();
  }
  EXPECT_EQ(misses, 0);
}

TEST(ParallaxTracer, AGrazingRayDoesNotStepOverABumpOneTexelWide) {
  // One raised column of texels: a ridge a texel wide across the map.
  const int size = 256;
  std::vector<float> h(std::size_t(size) * size, 0.0f);
  for (int y = 0; y < size; ++y) h[std::size_t(y) * size + 100] = 1.0f;
  ReliefSurface s;
  s.relief = ReliefMap(size, size, std::move(h), 0.05f);
  const ParallaxTracer tracer(s);
  int hits = 0;
  for (int i = 0; i < 64; ++i) {
    // Rays along +u that drop from 0.05 to 0.002 over the tile pass the ridge (0.05 at its crest,
    // u = 100.5 / 256, falling to 0 a texel either side) about 0.031 high: below it for 0.76 texel.
    // Their starts differ, so the linear samples fall at every phase against the ridge.
    const float v = (float(i) + 0.5f) / 64.0f;
    const Vec3f from(-0.01f - 0.0011f * float(i), v, 0.0499f), to(1.01f, v, 0.002f);
    const ParallaxHit hit = tracer.intersect(Rayf(from, glm::normalize(to - from)));
    if (hit.valid() && std::abs(hit.uv.x - 100.5f / 256.0f) < 1.0f / 256.0f) ++hits;
  }
  EXPECT_EQ(hits, 64);
}

TEST(ParallaxTracer, TheIndirectionMapShiftsTheColourFetch) {
  ReliefSurface s;
  s.relief = ramp(32, 0.1f);
  s.colors = Image<std::uint8_t>(64, 64, 3);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      s.colors.at(x, y, 0) = std::uint8_t(4 * x);
      s.colors.at(x, y, 1) = std::uint8_t(4 * y);
      s.colors.at(x, y, 2) = 7;
    }
  const ParallaxTracer plain(s);
  ReliefSurface shifted = s;
  shifted.indirection = Image<float>(16, 16, 2);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      shifted.indirection.at(x, y, 0) = 0.25f;
      shifted.indirection.at(x, y, 1) = -0.125f;
    }
  const ParallaxTracer withIndirection(shifted);
  for (int i = 0; i < 20; ++i) {
    ParallaxHit h;
    h.t = 1;
    h.uv = Vec2f(0.3f + 0.02f * float(i), 0.4f + 0.01f * float(i));
    ParallaxHit moved = h;
    moved.uv += Vec2f(0.25f, -0.125f);
    EXPECT_EQ(withIndirection.colorAt(h), plain.colorAt(moved)) << i;
    EXPECT_NE(withIndirection.colorAt(h), plain.colorAt(h)) << i;
  }
  // Without a colour map, the checkerboard's squares move by the same offset.
  s.colors = {};
  shifted.colors = {};
  const ParallaxTracer checkerPlain(s), checkerShifted(shifted);
  ParallaxHit h;
  h.t = 1;
  h.uv = Vec2f(0.51f, 0.52f);
  ParallaxHit moved = h;
  moved.uv += Vec2f(0.25f, -0.125f);
  EXPECT_EQ(checkerShifted.colorAt(h), checkerPlain.colorAt(moved));
}

/// A grid of n x n quads over the square's top plane (height `top` tile widths), UVs as the
/// square's (u, v), so that its frames are the square's.
std::shared_ptr<TriangleMesh> meshOverSquare(const ReliefSurface& square, float top, int n) {
  auto mesh = std::make_shared<TriangleMesh>();
  const Vec3f up = square.normalWS() * (top * square.sideWS());
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      mesh->positions.push_back(square.originWS + up + (float(i) / n) * square.uAxisWS + (float(j) / n) * square.vAxisWS);
  const auto id = [n](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
  const auto uv = [n](int i, int j) { return Vec2f(float(i) / n, float(j) / n); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      mesh->triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh->uvs.insert(mesh->uvs.end(), {uv(i, j), uv(i + 1, j), uv(i + 1, j + 1)});
      mesh->triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      mesh->uvs.insert(mesh->uvs.end(), {uv(i, j), uv(i + 1, j + 1), uv(i, j + 1)});
    }
  return mesh;
}

/// Smooth bumps: 0.5 + 0.25 (sin 6 pi u + cos 4 pi v).
ReliefMap bumps(int size, float scale, Wrap wrap = Wrap::Clamp) {
  std::vector<float> h(std::size_t(size) * size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const float u = (x + 0.5f) / size, v = (y + 0.5f) / size;
      h[std::size_t(y) * size + x] = 0.5f + 0.25f * (std::sin(6 * 3.14159265f * u) + std::cos(4 * 3.14159265f * v));
    }
  return ReliefMap(size, size, std::move(h), scale, wrap);
}

TEST(ParallaxTracer, AFlatMeshAtTheTopOfTheSlabTracesAsTheSquare) {
  const ReliefSurface square = placed(bumps(64, 0.2f));
  const ParallaxTracer squareTracer(square);
  ReliefSurface onMesh = square;
  onMesh.baseMesh = meshOverSquare(square, squareTracer.top(), 3);
  const ParallaxTracer meshTracer(onMesh);
  const float side = square.sideWS();
  const Vec3f U = square.uAxisWS / side, V = square.vAxisWS / side, N = square.normalWS();
  int compared = 0;
  for (int i = 0; i < 400; ++i) {
    // Rays through the top that leave through the floor (the mesh's march always ends there).
    const float u = 0.2f + 0.6f * float(i % 20) / 19.0f, v = 0.2f + 0.6f * float(i / 20) / 19.0f;
    const Vec3f floorPoint = square.originWS + side * (u * U + v * V);
    const Vec3f from = floorPoint + side * (2.0f * N + 0.5f * std::sin(float(i)) * U + 0.5f * std::cos(1.7f * float(i)) * V);
    const Rayf ray(from, glm::normalize(floorPoint - from));
    const ParallaxHit a = squareTracer.intersect(ray), b = meshTracer.intersect(ray);
    ASSERT_TRUE(a.valid() && b.valid()) << i;
    EXPECT_EQ(b.face, kReliefFace);
    EXPECT_NEAR(b.t, a.t, 2e-4f * side) << i;
    EXPECT_LT(glm::length(b.uv - a.uv), 2e-4f) << i;
    EXPECT_NEAR(b.height, a.height, 2e-4f) << i;
    EXPECT_LT(glm::length(meshTracer.normalAt(b) - squareTracer.normalAt(a)), 2e-2f) << i;
    ++compared;
  }
  EXPECT_EQ(compared, 400);
}

TEST(ParallaxTracer, AMeshSurfaceIsOneSided) {
  const ReliefSurface square = placed(bumps(32, 0.2f));
  ReliefSurface onMesh = square;
  onMesh.baseMesh = meshOverSquare(square, 0.2f, 2);
  const ParallaxTracer tracer(onMesh);
  const Vec3f centre = square.originWS + 0.5f * (square.uAxisWS + square.vAxisWS), N = square.normalWS();
  EXPECT_TRUE(tracer.intersect(Rayf(centre + 3.0f * N, -N)).valid());
  EXPECT_TRUE(tracer.occluded(Rayf(centre + 3.0f * N, -N)));
  // From below (or from inside the relief, as a shadow or mirror ray leaves it), the mesh is not there.
  EXPECT_FALSE(tracer.intersect(Rayf(centre - 3.0f * N, N)).valid());
  EXPECT_FALSE(tracer.occluded(Rayf(centre - 0.01f * N, N)));
}

TEST(ParallaxTracer, ARampOnAMeshShadowsItselfWhereTheLightIsBelowItsSlope) {
  // H = 0.3 u: the ramp rises along +u at atan(0.3), about 16.7 degrees.
  const ReliefSurface square = placed(ramp(64, 0.3f));
  const ParallaxTracer squareTracer(square);
  ReliefSurface onMesh = square;
  onMesh.baseMesh = meshOverSquare(square, squareTracer.top(), 2);
  const ParallaxTracer tracer(onMesh);
  const float side = square.sideWS();
  const Vec3f U = square.uAxisWS / side, N = square.normalWS();
  const Vec3f target = square.originWS + side * (0.3f * U + 0.5f * (square.vAxisWS / side));
  const ParallaxHit hit = tracer.intersect(Rayf(target + 2.0f * side * N, -N));
  ASSERT_TRUE(hit.valid());
  ASSERT_NEAR(hit.uv.x, 0.3f, 1e-3f);
  const Vec3f normal = tracer.normalAt(hit);
  const float offset = tracer.surfaceOffset();
  const auto light = [&](float degrees, float towardsU) {
    const float a = degrees * 3.14159265f / 180.0f;
    return glm::normalize(std::cos(a) * towardsU * U + std::sin(a) * N);
  };
  EXPECT_TRUE(tracer.selfShadowed(hit, normal, light(10, 1), offset));    // lower than the ramp ahead
  EXPECT_FALSE(tracer.selfShadowed(hit, normal, light(30, 1), offset));   // higher than it
  EXPECT_FALSE(tracer.selfShadowed(hit, normal, light(10, -1), offset));  // from where it falls away
  EXPECT_TRUE(tracer.selfShadowed(hit, normal, -N, offset));              // from below
  // A square's hits leave shadows to the world ray (occluded()).
  EXPECT_FALSE(squareTracer.selfShadowed(squareTracer.intersect(Rayf(target + 2.0f * side * N, -N)), normal,
                                         light(10, 1), offset));
}

/// A latitude-longitude sphere with UVs (u around, v from pole to pole), the seam's vertices split.
std::shared_ptr<TriangleMesh> uvSphere(float radius, int rings, int segments) {
  auto mesh = std::make_shared<TriangleMesh>();
  for (int j = 0; j <= rings; ++j)
    for (int i = 0; i <= segments; ++i) {
      const float theta = 3.14159265f * float(j) / rings, phi = 2 * 3.14159265f * float(i % segments) / segments;
      mesh->positions.push_back(radius * Vec3f(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  const auto id = [segments](int i, int j) { return std::uint32_t(j * (segments + 1) + i); };
  const auto uv = [&](int i, int j) { return Vec2f(float(i) / segments, 1.0f - float(j) / rings); };
  for (int j = 0; j < rings; ++j)
    for (int i = 0; i < segments; ++i) {
      // Counter-clockwise seen from outside, so the front faces face out.
      if (j > 0) {
        mesh->triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j)});
        mesh->uvs.insert(mesh->uvs.end(), {uv(i, j), uv(i, j + 1), uv(i + 1, j)});
      }
      if (j + 1 < rings) {
        mesh->triangles.push_back({id(i + 1, j), id(i, j + 1), id(i + 1, j + 1)});
        mesh->uvs.insert(mesh->uvs.end(), {uv(i + 1, j), uv(i, j + 1), uv(i + 1, j + 1)});
      }
    }
  return mesh;
}

TEST(ParallaxTracer, OnASphereEveryHitLiesWithinTheReliefBelowTheMesh) {
  ReliefSurface s;
  s.relief = bumps(64, 0.02f, Wrap::Repeat);
  s.baseMesh = uvSphere(1.5f, 24, 48);
  s.uvScale = 2.0f;
  const ParallaxTracer tracer(s);
  const TriangleBvh<float> bvh(s.baseMesh->positions, s.baseMesh->triangles);
  int hits = 0, below = 0;
  for (int i = 0; i < 2000; ++i) {
    const float z = 1.0f - 2.0f * (float(i) + 0.5f) / 2000.0f, phi = 2.39996323f * float(i);
    const Vec3f eye = 5.0f * Vec3f(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
    const Vec3f target(1.6f * std::sin(1.3f * float(i)), 1.6f * std::cos(0.7f * float(i)), 1.6f * std::sin(0.31f * float(i)));
    const Rayf ray(eye, glm::normalize(target - eye));
    const Hitf base = bvh.closestHit(ray, kInvalidId, Faces::Front);
    const ParallaxHit h = tracer.intersect(ray);
    ASSERT_EQ(h.valid(), base.valid()) << i;
    if (!base.valid()) continue;
    ++hits;
    EXPECT_GE(h.t, base.t) << i;
    EXPECT_GE(h.height, -1e-5f) << i;
    EXPECT_LE(h.height, tracer.top() + 1e-6f) << i;
    // At most the relief's depth below the tangent plane, along the ray: top tile widths over the
    // cosine, a tile width being 1 / |rowW| at the hit.
    const float cosine = -glm::dot(ray.direction, glm::normalize(h.frame.rowW));
    if (cosine > 0.05f) {
      EXPECT_LE(h.t - base.t, tracer.top() / glm::length(h.frame.rowW) / cosine * 1.001f + 1e-5f) << i;
      below += h.t > base.t;
    }
    // Inside the sphere where the ray is steep; a grazing ray follows the tangent plane (the
    // classic POM approximation) and may leave the mesh's hull below the silhouette.
    if (cosine > 0.5f) EXPECT_LE(glm::length(ray.at(h.t)), 1.5f + 1e-4f) << i;
  }
  EXPECT_GT(hits, 900);
  EXPECT_GT(below, hits / 2);  // the relief is carved in, not drawn on the mesh
}

TEST(ParallaxTracer, AMeshWithoutUVsIsRefused) {
  ReliefSurface s;
  s.relief = ramp(8, 0.1f);
  auto mesh = uvSphere(1.0f, 6, 8);
  mesh->uvs.clear();
  s.baseMesh = mesh;
  EXPECT_THROW(ParallaxTracer{s}, Error);
  auto flat = uvSphere(1.0f, 6, 8);
  for (Vec2f& uv : flat->uvs) uv = Vec2f(0.5f);  // UVs that cover no area
  s.baseMesh = flat;
  EXPECT_THROW(ParallaxTracer{s}, Error);
  auto nan = uvSphere(1.0f, 6, 8);
  nan->uvs[4].x = NAN;
  s.baseMesh = nan;
  EXPECT_THROW(ParallaxTracer{s}, Error);
}

TEST(ParallaxTracer, ATilingSurfaceRepeatsItsIndirectionMapWithItsTiles) {
  // On a mesh whose UVs span several tiles, (u, v) and (u + 1, v + 2) are the same point of the map.
  ReliefSurface s;
  s.relief = bumps(32, 0.1f, Wrap::Repeat);
  s.colors = Image<std::uint8_t>(16, 16, 3);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) s.colors.at(x, y, 0) = std::uint8_t(16 * x), s.colors.at(x, y, 1) = std::uint8_t(16 * y);
  s.indirection = Image<float>(8, 8, 2);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) s.indirection.at(x, y, 0) = 0.05f * std::sin(float(x)), s.indirection.at(x, y, 1) = 0.04f * float(y % 3);
  const ParallaxTracer tracer(s);
  for (int i = 0; i < 20; ++i) {
    ParallaxHit h;
    h.t = 1;
    h.uv = Vec2f(0.013f + 0.049f * float(i), 0.97f - 0.047f * float(i));
    ParallaxHit far = h;
    far.uv += Vec2f(1.0f, 2.0f);
    EXPECT_LT(glm::length(tracer.colorAt(h) - tracer.colorAt(far)), 1e-4f) << i;
  }
}

TEST(ParallaxTracer, ASurfaceThatIsNotASquareTileIsRefused) {
  ReliefSurface s;
  s.relief = ramp(8, 0.1f);
  s.vAxisWS = Vec3f(0, 2, 0);  // a rectangle
  EXPECT_THROW(ParallaxTracer{s}, Error);
  s.vAxisWS = Vec3f(0.5f, 1, 0);  // not orthogonal
  EXPECT_THROW(ParallaxTracer{s}, Error);
  s.vAxisWS = Vec3f(0, NAN, 0);
  EXPECT_THROW(ParallaxTracer{s}, Error);
  s.vAxisWS = Vec3f(0, 1, 0);
  s.indirection = Image<float>(4, 4, 3);
  EXPECT_THROW(ParallaxTracer{s}, Error);
  s.indirection = Image<float>(4, 4, 2);
  EXPECT_NO_THROW(ParallaxTracer{s});
}

}  // namespace
}  // namespace cellrelief::trace::parallax_tracer_tests
