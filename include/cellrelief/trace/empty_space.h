// SPDX-License-Identifier: MIT
/// @file empty_space.h
/// Conservative empty-space skipping for the relief tracer, beyond the paper: a min pyramid of
/// each distance layer (a "maximum mipmap" in the sense of Tevs et al. 2008, with distances from
/// the face instead of heights). Level 0 stands for each texel cell between four vertex-centred
/// samples and the smallest of their distance codes: the bilinear surface over that texel cell
/// never comes closer to the face than this (the tracer reads it from the samples; it is not
/// stored). Level k takes the minimum over 2x2 nodes of level k-1. A ray segment whose distance from the face stays below a node's minimum over the node's
/// footprint cannot meet the surface there and is skipped in one step, so thin features are
/// never missed (the bound is exact, not sampled).
///
/// Codes, not distances, are stored: dequantization is monotonic, so the minimum code is the
/// minimum distance, and the pyramid costs 2 bytes per node of levels 1 and up (about 0.7 bytes
/// per sample in all). An empty sample (no surface on its projection line) has the empty code, the
/// largest, so a texel cell with any empty corner reads as "no surface", as the tracer reads it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "cellrelief/relief/relief_model.h"

namespace cellrelief::trace {

class EmptySpacePyramid {
 public:
  EmptySpacePyramid() = default;

  explicit EmptySpacePyramid(const relief::ReliefModel& model) {
    mLayers = model.layerCount();
    const int base = std::max(1, model.texels - 1);
    // Level 0 (one node per texel cell) is not stored: the tracer reads the four samples of a
    // texel cell anyway, and keeping it would cost more than the distance map itself.
    mSizes.push_back(base);
    mOffsets.push_back(0);
    for (int size = base; size > 1;) {
      size = (size + 1) / 2;
      mSizes.push_back(size);
      mOffsets.push_back(mLayerStride);
      mLayerStride += std::size_t(size) * std::size_t(size);
    }
    mCodes.assign(mLayerStride * std::size_t(mLayers), kEmpty);
    mCodec = model.distanceCodec;
    model.visitDistanceCodes([&](const auto& codes) { build(codes, base); });
  }

  static constexpr std::uint16_t kEmpty = 0xffffu;

  int levels() const { return int(mSizes.size()); }
  /// Texel cells per side at a level (level 0: T - 1).
  int size(int level) const { return mSizes[level]; }
  /// Smallest code over a node of level >= 1; a code >= the model's empty code means no surface
  /// under it.
  std::uint32_t code(int layer, int level, int a, int b) const {
    return mCodes[std::size_t(layer) * mLayerStride + mOffsets[level] +
                  std::size_t(b) * mSizes[level] + a];
  }
  bool isEmptyCode(std::uint32_t c) const { return mCodec.isEmpty(c); }
  /// Distance (cell units) of a code, as ReliefModel::distance dequantizes it.
  double toDistance(std::uint32_t c) const { return (double(c) - double(mCodec.zeroCode)) * mCodec.scale(); }
  std::size_t byteSize() const { return mCodes.size() * sizeof(std::uint16_t); }

 private:
  /// Level 0 from the model's codes (an empty corner makes the whole texel cell empty for the
  /// tracer), then each level the minimum of four nodes below.
  template <class Codes>
  void build(const Codes& codes, int base) {
    std::vector<std::uint16_t> level0(std::size_t(base) * base);
    for (int layer = 0; layer < mLayers; ++layer) {
      for (int b = 0; b < base; ++b)
        for (int a = 0; a < base; ++a) {
          const std::uint32_t c[4] = {codes(layer, a, b), codes(layer, a + 1, b), codes(layer, a, b + 1),
                                      codes(layer, a + 1, b + 1)};
          const bool anyEmpty = mCodec.isEmpty(c[0]) || mCodec.isEmpty(c[1]) || mCodec.isEmpty(c[2]) ||
                                mCodec.isEmpty(c[3]);
          level0[std::size_t(b) * base + a] =
              anyEmpty ? kEmpty : std::uint16_t(std::min({c[0], c[1], c[2], c[3]}));
        }
      for (int level = 1; level < levels(); ++level) {
        const int size = mSizes[level], below = mSizes[level - 1];
        const std::uint16_t* src = level == 1 ? level0.data() : levelData(layer, level - 1);
        std::uint16_t* dst = levelData(layer, level);
        for (int b = 0; b < size; ++b)
          for (int a = 0; a < size; ++a) {
            std::uint16_t m = kEmpty;
            for (int k = 0; k < 4; ++k) {
              const int x = 2 * a + (k & 1), y = 2 * b + (k >> 1);
              if (x < below && y < below) m = std::min(m, src[std::size_t(y) * below + x]);
            }
            dst[std::size_t(b) * size + a] = m;
          }
      }
    }
  }

  std::uint16_t* levelData(int layer, int level) {
    return mCodes.data() + std::size_t(layer) * mLayerStride + mOffsets[level];
  }

  int mLayers = 0;
  std::vector<int> mSizes;
  std::vector<std::size_t> mOffsets;
  std::size_t mLayerStride = 0;
  std::vector<std::uint16_t> mCodes;
  relief::DistanceCodec mCodec;
};

}  // namespace cellrelief::trace
