// SPDX-License-Identifier: MIT
/// @file atlas.h
/// The maps of a relief model as PNG atlases, for looking at them: the layers side by side in a
/// grid of tiles. Distances as 16-bit gray (near surface bright, empty samples black), normals as
/// RGB (n * 0.5 + 0.5), colors as RGBA.
#pragma once

#include <cmath>
#include <filesystem>
#include <vector>

#include "cellrelief/io/image_io.h"
#include "cellrelief/relief/relief_model.h"

namespace cellrelief::relief {

/// Writes distance.png (and normal.png, color.png when present) into `folder`; returns the paths.
inline std::vector<std::filesystem::path> writeAtlases(const ReliefModel& model,
                                                       const std::filesystem::path& folder,
                                                       int maxLayers = 4096) {
  std::filesystem::create_directories(folder);
  const int layers = std::min(model.layerCount(), maxLayers);
  std::vector<std::filesystem::path> written;
  if (layers == 0) return written;
  const int T = model.texels, gap = 1;
  const int columns = int(std::ceil(std::sqrt(double(layers))));
  const int rows = (layers + columns - 1) / columns;
  const int width = columns * (T + gap), height = rows * (T + gap);
  auto origin = [&](int layer) { return Vec2i((layer % columns) * (T + gap), (layer / columns) * (T + gap)); };

  Image<std::uint16_t> distance(width, height, 1, 0);
  for (int l = 0; l < layers; ++l)
    for (int b = 0; b < T; ++b)
      for (int a = 0; a < T; ++a) {
        const std::uint32_t code = model.distanceCode(l, a, b);
        if (!model.distanceCodec.hasSurface(code)) continue;
        const double nearness = 1.0 - double(model.distanceCodec.decode(code)) / double(model.distanceCodec.distanceMax);
        distance.at(origin(l).x + a, origin(l).y + b, 0) =
            std::uint16_t(std::lround(1024 + nearness * (65535 - 1024)));
      }
  io::writePng(distance, folder / "distance.png");
  written.push_back(folder / "distance.png");

  if (model.normalFormat != NormalFormat::None) {
    Image<std::uint8_t> normal(width, height, 3, 0);
    for (int l = 0; l < layers; ++l)
      for (int b = 0; b < T; ++b)
        for (int a = 0; a < T; ++a) {
          if (!model.distanceCodec.hasSurface(model.distanceCode(l, a, b))) continue;
          const Vec3f n = model.normal(l, a, b) * 0.5f + 0.5f;
          for (int c = 0; c < 3; ++c)
            normal.at(origin(l).x + a, origin(l).y + b, c) = quantizeUnorm<std::uint8_t>(n[c]);
        }
    io::writePng(normal, folder / "normal.png");
    written.push_back(folder / "normal.png");
  }
  if (model.colorFormat == ColorFormat::Rgba8) {
    Image<std::uint8_t> color(width, height, 4, 0);
    for (int l = 0; l < layers; ++l)
      for (int b = 0; b < T; ++b)
        for (int a = 0; a < T; ++a)
          for (int c = 0; c < 4; ++c)
            color.at(origin(l).x + a, origin(l).y + b, c) = model.colors.at(a, b, l, c);
    io::writePng(color, folder / "color.png");
    written.push_back(folder / "color.png");
  }
  return written;
}

}  // namespace cellrelief::relief
