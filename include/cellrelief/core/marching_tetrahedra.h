// SPDX-License-Identifier: MIT
/// @file marching_tetrahedra.h
/// The zero set of a field sampled on a cubic lattice, as triangles, by marching tetrahedra over
/// the Kuhn (Freudenthal) triangulation of each lattice cube.
///
/// Why tetrahedra and not marching cubes: the linear interpolant on a tetrahedron has no ambiguous
/// case, and the Kuhn triangulation (six tetrahedra around the diagonal from corner 0 to corner 7)
/// splits every face of a cube along the same diagonal as the neighbouring cube splits it. The
/// pieces of neighbouring cubes therefore meet edge to edge: when every lattice point has one
/// value, every cube with a sign change is polygonized, and "inside" is strictly f > 0, the result
/// is a closed, consistently oriented 2-manifold (the level set of a piecewise-linear function at
/// a regular value). Vertices lie on the lattice edges of the triangulation, so a caller welds them
/// by edge (latticeEdgeKey), never by position.
///
/// Corners of a cube are numbered by their offset: bit 0 = x, bit 1 = y, bit 2 = z.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

#include "cellrelief/core/math.h"

namespace cellrelief {

/// One edge of the triangulation inside a cube, from an inside corner to an outside one.
struct CubeEdge {
  std::uint8_t inside = 0;
  std::uint8_t outside = 0;
};

/// The triangles of one cube's sign pattern, wound so that their normals point outside (towards
/// f <= 0) by the right-hand rule.
struct CubeTriangles {
  std::array<std::array<CubeEdge, 3>, 12> triangles{};
  int count = 0;
};

namespace detail {

/// The six tetrahedra of the Kuhn triangulation: the monotone paths 0 -> 7 along the axes.
inline constexpr std::array<std::array<int, 4>, 6> kKuhnTetrahedra{
    {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};

/// Small integer vectors of the table's construction (GLM's are not constexpr).
struct Int3 {
  int x = 0, y = 0, z = 0;
  constexpr Int3 operator+(const Int3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Int3 operator-(const Int3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Int3 operator*(int s) const { return {x * s, y * s, z * s}; }
  constexpr int dot(const Int3& o) const { return x * o.x + y * o.y + z * o.z; }
  constexpr Int3 cross(const Int3& o) const { return {y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x}; }
};

constexpr Int3 cornerOffset(int corner) { return {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1}; }

/// Twice the midpoint of an edge (integer arithmetic: the orientation test below is exact).
constexpr Int3 doubledMidpoint(const CubeEdge& e) { return cornerOffset(e.inside) + cornerOffset(e.outside); }

/// Appends the triangle, flipped if its normal (measured at the edge midpoints, where no
/// triangle is degenerate) does not point from the inside corners towards the outside ones.
constexpr void appendOriented(CubeTriangles& out, CubeEdge a, CubeEdge b, CubeEdge c,
                              const Int3& insideToOutside) {
  const Int3 pa = doubledMidpoint(a), pb = doubledMidpoint(b), pc = doubledMidpoint(c);
  const int facing = (pb - pa).cross(pc - pa).dot(insideToOutside);
  out.triangles[out.count++] = facing > 0 ? std::array<CubeEdge, 3>{a, b, c} : std::array<CubeEdge, 3>{a, c, b};
}

/// The triangles of one tetrahedron for the sign pattern `insideMask` of its four corners.
constexpr void polygonizeTetrahedron(CubeTriangles& out, const std::array<int, 4>& corner, int insideMask) {
  int in[4]{}, outCorners[4]{}, nIn = 0, nOut = 0;
  for (int k = 0; k < 4; ++k) {
    if (insideMask & (1 << k)) in[nIn++] = corner[k];
    else outCorners[nOut++] = corner[k];
  }
  if (nIn == 0 || nOut == 0) return;
  // Direction from the inside corners' centroid to the outside ones' (times nIn * nOut).
  Int3 insideSum, outsideSum;
  for (int k = 0; k < nIn; ++k) insideSum = insideSum + cornerOffset(in[k]);
  for (int k = 0; k < nOut; ++k) outsideSum = outsideSum + cornerOffset(outCorners[k]);
  const Int3 direction = outsideSum * nIn - insideSum * nOut;
  auto edge = [](int i, int o) { return CubeEdge{std::uint8_t(i), std::uint8_t(o)}; };
  if (nIn == 1) {
    appendOriented(out, edge(in[0], outCorners[0]), edge(in[0], outCorners[1]), edge(in[0], outCorners[2]), direction);
  } else if (nOut == 1) {
    appendOriented(out, edge(in[0], outCorners[0]), edge(in[1], outCorners[0]), edge(in[2], outCorners[0]), direction);
  } else {
    // Two and two: a quad whose corners, in order, share an inside or an outside corner in turn.
    const CubeEdge q0 = edge(in[0], outCorners[0]), q1 = edge(in[0], outCorners[1]),
                   q2 = edge(in[1], outCorners[1]), q3 = edge(in[1], outCorners[0]);
    appendOriented(out, q0, q1, q2, direction);
    appendOriented(out, q0, q2, q3, direction);
  }
}

constexpr std::array<CubeTriangles, 256> makeCubeTable() {
  std::array<CubeTriangles, 256> table{};
  for (int mask = 0; mask < 256; ++mask)
    for (const auto& tet : kKuhnTetrahedra) {
      int tetMask = 0;
      for (int k = 0; k < 4; ++k)
        if (mask & (1 << tet[k])) tetMask |= 1 << k;
      polygonizeTetrahedron(table[mask], tet, tetMask);
    }
  return table;
}

}  // namespace detail

/// Triangles of every sign pattern of a cube: bit c of the index is set when corner c is inside.
inline constexpr std::array<CubeTriangles, 256> kMarchingTetrahedraTable = detail::makeCubeTable();

/// The sign pattern of a cube's corner values: inside is strictly f > 0.
inline int insideMask(const std::array<float, 8>& values) {
  int mask = 0;
  for (int c = 0; c < 8; ++c)
    if (values[c] > 0.0f) mask |= 1 << c;
  return mask;
}

/// The offset of cube corner c from corner 0.
inline Vec3i cubeCorner(int c) { return {c & 1, (c >> 1) & 1, (c >> 2) & 1}; }

/// A key for the lattice edge of the triangulation between cube corners a and b of the cube whose
/// corner 0 is lattice point `base` (coordinates below 2^20): the lower end point and the edge's
/// direction (a non-zero 0/1 vector; every edge of the Kuhn triangulation is monotone).
inline std::uint64_t latticeEdgeKey(const Vec3i& base, int a, int b) {
  const Vec3i pa = base + cubeCorner(a), pb = base + cubeCorner(b);
  const Vec3i lower = glm::min(pa, pb);
  const Vec3i direction = glm::abs(pb - pa);
  return (std::uint64_t(lower.x) << 43) | (std::uint64_t(lower.y) << 23) | (std::uint64_t(lower.z) << 3) |
         std::uint64_t(direction.x | (direction.y << 1) | (direction.z << 2));
}

/// Where the linear interpolant crosses zero on the edge from an inside value (> 0) to an outside
/// one (<= 0), as a fraction of the way from the inside end, kept off the end points by
/// `margin` so that vertices on different edges never coincide.
inline float zeroCrossing(float inside, float outside, float margin = 0.01f) {
  const float t = inside / (inside - outside);
  return std::clamp(t, margin, 1.0f - margin);
}

}  // namespace cellrelief
