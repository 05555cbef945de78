// SPDX-License-Identifier: MIT
// Parallax occlusion mapping of relief surfaces against analytic answers: a flat relief and a
// ramp on a rotated, scaled square (the bilinear interpolant of a linear function is that
// function, so the hit is a ray-plane intersection), the walls of the slab, thin bumps at grazing
// angles, and the indirection map's shift of the colour fetch.
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
