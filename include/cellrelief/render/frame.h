// SPDX-License-Identifier: MIT
/// @file frame.h
/// The buffers a backend renders into and reads back: color, depth, normal and hit mask, and two
/// diagnostics (cell id and traversal steps per ray, for the viewer's heat map). Only the
/// channels a caller asks for are allocated and written (a depth-only verification pass costs no
/// shading), and every backend produces the same layout so that their images compare texel by texel.
#pragma once

#include <cstdint>
#include <limits>

#include "cellrelief/core/image.h"

namespace cellrelief::render {

/// Which buffers to produce, as bit flags.
enum FrameChannel : unsigned {
  kColor = 1u << 0,
  kDepth = 1u << 1,
  kNormal = 1u << 2,
  kMask = 1u << 3,
  kCell = 1u << 4,   ///< diagnostics: the grey cell each primary ray hit
  kSteps = 1u << 5,  ///< diagnostics: the traversal's work per primary ray
  kAllChannels = kColor | kDepth | kNormal | kMask | kCell | kSteps,
};

struct Frame {
  int width = 0;
  int height = 0;
  unsigned channels = 0;
  Image<std::uint8_t> color;  ///< RGBA8, sRGB-ish display values; alpha 0 where nothing was hit
  Image<float> depth;         ///< distance along the (unit) primary ray; +infinity where missed
  Image<float> normal;        ///< 3 channels, unit world-space shading normal; 0 where missed
  Image<std::uint8_t> mask;   ///< 1 where the primary ray hit, 0 elsewhere
  /// Index of the hit cell in its model's cell table, -1 where missed (a float: exact below
  /// 2^24 cells, far beyond real models).
  Image<float> cell;
  /// Field evaluations and skip steps of the primary ray over every model, hit or miss.
  Image<float> steps;

  /// Allocates the requested buffers (and frees the others) for a width x height frame.
  void resize(int w, int h, unsigned wanted) {
    width = w;
    height = h;
    channels = wanted;
    color = wanted & kColor ? Image<std::uint8_t>(w, h, 4) : Image<std::uint8_t>();
    depth = wanted & kDepth ? Image<float>(w, h, 1, std::numeric_limits<float>::infinity())
                            : Image<float>();
    normal = wanted & kNormal ? Image<float>(w, h, 3) : Image<float>();
    mask = wanted & kMask ? Image<std::uint8_t>(w, h, 1) : Image<std::uint8_t>();
    cell = wanted & kCell ? Image<float>(w, h, 1, -1.0f) : Image<float>();
    steps = wanted & kSteps ? Image<float>(w, h, 1) : Image<float>();
  }
  bool has(FrameChannel c) const { return (channels & c) != 0; }
};

}  // namespace cellrelief::render
