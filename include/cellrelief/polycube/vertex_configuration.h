// SPDX-License-Identifier: MIT
/// @file vertex_configuration.h
/// The configurations of a polycube's surface around one lattice vertex (Tarini et al. 2004,
/// section 4), as compile-time tables.
///
/// PolyCube-Maps cut space into unit cells centred at the polycube's lattice vertices (dual cells).
/// The surface inside the dual cell of vertex v depends only on which of the eight unit cubes
/// around v (its octants) belong to the polycube: an 8-bit configuration, bit o set for octant o =
/// x + 2y + 4z, the cube whose minimum corner is v - (1, 1, 1) + (x, y, z). The surface there is
/// made of squarelets: each face between an octant in the polycube and a face-adjacent octant
/// outside it, a half-unit square with one corner at v (12 are possible).
///
/// The surface is a 2-manifold at v when the octants inside and the octants outside are each
/// face-connected within the block (two cubes that share only an edge or a corner are not). A
/// configuration and its complement have the same squarelets, so the 126 manifold configurations
/// are 63 surfaces, and the 48 symmetries of the cube (24 rotations, each with or without a
/// reflection) reduce them to six basic cases named by their squarelet count:
///
/// | case | canonical octants | surfaces | shape |
/// |---|---|---|---|
/// | 3  | 0                | 8  | a corner (convex or concave) |
/// | 4a | 0 1 2 3          | 3  | a flat vertex |
/// | 4b | 0 1              | 12 | a vertex on a straight edge |
/// | 5  | 0 1 2            | 24 | where an edge turns into a flat region (an L of cubes) |
/// | 6a | 0 1 2 4          | 4  | a saddle of three edges (a tetrapod of cubes) |
/// | 6b | 0 1 3 7          | 12 | a saddle of two edges (a skew path of cubes) |
///
/// Case 6b is chiral: a rotation cannot turn the skew path 0-1-3-7 into its mirror image 0-2-3-7,
/// so half of its surfaces need a reflection. The paper's 5 bits hold the 24 rotations; a sixth
/// bit here holds the reflection (transform indices 24-47), which only case 6b needs (the
/// paper's shader left 6a and 6b out).
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include "cellrelief/cells/configuration.h"
#include "cellrelief/core/math.h"

namespace cellrelief::polycube {

enum class VertexCase : std::uint8_t { k3, k4a, k4b, k5, k6a, k6b };
inline constexpr int kVertexCaseCount = 6;
inline constexpr std::array<std::string_view, kVertexCaseCount> kVertexCaseNames{"3", "4a", "4b",
                                                                                  "5", "6a", "6b"};
constexpr std::string_view toString(VertexCase c) { return kVertexCaseNames[static_cast<int>(c)]; }

/// Octants of the canonical configuration of each case (the table above).
inline constexpr std::array<std::uint8_t, kVertexCaseCount> kCanonicalOctants{
    0b00000001,  // 3:  0
    0b00001111,  // 4a: 0 1 2 3 (the z- layer)
    0b00000011,  // 4b: 0 1
    0b00000111,  // 5:  0 1 2
    0b00010111,  // 6a: 0 1 2 4
    0b10001011,  // 6b: 0 1 3 7
};

/// Direction from the vertex to the centre of octant o, as signs: (2x - 1, 2y - 1, 2z - 1).
constexpr Vec3i octantDirection(int octant) {
  return {(octant & 1) ? 1 : -1, (octant & 2) ? 1 : -1, (octant & 4) ? 1 : -1};
}
constexpr int octantOf(const Vec3i& direction) {
  return (direction.x > 0 ? 1 : 0) | (direction.y > 0 ? 2 : 0) | (direction.z > 0 ? 4 : 0);
}

/// A symmetry of the cube: transform s < 24 is cells::kRotations[s]; s >= 24 is kRotations[s - 24]
/// after the reflection x -> -x. It maps a direction (or a point relative to the vertex) d to the
/// transformed one.
template <class V>
constexpr V applyTransformTo(int transform, V d) {
  if (transform >= 24) d.x = -d.x;
  return cells::kRotations[transform % 24].apply(d);
}
constexpr Vec3i applyTransform(int transform, const Vec3i& d) { return applyTransformTo(transform, d); }
template <Real T>
Vec3<T> applyTransform(int transform, const Vec3<T>& d) { return applyTransformTo(transform, d); }
/// The inverse (a signed permutation: its transpose, then the reflection).
template <Real T>
Vec3<T> applyInverseTransform(int transform, const Vec3<T>& d) {
  Vec3<T> r = cells::kRotations[transform % 24].inverse().apply(d);
  if (transform >= 24) r.x = -r.x;
  return r;
}
inline constexpr int kTransformCount = 48;

constexpr std::uint8_t transformOctants(std::uint8_t octants, int transform) {
  std::uint8_t out = 0;
  for (int o = 0; o < 8; ++o)
    if (octants & (1u << o)) out |= std::uint8_t(1u << octantOf(applyTransform(transform, octantDirection(o))));
  return out;
}

/// Squarelet index: the face between octants o and o ^ (1 << axis), with o's bit on that axis 0;
/// index = 4 * axis + the two other bits of o (lower axis first). It lies in the plane through the
/// vertex normal to `axis`, on the side of the other two axes that o's bits say.
constexpr int squareletIndex(int octant, int axis) {
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const int lo = a < b ? a : b, hi = a < b ? b : a;
  return 4 * axis + ((octant >> lo) & 1) + 2 * ((octant >> hi) & 1);
}

/// Squarelet `index` as a box relative to the vertex: zero thickness on its axis, [0, 1/2] or
/// [-1/2, 0] on the other two as its index's bits say (the inverse of squareletIndex).
struct SquareletBounds {
  int axis = 0;
  Vec3d min{0.0}, max{0.0};
};
inline SquareletBounds squareletBounds(int index) {
  SquareletBounds box;
  box.axis = index / 4;
  const int a = (box.axis + 1) % 3, b = (box.axis + 2) % 3;
  const int lo = a < b ? a : b, hi = a < b ? b : a;
  (index & 1 ? box.max : box.min)[lo] = (index & 1) ? 0.5 : -0.5;
  (index & 2 ? box.max : box.min)[hi] = (index & 2) ? 0.5 : -0.5;
  return box;
}

/// The 12-bit mask of the squarelets of a configuration.
constexpr std::uint16_t squareletMask(std::uint8_t octants) {
  std::uint16_t mask = 0;
  for (int o = 0; o < 8; ++o)
    for (int axis = 0; axis < 3; ++axis) {
      const int n = o ^ (1 << axis);
      if (((octants >> o) & 1) != ((octants >> n) & 1)) mask |= std::uint16_t(1u << squareletIndex(o & ~(1 << axis), axis));
    }
  return mask;
}

constexpr int popcount8(unsigned v) {
  int n = 0;
  for (; v; v &= v - 1) ++n;
  return n;
}

/// Whether the octants of `set` are face-connected within the block (an empty set is not).
constexpr bool faceConnected(std::uint8_t set) {
  if (set == 0) return false;
  std::uint8_t reached = std::uint8_t(set & -set), previous = 0;
  while (reached != previous) {
    previous = reached;
    for (int o = 0; o < 8; ++o)
      if (reached & (1u << o))
        for (int axis = 0; axis < 3; ++axis) {
          const int n = o ^ (1 << axis);
          if (set & (1u << n)) reached |= std::uint8_t(1u << n);
        }
  }
  return reached == set;
}

/// Whether the surface is a 2-manifold at a vertex with this configuration (0 and 255: no surface).
constexpr bool isManifold(std::uint8_t octants) {
  return octants == 0 || octants == 255 ||
         (faceConnected(octants) && faceConnected(std::uint8_t(~octants)));
}

struct VertexConfigurationInfo {
  bool surface = false;       ///< some squarelet lies here (octants neither 0 nor 255)
  bool manifold = false;      ///< the surface is a 2-manifold here
  VertexCase vertexCase = VertexCase::k3;
  std::uint8_t transform = 0;  ///< the lowest s: transformOctants(canonical, s) is the configuration or its complement
  bool complement = false;     ///< the transformed canonical octants are the complement (outside)
  std::uint16_t squarelets = 0;
};

namespace detail {
/// Each transform as a permutation of the octants (cheap to apply at compile time).
constexpr std::array<std::array<std::uint8_t, 8>, kTransformCount> makeOctantPermutations() {
  std::array<std::array<std::uint8_t, 8>, kTransformCount> table{};
  for (int s = 0; s < kTransformCount; ++s)
    for (int o = 0; o < 8; ++o) table[s][o] = std::uint8_t(octantOf(applyTransform(s, octantDirection(o))));
  return table;
}

constexpr std::array<VertexConfigurationInfo, 256> makeVertexConfigurationTable() {
  constexpr auto permutations = makeOctantPermutations();
  std::array<VertexConfigurationInfo, 256> table{};
  std::array<bool, 256> assigned{};
  for (int c = 0; c < 256; ++c) {
    table[c].surface = c != 0 && c != 255;
    table[c].manifold = isManifold(std::uint8_t(c));
    table[c].squarelets = squareletMask(std::uint8_t(c));
  }
  // The lowest transform first, then the lowest case: each configuration keeps the first match.
  for (int s = 0; s < kTransformCount; ++s)
    for (int k = 0; k < kVertexCaseCount; ++k) {
      std::uint8_t t = 0;
      for (int o = 0; o < 8; ++o)
        if (kCanonicalOctants[k] & (1u << o)) t |= std::uint8_t(1u << permutations[s][o]);
      for (const bool complement : {false, true}) {
        const std::uint8_t c = complement ? std::uint8_t(~t) : t;
        if (assigned[c]) continue;
        assigned[c] = true;
        table[c].vertexCase = static_cast<VertexCase>(k);
        table[c].transform = std::uint8_t(s);
        table[c].complement = complement;
      }
    }
  return table;
}
}  // namespace detail

/// Case, transform and squarelets of each of the 256 configurations.
inline constexpr std::array<VertexConfigurationInfo, 256> kVertexConfigurations =
    detail::makeVertexConfigurationTable();

}  // namespace cellrelief::polycube
