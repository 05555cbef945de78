// SPDX-License-Identifier: MIT
/// @file lookup_table.h
/// The 3D look-up table of PolyCube-Maps (the paper's T3LUT) and the squarelet mapping M.
///
/// One entry per lattice vertex of the polycube's box (one texel of a 3D texture), empty cells
/// included: the vertex's case, the transform that turns the case's canonical configuration into
/// the vertex's (vertex_configuration.h: the paper's 5 bits of rotation and a sixth for the mirror
/// image of case 6b), whether the octants are the complement, and where its squarelets start in
/// the 2D texture T2.
///
/// T2 holds one tile per squarelet (polycube_texture.h lays them out). A vertex's squarelets take
/// consecutive tiles in the order of their squarelet index, so M is a rank in the vertex's 12-bit
/// squarelet mask and the tile's corner, and is injective by construction. Every face of the polycube has one
/// squarelet at each of its four corners, so T2 holds 4 x faces tiles, and the texels of one face
/// are those of its four tiles.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "cellrelief/polycube/polycube.h"

namespace cellrelief::polycube {

struct LutEntry {
  static constexpr std::uint8_t kEmpty = 0xff;  ///< no surface at this vertex
  std::uint8_t vertexCase = kEmpty;
  std::uint8_t transform = 0;
  std::uint8_t complement = 0;
  std::uint8_t configuration = 0;  ///< the 8 octants, for checks and the CPU reference
  std::uint32_t firstTile = 0;

  bool empty() const { return vertexCase == kEmpty; }
  std::uint16_t squarelets() const { return kVertexConfigurations[configuration].squarelets; }
  /// The tile of squarelet `index`, which must be one of this vertex's.
  std::uint32_t tileOf(int index) const {
    return firstTile + std::uint32_t(std::popcount(unsigned(squarelets()) & ((1u << index) - 1u)));
  }
};

/// A point of the polycube's surface as M reads it: the vertex whose dual cell holds it, the
/// squarelet, and coordinates in the squarelet from the vertex outwards (each 0..1 over half a
/// cube), along the squarelet plane's two axes in increasing order.
struct SquareletPoint {
  Vec3i vertex{0};
  int squarelet = 0;
  Vec2d st{0.0};
};

class PolycubeLut {
 public:
  PolycubeLut() = default;
  explicit PolycubeLut(const Polycube& polycube) {
    if (polycube.empty()) throw Error(ErrorKind::InvalidArgument, "polycube look-up table: the polycube is empty");
    mOrigin = polycube.minCube();
    mSize = polycube.maxCube() + Vec3i(2) - mOrigin;
    const double entries = double(mSize.x) * mSize.y * mSize.z;
    if (entries > double(1u << 28))
      throw Error(ErrorKind::ResourceLimit, "polycube look-up table: " + std::to_string(mSize.x) + " x " +
                                                std::to_string(mSize.y) + " x " + std::to_string(mSize.z) +
                                                " vertices is too large a 3D texture");
    mEntries.resize(std::size_t(entries));
    std::uint32_t tiles = 0;
    for (int z = 0; z < mSize.z; ++z)
      for (int y = 0; y < mSize.y; ++y)
        for (int x = 0; x < mSize.x; ++x) {
          const Vec3i v = mOrigin + Vec3i(x, y, z);
          const std::uint8_t configuration = polycube.vertexConfiguration(v);
          const VertexConfigurationInfo& info = kVertexConfigurations[configuration];
          LutEntry& e = mEntries[index({x, y, z})];
          e.configuration = configuration;
          if (!info.surface) continue;
          if (!info.manifold)
            throw Error(ErrorKind::InvalidInput, "polycube look-up table: the surface is not manifold at vertex (" +
                                                     std::to_string(v.x) + ", " + std::to_string(v.y) + ", " +
                                                     std::to_string(v.z) + ")");
          e.vertexCase = std::uint8_t(info.vertexCase);
          e.transform = info.transform;
          e.complement = info.complement ? 1 : 0;
          e.firstTile = tiles;
          tiles += std::uint32_t(std::popcount(unsigned(info.squarelets)));
        }
    mTileCount = tiles;
  }

  /// Lattice coordinates of the first vertex, and vertices per axis.
  Vec3i origin() const { return mOrigin; }
  Vec3i size() const { return mSize; }
  std::uint32_t tileCount() const { return mTileCount; }
  std::span<const LutEntry> entries() const { return mEntries; }

  /// The entry of a lattice vertex; an empty one outside the box.
  const LutEntry& at(const Vec3i& vertex) const {
    static const LutEntry kOutside{};
    const Vec3i l = vertex - mOrigin;
    if (glm::any(glm::lessThan(l, Vec3i(0))) || glm::any(glm::greaterThanEqual(l, mSize))) return kOutside;
    return mEntries[index(l)];
  }

  /// The squarelet that holds a point of the surface (lattice coordinates): the nearest vertex's
  /// cell, the coordinate plane through that vertex the point lies in (within `tolerance` cubes),
  /// and a squarelet of that vertex on that side. Nothing when the point is not on the surface.
  std::optional<SquareletPoint> locate(const Vec3d& p, double tolerance = 1e-9) const {
    const Vec3i vertex(glm::floor(p + Vec3d(0.5)));
    const Vec3d d = p - Vec3d(vertex);
    const LutEntry& e = at(vertex);
    if (e.empty()) return std::nullopt;
    // Try the planes the point is nearest first (on an edge of the lattice two or three qualify).
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int a, int b) { return std::abs(d[a]) < std::abs(d[b]); });
    for (int axis : order) {
      if (std::abs(d[axis]) > tolerance) break;
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      const int lo = std::min(a, b), hi = std::max(a, b);
      // On a lattice line through the vertex (a coordinate within tolerance of 0) the point lies
      // in the squarelets of both sides: try each.
      const int loSides = std::abs(d[lo]) <= tolerance ? 2 : 1, hiSides = std::abs(d[hi]) <= tolerance ? 2 : 1;
      for (int i = 0; i < loSides; ++i)
        for (int j = 0; j < hiSides; ++j) {
          const bool loPositive = loSides == 2 ? i == 1 : d[lo] > 0, hiPositive = hiSides == 2 ? j == 1 : d[hi] > 0;
          const int octant = (loPositive ? 1 << lo : 0) | (hiPositive ? 1 << hi : 0);
          const int squarelet = squareletIndex(octant, axis);
          if (e.squarelets() & (1u << squarelet))
            return SquareletPoint{vertex, squarelet, 2.0 * Vec2d(std::abs(d[lo]), std::abs(d[hi]))};
        }
    }
    return std::nullopt;
  }

 private:
  std::size_t index(const Vec3i& l) const {
    return (std::size_t(l.z) * std::size_t(mSize.y) + std::size_t(l.y)) * std::size_t(mSize.x) + std::size_t(l.x);
  }

  Vec3i mOrigin{0}, mSize{0};
  std::vector<LutEntry> mEntries;
  std::uint32_t mTileCount = 0;
};

}  // namespace cellrelief::polycube
