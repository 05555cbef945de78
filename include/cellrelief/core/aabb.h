// SPDX-License-Identifier: MIT
/// @file aabb.h
/// Axis-aligned box and a robust ray/box slab test. Robust means: a ray parallel to a slab is
/// decided by its origin (no 0 * inf = NaN), a ray starting on a face or grazing it hits (boxes are
/// closed), and the far distance is widened by roundingGamma(3) so that rounding never opens a gap
/// between neighbouring cells during traversal (Ize, "Robust BVH Ray Traversal", JCGT 2013).
#pragma once

#include <algorithm>
#include <limits>
#include <utility>

#include "cellrelief/core/math.h"
#include "cellrelief/core/ray.h"

namespace cellrelief {

template <Real T>
struct Aabb {
  /// The empty box: min = +inf, max = -inf, so that extend() of any point gives that point.
  Vec3<T> min{std::numeric_limits<T>::infinity()};
  Vec3<T> max{-std::numeric_limits<T>::infinity()};

  Aabb() = default;
  Aabb(const Vec3<T>& lo, const Vec3<T>& hi) : min(lo), max(hi) {}

  bool isEmpty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  void extend(const Vec3<T>& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  void extend(const Aabb& b) {
    min = glm::min(min, b.min);
    max = glm::max(max, b.max);
  }
  Vec3<T> center() const { return (min + max) * T(0.5); }
  Vec3<T> extent() const { return max - min; }
  T diagonal() const { return isEmpty() ? T(0) : glm::length(extent()); }
  /// Closed-box containment: points on faces are inside.
  bool contains(const Vec3<T>& p) const {
    return p.x >= min.x && p.y >= min.y && p.z >= min.z && p.x <= max.x && p.y <= max.y &&
           p.z <= max.z;
  }
  /// The smallest cube with the same centre that contains this box, grown by `margin` (relative to
  /// the longest side) on every side: the domain of an N^3 cell grid.
  Aabb boundingCube(T margin = T(0)) const {
    const Vec3<T> c = center();
    const Vec3<T> e = extent();
    const T half = std::max({e.x, e.y, e.z}) * (T(0.5) + margin);
    return Aabb(c - Vec3<T>(half), c + Vec3<T>(half));
  }
};

using Aabbf = Aabb<float>;
using Aabbd = Aabb<double>;

/// Entry and exit distance of a ray through a box, clipped to [ray.tmin, ray.tmax].
template <Real T>
struct RayInterval {
  T t0 = std::numeric_limits<T>::infinity();
  T t1 = -std::numeric_limits<T>::infinity();
  bool hit = false;
};

/// Slab test against the closed box. A direction component that is exactly zero is decided by the
/// origin alone; otherwise the two slab distances are computed with the precomputed inverse.
template <Real T>
RayInterval<T> intersect(const Ray<T>& ray, const Aabb<T>& box) {
  T t0 = ray.tmin;
  T t1 = ray.tmax;
  for (int a = 0; a < 3; ++a) {
    if (ray.direction[a] == T(0)) {
      if (ray.origin[a] < box.min[a] || ray.origin[a] > box.max[a]) return {};
      continue;
    }
    T tNear = (box.min[a] - ray.origin[a]) * ray.invDirection[a];
    T tFar = (box.max[a] - ray.origin[a]) * ray.invDirection[a];
    if (tNear > tFar) std::swap(tNear, tFar);
    tFar *= T(1) + 2 * roundingGamma<T>(3);
    t0 = tNear > t0 ? tNear : t0;
    t1 = tFar < t1 ? tFar : t1;
    if (t0 > t1) return {};
  }
  return {t0, t1, true};
}

}  // namespace cellrelief
