// SPDX-License-Identifier: MIT
/// @file past_line_end.h
/// Test helper: empties the samples whose stored hit lies past their projection line's end
/// (convert.h, kPastLineEndSamples), to measure a model without them.
#pragma once

#include <cstddef>
#include <cstdint>

#include <cellrelief/projection/choice.h>
#include <cellrelief/projection/projections.h>
#include <cellrelief/relief/relief_model.h>

namespace cellrelief::test {

/// Empties, in the cells of projection `type`, every sample whose distance exceeds its projection
/// line's length (what CellProjection::lineEnd gives); returns how many. 16-bit models only.
inline std::size_t emptySamplesPastLineEnd(relief::ReliefModel& model, projection::ProjectionType type) {
  std::size_t emptied = 0;
  for (const relief::CellRecord& r : model.cells) {
    const auto proj = r.projection<double>();
    if (proj.type != type) continue;
    for (int f = 0; f < cells::kFaceCount; ++f) {
      const int layer = r.layerOf(f);
      if (layer < 0) continue;
      for (int b = 0; b < model.texels; ++b)
        for (int a = 0; a < model.texels; ++a) {
          const Vec2d uv(double(a) / (model.texels - 1), double(b) / (model.texels - 1));
          const Vec3d onFace = projection::facePoint(f, uv);
          if (model.distance(layer, a, b) > glm::length(proj.lineEnd(f, onFace) - onFace)) {
            model.distances16.at(a, b, layer, 0) = std::uint16_t(model.distanceCodec.emptyCode());
            ++emptied;
          }
        }
    }
  }
  return emptied;
}

}  // namespace cellrelief::test
