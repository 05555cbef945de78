// SPDX-License-Identifier: MIT
/// @file low_discrepancy.h
/// The R2 low-discrepancy sequence (Roberts 2018) and its use for area-uniform points in a
/// triangle: deterministic sampling for estimates that must repeat exactly from run to run.
#pragma once

#include <cmath>
#include <cstddef>

#include "cellrelief/core/math.h"

namespace cellrelief {

inline constexpr double kR2Alpha1 = 0.7548776662466927;  // 1 / g, g the plastic number
inline constexpr double kR2Alpha2 = 0.5698402909980532;  // 1 / g^2

/// The i-th point of the R2 sequence in [0, 1)^2.
inline Vec2d r2Point(std::size_t i) {
  return {std::fmod(0.5 + kR2Alpha1 * double(i), 1.0), std::fmod(0.5 + kR2Alpha2 * double(i), 1.0)};
}

/// A point of [0, 1)^2 folded into the triangle (a, b, c), area-uniformly.
inline Vec3d pointInTriangle(const Vec3d& a, const Vec3d& b, const Vec3d& c, Vec2d r) {
  if (r.x + r.y > 1.0) r = Vec2d(1.0) - r;
  return a + r.x * (b - a) + r.y * (c - a);
}

}  // namespace cellrelief
