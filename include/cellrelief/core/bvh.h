// SPDX-License-Identifier: MIT
/// @file bvh.h
/// A bounding volume hierarchy over triangles, for the CPU-side ray queries of conversion (is this
/// projection segment blocked? where does this texel's projection line meet the surface?). Median
/// split on the longest centroid axis, four triangles per leaf, triangles stored in leaf order as
/// (v0, e1, e2) so a leaf reads contiguous memory. Verification uses Embree instead; this is the
/// library's own, dependency-free structure.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <span>
#include <vector>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/error.h"
#include "cellrelief/core/hit.h"

namespace cellrelief {

template <Real T>
class TriangleBvh {
 public:
  static constexpr int kLeafSize = 4;

  TriangleBvh() = default;
  TriangleBvh(std::span<const Vec3<T>> positions, std::span<const Vec3u> triangles) {
    const std::size_t n = triangles.size();
    if (n >= (1u << 31)) throw Error(ErrorKind::ResourceLimit, "too many triangles for the BVH");
    std::vector<std::uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    std::vector<Vec3<T>> centroids(n);
    std::vector<Aabb<T>> boxes(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3u& t = triangles[i];
      boxes[i].extend(positions[t[0]]);
      boxes[i].extend(positions[t[1]]);
      boxes[i].extend(positions[t[2]]);
      centroids[i] = boxes[i].center();
    }
    mNodes.reserve(n > 0 ? 2 * (n / kLeafSize + 1) : 1);
    if (n > 0) build(order, 0, std::uint32_t(n), centroids, boxes);
    mV0.resize(n);
    mE1.resize(n);
    mE2.resize(n);
    mIds = order;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3u& t = triangles[order[i]];
      mV0[i] = positions[t[0]];
      mE1[i] = positions[t[1]] - positions[t[0]];
      mE2[i] = positions[t[2]] - positions[t[0]];
    }
  }

  std::size_t triangleCount() const { return mIds.size(); }
  std::size_t nodeCount() const { return mNodes.size(); }

  /// True when the ray meets a triangle other than `skip` with t in [tmin, tmax].
  bool anyHit(const Ray<T>& ray, std::uint32_t skip = kInvalidId) const {
    bool found = false;
    traverse(ray, [&](std::uint32_t i, Hit<T>& hit) {
      if (mIds[i] == skip) return false;
      if (intersectPrim(ray, i, hit)) found = true;
      return found;
    });
    return found;
  }

  /// The nearest hit with t in [tmin, tmax] (hit.valid() is false when there is none); primId is
  /// the index of the triangle in the input.
  Hit<T> closestHit(const Ray<T>& ray, std::uint32_t skip = kInvalidId) const {
    Hit<T> best;
    best.t = ray.tmax;
    traverse(ray, [&](std::uint32_t i, Hit<T>& hit) {
      if (mIds[i] != skip) intersectPrim(ray, i, hit);
      return false;
    }, &best);
    if (!best.valid()) best.t = std::numeric_limits<T>::infinity();
    return best;
  }

 private:
  struct Node {
    Aabb<T> box;
    std::uint32_t first = 0;  // leaf: first primitive; inner: index of the right child
    std::uint32_t count = 0;  // leaf: number of primitives; inner: 0 (left child follows)
  };

  std::uint32_t build(std::vector<std::uint32_t>& order, std::uint32_t begin, std::uint32_t end,
                      const std::vector<Vec3<T>>& centroids, const std::vector<Aabb<T>>& boxes) {
    const std::uint32_t index = std::uint32_t(mNodes.size());
    mNodes.emplace_back();
    Aabb<T> box, centroidBox;
    for (std::uint32_t i = begin; i < end; ++i) {
      box.extend(boxes[order[i]]);
      centroidBox.extend(centroids[order[i]]);
    }
    mNodes[index].box = box;
    const Vec3<T> extent = centroidBox.extent();
    if (end - begin <= kLeafSize || std::max({extent.x, extent.y, extent.z}) <= T(0)) {
      mNodes[index].first = begin;
      mNodes[index].count = end - begin;
      return index;
    }
    const int axis = maxDimension(extent);
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                     [&](std::uint32_t a, std::uint32_t b) {
                       return centroids[a][axis] < centroids[b][axis];
                     });
    build(order, begin, mid, centroids, boxes);
    const std::uint32_t right = build(order, mid, end, centroids, boxes);
    mNodes[index].first = right;
    mNodes[index].count = 0;
    return index;
  }

  bool intersectPrim(const Ray<T>& ray, std::uint32_t i, Hit<T>& hit) const {
    const std::uint32_t id = mIds[i];
    const T before = hit.t;
    intersectTriangle(ray.origin, ray.direction, ray.tmin, mV0[i], mV0[i] + mE1[i],
                      mV0[i] + mE2[i], id, 0u, hit);
    return hit.t < before;
  }

  /// Visits leaf primitives whose boxes the ray reaches before `hit.t`; `visit` returns true to stop.
  template <class Visit>
  void traverse(const Ray<T>& ray, Visit&& visit, Hit<T>* external = nullptr) const {
    if (mNodes.empty()) return;
    Hit<T> local;
    local.t = ray.tmax;
    Hit<T>& hit = external ? *external : local;
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = mNodes[stack[--top]];
      Ray<T> clipped = ray;
      clipped.tmax = hit.t;
      if (!intersect(clipped, node.box).hit) continue;
      if (node.count > 0) {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
          if (visit(i, hit)) return;
        continue;
      }
      const std::uint32_t left = std::uint32_t(&node - mNodes.data()) + 1;
      stack[top++] = node.first;
      stack[top++] = left;
    }
  }

  std::vector<Node> mNodes;
  std::vector<Vec3<T>> mV0, mE1, mE2;
  std::vector<std::uint32_t> mIds;
};

}  // namespace cellrelief
