// SPDX-License-Identifier: MIT
/// @file geotex_layout.h
/// The scene's geometry-texture models in the layout the GPU backends upload: one storage buffer
/// of 32-bit words, read by the shader (relief_trace.comp, "geometry textures") with the offsets
/// written here; the layout's constants go to it as #defines (shader_preamble.h), never typed twice.
///
/// Words: [0] the model count; then per model kModelInfoWords of ModelWord fields; then per model
/// its charts (kChartWords: the world-to-chart rows as trace::GeoTexTracer holds them, the box in
/// chart units, the height scale, the map size and first texel), the BVH over their boxes
/// (kNodeWords, BoxBvh's depth-first order) and its leaf order, the height codes two to a word
/// (texel 2i in the low half), one octahedral normal word per texel, one RGBA8 word per texel
/// when the model has colours, and the charts' height pyramids (trace::GeoTexTracer::pyramids(),
/// one word per node). Texels are in the model's own order, so chart records point into them
/// unchanged.
#pragma once

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "cellrelief/core/bvh.h"
#include "cellrelief/core/error.h"
#include "cellrelief/render/scene.h"
#include "cellrelief/trace/geotex_tracer.h"

namespace cellrelief::gpu {

namespace geotex_words {
inline constexpr int kModelInfoWords = 12;
inline constexpr int kChartWords = 20;
inline constexpr int kNodeWords = 8;
/// The fields of a model's info block.
enum ModelWord : int {
  kChartOffset = 0,
  kNodeOffset = 1,
  kPrimitiveOffset = 2,
  kHeightOffset = 3,
  kNormalOffset = 4,
  kColorOffset = 5,  ///< 0 when the model has no colours
  kEmptyCode = 6,
  kSurfaceOffset = 7,  ///< float
};
/// The fields of a chart record.
enum ChartWord : int {
  kOrigin = 0,       ///< 3 floats
  kRowX = 3,         ///< 3 floats: world to chart x (texels)
  kRowY = 6,         ///< 3 floats
  kRowZ = 9,         ///< 3 floats: world to height (world units)
  kBoxSize = 12,     ///< 3 floats: width, height (texels), z size
  kHeightScale = 15, ///< float: world units per height code
  kWidth = 16,
  kHeight = 17,
  kFirstTexel = 18,
  kPyramid = 19,     ///< the word of the chart's first pyramid node (level 1)
};
static_assert(kPyramid < kChartWords);
}  // namespace geotex_words

struct GeoTexGpu {
  std::vector<std::uint32_t> words{0u};  ///< at least the model count
  bool empty() const { return words.size() <= 1; }
  std::size_t bytes() const { return words.size() * 4; }
};

/// Packs the scene's geometry-texture models. Throws ResourceLimit when the words exceed
/// `maxStorageBytes` or 32-bit indices.
inline GeoTexGpu packGeoTexModels(const render::Scene& scene, std::size_t maxStorageBytes) {
  using namespace geotex_words;
  GeoTexGpu out;
  if (scene.geotexModels.empty()) return out;
  const auto floatWord = [](float v) { return std::bit_cast<std::uint32_t>(v); };
  const std::size_t models = scene.geotexModels.size();
  out.words.assign(1 + models * kModelInfoWords, 0u);
  out.words[0] = std::uint32_t(models);
  for (std::size_t i = 0; i < models; ++i) {
    const geotex::GeoTexModel& model = *scene.geotexModels[i];
    const trace::GeoTexTracer<float> tracer(model);  // the rows, the BVH and pyramids, as the CPU traces them
    std::uint64_t words = out.words.size() + model.charts.size() * (kChartWords + 2 * kNodeWords + 1) +
                          (model.texelCount() + 1) / 2 + model.texelCount() * (model.hasColors() ? 2 : 1) +
                          tracer.pyramids().size();
    if (words * 4 > maxStorageBytes || words >= (1ull << 31))
      throw Error(ErrorKind::ResourceLimit, "the scene's geometry textures need " + std::to_string(words * 4) +
                                                " bytes, beyond the device's storage buffer limit");
    const auto setInfo = [&](int field, std::uint32_t v) { out.words[1 + i * kModelInfoWords + std::size_t(field)] = v; };
    const std::size_t firstChart = out.words.size();
    setInfo(kChartOffset, std::uint32_t(firstChart));
    for (const geotex::ChartBox& c : model.charts) {
      const std::size_t at = out.words.size();
      out.words.resize(at + kChartWords, 0u);
      const Vec3d rows[3] = {c.axisWS[0] * (double(c.width) / c.sizeWS.x), c.axisWS[1] * (double(c.height) / c.sizeWS.y),
                             c.axisWS[2]};
      for (int a = 0; a < 3; ++a) {
        out.words[at + kOrigin + a] = floatWord(float(c.originWS[a]));
        out.words[at + kRowX + a] = floatWord(float(rows[0][a]));
        out.words[at + kRowY + a] = floatWord(float(rows[1][a]));
        out.words[at + kRowZ + a] = floatWord(float(rows[2][a]));
      }
      out.words[at + kBoxSize + 0] = floatWord(float(c.width));
      out.words[at + kBoxSize + 1] = floatWord(float(c.height));
      out.words[at + kBoxSize + 2] = floatWord(float(c.sizeWS.z));
      out.words[at + kHeightScale] = floatWord(float(c.sizeWS.z) / float(model.heightCodec.largestCode()));
      out.words[at + kWidth] = c.width;
      out.words[at + kHeight] = c.height;
      out.words[at + kFirstTexel] = std::uint32_t(c.firstTexel);
    }
    setInfo(kNodeOffset, std::uint32_t(out.words.size()));
    for (const auto& node : tracer.bvh().nodes()) {
      for (int a = 0; a < 3; ++a) out.words.push_back(floatWord(node.box.min[a]));
      for (int a = 0; a < 3; ++a) out.words.push_back(floatWord(node.box.max[a]));
      out.words.push_back(node.first);
      out.words.push_back(node.count);
    }
    setInfo(kPrimitiveOffset, std::uint32_t(out.words.size()));
    for (const std::uint32_t id : tracer.bvh().primitiveIds()) out.words.push_back(id);
    setInfo(kHeightOffset, std::uint32_t(out.words.size()));
    for (std::size_t t = 0; t < model.heights.size(); t += 2)
      out.words.push_back(model.heights[t] | (t + 1 < model.heights.size() ? std::uint32_t(model.heights[t + 1]) << 16 : 0u));
    setInfo(kNormalOffset, std::uint32_t(out.words.size()));
    out.words.insert(out.words.end(), model.normals.begin(), model.normals.end());
    if (model.hasColors()) {
      setInfo(kColorOffset, std::uint32_t(out.words.size()));
      for (const Color8& c : model.colors)
        out.words.push_back(std::uint32_t(c.r) | std::uint32_t(c.g) << 8 | std::uint32_t(c.b) << 16 | std::uint32_t(c.a) << 24);
    }
    const std::size_t firstPyramidWord = out.words.size();
    out.words.insert(out.words.end(), tracer.pyramids().begin(), tracer.pyramids().end());
    for (std::size_t c = 0; c < model.charts.size(); ++c)
      out.words[firstChart + c * kChartWords + kPyramid] =
          std::uint32_t(firstPyramidWord + tracer.firstPyramidNode(std::uint32_t(c)));
    setInfo(kEmptyCode, model.heightCodec.emptyCode());
    setInfo(kSurfaceOffset, floatWord(tracer.surfaceOffset()));
  }
  if (out.words.size() * 4 > maxStorageBytes)
    throw Error(ErrorKind::ResourceLimit, "the scene's geometry textures need " + std::to_string(out.words.size() * 4) +
                                              " bytes, beyond the device's storage buffer limit");
  return out;
}

}  // namespace cellrelief::gpu
