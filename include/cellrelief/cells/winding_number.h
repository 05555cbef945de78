// SPDX-License-Identifier: MIT
/// @file winding_number.h
/// Generalized winding number (Jacobson et al. 2013): the sum of the signed solid angles of the
/// triangles seen from a point, over 4 pi. It is 1 inside and 0 outside a closed, outward-oriented
/// mesh, and degrades gracefully for open, non-manifold and self-intersecting ones (about 1/2 near
/// a hole, 2 where two shells overlap), which is why inside/outside tests use it.
#pragma once

#include <cmath>
#include <numbers>
#include <span>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "cellrelief/core/math.h"

namespace cellrelief::cells {

/// Signed solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee).
inline double solidAngle(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
  const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
  const double numerator = glm::dot(a, glm::cross(b, c));
  const double denominator =
      la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
  return 2.0 * std::atan2(numerator, denominator);
}

/// Winding number of point p with respect to the triangles (positions as double), in parallel.
inline double windingNumber(std::span<const Vec3d> positions, std::span<const Vec3u> triangles,
                            const Vec3d& p) {
  const double sum = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, triangles.size(), 4096), 0.0,
      [&](const tbb::blocked_range<std::size_t>& r, double acc) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          const Vec3u& t = triangles[i];
          acc += solidAngle(positions[t[0]] - p, positions[t[1]] - p, positions[t[2]] - p);
        }
        return acc;
      },
      [](double x, double y) { return x + y; });
  return sum / (4.0 * std::numbers::pi);
}

}  // namespace cellrelief::cells
