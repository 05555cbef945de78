// SPDX-License-Identifier: MIT
/// @file polycube.h
/// A polycube: unit cubes on the integer lattice, the texture domain of PolyCube-Maps (Tarini et
/// al. 2004). Cube c occupies [c, c + 1]^3 in lattice units; where the polycube sits in world space
/// is the `PolycubeFrame` beside it (origin and cube size), so the cubes stay exact integers.
///
/// What the maps need of it, checked here: its surface is a closed 2-manifold (every lattice
/// vertex has one of the 126 manifold configurations of vertex_configuration.h), it is one piece,
/// and its genus is the mesh's. `makeManifold` repairs a cube set that touches itself along an
/// edge or at a corner by adding the fewest cubes per offending vertex, which never uncovers
/// space the cubes covered.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <unordered_set>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/math.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/polycube/vertex_configuration.h"

namespace cellrelief::polycube {

/// Where lattice coordinates lie in world space: p_WS = origin + cubeSize * p_lattice.
struct PolycubeFrame {
  Vec3d origin{0.0};
  double cubeSize = 1.0;
};

/// Counts of a polycube's surface: faces (unit squares), lattice vertices and edges on it,
/// connected pieces, and the vertices per case.
struct SurfaceStats {
  std::size_t faces = 0, vertices = 0, edges = 0, components = 0;
  std::size_t nonManifoldVertices = 0;
  std::array<std::size_t, kVertexCaseCount> perCase{};
  long long eulerCharacteristic() const {
    return (long long)vertices - (long long)edges + (long long)faces;
  }
  /// Genus of a closed, connected, manifold surface; nullopt otherwise.
  std::optional<int> genus() const {
    if (nonManifoldVertices != 0 || components != 1 || (2 - eulerCharacteristic()) % 2 != 0) return std::nullopt;
    return int((2 - eulerCharacteristic()) / 2);
  }
};

class Polycube {
 public:
  /// Lattice coordinates are limited so that every derived coordinate fits an int.
  static constexpr int kMaxCoordinate = 1 << 20;

  Polycube() = default;
  /// Sorts and removes repeats; throws InvalidArgument for a coordinate out of range.
  explicit Polycube(std::vector<Vec3i> cubes);

  std::span<const Vec3i> cubes() const { return mCubes; }
  std::size_t size() const { return mCubes.size(); }
  bool empty() const { return mCubes.empty(); }
  bool contains(const Vec3i& c) const { return mSet.count(key(c)) != 0; }
  /// Smallest and largest cube coordinates (meaningless when empty).
  Vec3i minCube() const { return mMin; }
  Vec3i maxCube() const { return mMax; }

  /// The 8-bit configuration of lattice vertex v (bit o: octant o is a cube).
  std::uint8_t vertexConfiguration(const Vec3i& v) const;
  /// Every lattice vertex with surface (a configuration other than 0 and 255), sorted.
  std::vector<Vec3i> surfaceVertices() const;
  std::vector<Vec3i> nonManifoldVertices() const;
  SurfaceStats surfaceStats() const;

  /// The surface as a triangle mesh in world space: two triangles per face, oriented outwards,
  /// vertices shared by lattice position (so a manifold polycube gives a closed manifold mesh).
  TriangleMesh surfaceMesh(const PolycubeFrame& frame = {}) const;

  /// 6-connected pieces of the cubes, largest first.
  std::vector<std::vector<Vec3i>> components() const;

  /// A lattice point as one integer (21 bits per coordinate), for hash sets.
  static std::uint64_t key(const Vec3i& c) {
    const auto u = [](int v) { return std::uint64_t(std::uint32_t(v + kMaxCoordinate)) & 0x1fffffu; };
    return u(c.x) | (u(c.y) << 21) | (u(c.z) << 42);
  }

 private:
  /// Calls visit(corner, axis, positive) for every face between a cube and empty space: the
  /// face lies in the plane normal to `axis` through its lowest corner, and faces +axis when
  /// `positive`.
  template <class Visit>
  void forEachSurfaceFace(Visit&& visit) const;

  std::vector<Vec3i> mCubes;  ///< sorted by (z, y, x)
  std::unordered_set<std::uint64_t> mSet;
  Vec3i mMin{0}, mMax{0};
};

/// Adds cubes until every lattice vertex is manifold: at each offending vertex, the fewest empty
/// octants whose cubes make its block manifold (ties: the octants `prefer` ranks highest, then
/// the lowest mask). Returns how many cubes were added. Throws when `maxAdded` cubes did not do.
template <class Preference>
std::size_t makeManifold(Polycube& polycube, Preference&& prefer, std::size_t maxAdded = 1u << 20);
std::size_t makeManifold(Polycube& polycube);

/// The vertices of one case, sorted.
std::vector<Vec3i> verticesOfCase(const Polycube& polycube, VertexCase vertexCase);

/// Adds or removes cubes until no vertex is of the given case, keeping the surface one manifold
/// piece of the same genus. At each such vertex it toggles the one cube of its block that lowers
/// the count among the vertices it changes the most (ties: the one `prefer` ranks highest for a
/// cube added, 1 - prefer for one removed); where no single cube helps, the best pair of cubes
/// within two of the vertex. Vertices neither removes stay. Returns the cubes toggled. Used for
/// case 6b, whose projection stretches more than the other cases' (projection.h); the paper's
/// own polycubes avoided 6a and 6b.
template <class Preference>
std::size_t removeVerticesOfCase(Polycube& polycube, VertexCase vertexCase, Preference&& prefer, int maxRounds = 64);

/// Keeps the largest 6-connected piece and fills every cavity (empty space the outside does not
/// reach), so that the surface is one closed shell.
Polycube keepLargestAndFill(const Polycube& polycube);

}  // namespace cellrelief::polycube

#include "cellrelief/polycube/polycube.ipp"
