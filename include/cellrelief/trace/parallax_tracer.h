// SPDX-License-Identifier: MIT
/// @file parallax_tracer.h
/// Parallax occlusion mapping of an indirection::ReliefSurface, ray by ray: the CPU reference of the
/// GPU path (relief_trace.comp, "relief surfaces"), which follows it line by line.
///
/// A ray is taken into the square's frame (u, v in [0, 1], w in tile widths along the normal; t
/// stays the world ray's parameter) and clipped to the slab [0, 1]^2 x [0, top], top the highest
/// height. It is sampled linearly from where it enters to where it leaves, two samples per texel it
/// crosses (a ray that passes below a one-texel peak of the bilinear surface for half a texel or
/// more is not stepped over; the cost grows with the path, not with the map), and the first sample
/// below the relief is refined by bisection and a last secant step. A ray that enters
/// a wall of the slab below the relief hits that wall: the slab is a solid block, so a tile seen
/// from the side is closed. The colour is fetched at (u, v) + I(u, v) (the paper's one extra fetch);
/// the normal comes from the normal map, or from the height interpolant where there is none.
///
/// Every map is sampled as ReliefMap samples heights (bilinear between texel centres, clamped or
/// repeated), in float, with the same order of operations as the shader, so that the GPU backends
/// can match this tracer pixel for pixel.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "cellrelief/core/image.h"
#include "cellrelief/core/ray.h"
#include "cellrelief/indirection/relief_surface.h"
#include "cellrelief/trace/trace_options.h"

namespace cellrelief::trace {

namespace parallax_constants {
inline constexpr float kStepsPerTexel = 2.0f;  ///< linear samples per texel the ray's path crosses
inline constexpr int kMinLinearSteps = 8;
inline constexpr int kMaxLinearSteps = 2048;   ///< a bound on a grazing ray's cost (a 2048^2 map's diagonal)
inline constexpr int kRefineSteps = 10;        ///< bisection steps after the first sample below
inline constexpr float kCheckerLight[3] = {0.92f, 0.9f, 0.85f};
inline constexpr float kCheckerDark[3] = {0.2f, 0.35f, 0.6f};
}  // namespace parallax_constants

/// The slab's faces, as ParallaxHit::face: where a ray entered the block below the relief.
enum ParallaxFace : int { kReliefFace = -1, kFaceU0 = 0, kFaceU1, kFaceV0, kFaceV1, kFaceBottom };

struct ParallaxHit {
  float t = std::numeric_limits<float>::infinity();
  Vec2f uv{0.0f};  ///< the square's coordinates of the hit
  int face = kReliefFace;
  std::uint32_t samples = 0;  ///< height samples taken, hit or miss
  bool valid() const { return std::isfinite(t); }
};

namespace detail {
inline float lerp(float a, float b, float t) { return a + (b - a) * t; }

/// The first `channels` channels of `image` at uv, bilinear as ReliefMap samples heights
/// (unsampled channels 0).
template <TexelScalar T>
Vec4f bilinear(const Image<T>& image, Vec2f uv, bool repeat, int channels) {
  int x0, x1, y0, y1;
  float fx, fy, slope;
  indirection::bilinearAxis(uv.x, image.width(), repeat, x0, x1, fx, slope);
  indirection::bilinearAxis(uv.y, image.height(), repeat, y0, y1, fy, slope);
  Vec4f out(0.0f);
  for (int c = 0; c < channels; ++c) {
    const float a = lerp(texelToFloat(image.at(x0, y0, c)), texelToFloat(image.at(x1, y0, c)), fx);
    const float b = lerp(texelToFloat(image.at(x0, y1, c)), texelToFloat(image.at(x1, y1, c)), fx);
    out[c] = lerp(a, b, fy);
  }
  return out;
}
}  // namespace detail

class ParallaxTracer {
 public:
  explicit ParallaxTracer(const indirection::ReliefSurface& surface) : mSurface(&surface) {
    surface.validate();
    const float side = surface.sideWS();
    mOrigin = surface.originWS;
    mAxisU = surface.uAxisWS / side;
    mAxisV = surface.vAxisWS / side;
    mAxisW = surface.normalWS();
    mRowU = mAxisU / side;
    mRowV = mAxisV / side;
    mRowW = mAxisW / side;
    mTop = std::max(surface.relief.maxHeight(), 1e-6f);
  }

  const indirection::ReliefSurface& surface() const { return *mSurface; }
  /// The slab's height in tile widths.
  float top() const { return mTop; }
  /// World to the square's frame: u = dot(p - origin, rowU()), likewise v and the height.
  Vec3f rowU() const { return mRowU; }
  Vec3f rowV() const { return mRowV; }
  Vec3f rowW() const { return mRowW; }

  /// The point's coordinates in the square's frame: (u, v, height in tile widths).
  Vec3f localPoint(const Vec3f& p) const {
    const Vec3f r = p - mOrigin;
    return {glm::dot(r, mRowU), glm::dot(r, mRowV), glm::dot(r, mRowW)};
  }
  Vec3f localDirection(const Vec3f& d) const { return {glm::dot(d, mRowU), glm::dot(d, mRowV), glm::dot(d, mRowW)}; }
  /// A local direction (a normal of the square's frame, which is a similarity) in world space.
  Vec3f worldDirection(const Vec3f& n) const { return n.x * mAxisU + n.y * mAxisV + n.z * mAxisW; }

  /// The first hit of the ray with the relief (or a wall of its slab) within [tmin, tmax].
  ParallaxHit intersect(const Rayf& ray) const { return march(ray, false); }

  /// Whether the ray meets the relief within [tmin, tmax]: the march stops at the first sample
  /// below it, without refining where (shadow rays).
  bool occluded(const Rayf& ray) const { return march(ray, true).valid(); }

  /// The shading normal of a hit (world space, unit, facing up from the relief or out of a wall).
  Vec3f normalAt(const ParallaxHit& hit) const {
    Vec3f n;
    switch (hit.face) {
      case kFaceU0: n = Vec3f(-1, 0, 0); break;
      case kFaceU1: n = Vec3f(1, 0, 0); break;
      case kFaceV0: n = Vec3f(0, -1, 0); break;
      case kFaceV1: n = Vec3f(0, 1, 0); break;
      case kFaceBottom: n = Vec3f(0, 0, -1); break;
      default: n = reliefNormal(hit.uv);
    }
    return worldDirection(n);
  }

  /// The base colour of a hit (0..1): the colour map (or checkerboard) at (u, v) + I(u, v).
  Vec3f colorAt(const ParallaxHit& hit) const {
    using namespace parallax_constants;
    const indirection::ReliefSurface& s = *mSurface;
    Vec2f st = hit.uv;
    if (s.hasIndirection()) {
      const Vec4f offset = detail::bilinear(s.indirection, hit.uv, false, 2);
      st += Vec2f(offset.x, offset.y);
    }
    if (!s.colors.isEmpty()) return Vec3f(detail::bilinear(s.colors, st, repeats(), 3));
    const float n = float(s.checkerSquares);
    const int parity = int(std::floor(st.x * n)) + int(std::floor(st.y * n));
    const float* c = (parity & 1) ? kCheckerLight : kCheckerDark;
    return {c[0], c[1], c[2]};
  }

  /// How far a secondary ray starts off the surface (world units): two texels.
  float surfaceOffset() const { return constants::kSurfaceOffsetSamples * mSurface->sideWS() * mSurface->relief.texelSize(); }

 private:
  bool repeats() const { return mSurface->relief.wrap() == Wrap::Repeat; }

  /// The normal of the relief at uv in the square's frame.
  Vec3f reliefNormal(Vec2f uv) const {
    const indirection::ReliefSurface& s = *mSurface;
    if (!s.normals.isEmpty()) {
      const Vec4f rgb = detail::bilinear(s.normals, uv, repeats(), 3);
      const Vec3f n = Vec3f(rgb) * 2.0f - 1.0f;
      const float length = glm::length(n);
      return length > 1e-6f ? n / length : Vec3f(0, 0, 1);
    }
    const Vec2f g = s.relief.gradientAt(uv.x, uv.y);
    return glm::normalize(Vec3f(-g.x, -g.y, 1.0f));
  }

  /// intersect(); with `anyHit`, the first sample below the relief ends it unrefined.
  ParallaxHit march(const Rayf& ray, bool anyHit) const {
    using namespace parallax_constants;
    ParallaxHit hit;
    const Vec3f o = localPoint(ray.origin), d = localDirection(ray.direction);
    float t0 = ray.tmin, t1 = ray.tmax;
    int entry = -1;  // the face the ray enters the slab through (-1: it starts inside, or the top)
    bool exitsThroughFloor = false;
    if (!clipToSlab(o, d, t0, t1, entry, exitsThroughFloor)) return hit;
    const indirection::ReliefMap& relief = mSurface->relief;
    const auto gap = [&](float t) {  // height above the relief, <= 0 below it
      ++hit.samples;
      const Vec3f p = o + t * d;
      return p.z - relief.heightAt(p.x, p.y);
    };
    float gapA = gap(t0);
    if (gapA <= 0) {  // entered below the relief: a wall (or the start of a ray inside the block)
      hit.t = t0;
      hit.face = entry;
      hit.uv = Vec2f(o.x + t0 * d.x, o.y + t0 * d.y);
      return hit;
    }
    const float span = t1 - t0;
    const float texels = std::max(std::abs(span * d.x) * float(relief.width()), std::abs(span * d.y) * float(relief.height()));
    const int steps = int(std::clamp(std::ceil(texels * kStepsPerTexel), float(kMinLinearSteps), float(kMaxLinearSteps)));
    float a = t0;
    for (int k = 1; k <= steps; ++k) {
      const float b = t0 + span * float(k) / float(steps);
      // The floor is at or below the relief everywhere (heights are >= 0): a ray that leaves
      // through it has met the relief, even where rounding puts its last sample a hair above.
      const float gapB = k == steps && exitsThroughFloor ? std::min(gap(b), 0.0f) : gap(b);
      if (gapB > 0) {
        a = b;
        gapA = gapB;
        continue;
      }
      if (anyHit) {
        hit.t = b;
        return hit;
      }
      float lo = a, hi = b, gapHi = gapB;
      for (int s = 0; s < kRefineSteps; ++s) {
        const float m = 0.5f * (lo + hi);
        const float gm = gap(m);
        if (gm > 0) {
          lo = m;
          gapA = gm;
        } else {
          hi = m;
          gapHi = gm;
        }
      }
      hit.t = lo + (hi - lo) * (gapA / (gapA - gapHi));  // the secant; gapA > 0 >= gapHi
      hit.uv = Vec2f(o.x + hit.t * d.x, o.y + hit.t * d.y);
      return hit;
    }
    return hit;
  }

  /// Clips [t0, t1] to the slab (the slab test of core/aabb.h); `entry`: the face crossed at t0
  /// when the ray enters from outside through a wall or the bottom, else kReliefFace; `floorExit`:
  /// whether t1 is where the ray leaves through the bottom.
  bool clipToSlab(const Vec3f& o, const Vec3f& d, float& t0, float& t1, int& entry, bool& floorExit) const {
    const float lo[3] = {0.0f, 0.0f, 0.0f}, hi[3] = {1.0f, 1.0f, mTop};
    entry = kReliefFace;
    floorExit = false;
    for (int a = 0; a < 3; ++a) {
      if (d[a] == 0.0f) {
        if (!(o[a] >= lo[a] && o[a] <= hi[a])) return false;
        continue;
      }
      const float inv = 1.0f / d[a];
      float ta = (lo[a] - o[a]) * inv, tb = (hi[a] - o[a]) * inv;
      const bool towardsLow = ta > tb;  // entering through the high face
      if (towardsLow) std::swap(ta, tb);
      if (ta > t0) {
        t0 = ta;
        entry = a == 2 ? (towardsLow ? kReliefFace : kFaceBottom) : 2 * a + (towardsLow ? 1 : 0);
      }
      if (tb < t1) {
        t1 = tb;
        floorExit = a == 2 && towardsLow;
      } else if (tb == t1 && a == 2 && towardsLow) {
        floorExit = true;  // through an edge of the floor
      }
    }
    return t0 <= t1;
  }

  const indirection::ReliefSurface* mSurface;
  Vec3f mOrigin{0.0f}, mAxisU{0.0f}, mAxisV{0.0f}, mAxisW{0.0f}, mRowU{0.0f}, mRowV{0.0f}, mRowW{0.0f};
  float mTop = 0;
};

}  // namespace cellrelief::trace
