// SPDX-License-Identifier: MIT
/// @file relief_model.h
/// The relief representation (Apaza & Andujar, 3.4): a look-up table of grey cells and, per domain
/// face of every grey cell, a T x T distance map (plus normal and color maps when the mesh has those
/// signals), stored as array textures with one layer per face, in the memory layout the GPU
/// backends upload as is (docs/format.md).
///
/// Samples are vertex-centred: sample (a, b) of a face lies at face coordinates (a, b) / (T - 1), so
/// the first and last samples lie on the face's edges. Two faces of a cell that share an edge then
/// sample the same projection lines along it, and reconstructions of neighbouring faces meet.
/// A GPU samples it with texture coordinate (uv (T - 1) + 0.5) / T.
///
/// Distances are in cell units (multiply by cellSizeWS for world units), quantized to 16 bits (or 8)
/// over [0, distanceMax]; the largest code marks an empty sample (no surface projects there), and
/// in interior cells codes below the zero code are distances before the face (where an empty
/// line's continuation outside the cell meets the surface): DistanceCodec (distance_codec.h).
/// Faces on which no surface projects get no layer at all.
#pragma once

#include <algorithm>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "cellrelief/cells/configuration.h"
#include "cellrelief/core/error.h"
#include "cellrelief/core/image.h"
#include "cellrelief/core/math.h"
#include "cellrelief/core/octahedral.h"
#include "cellrelief/projection/choice.h"
#include "cellrelief/relief/distance_codec.h"

namespace cellrelief::relief {

enum class NormalFormat : std::uint8_t {
  None = 0,          ///< no normal map (shading from the distance gradient)
  Rgba8 = 1,         ///< n * 0.5 + 0.5 in RGB, 8 bits each, alpha 255
  Octahedral16 = 2,  ///< octahedral encoding, two 16-bit UNORM channels
};
enum class ColorFormat : std::uint8_t { None = 0, Rgba8 = 1 };

/// One grey cell of the look-up table, 24 bytes, as a std430 struct of 32-bit words.
struct CellRecord {
  std::uint32_t packedIjk = 0;  ///< i | j << 10 | k << 20 | kCentreInside | kOpenSurface
  std::uint8_t configuration = 0;
  std::uint8_t projectionType = 0;  ///< projection::ProjectionType
  std::uint8_t faceOrAxis = 0;      ///< parallel: the face; planar, axial: the axis
  std::uint8_t presentFaces = 0;    ///< domain faces that have a layer (some surface projects there)
  std::uint32_t firstLayer = 0;     ///< layer of its first present face; the others follow in face order
  float point[3] = {0, 0, 0};       ///< perspective centre or a point of the axis, unit-cell coordinates

  /// Set in interior cells (case 0) whose centre of projection is inside the object. Their
  /// domain faces border grey or black cells, so a projection line with no surface on it may lie
  /// inside or outside; it lies on the centre's side, and this bit says which that is.
  static constexpr std::uint32_t kCentreInside = 1u << 30;
  bool centreInside() const { return (packedIjk & kCentreInside) != 0; }
  /// Set in cells that hold a boundary edge of the input (the rim of a hole, the border of an
  /// open sheet). Through a hole a projection line may see no surface where the object's inside
  /// is, so there an empty line says nothing of the side: the tracer takes no step between an
  /// empty line and one with surface for a crossing (and ReliefModel::openSurface() holds).
  static constexpr std::uint32_t kOpenSurface = 1u << 31;
  bool openSurface() const { return (packedIjk & kOpenSurface) != 0; }

  Vec3i ijk() const {
    return {int(packedIjk & 1023u), int((packedIjk >> 10) & 1023u), int((packedIjk >> 20) & 1023u)};
  }
  static std::uint32_t packIjk(const Vec3i& p) {
    return std::uint32_t(p.x) | (std::uint32_t(p.y) << 10) | (std::uint32_t(p.z) << 20);
  }
  /// Layer of face f, or -1 when the face has none.
  int layerOf(int face) const {
    if (!(presentFaces & (1u << face))) return -1;
    // A table, not std::popcount: without -mpopcnt that is a library call, in the tracer's
    // innermost loop.
    static constexpr std::uint8_t kBits[64] = {
        0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4, 1, 2, 2, 3, 2, 3, 3, 4, 2, 3, 3, 4, 3, 4, 4, 5,
        1, 2, 2, 3, 2, 3, 3, 4, 2, 3, 3, 4, 3, 4, 4, 5, 2, 3, 3, 4, 3, 4, 4, 5, 3, 4, 4, 5, 4, 5, 5, 6};
    return int(firstLayer) + kBits[presentFaces & ((1u << face) - 1u) & 63u];
  }
  template <Real T>
  projection::CellProjection<T> projection() const {
    projection::CellProjection<T> p;
    p.type = static_cast<projection::ProjectionType>(projectionType);
    p.faceOrAxis = faceOrAxis;
    p.point = Vec3<T>(point[0], point[1], point[2]);
    p.faces = cells::domainFacesOf(configuration);
    return p;
  }
};
static_assert(sizeof(CellRecord) == 24);

using ::cellrelief::octahedralDecode;  // core/octahedral.h
using ::cellrelief::octahedralEncode;

struct ReliefModel {
  int gridSize = 0;
  Vec3d originWS{0};       ///< the bounding cube's minimum corner
  double cellSizeWS = 0;
  int texels = 0;          ///< T: samples per side of a face
  DistanceCodec distanceCodec;  ///< 8 or 16 bits over [distanceMin(), distanceMax] cell units
  NormalFormat normalFormat = NormalFormat::None;
  ColorFormat colorFormat = ColorFormat::None;
  std::vector<CellRecord> cells;    ///< sorted by (k, j, i)
  ImageArray<std::uint16_t> distances16;  ///< when distanceCodec.bits == 16: 1 channel
  ImageArray<std::uint8_t> distances8;    ///< when distanceCodec.bits == 8: 1 channel
  ImageArray<std::uint16_t> normals16;    ///< Octahedral16: 2 channels
  ImageArray<std::uint8_t> normals8;      ///< Rgba8: 4 channels
  ImageArray<std::uint8_t> colors;        ///< Rgba8: 4 channels

  /// Calls f with the distance layers of the model's width (distances16 or distances8).
  template <class F>
  decltype(auto) visitDistances(F&& f) const {
    return distanceCodec.bits == 16 ? f(distances16) : f(distances8);
  }
  template <class F>
  decltype(auto) visitDistances(F&& f) {
    return distanceCodec.bits == 16 ? f(distances16) : f(distances8);
  }
  /// Calls f with DistanceCodes over the level-0 codes: the width is chosen here, once.
  template <class F>
  decltype(auto) visitDistanceCodes(F&& f) const {
    return visitDistances([&](const auto& maps) {
      using Code = typename std::decay_t<decltype(maps)>::Scalar;
      return f(DistanceCodes<Code>{maps.isEmpty() ? nullptr : maps.levelData(0).data(), std::size_t(texels)});
    });
  }

  int layerCount() const {
    return visitDistances([](const auto& maps) { return maps.isEmpty() ? 0 : maps.layers(); });
  }

  std::uint32_t distanceCode(int layer, int a, int b) const {
    return visitDistances([&](const auto& maps) -> std::uint32_t { return maps.at(a, b, layer, 0); });
  }
  /// Distance in cell units at sample (a, b) of a layer; NaN when empty, negative before the face
  /// (DistanceCodec::hasSurface tells a sample whose line met the surface).
  float distance(int layer, int a, int b) const { return distanceCodec.decode(distanceCode(layer, a, b)); }
  /// Largest error of the distance quantization, in cell units.
  double quantizationError() const { return distanceCodec.quantizationError(); }

  Vec3f normal(int layer, int a, int b) const {
    switch (normalFormat) {
      case NormalFormat::Octahedral16:
        return octahedralDecode(Vec2f(texelToFloat(normals16.at(a, b, layer, 0)),
                                      texelToFloat(normals16.at(a, b, layer, 1))));
      case NormalFormat::Rgba8:
        return glm::normalize(Vec3f(texelToFloat(normals8.at(a, b, layer, 0)),
                                    texelToFloat(normals8.at(a, b, layer, 1)),
                                    texelToFloat(normals8.at(a, b, layer, 2))) * 2.0f - 1.0f);
      case NormalFormat::None: break;
    }
    return Vec3f(0);
  }

  /// Bytes of the look-up table and the maps (what a GPU holds).
  std::size_t byteSize() const {
    return cells.size() * sizeof(CellRecord) + distances16.byteSize() + distances8.byteSize() +
           normals16.byteSize() + normals8.byteSize() + colors.byteSize();
  }
  /// World position of the unit-cell point p of a cell.
  Vec3d toWorld(const Vec3i& ijk, const Vec3d& p) const {
    return originWS + (Vec3d(ijk) + p) * cellSizeWS;
  }
  double diagonalWS() const { return std::sqrt(3.0) * cellSizeWS * gridSize; }
  /// World distance between neighbouring samples of a face: the unit errors are measured in.
  double sampleSpacingWS() const { return cellSizeWS / double(std::max(1, texels - 1)); }
  /// Whether the input was open (some cell holds a boundary edge, CellRecord::kOpenSurface). Its
  /// white space then reaches both sides of the surface through the holes, so a cell's reading of
  /// the side says nothing of its neighbour's, and the tracer carries no side across cell faces.
  bool openSurface() const {
    return std::any_of(cells.begin(), cells.end(), [](const CellRecord& r) { return r.openSurface(); });
  }
};

/// The largest level of detail: samples are taken every 2^L, so (T - 1) must divide by 2^L.
inline int maxLevelOfDetail(const ReliefModel& model) {
  int level = 0;
  while (((model.texels - 1) % (2 << level)) == 0 && (model.texels - 1) / (2 << level) >= 1) ++level;
  return level;
}

/// Throws InvalidArgument unless 0 <= lod <= maxLevelOfDetail(model).
inline void checkLevelOfDetail(const ReliefModel& model, int lod) {
  if (lod < 0 || lod > maxLevelOfDetail(model))
    throw Error(ErrorKind::InvalidArgument,
                "level of detail " + std::to_string(lod) + " is out of range (0 to " +
                    std::to_string(maxLevelOfDetail(model)) + " for T = " +
                    std::to_string(model.texels) + ")");
}

}  // namespace cellrelief::relief
