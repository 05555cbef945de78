// SPDX-License-Identifier: MIT
/// @file bvh.h
/// Bounding volume hierarchies: BoxBvh over boxes, and TriangleBvh on it for the CPU-side ray
/// queries of conversion (is this projection segment blocked? where does this texel's projection
/// line meet the surface?). Median split on the longest centroid axis, four primitives per leaf,
/// triangles stored in leaf order as (v0, e1, e2) so a leaf reads contiguous memory. Verification uses Embree instead; this is the
/// library's own, dependency-free structure.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>
#include <span>
#include <vector>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/error.h"
#include "cellrelief/core/hit.h"
#include "cellrelief/core/triangle_mesh.h"

namespace cellrelief {

/// Barycentric weights of the point of triangle (a, b, c) nearest to p (Ericson, Real-Time
/// Collision Detection 5.1.5); a degenerate triangle is treated as its three edges.
template <Real T>
Vec3<T> closestPointBarycentrics(const Vec3<T>& p, const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c) {
  const Vec3<T> ab = b - a, ac = c - a, ap = p - a;
  const Vec3<T> n = glm::cross(ab, ac);
  if (glm::dot(n, n) == T(0)) {
    // The nearest of the three edges, each as a segment parameter.
    const auto onSegment = [&](const Vec3<T>& from, const Vec3<T>& to) {
      const Vec3<T> d = to - from;
      const T len2 = glm::dot(d, d);
      return len2 > 0 ? glm::clamp(glm::dot(p - from, d) / len2, T(0), T(1)) : T(0);
    };
    const T tab = onSegment(a, b), tbc = onSegment(b, c), tca = onSegment(c, a);
    const Vec3<T> candidates[3] = {Vec3<T>(1 - tab, tab, 0), Vec3<T>(0, 1 - tbc, tbc), Vec3<T>(tca, 0, 1 - tca)};
    Vec3<T> best = candidates[0];
    T bestDistance2 = std::numeric_limits<T>::infinity();
    for (const Vec3<T>& w : candidates) {
      const Vec3<T> d = p - (w[0] * a + w[1] * b + w[2] * c);
      if (glm::dot(d, d) < bestDistance2) {
        bestDistance2 = glm::dot(d, d);
        best = w;
      }
    }
    return best;
  }
  const T d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const Vec3<T> bp = p - b;
  const T d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const T vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const T v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const Vec3<T> cp = p - c;
  const T d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const T vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const T w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const T va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const T w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const T denom = T(1) / (va + vb + vc);
  const T v = vb * denom, w = vc * denom;
  return {1 - v - w, v, w};
}

/// Squared distance from p to the triangle (a, b, c).
template <Real T>
T pointTriangleDistance2(const Vec3<T>& p, const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c) {
  const Vec3<T> w = closestPointBarycentrics(p, a, b, c);
  const Vec3<T> d = p - (w[0] * a + w[1] * b + w[2] * c);
  return glm::dot(d, d);
}

/// A bounding volume hierarchy over boxes: median split on the longest centroid axis, a few
/// primitives per leaf, nodes in depth-first order. It knows only boxes and ids; the structures
/// built on it (triangles below, geometry-texture charts in trace/) keep their primitives in its
/// leaf order so a leaf reads contiguous memory.
template <Real T>
class BoxBvh {
 public:
  static constexpr int kLeafSize = 4;

  /// The tree as a GPU backend uploads it: nodes in depth-first order (an inner node's left
  /// child follows it, `first` is its right child; a leaf's `first` and `count` index
  /// primitiveIds()), and the primitive ids in leaf order.
  struct Node {
    Aabb<T> box;
    std::uint32_t first = 0;  // leaf: first primitive; inner: index of the right child
    std::uint32_t count = 0;  // leaf: number of primitives; inner: 0 (left child follows)
  };

  BoxBvh() = default;
  explicit BoxBvh(std::span<const Aabb<T>> boxes) {
    const std::size_t n = boxes.size();
    if (n >= (1u << 31)) throw Error(ErrorKind::ResourceLimit, "too many primitives for the BVH");
    std::vector<Primitive> primitives(n);
    for (std::size_t i = 0; i < n; ++i) primitives[i] = {boxes[i].center(), std::uint32_t(i)};
    mNodes.reserve(n > 0 ? 2 * (n / kLeafSize + 1) : 1);
    if (n > 0) build(0, std::uint32_t(n), primitives, boxes);
    mIds.resize(n);
    for (std::size_t i = 0; i < n; ++i) mIds[i] = primitives[i].id;
  }

  std::size_t primitiveCount() const { return mIds.size(); }
  std::size_t nodeCount() const { return mNodes.size(); }
  std::span<const Node> nodes() const { return mNodes; }
  std::span<const std::uint32_t> primitiveIds() const { return mIds; }

  /// Visits, as visit(i, tmax), the leaf slots i (index into primitiveIds()) whose boxes the ray
  /// reaches before `tmax`; the visitor may lower tmax (a nearer hit prunes the rest) and returns
  /// true to stop.
  template <class Visit>
  void traverse(const Ray<T>& ray, T& tmax, Visit&& visit) const {
    if (mNodes.empty()) return;
    const RaySlabs<T> slabs(ray);
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = mNodes[stack[--top]];
      T entry;
      if (!slabs.enters(node.box, ray.tmin, tmax, entry)) continue;
      if (node.count > 0) {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
          if (visit(i, tmax)) return;
        continue;
      }
      const std::uint32_t left = std::uint32_t(&node - mNodes.data()) + 1;
      stack[top++] = node.first;
      stack[top++] = left;
    }
  }

  /// As traverse, nearer first: at each inner node the child the ray enters first is visited
  /// first, and a node entered past tmax (lowered by a hit meanwhile) is skipped. For nearest-hit
  /// queries whose primitives cost more than a box test (a height-map search per box): boxes
  /// behind the first hit are then seldom searched.
  template <class Visit>
  void traverseNearFirst(const Ray<T>& ray, T& tmax, Visit&& visit) const {
    if (mNodes.empty()) return;
    const RaySlabs<T> slabs(ray);
    const auto enters = [&](const Node& node, T& entry) { return slabs.enters(node.box, ray.tmin, tmax, entry); };
    std::pair<T, std::uint32_t> stack[64];
    int top = 0;
    T rootEntry;
    if (!enters(mNodes[0], rootEntry)) return;
    stack[top++] = {rootEntry, 0};
    while (top > 0) {
      const auto [entry, index] = stack[--top];
      if (entry > tmax) continue;
      const Node& node = mNodes[index];
      if (node.count > 0) {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
          if (visit(i, tmax)) return;
        continue;
      }
      const std::uint32_t left = index + 1, right = node.first;
      T leftEntry, rightEntry;
      const bool hitsLeft = enters(mNodes[left], leftEntry), hitsRight = enters(mNodes[right], rightEntry);
      if (hitsLeft && hitsRight) {
        const bool leftFirst = leftEntry <= rightEntry;
        stack[top++] = leftFirst ? std::pair{rightEntry, right} : std::pair{leftEntry, left};
        stack[top++] = leftFirst ? std::pair{leftEntry, left} : std::pair{rightEntry, right};
      } else if (hitsLeft) {
        stack[top++] = {leftEntry, left};
      } else if (hitsRight) {
        stack[top++] = {rightEntry, right};
      }
    }
  }

  /// Visits, as visit(i), the leaf slots i whose boxes overlap `box` (closed boxes: touching
  /// counts); the visitor returns true to stop.
  template <class Visit>
  void overlapping(const Aabb<T>& box, Visit&& visit) const {
    if (mNodes.empty()) return;
    const auto overlaps = [&](const Aabb<T>& b) {
      return glm::all(glm::lessThanEqual(b.min, box.max)) && glm::all(glm::lessThanEqual(box.min, b.max));
    };
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const std::uint32_t index = stack[--top];
      const Node& node = mNodes[index];
      if (!overlaps(node.box)) continue;
      if (node.count > 0) {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
          if (visit(i)) return;
        continue;
      }
      stack[top++] = node.first;
      stack[top++] = index + 1;
    }
  }

  /// Visits leaf slots in order of increasing box distance to p, as visit(i, best2) with best2
  /// the squared distance the visitor has found so far (it may lower it); subtrees farther than
  /// best2 are skipped.
  template <class Visit>
  void nearest(const Vec3<T>& p, T& best2, Visit&& visit) const {
    if (mNodes.empty()) return;
    std::pair<T, std::uint32_t> stack[64];
    int top = 0;
    stack[top++] = {boxDistance2(mNodes[0].box, p), 0};
    while (top > 0) {
      const auto [d2, index] = stack[--top];
      if (d2 > best2) continue;
      const Node& node = mNodes[index];
      if (node.count > 0) {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i) visit(i, best2);
        continue;
      }
      const std::uint32_t left = index + 1, right = node.first;
      const T dl = boxDistance2(mNodes[left].box, p), dr = boxDistance2(mNodes[right].box, p);
      // Push the farther child first so the nearer one is visited next.
      if (dl < dr) {
        if (dr <= best2) stack[top++] = {dr, right};
        if (dl <= best2) stack[top++] = {dl, left};
      } else {
        if (dl <= best2) stack[top++] = {dl, left};
        if (dr <= best2) stack[top++] = {dr, right};
      }
    }
  }

 private:
  /// A primitive while the tree is built: its centroid travels with its id, so the split reads
  /// contiguous memory instead of gathering a centroid per comparison (the same comparisons in
  /// the same order as on the ids alone, so the same tree).
  struct Primitive {
    Vec3<T> centroid;
    std::uint32_t id;
  };

  /// Builds the subtree of primitives [begin, end) and returns its node. Only leaves read the
  /// primitives' boxes; an inner node's box is its children's union (min and max are exact, so
  /// it is the box of its primitives).
  std::uint32_t build(std::uint32_t begin, std::uint32_t end, std::vector<Primitive>& primitives,
                      std::span<const Aabb<T>> boxes) {
    const std::uint32_t index = std::uint32_t(mNodes.size());
    mNodes.emplace_back();
    Aabb<T> centroidBox;
    for (std::uint32_t i = begin; i < end; ++i) centroidBox.extend(primitives[i].centroid);
    const Vec3<T> extent = centroidBox.extent();
    if (end - begin <= kLeafSize || std::max({extent.x, extent.y, extent.z}) <= T(0)) {
      Aabb<T> box;
      for (std::uint32_t i = begin; i < end; ++i) box.extend(boxes[primitives[i].id]);
      mNodes[index] = {box, begin, end - begin};
      return index;
    }
    const int axis = maxDimension(extent);
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(primitives.begin() + begin, primitives.begin() + mid, primitives.begin() + end,
                     [axis](const Primitive& a, const Primitive& b) {
                       return a.centroid[axis] < b.centroid[axis];
                     });
    const std::uint32_t left = build(begin, mid, primitives, boxes);
    const std::uint32_t right = build(mid, end, primitives, boxes);
    Aabb<T> box = mNodes[left].box;
    box.extend(mNodes[right].box);
    mNodes[index] = {box, right, 0};
    return index;
  }

  static T boxDistance2(const Aabb<T>& box, const Vec3<T>& p) {
    const Vec3<T> d = glm::max(glm::max(box.min - p, p - box.max), Vec3<T>(0));
    return glm::dot(d, d);
  }

  std::vector<Node> mNodes;
  std::vector<std::uint32_t> mIds;
};

/// A ray's nearest hit, and whether it meets the triangles again past it: a second crossing of
/// the surface, which a projection line cannot store (see closestHitAndNext).
template <Real T>
struct FirstAndNextHit {
  Hit<T> first;       ///< as closestHit's
  bool next = false;  ///< another hit lies in [after(first.t), within)
};

namespace detail {

/// The hits one closestHitAndNext query meets, in any order: keeps the nearest, and the t of the
/// others while it can (a ray crosses a surface a few times). A recorded hit past after(first) and
/// before `within` answers "next"; nothing beyond it can change the answer (a nearer first hit
/// keeps it past), so the search stops there, and until one is found it runs on to `within`.
/// When more hits come than it keeps, the caller's separate query answers instead.
template <Real T, class After>
class NextHitSearch {
 public:
  NextHitSearch(T tmax, T within, const After& after) : mTmax(tmax), mWithin(within), mAfter(after) {
    mResult.first.t = tmax;
  }

  /// Takes a triangle's hit; returns how far hits still matter. The nearest recorded hit past
  /// after(first) is kept as hits come, and found again among the recorded ones only when the
  /// first hit moves nearer (which moves after(first) too).
  T take(const Hit<T>& hit) {
    const bool recorded = mCount < kCapacity;
    if (recorded) mFound[mCount++] = hit.t;
    else mOverflow = true;
    if (hit.t < mResult.first.t) {
      mResult.first = hit;
      mNearestNext = nearestNext();
    } else if (recorded && qualifies(hit.t)) {
      mNearestNext = std::min(mNearestNext, hit.t);
    }
    return bound();
  }

  /// The answer for `ray`; `surface.anyHit` over [after(first), within) is asked only when hits
  /// were not all recorded and none recorded answers.
  template <class Surface>
  FirstAndNextHit<T> result(const Ray<T>& ray, const Surface& surface) const {
    FirstAndNextHit<T> out = mResult;
    out.next = mNearestNext < mWithin;
    if (!out.next && mOverflow && out.first.valid()) {
      Ray<T> rest = ray;
      rest.tmin = mAfter(out.first.t);
      rest.tmax = mWithin;
      out.next = rest.tmin < mWithin && surface.anyHit(rest);
    }
    if (!out.first.valid()) out.first.t = std::numeric_limits<T>::infinity();
    return out;
  }

 private:
  static constexpr int kCapacity = 16;

  bool qualifies(T t, T from) const { return t >= from && t < mWithin; }
  bool qualifies(T t) const { return qualifies(t, mAfter(mResult.first.t)); }
  T nearestNext() const {
    const T from = mAfter(mResult.first.t);
    T nearest = std::numeric_limits<T>::infinity();
    for (int i = 0; i < mCount; ++i)
      if (qualifies(mFound[i], from)) nearest = std::min(nearest, mFound[i]);
    return nearest;
  }
  T bound() const {
    if (mNearestNext < mWithin) return mNearestNext;
    return std::min(mTmax, std::max(mResult.first.t, mWithin));
  }

  T mTmax, mWithin;
  const After& mAfter;
  FirstAndNextHit<T> mResult;
  T mNearestNext = std::numeric_limits<T>::infinity();  ///< the nearest recorded hit past after(first)
  T mFound[kCapacity];
  int mCount = 0;
  bool mOverflow = false;
};

}  // namespace detail

/// Which sides of its triangles a ray query sees: both, or only the front, where the ray runs
/// against the winding's normal (a rasterizer's back-face culling; one-sided surfaces such as the
/// base mesh of parallax occlusion mapping, which rays leave from below).
enum class Faces { Both, Front };

/// Triangles on a BoxBvh, stored in its leaf order as (v0, e1, e2).
template <Real T>
class TriangleBvh {
 public:
  using Node = typename BoxBvh<T>::Node;

  TriangleBvh() = default;
  TriangleBvh(std::span<const Vec3<T>> positions, std::span<const Vec3u> triangles) {
    const std::size_t n = triangles.size();
    if (n >= (1u << 31)) throw Error(ErrorKind::ResourceLimit, "too many triangles for the BVH");
    std::vector<Aabb<T>> boxes(n);
    for (std::size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) boxes[i].extend(positions[triangles[i][k]]);
    mTree = BoxBvh<T>(boxes);
    const auto order = mTree.primitiveIds();
    mV0.resize(n);
    mE1.resize(n);
    mE2.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3u& t = triangles[order[i]];
      mV0[i] = positions[t[0]];
      mE1[i] = positions[t[1]] - positions[t[0]];
      mE2[i] = positions[t[2]] - positions[t[0]];
    }
  }

  std::size_t triangleCount() const { return mTree.primitiveCount(); }
  std::size_t nodeCount() const { return mTree.nodeCount(); }

  /// The tree as a GPU backend uploads it (see BoxBvh::nodes), the triangle ids in leaf order.
  std::span<const Node> nodes() const { return mTree.nodes(); }
  std::span<const std::uint32_t> primitiveIds() const { return mTree.primitiveIds(); }

  /// True when the ray meets a triangle other than `skip` with t in [tmin, tmax).
  bool anyHit(const Ray<T>& ray, std::uint32_t skip = kInvalidId, Faces faces = Faces::Both) const {
    bool found = false;
    Hit<T> hit;
    hit.t = ray.tmax;
    T tmax = ray.tmax;
    mTree.traverse(ray, tmax, [&](std::uint32_t i, T&) {
      if (mTree.primitiveIds()[i] == skip) return false;
      if (intersectPrim(ray, i, hit, faces)) found = true;
      return found;
    });
    return found;
  }

  /// The triangles, as leaf slots, whose bounding boxes overlap `box`, as visit(slot); the
  /// visitor returns true to stop.
  template <class Visit>
  void overlapping(const Aabb<T>& box, Visit&& visit) const {
    mTree.overlapping(box, visit);
  }
  /// The triangle at a leaf slot: its first corner, its two edges from it, its input index.
  const Vec3<T>& corner(std::uint32_t slot) const { return mV0[slot]; }
  const Vec3<T>& edge1(std::uint32_t slot) const { return mE1[slot]; }
  const Vec3<T>& edge2(std::uint32_t slot) const { return mE2[slot]; }
  std::uint32_t triangleId(std::uint32_t slot) const { return mTree.primitiveIds()[slot]; }

  /// The nearest point of the triangles to `p` within `maxDistance` (infinity: anywhere).
  /// Returns the squared distance (infinity when nothing is that close) and the triangle.
  std::pair<T, std::uint32_t> closestPoint(const Vec3<T>& p,
                                           T maxDistance = std::numeric_limits<T>::infinity()) const {
    T best = maxDistance == std::numeric_limits<T>::infinity() ? maxDistance : maxDistance * maxDistance;
    std::uint32_t bestId = kInvalidId;
    mTree.nearest(p, best, [&](std::uint32_t i, T& best2) {
      const T t2 = pointTriangleDistance2(p, mV0[i], mV0[i] + mE1[i], mV0[i] + mE2[i]);
      if (t2 < best2) {
        best2 = t2;
        bestId = mTree.primitiveIds()[i];
      }
    });
    return {best, bestId};
  }

  /// The nearest hit with t in [tmin, tmax) (hit.valid() is false when there is none); primId is
  /// the index of the triangle in the input.
  Hit<T> closestHit(const Ray<T>& ray, std::uint32_t skip = kInvalidId, Faces faces = Faces::Both) const {
    Hit<T> best;
    best.t = ray.tmax;
    T tmax = ray.tmax;
    mTree.traverseNearFirst(ray, tmax, [&](std::uint32_t i, T& limit) {
      if (mTree.primitiveIds()[i] != skip && intersectPrim(ray, i, best, faces)) limit = best.t;
      return false;
    });
    if (!best.valid()) best.t = std::numeric_limits<T>::infinity();
    return best;
  }

  /// The nearest hit (as closestHit) and whether the ray meets another triangle at t in
  /// [after(first.t), within), within <= ray.tmax: a second crossing past the first, found in
  /// the same descent (the nearer-first order meets the first hits first and the search stops at
  /// the first crossing past them), where closestHit and then anyHit would walk the tree twice.
  template <class After>
  FirstAndNextHit<T> closestHitAndNext(const Ray<T>& ray, T within, const After& after) const {
    detail::NextHitSearch<T, After> search(ray.tmax, within, after);
    T tmax = ray.tmax;
    mTree.traverseNearFirst(ray, tmax, [&](std::uint32_t i, T& limit) {
      Hit<T> hit;
      hit.t = limit;
      if (intersectPrim(ray, i, hit, Faces::Both)) limit = search.take(hit);
      return false;
    });
    return search.result(ray, *this);
  }

 private:
  bool intersectPrim(const Ray<T>& ray, std::uint32_t i, Hit<T>& hit, Faces faces) const {
    if (faces == Faces::Front && glm::dot(ray.direction, glm::cross(mE1[i], mE2[i])) >= T(0)) return false;
    const std::uint32_t id = mTree.primitiveIds()[i];
    const T before = hit.t;
    intersectTriangle(ray.origin, ray.direction, ray.tmin, mV0[i], mV0[i] + mE1[i],
                      mV0[i] + mE2[i], id, 0u, hit);
    return hit.t < before;
  }

  BoxBvh<T> mTree;
  std::vector<Vec3<T>> mV0, mE1, mE2;
};

/// The triangles of a TriangleBvh that may meet a box, for many short rays inside it (the
/// projection lines of one cell, 2x to 3x faster conversions): a list of triangles, most of them
/// rejected per ray by two cheap tests, beats a descent from the root of the whole mesh's tree.
/// Keeps a triangle when its bounding box and its plane meet the box grown by a margin (both are
/// necessary for the triangle to meet the box, so none a ray inside the box could hit is
/// dropped); per ray, skips those whose box misses the segment's box or whose plane has both of
/// the segment's ends clearly on one side (again necessary conditions). With more than
/// kMaxTriangles in the box, and for a ray that leaves it, it answers from the whole tree. Hits are
/// TriangleBvh's: the same Möller-Trumbore test on the same triangles.
template <Real T>
class TrianglesInBox {
 public:
  static constexpr std::size_t kMaxTriangles = 128;

  TrianglesInBox(const TriangleBvh<T>& bvh, const Aabb<T>& box) : mBvh(bvh) {
    const Vec3<T> margin = T(1e-9) * (box.extent() + glm::abs(box.min) + glm::abs(box.max));
    const Aabb<T> grown(box.min - margin, box.max + margin);
    const Vec3<T> centre = grown.center(), half = T(0.5) * grown.extent();
    bvh.overlapping(grown, [&](std::uint32_t slot) {
      // Plane against box: the box's corners must not all lie strictly on one side.
      const Vec3<T> n = glm::cross(bvh.edge1(slot), bvh.edge2(slot));
      const T reach = glm::dot(half, glm::abs(n));
      if (std::abs(glm::dot(n, centre - bvh.corner(slot))) <= reach * (1 + T(1e-9)))
        mPlanes.push_back(plane(bvh, slot, n));
      return mPlanes.size() > kMaxTriangles;
    });
    mWholeTree = mPlanes.size() > kMaxTriangles;
    if (mWholeTree) mPlanes = {};
    mBox = grown;
  }

  /// As TriangleBvh::closestHit.
  Hit<T> closestHit(const Ray<T>& ray) const {
    if (mWholeTree) return mBvh.closestHit(ray);
    const Segment segment(ray);
    if (!segment.within(mBox)) return mBvh.closestHit(ray);
    Hit<T> best;
    best.t = ray.tmax;
    for (const Plane& plane : mPlanes)
      if (segment.mayCross(plane)) intersect(ray, plane.slot, best);
    if (!best.valid()) best.t = std::numeric_limits<T>::infinity();
    return best;
  }
  /// As TriangleBvh::anyHit.
  bool anyHit(const Ray<T>& ray, std::uint32_t skip = kInvalidId) const {
    if (mWholeTree) return mBvh.anyHit(ray, skip);
    const Segment segment(ray);
    if (!segment.within(mBox)) return mBvh.anyHit(ray, skip);
    Hit<T> hit;
    hit.t = ray.tmax;
    for (const Plane& plane : mPlanes)
      if (segment.mayCross(plane) && mBvh.triangleId(plane.slot) != skip && intersect(ray, plane.slot, hit))
        return true;
    return false;
  }
  /// As TriangleBvh::closestHitAndNext.
  template <class After>
  FirstAndNextHit<T> closestHitAndNext(const Ray<T>& ray, T within, const After& after) const {
    if (mWholeTree) return mBvh.closestHitAndNext(ray, within, after);
    const Segment segment(ray);
    if (!segment.within(mBox)) return mBvh.closestHitAndNext(ray, within, after);
    detail::NextHitSearch<T, After> search(ray.tmax, within, after);
    T limit = ray.tmax;
    for (const Plane& plane : mPlanes) {
      if (!segment.mayCross(plane)) continue;
      Hit<T> hit;
      hit.t = limit;
      if (intersect(ray, plane.slot, hit)) limit = search.take(hit);
    }
    return search.result(ray, *this);
  }
  std::size_t triangleCount() const { return mWholeTree ? mBvh.triangleCount() : mPlanes.size(); }

 private:
  static T largestMagnitude(const Vec3<T>& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }
  /// A triangle's plane n . x = offset (n unnormalized); a point is surely on one side when
  /// n . x - offset is beyond 1e-9 |n| times the coordinates' size (the corner's and the point's):
  /// far above the rounding of the dot products, far below a cell at any placement tested.
  struct Plane {
    std::uint32_t slot;
    Vec3<T> n;
    T offset, slackPerSize, cornerSize;
    Aabb<T> box;  ///< the triangle's, grown by a millionth of its size
  };
  static Plane plane(const TriangleBvh<T>& bvh, std::uint32_t slot, const Vec3<T>& n) {
    const Vec3<T>& v0 = bvh.corner(slot);
    Aabb<T> box;
    for (const Vec3<T>& p : {v0, v0 + bvh.edge1(slot), v0 + bvh.edge2(slot)}) box.extend(p);
    const T cornerSize = std::max(largestMagnitude(box.min), largestMagnitude(box.max));
    const Vec3<T> margin(T(1e-6) * cornerSize);
    return {slot, n, glm::dot(n, v0), T(1e-9) * glm::length(n), cornerSize, Aabb<T>(box.min - margin, box.max + margin)};
  }
  /// A ray's segment [tmin, tmax]: most triangles of the box lie off the segment's bounding box
  /// or have both its ends on one side of their plane, found before the full test.
  struct Segment {
    Vec3<T> from, to, lo, hi;
    T size;
    explicit Segment(const Ray<T>& ray)
        : from(ray.at(ray.tmin)), to(ray.at(ray.tmax)), lo(glm::min(from, to)), hi(glm::max(from, to)),
          size(std::max(largestMagnitude(from), largestMagnitude(to))) {}
    /// Whether the segment lies in `box` (a box is convex: its two ends do); an infinite ray's
    /// far end is not a point, so it never does.
    bool within(const Aabb<T>& box) const { return box.contains(from) && box.contains(to); }
    bool mayCross(const Plane& plane) const {
      if (lo.x > plane.box.max.x || lo.y > plane.box.max.y || lo.z > plane.box.max.z || hi.x < plane.box.min.x ||
          hi.y < plane.box.min.y || hi.z < plane.box.min.z)
        return false;
      const T a = glm::dot(plane.n, from) - plane.offset, b = glm::dot(plane.n, to) - plane.offset;
      const T slack = plane.slackPerSize * (size + plane.cornerSize);
      return !((a > slack && b > slack) || (a < -slack && b < -slack));
    }
  };

  bool intersect(const Ray<T>& ray, std::uint32_t slot, Hit<T>& hit) const {
    const Vec3<T>& v0 = mBvh.corner(slot);
    return intersectTriangle(ray.origin, ray.direction, ray.tmin, v0, v0 + mBvh.edge1(slot),
                             v0 + mBvh.edge2(slot), mBvh.triangleId(slot), 0u, hit);
  }

  const TriangleBvh<T>& mBvh;
  std::vector<Plane> mPlanes;
  Aabb<T> mBox;
  bool mWholeTree = false;
};

/// A mesh in double precision with its BVH, built once and queried many times: projection
/// segments during conversion, closest points when measuring error.
struct MeshBvh {
  std::vector<Vec3d> positions;
  TriangleBvh<double> bvh;

  explicit MeshBvh(const TriangleMesh& mesh)
      : positions(mesh.positions.begin(), mesh.positions.end()), bvh(positions, mesh.triangles) {}

  /// Whether p is inside the surface: the parity of crossings along three skewed rays, by
  /// majority, so one ray through an edge, a hole or a fold does not decide alone.
  bool contains(const Vec3d& p) const {
    static constexpr double kDirections[3][3] = {
        {0.8721, 0.3917, 0.2933}, {-0.3109, 0.9011, -0.3024}, {0.2687, -0.3301, -0.9049}};
    int insideVotes = 0;
    for (const auto& d : kDirections) {
      Rayd ray(p, Vec3d(d[0], d[1], d[2]));
      int crossings = 0;
      for (int guard = 0; guard < 1 << 16; ++guard) {
        const Hitd hit = bvh.closestHit(ray);
        if (!hit.valid()) break;
        ++crossings;
        ray.tmin = hit.t * (1.0 + 1e-12) + 1e-12;
      }
      insideVotes += crossings & 1;
    }
    return insideVotes >= 2;
  }
};

}  // namespace cellrelief
