// SPDX-License-Identifier: MIT
/// @file past_line_end.h
/// Test helper: empties the samples whose stored hit lies past their projection line's end
/// (convert.h, kPastLineEndSamples), to measure a model without them.
#pragma once

#include <cstddef>
#include <cstdint>

#include <cellrelief/projection/choice.h>
#include <cellrelief/relief/relief_model.h>

namespace cellrelief::test {

/// Empties, in the cells of projection `type` (planar or parallel), every sample farther than
/// the line's length (half a cell, or a cell); returns how many. 16-bit models only.
inline std::size_t emptySamplesPastLineEnd(relief::ReliefModel& model, projection::ProjectionType type) {
  const float lineLength = type == projection::ProjectionType::Planar ? 0.5f : 1.0f;
  std::size_t emptied = 0;
  for (const relief::CellRecord& r : model.cells) {
    if (r.projection<double>().type != type) continue;
    for (int f = 0; f < cells::kFaceCount; ++f) {
      const int layer = r.layerOf(f);
      if (layer < 0) continue;
      for (int b = 0; b < model.texels; ++b)
        for (int a = 0; a < model.texels; ++a)
          if (model.distance(layer, a, b) > lineLength) {
            model.distances16.at(a, b, layer, 0) = std::uint16_t(model.distanceCodec.emptyCode());
            ++emptied;
          }
    }
  }
  return emptied;
}

}  // namespace cellrelief::test
