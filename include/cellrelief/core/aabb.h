// SPDX-License-Identifier: MIT
/// @file aabb.h
/// Axis-aligned box and a robust ray/box slab test. Robust means: a ray parallel to a slab is
/// decided by its origin (its infinities, and the NaN of an origin on the slab's plane, never
/// pass a comparison), a ray starting on a face or grazing it hits (boxes are
/// closed), and the far distance is widened by roundingGamma(3) so that rounding never opens a gap
/// between neighbouring cells during traversal (Ize, "Robust BVH Ray Traversal", JCGT 2013).
#pragma once

#include <algorithm>
#include <cmath>
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

/// The slab test against closed boxes, set up once per ray for many boxes (a BVH's descent) and
/// without branches. Each axis' near plane is chosen by the sign of the inverse direction; an axis
/// the ray runs parallel to gives +-infinity (origin off the slab: no entry) or NaN (origin on a
/// plane of it), which the comparisons ignore: inside the closed slab, no constraint. The far
/// distance is widened by the rounding of its three operations, so a ray through an edge or a
/// corner (or along a face) enters.
template <Real T>
class RaySlabs {
 public:
  explicit RaySlabs(const Ray<T>& ray) : mOrigin(ray.origin), mInv(ray.invDirection) {
    for (int a = 0; a < 3; ++a) mNearIsMax[a] = std::signbit(mInv[a]);
  }
  /// Clips [tmin, tmax] to the box; whether anything is left (an entry at infinity is none).
  bool clip(const Aabb<T>& box, T& tmin, T& tmax) const {
    constexpr T kFarMargin = T(1) + 2 * roundingGamma<T>(3);
    for (int a = 0; a < 3; ++a) {
      const T nearPlane = mNearIsMax[a] ? box.max[a] : box.min[a];
      const T farPlane = mNearIsMax[a] ? box.min[a] : box.max[a];
      const T tNear = (nearPlane - mOrigin[a]) * mInv[a];
      const T tFar = (farPlane - mOrigin[a]) * mInv[a] * kFarMargin;
      tmin = tNear > tmin ? tNear : tmin;
      tmax = tFar < tmax ? tFar : tmax;
    }
    return tmin <= tmax && tmin < std::numeric_limits<T>::infinity();
  }
  /// Whether the ray meets `box` within [tmin, tmax]; entry: where it enters.
  bool enters(const Aabb<T>& box, T tmin, T tmax, T& entry) const {
    const bool inside = clip(box, tmin, tmax);
    entry = tmin;
    return inside;
  }

 private:
  Vec3<T> mOrigin, mInv;
  bool mNearIsMax[3];
};

/// Entry and exit of a ray through the closed box within [ray.tmin, ray.tmax] (RaySlabs).
template <Real T>
RayInterval<T> intersect(const Ray<T>& ray, const Aabb<T>& box) {
  T t0 = ray.tmin, t1 = ray.tmax;
  if (!RaySlabs<T>(ray).clip(box, t0, t1)) return {};
  return {t0, t1, true};
}

}  // namespace cellrelief
