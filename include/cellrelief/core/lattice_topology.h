// SPDX-License-Identifier: MIT
/// @file lattice_topology.h
/// What one lattice point changing side does to the topology of a field's zero set, when the
/// field is polygonized by marching tetrahedra over the Kuhn triangulation (marching_tetrahedra.h).
///
/// Why the link decides it: the inside {f > 0} of the piecewise-linear interpolant retracts onto
/// the subcomplex of the triangulation spanned by the inside lattice points, so the surface's
/// topology is that subcomplex's. A point p joining a side cones off the part of its link (a
/// triangulated sphere of 14 neighbours and 24 triangles) on that side, which changes the side's
/// Euler characteristic by 1 - chi(that part). When that part is one circle, the other side's part
/// is two discs: if those two are joined elsewhere on their side, p was the only lattice point in
/// a loop's way, and the move removes exactly one handle (genus - 1, no component gained or lost);
/// if not, it would cut a piece off instead.
#pragma once

#include <array>
#include <cstdint>

#include "cellrelief/core/marching_tetrahedra.h"
#include "cellrelief/core/math.h"

namespace cellrelief {

/// The link of a lattice point in the Kuhn triangulation: its 14 neighbours (the vertices of the
/// 24 tetrahedra around it) and their edges. A set of link vertices is a 14-bit mask in the order
/// of offsets().
class KuhnLink {
 public:
  static constexpr int kSize = 14;
  using Mask = std::uint16_t;
  static constexpr Mask kAll = (1u << kSize) - 1;

  static const std::array<Vec3i, kSize>& offsets() { return tables().offsets; }

  /// True when the link vertices in `mask` span one circle (connected, Euler characteristic 0).
  static bool isCircle(Mask mask) {
    return eulerCharacteristic(mask) == 0 && components(mask, nullptr) == 1;
  }

  /// The Euler characteristic of the part of the link spanned by `mask`.
  static int eulerCharacteristic(Mask mask) {
    const Tables& t = tables();
    int vertices = 0, edges = 0, triangles = 0;
    for (int v = 0; v < kSize; ++v) {
      if (!(mask >> v & 1u)) continue;
      ++vertices;
      edges += __builtin_popcount(unsigned(t.adjacent[std::size_t(v)] & mask));
    }
    for (const auto& tri : t.triangles)
      if ((mask >> tri[0] & 1u) && (mask >> tri[1] & 1u) && (mask >> tri[2] & 1u)) ++triangles;
    return vertices - edges / 2 + triangles;
  }

  /// The connected components of the part spanned by `mask`; when `label` is given, each vertex
  /// of the mask gets its component's number (0, 1, ...) and the others -1.
  static int components(Mask mask, std::array<std::int8_t, kSize>* label) {
    const Tables& t = tables();
    std::array<std::int8_t, kSize> own;
    std::array<std::int8_t, kSize>& l = label ? *label : own;
    l.fill(-1);
    int count = 0;
    for (int seed = 0; seed < kSize; ++seed) {
      if (!(mask >> seed & 1u) || l[std::size_t(seed)] >= 0) continue;
      Mask reached = Mask(1u << seed), frontier = reached;
      while (frontier) {
        Mask next = 0;
        for (int v = 0; v < kSize; ++v)
          if (frontier >> v & 1u) next |= t.adjacent[std::size_t(v)];
        frontier = Mask(next & mask & ~reached);
        reached |= frontier;
      }
      for (int v = 0; v < kSize; ++v)
        if (reached >> v & 1u) l[std::size_t(v)] = std::int8_t(count);
      ++count;
    }
    return count;
  }

 private:
  struct Tables {
    std::array<Vec3i, kSize> offsets{};
    std::array<Mask, kSize> adjacent{};              ///< link edges, per vertex
    std::array<std::array<int, 3>, 24> triangles{};  ///< one per tetrahedron around the point
  };

  /// Built from the triangulation itself: the point is corner c of the 8 cubes around it, and
  /// each of those cubes' tetrahedra that holds corner c contributes its opposite triangle.
  static const Tables& tables() {
    static const Tables t = [] {
      Tables built;
      int vertexCount = 0, triangleCount = 0;
      auto vertexOf = [&](const Vec3i& offset) {
        for (int v = 0; v < vertexCount; ++v)
          if (built.offsets[std::size_t(v)] == offset) return v;
        built.offsets[std::size_t(vertexCount)] = offset;
        return vertexCount++;
      };
      auto corner = [](int k) { return Vec3i(k & 1, (k >> 1) & 1, (k >> 2) & 1); };
      for (int c = 0; c < 8; ++c)
        for (const auto& tet : detail::kKuhnTetrahedra) {
          int own = -1;
          for (int k = 0; k < 4; ++k)
            if (tet[std::size_t(k)] == c) own = k;
          if (own < 0) continue;
          std::array<int, 3>& tri = built.triangles[std::size_t(triangleCount++)];
          for (int k = 0, n = 0; k < 4; ++k)
            if (k != own) tri[std::size_t(n++)] = vertexOf(corner(tet[std::size_t(k)]) - corner(c));
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
              if (a != b)
                built.adjacent[std::size_t(tri[std::size_t(a)])] |= Mask(1u << tri[std::size_t(b)]);
        }
      return built;
    }();
    return t;
  }
};

}  // namespace cellrelief
