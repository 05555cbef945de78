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
/// On a base mesh with UVs (ReliefSurface::baseMesh) the ray first meets the mesh's nearest front
/// face, which is the top of the relief; below it the relief is marched in the hit's tangent frame
/// as the square's is in its own, down to the floor (the classic per-fragment POM: the relief of
/// the tangent plane, so the mesh's silhouette is kept). The frame interpolates per-corner normals
/// and UV tangents (dP/du, dP/dv averaged over the corners that share a vertex and a UV), made
/// orthogonal to the normal, so that shading is smooth across triangles; a tile width there is
/// sqrt|dP/du x dP/dv|. A shadow ray from a mesh hit first marches up through the relief in the
/// hit's frame (selfShadowed), then meets the rest of the mesh at its front faces.
///
/// Every map is sampled as ReliefMap samples heights (bilinear between texel centres, clamped or
/// repeated), in float, with the same order of operations as the shader, so that the GPU backends
/// can match this tracer pixel for pixel.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <array>
#include <bit>
#include <optional>
#include <unordered_map>
#include <vector>

#include "cellrelief/core/bvh.h"
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
/// A mesh hit's tangent frame is degenerate (the flat base is shown) when its UV tangents span
/// less than this share of the largest parallelogram their lengths allow (sin^2 of their angle).
inline constexpr float kMinFrameSpan = 1e-6f;
inline constexpr float kCheckerLight[3] = {0.92f, 0.9f, 0.85f};
inline constexpr float kCheckerDark[3] = {0.2f, 0.35f, 0.6f};
}  // namespace parallax_constants

/// The slab's faces, as ParallaxHit::face: where a ray entered the block below the relief.
enum ParallaxFace : int { kReliefFace = -1, kFaceU0 = 0, kFaceU1, kFaceV0, kFaceV1, kFaceBottom };

/// World directions to a relief's local coordinates: (u, v) in UV units, w in tile widths along
/// the normal. A square has one frame; a mesh has one per point (ParallaxTracer::frameAt).
struct ParallaxFrame {
  Vec3f rowU{0.0f}, rowV{0.0f}, rowW{0.0f};
  Vec3f local(const Vec3f& d) const { return {glm::dot(d, rowU), glm::dot(d, rowV), glm::dot(d, rowW)}; }
  /// A local normal in world space (the inverse transpose of the frame), unit length; the frame's
  /// own normal where n has no part in it.
  Vec3f worldNormal(const Vec3f& n) const {
    const Vec3f w = n.x * rowU + n.y * rowV + n.z * rowW;
    const float length = glm::length(w);
    return length > 0.0f ? w / length : glm::normalize(rowW);
  }
};

struct ParallaxHit {
  float t = std::numeric_limits<float>::infinity();
  Vec2f uv{0.0f};       ///< the relief's coordinates of the hit
  float height = 0.0f;  ///< w at the hit, tile widths
  int face = kReliefFace;
  ParallaxFrame frame;  ///< the frame it was traced in
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
    mTop = std::max(surface.relief.maxHeight(), 1e-6f);
    if (surface.onMesh()) {
      buildMesh(*surface.baseMesh, surface.uvScale);
      return;
    }
    const float side = surface.sideWS();
    mOrigin = surface.originWS;
    mAxisU = surface.uAxisWS / side;
    mAxisV = surface.vAxisWS / side;
    mAxisW = surface.normalWS();
    mRowU = mAxisU / side;
    mRowV = mAxisV / side;
    mRowW = mAxisW / side;
    mSideWS = side;
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

  /// The base mesh's BVH and per-corner frames as a GPU backend uploads them (empty for a square).
  const TriangleBvh<float>& meshBvh() const { return mBvh; }
  struct Corner {
    Vec2f uv{0.0f};
    Vec3f normal{0.0f};    ///< unit vertex normal
    Vec3f tangentU{0.0f};  ///< dP/du, averaged over the corners sharing the vertex and UV
    Vec3f tangentV{0.0f};  ///< dP/dv, likewise
  };
  const std::array<Corner, 3>& corners(std::size_t triangle) const { return mCorners[triangle]; }

  /// The first hit of the ray with the relief (or a wall of its slab) within [tmin, tmax].
  ParallaxHit intersect(const Rayf& ray) const { return mSurface->onMesh() ? marchMesh(ray) : march(ray, false); }

  /// Whether the ray meets the relief within [tmin, tmax]: the march stops at the first sample
  /// below it, without refining where (shadow rays). On a mesh: whether it meets a front face
  /// (every ray through one meets the relief below it, whose floor is solid).
  bool occluded(const Rayf& ray) const {
    return mSurface->onMesh() ? mBvh.anyHit(ray, kInvalidId, Faces::Front) : march(ray, true).valid();
  }

  /// Whether the relief around a mesh hit shadows it from a light in direction `towards`: a
  /// march up from `offset` world units off the surface along `normal` to the top of the relief,
  /// in the hit's frame. A light below the hit's tangent plane is shadowed. Squares answer false:
  /// occluded() on the world ray decides for them.
  bool selfShadowed(const ParallaxHit& hit, const Vec3f& normal, const Vec3f& towards, float offset) const {
    if (!mSurface->onMesh() || hit.face != kReliefFace) return false;
    const Vec3f start = Vec3f(hit.uv, hit.height) + hit.frame.local(offset * normal);
    const Vec3f d = hit.frame.local(towards);
    if (!(d.z > 0.0f)) return true;
    if (start.z >= mTop) return false;
    return marchSlab(start, d, 0.0f, (mTop - start.z) / d.z, kReliefFace, false, true).valid();
  }

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
    return hit.frame.worldNormal(n);
  }

  /// The base colour of a hit (0..1): the colour map (or checkerboard) at (u, v) + I(u, v).
  Vec3f colorAt(const ParallaxHit& hit) const {
    using namespace parallax_constants;
    const indirection::ReliefSurface& s = *mSurface;
    Vec2f st = hit.uv;
    if (s.hasIndirection()) {
      // Wrapped as the relief is: a tiling map's offsets repeat with it (a mesh's UVs may span tiles).
      const Vec4f offset = detail::bilinear(s.indirection, hit.uv, repeats(), 2);
      st += Vec2f(offset.x, offset.y);
    }
    if (!s.colors.isEmpty()) return Vec3f(detail::bilinear(s.colors, st, repeats(), 3));
    const float n = float(s.checkerSquares);
    const int parity = int(std::floor(st.x * n)) + int(std::floor(st.y * n));
    const float* c = (parity & 1) ? kCheckerLight : kCheckerDark;
    return {c[0], c[1], c[2]};
  }

  /// How far a secondary ray starts off the surface (world units): two texels (of the mesh's mean
  /// tile width on a mesh).
  float surfaceOffset() const { return constants::kSurfaceOffsetSamples * mSideWS * mSurface->relief.texelSize(); }

  /// A mesh hit's frame at barycentrics (b1, b2) of triangle `triangle`, and its UV; nullopt
  /// where the UV tangents are degenerate there.
  std::optional<ParallaxFrame> frameAt(std::uint32_t triangle, float b1, float b2, Vec2f& uv) const {
    const std::array<Corner, 3>& c = mCorners[triangle];
    const float b0 = 1.0f - b1 - b2;
    uv = b0 * c[0].uv + b1 * c[1].uv + b2 * c[2].uv;
    const Vec3f summed = b0 * c[0].normal + b1 * c[1].normal + b2 * c[2].normal;
    const float length = glm::length(summed);
    if (!(length > 0.0f)) return std::nullopt;
    const Vec3f n = summed / length;
    Vec3f tu = b0 * c[0].tangentU + b1 * c[1].tangentU + b2 * c[2].tangentU;
    Vec3f tv = b0 * c[0].tangentV + b1 * c[1].tangentV + b2 * c[2].tangentV;
    tu -= n * glm::dot(n, tu);
    tv -= n * glm::dot(n, tv);
    const float uu = glm::dot(tu, tu), uv2 = glm::dot(tu, tv), vv = glm::dot(tv, tv);
    const float det = uu * vv - uv2 * uv2;  // |tu x tv|^2
    if (!(det > parallax_constants::kMinFrameSpan * uu * vv) || !std::isfinite(det)) return std::nullopt;
    const float side = std::sqrt(std::sqrt(det));  // world length per UV unit
    ParallaxFrame f;
    f.rowU = (vv * tu - uv2 * tv) / det;
    f.rowV = (uu * tv - uv2 * tu) / det;
    f.rowW = n / side;
    return f;
  }

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
    hit = marchSlab(o, d, t0, t1, entry, exitsThroughFloor, anyHit);
    hit.frame = {mRowU, mRowV, mRowW};
    return hit;
  }

  /// The base mesh's nearest front face, then the march below it in the hit's frame: from the
  /// top of the relief at the face down to the floor, so every such ray hits. t is the world
  /// ray's: the face's t plus the march's, which starts at 0 there.
  ParallaxHit marchMesh(const Rayf& ray) const {
    const Hitf base = mBvh.closestHit(ray, kInvalidId, Faces::Front);
    if (!base.valid()) return {};
    Vec2f uv;
    const std::optional<ParallaxFrame> frame = frameAt(base.primId, base.u, base.v, uv);
    const Vec3f o(uv, mTop);
    const Vec3f d = frame ? frame->local(ray.direction) : Vec3f(0.0f);
    ParallaxHit hit;
    if (!frame || !(d.z < 0.0f)) {  // no frame, or a grazing ray below the smooth tangent plane: the base
      hit.t = base.t;
      hit.uv = uv;
      hit.height = mTop;
      hit.frame = frame ? *frame : ParallaxFrame{Vec3f(0.0f), Vec3f(0.0f), glm::normalize(base.geometricNormal)};
      return hit;
    }
    hit = marchSlab(o, d, 0.0f, -mTop / d.z, kReliefFace, true, false);
    hit.t += base.t;
    hit.frame = *frame;
    if (!(hit.t <= ray.tmax)) return {};
    return hit;
  }

  /// The march of local ray o + t d over [t0, t1] (see the file comment); `entry`: the face the
  /// ray entered through at t0; `floorExit`: whether t1 is on the floor.
  ParallaxHit marchSlab(const Vec3f& o, const Vec3f& d, float t0, float t1, int entry, bool exitsThroughFloor,
                        bool anyHit) const {
    using namespace parallax_constants;
    ParallaxHit hit;
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
      hit.height = o.z + t0 * d.z;
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
      hit.height = o.z + hit.t * d.z;
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

  /// The BVH, the per-corner UVs, normals and UV tangents, and the mean tile width.
  void buildMesh(const TriangleMesh& mesh, float uvScale) {
    mBvh = TriangleBvh<float>(mesh.positions, mesh.triangles);
    const std::vector<Vec3f> normals = mesh.normals.size() == mesh.positions.size() ? mesh.normals : computeVertexNormals(mesh);
    mCorners.resize(mesh.triangles.size());
    // Corners that share a vertex and a UV share their tangents: keyed by (vertex, u, v) bits.
    struct Key {
      std::uint32_t vertex, u, v;
      bool operator==(const Key&) const = default;
    };
    struct KeyHash {
      std::size_t operator()(const Key& k) const {
        return (std::size_t(k.vertex) * 0x9E3779B97F4A7C15ull) ^ (std::size_t(k.u) << 1) ^ (std::size_t(k.v) * 0xC2B2AE35ull);
      }
    };
    std::unordered_map<Key, std::size_t, KeyHash> groupOf;
    std::vector<Vec3f> groupU, groupV;
    std::vector<std::array<std::size_t, 3>> cornerGroup(mesh.triangles.size());
    double worldArea = 0, uvArea = 0;
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      const Vec3u& t = mesh.triangles[f];
      Vec2f uv[3];
      for (int k = 0; k < 3; ++k) {
        uv[k] = mesh.uvs[3 * f + std::size_t(k)] * uvScale;
        const Key key{t[k], std::bit_cast<std::uint32_t>(uv[k].x), std::bit_cast<std::uint32_t>(uv[k].y)};
        const auto [it, added] = groupOf.try_emplace(key, groupU.size());
        if (added) {
          groupU.emplace_back(0.0f);
          groupV.emplace_back(0.0f);
        }
        cornerGroup[f][std::size_t(k)] = it->second;
        Vec3f n = normals[t[k]];
        const float length = glm::length(n);
        mCorners[f][std::size_t(k)].uv = uv[k];
        mCorners[f][std::size_t(k)].normal = length > 0 ? n / length : Vec3f(0.0f);
      }
      // dP/du and dP/dv of the triangle, weighted by its world area as they are summed.
      const Vec3f e1 = mesh.positions[t[1]] - mesh.positions[t[0]], e2 = mesh.positions[t[2]] - mesh.positions[t[0]];
      const Vec2f d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
      const float r = d1.x * d2.y - d2.x * d1.y;
      const float area = 0.5f * glm::length(glm::cross(e1, e2));
      worldArea += area;
      uvArea += 0.5 * std::abs(double(r));
      if (r == 0.0f || !std::isfinite(1.0f / r)) continue;
      const Vec3f du = (e1 * d2.y - e2 * d1.y) / r, dv = (e2 * d1.x - e1 * d2.x) / r;
      for (int k = 0; k < 3; ++k) {
        groupU[cornerGroup[f][std::size_t(k)]] += area * du;
        groupV[cornerGroup[f][std::size_t(k)]] += area * dv;
      }
    }
    // Back to tangents per corner: the area-weighted mean over each group's triangles.
    std::vector<float> groupArea(groupU.size(), 0.0f);
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      const Vec3u& t = mesh.triangles[f];
      const float area = 0.5f * glm::length(glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]],
                                                        mesh.positions[t[2]] - mesh.positions[t[0]]));
      for (int k = 0; k < 3; ++k) groupArea[cornerGroup[f][std::size_t(k)]] += area;
    }
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        const std::size_t g = cornerGroup[f][std::size_t(k)];
        const float w = groupArea[g] > 0 ? 1.0f / groupArea[g] : 0.0f;
        mCorners[f][std::size_t(k)].tangentU = groupU[g] * w;
        mCorners[f][std::size_t(k)].tangentV = groupV[g] * w;
      }
    mSideWS = uvArea > 0 ? float(std::sqrt(worldArea / uvArea)) : 0.0f;
    if (!(mSideWS > 0) || !std::isfinite(mSideWS))
      throw Error(ErrorKind::InvalidArgument, "relief surface: the base mesh's UVs cover no area");
  }

  const indirection::ReliefSurface* mSurface;
  Vec3f mOrigin{0.0f}, mAxisU{0.0f}, mAxisV{0.0f}, mAxisW{0.0f}, mRowU{0.0f}, mRowV{0.0f}, mRowW{0.0f};
  float mTop = 0;
  float mSideWS = 0;  ///< the tile width: the square's side, a mesh's mean world length per UV unit
  TriangleBvh<float> mBvh;
  std::vector<std::array<Corner, 3>> mCorners;
};

}  // namespace cellrelief::trace
