// SPDX-License-Identifier: MIT
/// @file gpu_layout.h
/// A scene in the layout the GPU backends upload, shared by OpenGL and Vulkan (docs/format.md,
/// "GPU layout"). API-neutral: plain arrays of words and texels, packed to fit real device limits.
///
/// - Maps go into *atlases*: 2D array textures whose layers hold tiles of T x T samples, one tile
///   per face layer of the model, packed densely (tilesPerRow x rowsPerLayer per array layer,
///   both powers of two so the shader finds a tile with shifts). A model of 27,129 face layers of
///   9 x 9 (the armadillo) fits in two array layers of 1,152 x 1,152 where one texture layer per
///   face would need 13x the 2,048 layers software drivers allow.
///   The shader reads the four samples of a bilinear cell as integer texels (or one gather) and
///   filters them itself, exactly as the CPU tracer does: it must see the empty code of each
///   corner, which hardware filtering would blend away. So tiles need no border: a read never
///   leaves its tile (the cell's corners are samples 0 .. T - 1), and no filter crosses into a
///   neighbouring face.
/// - The cell lookup is an open-addressing hash table of the grey cells (load factor <= 1/2,
///   linear probing), so it costs memory in proportion to the grey cells, not to N^3; the DDA
///   pays one or two probes per white or black cell, as the CPU pays an OpenVDB accessor lookup.
/// - The cell table is the model's CellRecord array, each with its relief::CellReach (GpuCell,
///   32-byte std430 structs).
/// - The min pyramid of the empty-space skip (trace/empty_space.h), levels 1 and up, as 16-bit
///   codes, only when skipping is on and the model has cells other than interior ones.
/// Everything is counted in bytes(): what sceneBytes() reports.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/gpu/geotex_layout.h"
#include "cellrelief/gpu/parallax_layout.h"
#include "cellrelief/gpu/polycube_layout.h"
#include "cellrelief/relief/relief_model.h"
#include "cellrelief/relief/surface_bounds.h"
#include "cellrelief/render/scene.h"
#include "cellrelief/trace/empty_space.h"

namespace cellrelief::gpu {

/// What the device allows; the packer refuses a scene beyond it with a clear error.
struct DeviceLimits {
  int maxTextureSize = 2048;       ///< width and height of a 2D array texture layer
  int maxArrayLayers = 2048;       ///< layers of a 2D array texture
  std::size_t maxStorageBytes = std::size_t(128) << 20;  ///< one storage buffer
  std::size_t maxTotalBytes = 0;   ///< all of it (0: unknown, not checked)
};

/// The hash of the cell lookup; the shader computes the same (lowbias32, Wellons 2018).
constexpr std::uint32_t cellHash(std::uint32_t k) {
  k ^= k >> 16;
  k *= 0x7feb352du;
  k ^= k >> 15;
  k *= 0x846ca68bu;
  k ^= k >> 16;
  return k;
}
/// The key of a cell: its packed ijk without flag bits (30 bits), plus one so that 0 is "empty".
constexpr std::uint32_t cellKey(std::uint32_t packedIjk) { return (packedIjk & 0x3fffffffu) + 1u; }

/// Levels of the pyramid the layout can describe (T - 1 up to 2^11).
inline constexpr int kMaxPyramidLevels = 12;

/// Per model: where its data lies in the shared arrays and how to read it. std430 layout (every
/// member 4 bytes, the struct a multiple of 16).
struct ModelInfo {
  float origin[3];
  float cellSize;
  float distanceScale;  ///< code to distance (cell units)
  float texelsMinus1;
  float distanceMax;    ///< DistanceCodec::distanceMax (cell units)
  float surfaceMin[3];  ///< relief::surfaceBoundsWS: the box rays are clipped to (world units)
  float surfaceMax[3];
  std::int32_t gridSize;
  std::int32_t texels;
  std::int32_t cellOffset;  ///< index of its first cell in the cell table
  std::int32_t hashOffset;  ///< first slot of its hash table
  std::int32_t hashMask;    ///< slots - 1 (a power of two)
  std::int32_t layerBase;   ///< first array layer of its tiles in the atlases
  std::int32_t tilesPerRow;     ///< a power of two
  std::int32_t tilesPerLayer;   ///< a power of two (tilesPerRow x rows per array layer)
  std::int32_t tileRowShift;    ///< log2 tilesPerRow
  std::int32_t tileLayerShift;  ///< log2 tilesPerLayer
  std::int32_t emptyCode;
  std::int32_t normalFormat;  ///< relief::NormalFormat
  std::int32_t colorFormat;   ///< relief::ColorFormat
  std::int32_t pyramidOffset; ///< first node (16-bit units) of its pyramid, -1 when none
  std::int32_t pyramidLevels;
  std::int32_t pyramidLayerStride;
  std::int32_t layerCount;
  std::int32_t openSurface;  ///< ReliefModel::openSurface(): no side carried across cell faces
  std::int32_t zeroCode;  ///< DistanceCodec::zeroCode
  std::int32_t levelSize[kMaxPyramidLevels];
  std::int32_t levelOffset[kMaxPyramidLevels];
};
static_assert(sizeof(ModelInfo) % 16 == 0);

/// Which signals and projection types a scene uses: what the shader variant is specialized to.
struct SceneFeatures {
  bool parallel = false, planar = false, perspective = false, axial = false;
  bool octahedralNormals = false, rgbaNormals = false, colors = false;
  bool pyramid = false;  ///< a pyramid is uploaded (skipping on, cells other than interior ones present)
  bool polycube = false;  ///< polycube-mapped meshes (polycube_layout.h)
  bool geotex = false;    ///< geometry-texture models (geotex_layout.h)
  bool parallax = false;  ///< relief surfaces (parallax_layout.h)
};

/// A 2D array texture's texels, tightly packed [layer][row][column][channel].
template <class T>
struct Atlas {
  int width = 0, height = 0, layers = 0, channels = 0;
  std::vector<T> texels;
  bool empty() const { return texels.empty(); }
  std::size_t bytes() const { return texels.size() * sizeof(T); }
};

/// One cell as the shader reads it: the model's record and where its field can change side.
struct GpuCell {
  relief::CellRecord record;
  relief::CellReach reach;
};
static_assert(sizeof(GpuCell) == 32);

struct GpuScene {
  std::vector<ModelInfo> models;
  std::vector<GpuCell> cells;
  std::vector<std::uint32_t> hashSlots;   ///< pairs (key, cell index); key 0 is an empty slot
  std::vector<std::uint16_t> pyramid;     ///< min pyramid codes, levels >= 1
  Atlas<std::uint16_t> distances;         ///< R16UI: codes (8-bit models keep their own empty code)
  Atlas<std::uint16_t> normalsOct;        ///< RG16UI octahedral normals
  Atlas<std::uint8_t> normalsRgba;        ///< RGBA8UI normals
  Atlas<std::uint8_t> colors;             ///< RGBA8UI colors
  PolycubeGpu polycube;                   ///< polycube-mapped meshes and their T2s
  GeoTexGpu geotex;                       ///< geometry-texture models
  ParallaxGpu parallax;                   ///< relief surfaces
  SceneFeatures features;

  /// Frees the atlases' texels once they are on the device; the layout (models, features) stays.
  void dropTexels() {
    distances.texels = {};
    normalsOct.texels = {};
    normalsRgba.texels = {};
    colors.texels = {};
    polycube.t2 = {};
  }

  std::size_t bytes() const {
    return models.size() * sizeof(ModelInfo) + cells.size() * sizeof(GpuCell) +
           hashSlots.size() * sizeof(std::uint32_t) + pyramid.size() * sizeof(std::uint16_t) +
           distances.bytes() + normalsOct.bytes() + normalsRgba.bytes() + colors.bytes() + polycube.bytes() +
           geotex.bytes() + parallax.bytes();
  }
};

namespace detail {

inline std::string modelLabel(std::size_t i, const relief::ReliefModel& m) {
  return "scene model " + std::to_string(i) + " (N = " + std::to_string(m.gridSize) + ", " +
         std::to_string(m.layerCount()) + " layers of " + std::to_string(m.texels) + " x " +
         std::to_string(m.texels) + ")";
}

inline std::string mib(std::size_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / double(1 << 20));
  return text;
}

/// The hash table of one model's cells, appended to `slots`; returns (offset, mask).
inline std::pair<int, int> appendHashTable(const relief::ReliefModel& m, int cellOffset,
                                           std::vector<std::uint32_t>& slots) {
  const std::size_t capacity = std::bit_ceil(std::max<std::size_t>(16, 2 * m.cells.size()));
  const std::size_t offset = slots.size() / 2;
  slots.resize(slots.size() + 2 * capacity, 0u);
  std::uint32_t* table = slots.data() + 2 * offset;
  const std::uint32_t mask = std::uint32_t(capacity - 1);
  for (std::size_t i = 0; i < m.cells.size(); ++i) {
    const std::uint32_t key = cellKey(m.cells[i].packedIjk);
    std::uint32_t h = cellHash(key) & mask;
    while (table[2 * h] != 0) h = (h + 1) & mask;
    table[2 * h] = key;
    table[2 * h + 1] = std::uint32_t(cellOffset) + std::uint32_t(i);
  }
  return {int(offset), int(mask)};
}

}  // namespace detail

/// The cell index (into GpuScene::cells) of grid cell ijk of model `model`, or -1: the shader's
/// lookup, in C++ (for tests and for probe statistics).
inline int findCell(const GpuScene& scene, int model, const Vec3i& ijk, int* probes = nullptr) {
  const ModelInfo& info = scene.models[std::size_t(model)];
  const std::uint32_t key = cellKey(relief::CellRecord::packIjk(ijk));
  const std::uint32_t mask = std::uint32_t(info.hashMask);
  const std::uint32_t* table = scene.hashSlots.data() + 2 * std::size_t(info.hashOffset);
  int count = 0;
  for (std::uint32_t h = cellHash(key) & mask;; h = (h + 1) & mask) {
    ++count;
    if (table[2 * h] == 0 || table[2 * h] == key) {
      if (probes) *probes = count;
      return table[2 * h] == 0 ? -1 : int(table[2 * h + 1]);
    }
  }
}

/// Packs a scene for a device. `withPyramid`: upload the empty-space pyramid (skipping on).
/// Throws Error (ResourceLimit) naming the model and the limit when the scene cannot fit.
inline GpuScene packScene(const render::Scene& scene, const DeviceLimits& limits, bool withPyramid) {
  GpuScene out;
  // ---- the atlas size ------------------------------------------------------------------------------
  // Per model, tiles per row and rows per array layer are powers of two (the shader addresses a
  // tile with shifts and masks), as square as the layer count allows; the atlas is as wide as the
  // widest model and as tall as the tallest needs.
  auto floorPow2 = [](int v) { return v < 1 ? 0 : int(std::bit_floor(unsigned(v))); };
  struct TileGrid {
    int perRow = 1, rowsPerLayer = 1;
  };
  std::vector<TileGrid> grids(scene.models.size());
  int width = 1, height = 1;
  for (std::size_t i = 0; i < scene.models.size(); ++i) {
    const relief::ReliefModel& m = *scene.models[i];
    const int layers = m.layerCount();
    if (layers == 0) continue;
    const int cap = floorPow2(limits.maxTextureSize / m.texels);
    if (cap < 1)
      throw Error(ErrorKind::ResourceLimit, detail::modelLabel(i, m) + ": tiles of " +
                                                std::to_string(m.texels) + " samples exceed the device's " +
                                                std::to_string(limits.maxTextureSize) + " texel texture size");
    TileGrid& g = grids[i];
    g.perRow = std::min(cap, int(std::bit_ceil(unsigned(std::ceil(std::sqrt(double(layers)))))));
    const int rowsNeeded = (layers + g.perRow - 1) / g.perRow;
    g.rowsPerLayer = std::min(cap, int(std::bit_ceil(unsigned(rowsNeeded))));
    width = std::max(width, g.perRow * m.texels);
    height = std::max(height, std::min(g.rowsPerLayer, rowsNeeded) * m.texels);
  }
  // ---- per model: tables, tiles, pyramid ----------------------------------------------------------
  int arrayLayers = 0;
  for (std::size_t i = 0; i < scene.models.size(); ++i) {
    const relief::ReliefModel& m = *scene.models[i];
    ModelInfo info{};
    for (int a = 0; a < 3; ++a) info.origin[a] = float(m.originWS[a]);
    info.cellSize = float(m.cellSizeWS);
    info.distanceScale = float(m.distanceCodec.scale());
    info.texelsMinus1 = float(m.texels - 1);
    info.distanceMax = m.distanceCodec.distanceMax;
    const Aabbd surface = relief::surfaceBoundsWS(m);
    for (int a = 0; a < 3; ++a) {
      info.surfaceMin[a] = float(surface.min[a]);
      info.surfaceMax[a] = float(surface.max[a]);
    }
    info.gridSize = m.gridSize;
    info.texels = m.texels;
    info.openSurface = m.openSurface() ? 1 : 0;
    info.cellOffset = int(out.cells.size());
    std::tie(info.hashOffset, info.hashMask) =
        detail::appendHashTable(m, info.cellOffset, out.hashSlots);
    const std::vector<relief::CellReach> reaches = relief::cellReaches(m);
    for (std::size_t c = 0; c < m.cells.size(); ++c) out.cells.push_back({m.cells[c], reaches[c]});
    info.emptyCode = int(m.distanceCodec.emptyCode());
    info.zeroCode = int(m.distanceCodec.zeroCode);
    info.normalFormat = int(m.normalFormat);
    info.colorFormat = int(m.colorFormat);
    info.layerCount = m.layerCount();
    info.layerBase = arrayLayers;
    info.tilesPerRow = grids[i].perRow;
    info.tilesPerLayer = grids[i].perRow * grids[i].rowsPerLayer;
    info.tileRowShift = std::countr_zero(unsigned(info.tilesPerRow));
    info.tileLayerShift = std::countr_zero(unsigned(info.tilesPerLayer));
    if (m.layerCount() > 0) arrayLayers += (m.layerCount() + info.tilesPerLayer - 1) / info.tilesPerLayer;
    if (arrayLayers > limits.maxArrayLayers)
      throw Error(ErrorKind::ResourceLimit,
                  detail::modelLabel(i, m) + ": its maps need " + std::to_string(arrayLayers) +
                      " array layers of " + std::to_string(width) + " x " + std::to_string(height) +
                      ", beyond the device's " + std::to_string(limits.maxArrayLayers));
    info.pyramidOffset = -1;
    for (const relief::CellRecord& r : m.cells) {
      const auto type = projection::ProjectionType(r.projectionType);
      out.features.parallel |= type == projection::ProjectionType::Parallel;
      out.features.planar |= type == projection::ProjectionType::Planar;
      out.features.perspective |= type == projection::ProjectionType::Perspective;
      out.features.axial |= type == projection::ProjectionType::Axial;
    }
    out.features.octahedralNormals |= m.normalFormat == relief::NormalFormat::Octahedral16;
    out.features.rgbaNormals |= m.normalFormat == relief::NormalFormat::Rgba8;
    out.features.colors |= m.colorFormat == relief::ColorFormat::Rgba8;
    // Every cell but the interior ones can skip (ReliefTracer::searchInside).
    const bool skippable = std::any_of(m.cells.begin(), m.cells.end(), [](const auto& r) { return r.configuration != 0; });
    if (withPyramid && skippable && m.layerCount() > 0) {
      const trace::EmptySpacePyramid pyramid(m);
      if (pyramid.levels() > kMaxPyramidLevels)
        throw Error(ErrorKind::ResourceLimit, detail::modelLabel(i, m) + ": T = " +
                                                  std::to_string(m.texels) + " is beyond the GPU pyramid's " +
                                                  std::to_string(kMaxPyramidLevels) + " levels");
      info.pyramidOffset = int(out.pyramid.size());
      info.pyramidLevels = pyramid.levels();
      int stride = 0;
      for (int level = 0; level < pyramid.levels(); ++level) {
        info.levelSize[level] = pyramid.size(level);
        info.levelOffset[level] = level == 0 ? 0 : stride;
        if (level > 0) stride += pyramid.size(level) * pyramid.size(level);
      }
      info.pyramidLayerStride = stride;
      out.pyramid.reserve(out.pyramid.size() + std::size_t(stride) * std::size_t(m.layerCount()));
      for (int layer = 0; layer < m.layerCount(); ++layer)
        for (int level = 1; level < pyramid.levels(); ++level)
          for (int b = 0; b < pyramid.size(level); ++b)
            for (int a = 0; a < pyramid.size(level); ++a)
              out.pyramid.push_back(std::uint16_t(pyramid.code(layer, level, a, b)));
      out.features.pyramid = true;
    }
    out.models.push_back(info);
  }
  if (out.pyramid.size() % 2) out.pyramid.push_back(0xffffu);  // read as 32-bit words
  arrayLayers = std::max(arrayLayers, 1);

  // ---- atlases: only the signals some model has ---------------------------------------------------
  auto allocate = [&](auto& atlas, int channels) {
    atlas.width = width;
    atlas.height = height;
    atlas.layers = arrayLayers;
    atlas.channels = channels;
    atlas.texels.assign(std::size_t(width) * height * arrayLayers * channels, 0);
  };
  allocate(out.distances, 1);
  if (out.features.octahedralNormals) allocate(out.normalsOct, 2);
  if (out.features.rgbaNormals) allocate(out.normalsRgba, 4);
  if (out.features.colors) allocate(out.colors, 4);
  std::fill(out.distances.texels.begin(), out.distances.texels.end(), std::uint16_t(0xffffu));
  for (std::size_t i = 0; i < scene.models.size(); ++i) {
    const relief::ReliefModel& m = *scene.models[i];
    const ModelInfo& info = out.models[i];
    const int t = m.texels;
    for (int layer = 0; layer < m.layerCount(); ++layer) {
      const int arrayLayer = info.layerBase + layer / info.tilesPerLayer;
      const int r = layer % info.tilesPerLayer;
      const int x0 = (r % info.tilesPerRow) * t, y0 = (r / info.tilesPerRow) * t;
      for (int b = 0; b < t; ++b)
        for (int a = 0; a < t; ++a) {
          const std::size_t texel = (std::size_t(arrayLayer) * height + std::size_t(y0 + b)) * width + std::size_t(x0 + a);
          out.distances.texels[texel] = std::uint16_t(m.distanceCode(layer, a, b));
          if (m.normalFormat == relief::NormalFormat::Octahedral16)
            for (int c = 0; c < 2; ++c) out.normalsOct.texels[2 * texel + c] = m.normals16.at(a, b, layer, c);
          if (m.normalFormat == relief::NormalFormat::Rgba8)
            for (int c = 0; c < 4; ++c) out.normalsRgba.texels[4 * texel + c] = m.normals8.at(a, b, layer, c);
          if (m.colorFormat == relief::ColorFormat::Rgba8)
            for (int c = 0; c < 4; ++c) out.colors.texels[4 * texel + c] = m.colors.at(a, b, layer, c);
        }
    }
  }
  // ---- limits on buffers and on the whole ---------------------------------------------------------
  auto checkBuffer = [&](std::size_t bytes, const char* what) {
    if (bytes > limits.maxStorageBytes)
      throw Error(ErrorKind::ResourceLimit, std::string("the scene's ") + what + " needs " + detail::mib(bytes) +
                                                ", beyond the device's storage buffer limit of " +
                                                detail::mib(limits.maxStorageBytes));
  };
  checkBuffer(out.cells.size() * sizeof(GpuCell), "cell table");
  checkBuffer(out.hashSlots.size() * sizeof(std::uint32_t), "cell hash table");
  checkBuffer(out.pyramid.size() * sizeof(std::uint16_t), "empty-space pyramid");
  out.polycube = packPolycubeMeshes(scene, limits.maxTextureSize, limits.maxStorageBytes);
  out.features.polycube = !out.polycube.empty();
  out.geotex = packGeoTexModels(scene, limits.maxStorageBytes);
  out.features.geotex = !out.geotex.empty();
  out.parallax = packReliefSurfaces(scene, limits.maxStorageBytes);
  out.features.parallax = !out.parallax.empty();
  if (limits.maxTotalBytes > 0 && out.bytes() > limits.maxTotalBytes)
    throw Error(ErrorKind::ResourceLimit, "the scene needs " + detail::mib(out.bytes()) +
                                              " on the device, beyond its " + detail::mib(limits.maxTotalBytes));
  return out;
}

}  // namespace cellrelief::gpu
