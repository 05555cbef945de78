// SPDX-License-Identifier: MIT
/// @file geotex_tracer.h
/// Ray casting of geometry textures (de Toledo, Wang, Levy, CGF 2008, section 4.1), the CPU
/// reference: a BVH over the charts' oriented boxes; in each box the ray is searched against the
/// height map by linear steps, as many as the texels the ray's slant makes it cross (a steep ray
/// crosses few and takes few steps, a grazing one as many as it passes), then a binary search in
/// the step where it first goes from above the surface to below it, and a last secant step.
/// Overlapping boxes (the charts' rings) resolve to the nearest hit.
///
/// Skipping (not in the paper): pyramids of the maximum and minimum heights per chart (the maximum
/// mipmaps of Tevs, Ihrke & Seidel 2008, and their mirror) tell where the ray stays above every
/// surface point under it, or below every one, and the linear search passes over the steps that
/// fall there: none of them can be a passage from above to below. The steps it does take are the
/// same steps at the same parameters, so the hits are those of the search without skipping; only
/// the evaluations between them go.
///
/// The surface in a chart: heights interpolated bilinearly between texel centres over the texels
/// that hold a height; where the texel under the point is empty there is no surface. A hit is a
/// passage from above the surface to below it: a ray that enters a box below the surface (through
/// a side or from inside the solid), or that runs from an empty texel into the side of the height
/// field, must rise above the surface before a hit counts, so walls are never surfaces.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/bvh.h"
#include "cellrelief/core/hit.h"
#include "cellrelief/core/math.h"
#include "cellrelief/core/octahedral.h"
#include "cellrelief/core/quantize.h"
#include "cellrelief/core/ray.h"
#include "cellrelief/geotex/geotex_model.h"

namespace cellrelief::trace {

struct GeoTexTraceOptions {
  float linearStepsPerTexel = 1.0f;  ///< linear steps per texel the ray crosses in x and y
  int minLinearSteps = 3;            ///< a ray along z still takes this many
  int binarySteps = 8;
  bool skipSteps = true;             ///< pass over linear steps the pyramids show above or below the surface
};

/// Counts of the work done, for benchmarks (per tracer call; not thread-shared).
struct GeoTexTraceStats {
  std::uint64_t boxes = 0;    ///< boxes the ray entered
  std::uint64_t samples = 0;  ///< height-map evaluations
  std::uint64_t nodes = 0;    ///< pyramid nodes tested by the skipping
};

template <Real T>
class GeoTexTracer {
 public:
  GeoTexTracer() = default;
  /// Reads the model's maps in place: the model must outlive the tracer.
  explicit GeoTexTracer(const geotex::GeoTexModel& model, const GeoTexTraceOptions& options = {})
      : mModel(&model), mOptions(options) {
    std::vector<Aabb<T>> boxes;
    boxes.reserve(model.charts.size());
    for (const geotex::ChartBox& c : model.charts) {
      Chart chart;
      chart.origin = Vec3<T>(c.originWS);
      chart.rowX = Vec3<T>(c.axisWS[0] * (double(c.width) / c.sizeWS.x));
      chart.rowY = Vec3<T>(c.axisWS[1] * (double(c.height) / c.sizeWS.y));
      chart.rowZ = Vec3<T>(c.axisWS[2]);
      chart.box = Aabb<T>(Vec3<T>(0), Vec3<T>(T(c.width), T(c.height), T(c.sizeWS.z)));
      chart.heightScale = T(c.sizeWS.z) / T(model.heightCodec.largestCode());
      chart.width = int(c.width);
      chart.height = int(c.height);
      chart.firstTexel = c.firstTexel;
      addPyramids(chart);
      mCharts.push_back(chart);
      const Aabbd b = c.boundsWS();
      boxes.push_back(Aabb<T>(Vec3<T>(b.min), Vec3<T>(b.max)));
      const Vec2d texel = c.texelSizeWS();
      mSurfaceOffset = std::max(mSurfaceOffset, T(2 * std::max(texel.x, texel.y)));
    }
    mBvh = BoxBvh<T>(boxes);
  }

  const geotex::GeoTexModel& model() const { return *mModel; }
  const BoxBvh<T>& bvh() const { return mBvh; }
  const GeoTexTraceOptions& options() const { return mOptions; }
  /// The search's options change the steps, not what is built (the BVH and the pyramids are
  /// built either way), so a tracer takes new ones in place.
  void setOptions(const GeoTexTraceOptions& options) { mOptions = options; }
  /// Bytes the tracer adds to the model's: the BVH, the chart frames and the pyramids.
  std::size_t accelerationBytes() const {
    return mBvh.nodeCount() * sizeof(typename BoxBvh<T>::Node) + mCharts.size() * sizeof(Chart) +
           mPyramids.size() * sizeof(std::uint32_t);
  }
  /// Every chart's pyramid nodes (level 1 up, level by level; the maximum code + 1 in the low half,
  /// the minimum code + 1 in the high half, 0 for none) and where chart c's begin.
  const std::vector<std::uint32_t>& pyramids() const { return mPyramids; }
  std::uint32_t firstPyramidNode(std::uint32_t c) const { return mCharts[c].firstNode[1]; }

  /// The nearest hit in [ray.tmin, ray.tmax): t, the unit shading normal in world space (as
  /// geometricNormal), primId the chart, u and v the chart coordinates in texels; geomId 0.
  Hit<T> intersect(const Ray<T>& ray, GeoTexTraceStats* stats = nullptr) const {
    Hit<T> best;
    T tmax = ray.tmax;
    mBvh.traverseNearFirst(ray, tmax, [&](std::uint32_t slot, T& limit) {
      const std::uint32_t c = mBvh.primitiveIds()[slot];
      if (intersectChart(ray, c, limit, best, stats)) limit = best.t;
      return false;
    });
    if (!best.valid()) best.t = std::numeric_limits<T>::infinity();
    return best;
  }

  /// Whether anything lies on the ray in [tmin, tmax) (shadow rays).
  bool occluded(const Ray<T>& ray) const {
    Hit<T> scratch;
    bool found = false;
    T tmax = ray.tmax;
    mBvh.traverse(ray, tmax, [&](std::uint32_t slot, T& limit) {
      found = intersectChart(ray, mBvh.primitiveIds()[slot], limit, scratch, nullptr);
      return found;
    });
    return found;
  }

  /// The surface height of chart c at chart point (x, y), or -infinity where there is none.
  T heightAt(std::uint32_t c, T x, T y) const { return height(mCharts[c], x, y); }

  /// The base colour at a hit (0..1): the colour map filtered like the heights, or the neutral
  /// grey of every representation when the model has no colour.
  Vec3f colorAt(const Hit<T>& hit) const {
    if (!mModel->hasColors() || !hit.valid()) return Vec3f(kNeutralGrey);
    const Taps t = taps(mCharts[hit.primId], hit.u, hit.v);
    if (!(t.total > 0)) return Vec3f(kNeutralGrey);
    Vec3f c(0);
    for (int k = 0; k < 4; ++k) c += float(t.weight[k] / t.total) * Vec3f(Vec4f(mModel->colors[t.texel[k]]));
    return c / 255.0f;
  }

  /// How far a secondary ray starts off the surface (world units): two texels of the coarsest
  /// chart, past the reach of the height field's own error.
  T surfaceOffset() const { return mSurfaceOffset; }

  static constexpr float kNeutralGrey = 200.0f / 255;

 private:
  // Enough levels for the largest map the model allows (4096 texels a side).
  static constexpr int kMaxLevels = 14;
  // Chart coordinates beyond this are far outside any map (and beyond an int's range soon after).
  static constexpr T kFar = T(1 << 30);

  struct Chart {
    Vec3<T> origin, rowX, rowY, rowZ;  // world -> chart: ((p - origin) . rowX, ...)
    Aabb<T> box;
    T heightScale = 1;
    int width = 0, height = 0;
    std::uint64_t firstTexel = 0;
    int levels = 0;                           // pyramid levels: 0 the texels, 1 stored first, the last 1 x 1
    std::uint32_t firstNode[kMaxLevels] = {};  // each stored level's first node in mPyramids
  };

  /// Level L's node count along an axis of `texels` texels.
  static int nodesAlong(int texels, int level) { return ((texels - 1) >> level) + 1; }

  /// A pyramid node: the maximum code + 1 in the low half, the minimum code + 1 in the high half.
  static std::uint32_t pyramidNode(int maxPlusOne, int minPlusOne) {
    return std::uint32_t(maxPlusOne) | std::uint32_t(minPlusOne) << 16;
  }

  /// The chart's pyramids, appended to mPyramids, from level 1 (2 x 2 texels a node: a quarter of
  /// the bytes of per-texel bounds, for about 10% more samples). A level-1 node
  /// bounds the surface over its texels: bilinear heights mix the texels around a point, one
  /// further out at most (clamped at the map's edge), with weights summing to one, so the largest
  /// and smallest codes of the 4 x 4 texels around the node bound them. A bound is stored as
  /// code + 1, with 0 for "none": no maximum where all those texels are empty (no surface), no
  /// minimum where a texel of the node is (a ray is never below the surface there). Each level
  /// above holds the extremes of its 2 x 2 children (0 wins both: none above, none below). A node
  /// is one word (pyramidNode), as the GPU backends read it.
  void addPyramids(Chart& c) {
    const std::uint16_t empty = mModel->heightCodec.emptyCode();
    auto code = [&](int i, int j) { return mModel->heights[c.firstTexel + std::uint64_t(j) * c.width + i]; };
    c.levels = 2;
    while (std::max(nodesAlong(c.width, c.levels - 1), nodesAlong(c.height, c.levels - 1)) > 1) ++c.levels;
    c.firstNode[1] = std::uint32_t(mPyramids.size());
    for (int j = 0; j < nodesAlong(c.height, 1); ++j)
      for (int i = 0; i < nodesAlong(c.width, 1); ++i) {
        int highest = -1, lowest = 1 << 16;
        bool emptyInside = false;
        for (int tj = std::max(0, 2 * j - 1); tj <= std::min(c.height - 1, 2 * j + 2); ++tj)
          for (int ti = std::max(0, 2 * i - 1); ti <= std::min(c.width - 1, 2 * i + 2); ++ti) {
            const std::uint16_t k = code(ti, tj);
            if (k == empty) {
              emptyInside |= ti >> 1 == i && tj >> 1 == j;
              continue;
            }
            highest = std::max(highest, int(k));
            lowest = std::min(lowest, int(k));
          }
        mPyramids.push_back(pyramidNode(highest + 1, emptyInside || highest < 0 ? 0 : lowest + 1));
      }
    for (int level = 2; level < c.levels; ++level) {
      c.firstNode[level] = std::uint32_t(mPyramids.size());
      const int w = nodesAlong(c.width, level), h = nodesAlong(c.height, level);
      const int wc = nodesAlong(c.width, level - 1), hc = nodesAlong(c.height, level - 1);
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
          std::uint32_t highest = 0, lowest = 0xffff;
          for (int cj = 2 * j; cj <= std::min(hc - 1, 2 * j + 1); ++cj)
            for (int ci = 2 * i; ci <= std::min(wc - 1, 2 * i + 1); ++ci) {
              const std::uint32_t child = mPyramids[c.firstNode[level - 1] + std::uint32_t(cj) * wc + ci];
              highest = std::max(highest, child & 0xffffu);
              lowest = std::min(lowest, child >> 16);
            }
          mPyramids.push_back(pyramidNode(int(highest), int(lowest)));
        }
    }
  }

  struct SameSide {
    T until;  ///< the ray stays on its side of the surface from t to here
    T retry;  ///< where the level-1 node the walk stopped in ends: no new walk pays before it
  };

  /// How far, from parameter t (in the box, not past tEnd), the chart-space ray stays on one side
  /// of every surface point under it by the pyramids: above when `above`, else below; t itself
  /// when they cannot tell. The walk climbs a level after each node it passes and descends where
  /// it cannot pass, as maximum mipmaps do. Where it stops, a level-1 node the ray cannot pass: a
  /// walk from further on in that node fails too when the ray moves away from the side it is on
  /// (down when above), and gains at most the node's two texels otherwise, so the search walks
  /// again only after it.
  SameSide sameSideUntil(const Chart& c, const Vec3<T>& o, const Vec3<T>& d, T t, T tEnd, bool above,
                         GeoTexTraceStats* stats) const {
    // Widened by a millionth of the box so that rounding in the interpolation never crosses them.
    const T margin = T(1e-6) * c.box.max.z;
    const T inverse[2] = {T(1) / d.x, T(1) / d.y};
    int level = 1;
    // Each pass moves t on or changes the level; bounded, so a rounding stall only ends the skip.
    for (int pass = 0; pass < 8 * (c.width + c.height) && t < tEnd; ++pass) {
      if (stats) ++stats->nodes;
      const int w = nodesAlong(c.width, level), h = nodesAlong(c.height, level);
      const Vec3<T> p = o + t * d;
      // Far outside the map (rounding in a huge box) or not a number: no walk, no integer of it.
      if (!(std::abs(p.x) < kFar && std::abs(p.y) < kFar)) return {t, t};
      int i = std::clamp(int(std::floor(p.x)) >> level, 0, w - 1);
      int j = std::clamp(int(std::floor(p.y)) >> level, 0, h - 1);
      // The node the ray is in as it leaves t: a point on a node's far side belongs to the next.
      auto exitAlong = [&](int axis, int& node, int count) {
        const T dir = d[axis];
        for (;;) {
          if (dir == 0) return std::numeric_limits<T>::infinity();
          const T exit = (T((dir > 0 ? node + 1 : node) << level) - o[axis]) * inverse[axis];
          const int next = node + (dir > 0 ? 1 : -1);
          if (exit > t || next < 0 || next >= count) return exit;
          node = next;
        }
      };
      const T exit = std::min({exitAlong(0, i, w), exitAlong(1, j, h), tEnd});
      const T zExit = o.z + exit * d.z;
      const std::uint32_t node = mPyramids[c.firstNode[level] + std::uint32_t(j) * w + i];
      const std::uint32_t stored = above ? node & 0xffffu : node >> 16;
      const T bound = T(int(stored) - 1) * c.heightScale;
      const bool passes = above ? stored == 0 || std::min(p.z, zExit) > bound + margin
                                : stored != 0 && std::max(p.z, zExit) < bound - margin;
      if (exit > t && passes) {
        t = exit;
        level = std::min(level + 1, c.levels - 1);
      } else if (level == 1) {
        return {t, std::max(t, exit)};
      } else {
        --level;
      }
    }
    return {std::min(t, tEnd), t};
  }

  /// Bilinear taps around (x, y) over texel centres, clamped to the map; weights of empty taps 0.
  struct Taps {
    std::uint64_t texel[4] = {0, 0, 0, 0};
    T weight[4] = {0, 0, 0, 0};
    T total = 0;
  };

  Taps taps(const Chart& c, T x, T y) const {
    Taps t;
    // Far outside the map (or not a number): no surface, and no integer conversion of it.
    if (!(x > -kFar && x < kFar && y > -kFar && y < kFar)) return t;
    const int ni = std::clamp(int(std::floor(x)), 0, c.width - 1), nj = std::clamp(int(std::floor(y)), 0, c.height - 1);
    if (mModel->heights[c.firstTexel + std::uint64_t(nj) * c.width + ni] == mModel->heightCodec.emptyCode())
      return t;  // no surface under this point
    const T fx = x - T(0.5), fy = y - T(0.5);
    const int i0 = int(std::floor(fx)), j0 = int(std::floor(fy));
    const T ax = fx - T(i0), ay = fy - T(j0);
    for (int k = 0; k < 4; ++k) {
      const int i = std::clamp(i0 + (k & 1), 0, c.width - 1), j = std::clamp(j0 + (k >> 1), 0, c.height - 1);
      t.texel[k] = c.firstTexel + std::uint64_t(j) * c.width + i;
      const T w = ((k & 1) ? ax : 1 - ax) * ((k >> 1) ? ay : 1 - ay);
      t.weight[k] = mModel->heights[t.texel[k]] == mModel->heightCodec.emptyCode() ? T(0) : w;
      t.total += t.weight[k];
    }
    return t;
  }

  /// Linear steps for a ray crossing this many texels: one per texel at the default density,
  /// within [minLinearSteps, 4 (width + height) + minLinearSteps]; the most when the count is not
  /// a number (a ray along a box face of a degenerate chart).
  int linearSteps(const Chart& c, T texelsCrossed) const {
    const int most = 4 * (c.width + c.height) + mOptions.minLinearSteps;
    const T wanted = texelsCrossed * T(mOptions.linearStepsPerTexel);
    return wanted < T(most) ? std::max(mOptions.minLinearSteps, int(std::ceil(wanted))) : most;
  }

  T height(const Chart& c, T x, T y) const {
    const Taps t = taps(c, x, y);
    if (!(t.total > 0)) return -std::numeric_limits<T>::infinity();
    T h = 0;
    for (int k = 0; k < 4; ++k) h += t.weight[k] * T(mModel->heights[t.texel[k]]);
    return h / t.total * c.heightScale;
  }

  Vec3<T> normal(const Chart& c, T x, T y) const {
    const Taps t = taps(c, x, y);
    Vec3<T> n(0);
    for (int k = 0; k < 4; ++k) {
      if (t.weight[k] == 0) continue;
      const std::uint32_t e = mModel->normals[t.texel[k]];
      const Vec2f uv(dequantizeUnorm<std::uint16_t>(std::uint16_t(e & 0xffffu)),
                     dequantizeUnorm<std::uint16_t>(std::uint16_t(e >> 16)));
      n += t.weight[k] * Vec3<T>(octahedralDecode(uv));
    }
    const T len = glm::length(n);
    return len > 0 ? n / len : Vec3<T>(0, 0, 1);
  }

  /// Searches chart c for a hit before `limit`; on success fills `hit` and returns true.
  bool intersectChart(const Ray<T>& rayWS, std::uint32_t index, T limit, Hit<T>& hit,
                      GeoTexTraceStats* stats) const {
    const Chart& c = mCharts[index];
    const Vec3<T> d0 = rayWS.origin - c.origin;
    const Vec3<T> o(glm::dot(d0, c.rowX), glm::dot(d0, c.rowY), glm::dot(d0, c.rowZ));
    const Vec3<T> d(glm::dot(rayWS.direction, c.rowX), glm::dot(rayWS.direction, c.rowY),
                    glm::dot(rayWS.direction, c.rowZ));
    const Ray<T> ray(o, d, rayWS.tmin, limit);
    const RayInterval<T> span = cellrelief::intersect(ray, c.box);
    if (!span.hit) return false;
    if (stats) ++stats->boxes;
    const T texelsCrossed = std::hypot(d.x, d.y) * (span.t1 - span.t0);
    const int steps = linearSteps(c, texelsCrossed);
    const T dt = (span.t1 - span.t0) / T(steps);
    // gap = ray z - surface height: +infinity over an empty texel (no surface), positive above
    // the surface, not positive below it.
    auto gapAt = [&](T t) {
      const Vec3<T> p = o + t * d;
      if (stats) ++stats->samples;
      return p.z - height(c, p.x, p.y);
    };
    auto stepT = [&](int k) { return k == steps ? span.t1 : span.t0 + T(k) * dt; };
    T tBefore = span.t0;
    T gapBefore = gapAt(span.t0);
    T walkFrom = span.t0;  // the pyramid walk's next try, not before
    for (int k = 1; k <= steps; ++k) {
      if (mOptions.skipSteps && k < steps && tBefore >= walkFrom) {
        // Steps k..m lie where the ray stays on the side of the surface it is on at step k - 1:
        // none is a passage from above to below, so the search goes on from step m, evaluated,
        // as it would have.
        const bool above = gapBefore > 0;
        const auto [safe, retry] = sameSideUntil(c, o, d, tBefore, span.t1, above, stats);
        if (safe >= span.t1) return false;
        walkFrom = retry;
        const T along = (safe - span.t0) / dt;  // steps passed; not a number in a degenerate box
        int m = along >= 0 ? int(std::min(along, T(steps - 1))) : k - 1;
        while (m >= k && stepT(m) > safe) --m;
        if (m > k) {
          const T gapM = gapAt(stepT(m));
          if ((gapM > 0) == above) {  // as the pyramid said (rounding aside); else step k as usual
            tBefore = stepT(m);
            gapBefore = gapM;
            k = m;
            continue;
          }
        }
      }
      const T t = stepT(k);
      const T gap = gapAt(t);
      if (gap <= 0 && gapBefore > 0) {
        if (std::isfinite(gapBefore)) return refine(c, o, d, tBefore, t, gapBefore, gap, index, hit, gapAt);
        // From no surface to below one: either the ray passed the map's edge above the surface
        // and then went down through it (a hit), or it ran into the side of the height field
        // (a wall, not a surface). The edge crossing tells which.
        T ta = tBefore, tb = t;
        for (int b = 0; b < mOptions.binarySteps + 4; ++b) {
          const T tm = T(0.5) * (ta + tb);
          const T gm = gapAt(tm);
          if (gm > 0 && std::isfinite(gm)) return refine(c, o, d, tm, tb, gm, gap, index, hit, gapAt);
          (gm > 0 ? ta : tb) = tm;
        }
      }
      tBefore = t;
      gapBefore = gap;
    }
    return false;
  }

  /// Binary search in [ta, tb] (above the surface at ta, below at tb), then a secant step in the
  /// last bracket where both gaps are finite.
  template <class GapAt>
  bool refine(const Chart& c, const Vec3<T>& o, const Vec3<T>& d, T ta, T tb, T gapA, T gapB,
              std::uint32_t index, Hit<T>& hit, GapAt& gapAt) const {
    for (int k = 0; k < mOptions.binarySteps; ++k) {
      const T tm = T(0.5) * (ta + tb);
      const T gap = gapAt(tm);
      if (gap > 0) {
        ta = tm;
        gapA = gap;
      } else {
        tb = tm;
        gapB = gap;
      }
    }
    T t = tb;
    if (std::isfinite(gapA) && gapA - gapB > 0) t = ta + (tb - ta) * gapA / (gapA - gapB);
    const Vec3<T> p = o + t * d;
    hit.t = t;
    hit.u = p.x;
    hit.v = p.y;
    hit.geometricNormal = normal(c, p.x, p.y);
    hit.primId = index;
    hit.geomId = 0;
    return true;
  }

  const geotex::GeoTexModel* mModel = nullptr;
  GeoTexTraceOptions mOptions;
  std::vector<Chart> mCharts;
  std::vector<std::uint32_t> mPyramids;  // every chart's pyramid nodes, level by level
  BoxBvh<T> mBvh;
  T mSurfaceOffset = 0;
};

}  // namespace cellrelief::trace
