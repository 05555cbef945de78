// SPDX-License-Identifier: MIT
/// @file ray.h
/// A ray with its parameter interval and precomputed inverse direction. The inverse is stored
/// because every traversal step (slab tests, grid DDA) divides by the direction; a zero component
/// gives a signed infinity, which the slab test in aabb.h handles explicitly.
#pragma once

#include <limits>

#include "cellrelief/core/math.h"

namespace cellrelief {

template <Real T>
struct Ray {
  Vec3<T> origin{0};
  Vec3<T> direction{0, 0, 1};
  T tmin = 0;
  T tmax = std::numeric_limits<T>::infinity();
  Vec3<T> invDirection{std::numeric_limits<T>::infinity(), std::numeric_limits<T>::infinity(), 1};

  Ray() = default;
  Ray(const Vec3<T>& o, const Vec3<T>& d, T t0 = T(0),
      T t1 = std::numeric_limits<T>::infinity())
      : origin(o), tmin(t0), tmax(t1) {
    setDirection(d);
  }

  /// Sets the direction and recomputes its inverse (1/±0 gives ±infinity, as IEEE defines).
  void setDirection(const Vec3<T>& d) {
    direction = d;
    invDirection = Vec3<T>(T(1) / d.x, T(1) / d.y, T(1) / d.z);
  }

  Vec3<T> at(T t) const { return origin + t * direction; }
};

using Rayf = Ray<float>;
using Rayd = Ray<double>;

/// gamma(n) of Pharr et al.: a bound on the relative error of n floating-point operations, used to
/// widen intervals so that a ray never slips between two boxes that share a face.
template <Real T>
constexpr T roundingGamma(int n) {
  constexpr T eps = std::numeric_limits<T>::epsilon() / 2;
  return (T(n) * eps) / (T(1) - T(n) * eps);
}

}  // namespace cellrelief
