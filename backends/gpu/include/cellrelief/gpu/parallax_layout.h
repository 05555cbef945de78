// SPDX-License-Identifier: MIT
/// @file parallax_layout.h
/// The scene's relief surfaces (parallax occlusion mapping with an indirection map) in the layout
/// the GPU backends upload: one storage buffer of 32-bit words, read by the shader
/// (relief_trace.comp, "relief surfaces") with the offsets written here; the constants reach it
/// as #defines (shader_preamble.h).
///
/// Words: [0] the surface count; then per surface kSurfaceWords of SurfaceWord fields; then per
/// surface its heights (float, pre-scaled, row-major), its indirection map (two floats per texel)
/// when it has one, its colour map and its normal map (one RGBA8 word per texel) when it has them.
/// Heights and offsets are floats, not codes, so that the shader samples exactly the values the
/// CPU tracer samples (trace/parallax_tracer.h).
#pragma once

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/render/scene.h"
#include "cellrelief/trace/parallax_tracer.h"

namespace cellrelief::gpu {

namespace parallax_words {
inline constexpr int kSurfaceWords = 40;
/// The fields of a surface's record.
enum SurfaceWord : int {
  kOrigin = 0,             ///< 3 floats
  kRowU = 3,               ///< 3 floats: world to u (ParallaxTracer::localPoint)
  kRowV = 6,               ///< 3 floats
  kRowW = 9,               ///< 3 floats: world to height in tile widths
  kAxisU = 12,             ///< 3 floats: the unit frame, for normals back to world space
  kAxisV = 15,             ///< 3 floats
  kAxisW = 18,             ///< 3 floats
  kTop = 21,               ///< float: the slab's height
  kHeightWidth = 22,
  kHeightHeight = 23,
  kRepeat = 24,            ///< 1: the maps repeat (tiling), 0: they clamp
  kHeightOffset = 25,
  kIndirectionOffset = 26, ///< 0 when there is no indirection map
  kIndirectionWidth = 27,
  kIndirectionHeight = 28,
  kColorOffset = 29,       ///< 0 when there is no colour map (a checkerboard)
  kColorWidth = 30,
  kColorHeight = 31,
  kNormalOffset = 32,      ///< 0 when there is no normal map
  kNormalWidth = 33,
  kNormalHeight = 34,
  kCheckerSquares = 35,
  kSurfaceOffset = 36,     ///< float: ParallaxTracer::surfaceOffset
};
static_assert(kSurfaceOffset < kSurfaceWords);
}  // namespace parallax_words

struct ParallaxGpu {
  std::vector<std::uint32_t> words{0u};  ///< at least the surface count
  bool empty() const { return words.size() <= 1; }
  std::size_t bytes() const { return words.size() * 4; }
};

namespace detail {
inline std::uint32_t rgba8Word(const Image<std::uint8_t>& image, int x, int y) {
  const int channels = image.channels();
  std::uint32_t w = 0;
  for (int c = 0; c < 4; ++c) {
    const std::uint32_t v = c < channels ? image.at(x, y, c) : 255u;
    w |= v << (8 * c);
  }
  return w;
}
}  // namespace detail

/// Packs the scene's relief surfaces. Throws ResourceLimit when the words exceed
/// `maxStorageBytes` or 32-bit indices.
inline ParallaxGpu packReliefSurfaces(const render::Scene& scene, std::size_t maxStorageBytes) {
  using namespace parallax_words;
  ParallaxGpu out;
  if (scene.reliefSurfaces.empty()) return out;
  const auto floatWord = [](float v) { return std::bit_cast<std::uint32_t>(v); };
  const std::size_t count = scene.reliefSurfaces.size();
  std::uint64_t total = 1 + count * kSurfaceWords;
  for (const auto& s : scene.reliefSurfaces)
    total += std::uint64_t(s->relief.width()) * s->relief.height() +
             (s->hasIndirection() ? 2 * std::uint64_t(s->indirection.width()) * s->indirection.height() : 0) +
             (s->colors.isEmpty() ? 0 : std::uint64_t(s->colors.width()) * s->colors.height()) +
             (s->normals.isEmpty() ? 0 : std::uint64_t(s->normals.width()) * s->normals.height());
  if (total * 4 > maxStorageBytes || total >= (1ull << 31))
    throw Error(ErrorKind::ResourceLimit, "the scene's relief surfaces need " + std::to_string(total * 4) +
                                              " bytes, beyond the device's storage buffer limit");
  out.words.assign(1 + count * kSurfaceWords, 0u);
  out.words.reserve(total);
  out.words[0] = std::uint32_t(count);
  for (std::size_t i = 0; i < count; ++i) {
    const indirection::ReliefSurface& s = *scene.reliefSurfaces[i];
    const trace::ParallaxTracer tracer(s);  // the frame, as the CPU traces it
    const std::size_t info = 1 + i * kSurfaceWords;
    const auto set = [&](int field, std::uint32_t v) { out.words[info + std::size_t(field)] = v; };
    const auto setVec3 = [&](int field, Vec3f v) {
      for (int a = 0; a < 3; ++a) set(field + a, floatWord(v[a]));
    };
    setVec3(kOrigin, s.originWS);
    setVec3(kRowU, tracer.rowU());
    setVec3(kRowV, tracer.rowV());
    setVec3(kRowW, tracer.rowW());
    setVec3(kAxisU, tracer.worldDirection(Vec3f(1, 0, 0)));
    setVec3(kAxisV, tracer.worldDirection(Vec3f(0, 1, 0)));
    setVec3(kAxisW, tracer.worldDirection(Vec3f(0, 0, 1)));
    set(kTop, floatWord(tracer.top()));
    set(kHeightWidth, std::uint32_t(s.relief.width()));
    set(kHeightHeight, std::uint32_t(s.relief.height()));
    set(kRepeat, s.relief.wrap() == Wrap::Repeat ? 1u : 0u);
    set(kCheckerSquares, std::uint32_t(s.checkerSquares));
    set(kSurfaceOffset, floatWord(tracer.surfaceOffset()));
    set(kHeightOffset, std::uint32_t(out.words.size()));
    for (int y = 0; y < s.relief.height(); ++y)
      for (int x = 0; x < s.relief.width(); ++x) out.words.push_back(floatWord(s.relief.texel(x, y)));
    if (s.hasIndirection()) {
      set(kIndirectionOffset, std::uint32_t(out.words.size()));
      set(kIndirectionWidth, std::uint32_t(s.indirection.width()));
      set(kIndirectionHeight, std::uint32_t(s.indirection.height()));
      for (int y = 0; y < s.indirection.height(); ++y)
        for (int x = 0; x < s.indirection.width(); ++x)
          for (int c = 0; c < 2; ++c) out.words.push_back(floatWord(s.indirection.at(x, y, c)));
    }
    const auto packRgba = [&](const Image<std::uint8_t>& image, int offsetField) {
      if (image.isEmpty()) return;
      set(offsetField, std::uint32_t(out.words.size()));
      set(offsetField + 1, std::uint32_t(image.width()));
      set(offsetField + 2, std::uint32_t(image.height()));
      for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) out.words.push_back(detail::rgba8Word(image, x, y));
    };
    packRgba(s.colors, kColorOffset);
    packRgba(s.normals, kNormalOffset);
  }
  return out;
}

}  // namespace cellrelief::gpu
