// SPDX-License-Identifier: MIT
/// @file triangle_box.h
/// Exact triangle / closed-box overlap on fixed-point coordinates.
///
/// Why fixed point: an exact test on floating-point input needs adaptive-precision predicates.
/// Instead, vertices are snapped once to a lattice of 2^-kFractionBits cell units in index space
/// (a vertex moves by at most 2^-21 of a cell), and the 13-axis separating-axis test of
/// Akenine-Moller then runs in 128-bit integer arithmetic without any rounding. The verification
/// against CGAL passes CGAL the same snapped coordinates, so "exact" means exact for them.
///
/// Tie rule: cells are closed boxes. A triangle that touches a cell (lies in one of its faces, runs
/// along an edge, passes through a corner, or has a vertex on a grid point) overlaps it, exactly as
/// CGAL's do_intersect(Triangle_3, Iso_cuboid_3) decides. A surface lying in a grid plane therefore
/// makes the cells on both sides grey.
#pragma once

#include <algorithm>
#include <cstdint>

#include "cellrelief/core/math.h"

namespace cellrelief::cells {

/// Fraction bits of the fixed-point lattice; with grid sizes up to kMaxGridSize (2^10) every
/// coordinate fits 30 bits, so products of three differences fit a signed 128-bit integer.
inline constexpr int kFractionBits = 20;
inline constexpr int kMaxGridSize = 1024;
inline constexpr std::int64_t kCellUnits = std::int64_t(1) << kFractionBits;

using FixedPoint3 = glm::vec<3, std::int64_t, glm::defaultp>;
__extension__ typedef __int128 Int128;  // GCC and Clang on 64-bit targets

namespace detail {
inline Int128 dot128(const FixedPoint3& a, const FixedPoint3& b) {
  return Int128(a.x) * b.x + Int128(a.y) * b.y + Int128(a.z) * b.z;
}
}  // namespace detail

/// Overlap of the triangle (v0, v1, v2) with the closed box [lo, hi], all in fixed point.
inline bool triangleOverlapsBox(const FixedPoint3& v0, const FixedPoint3& v1,
                                const FixedPoint3& v2, const FixedPoint3& lo,
                                const FixedPoint3& hi) {
  // Work relative to the box corner: coordinates stay below 2^32 in magnitude.
  const FixedPoint3 a = v0 - lo, b = v1 - lo, c = v2 - lo, size = hi - lo;
  // 1-3: the box's face normals.
  for (int i = 0; i < 3; ++i) {
    if (std::max({a[i], b[i], c[i]}) < 0 || std::min({a[i], b[i], c[i]}) > size[i]) return false;
  }
  const FixedPoint3 edges[3] = {b - a, c - b, a - c};
  // Projections of the box [0, size] onto an axis: the interval spanned by its corners.
  auto boxInterval = [&](const FixedPoint3& n, Int128& bmin, Int128& bmax) {
    bmin = bmax = 0;
    for (int i = 0; i < 3; ++i) {
      const Int128 t = Int128(n[i]) * size[i];
      if (t < 0) bmin += t; else bmax += t;
    }
  };
  auto separated = [&](const FixedPoint3& n) {
    const Int128 pa = detail::dot128(n, a), pb = detail::dot128(n, b), pc = detail::dot128(n, c);
    Int128 bmin, bmax;
    boxInterval(n, bmin, bmax);
    return std::max({pa, pb, pc}) < bmin || std::min({pa, pb, pc}) > bmax;
  };
  // 4-12: cross products of the box axes with the triangle edges (components below 2^33).
  for (const FixedPoint3& e : edges) {
    if (separated(FixedPoint3(0, -e.z, e.y))) return false;
    if (separated(FixedPoint3(e.z, 0, -e.x))) return false;
    if (separated(FixedPoint3(-e.y, e.x, 0))) return false;
  }
  // 13: the triangle's normal (components below 2^65: kept in 128 bits).
  const FixedPoint3& e0 = edges[0];
  const FixedPoint3 e1 = c - a;
  const Int128 nx = Int128(e0.y) * e1.z - Int128(e0.z) * e1.y;
  const Int128 ny = Int128(e0.z) * e1.x - Int128(e0.x) * e1.z;
  const Int128 nz = Int128(e0.x) * e1.y - Int128(e0.y) * e1.x;
  const Int128 d = nx * a.x + ny * a.y + nz * a.z;  // below 2^98
  Int128 bmin = 0, bmax = 0;
  const Int128 terms[3] = {nx * size.x, ny * size.y, nz * size.z};
  for (const Int128 t : terms) {
    if (t < 0) bmin += t; else bmax += t;
  }
  return !(d < bmin || d > bmax);
}

}  // namespace cellrelief::cells
