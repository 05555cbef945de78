// SPDX-License-Identifier: MIT
/// @file parallax_layout.h
/// The scene's relief surfaces (parallax occlusion mapping with an indirection map) in the layout
/// the GPU backends upload: one storage buffer of 32-bit words, read by the shader
/// (relief_trace.comp, "relief surfaces") with the offsets written here; the constants reach it
/// as #defines (shader_preamble.h).
///
/// Words: [0] the surface count; then per surface kSurfaceWords of SurfaceWord fields; then per
/// surface its heights (float, pre-scaled, row-major), its indirection map (two floats per texel)
/// when it has one, its colour map and its normal map (one RGBA8 word per texel) when it has them,
/// and on a base mesh its BVH nodes (kNodeWords each: box min, box max, first, count as BoxBvh
/// numbers them) and its triangles in the BVH's leaf order (kTriangleWords each: v0, e1, e2 as
/// TriangleBvh stores them, then per corner its UV, normal, dP/du and dP/dv).
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
inline constexpr int kSurfaceWords = 32;
inline constexpr int kNodeWords = 8;
inline constexpr int kCornerWords = 11;
inline constexpr int kTriangleWords = 9 + 3 * kCornerWords;
/// The fields of a surface's record.
enum SurfaceWord : int {
  kOrigin = 0,             ///< 3 floats
  kRowU = 3,               ///< 3 floats: world to u (ParallaxTracer::localPoint)
  kRowV = 6,               ///< 3 floats
  kRowW = 9,               ///< 3 floats: world to height in tile widths
  kTop = 12,               ///< float: the slab's height
  kHeightWidth = 13,
  kHeightHeight = 14,
  kRepeat = 15,            ///< 1: the maps repeat (tiling), 0: they clamp
  kHeightOffset = 16,
  kIndirectionOffset = 17, ///< 0 when there is no indirection map
  kIndirectionWidth = 18,
  kIndirectionHeight = 19,
  kColorOffset = 20,       ///< 0 when there is no colour map (a checkerboard)
  kColorWidth = 21,
  kColorHeight = 22,
  kNormalOffset = 23,      ///< 0 when there is no normal map
  kNormalWidth = 24,
  kNormalHeight = 25,
  kCheckerSquares = 26,
  kSurfaceOffset = 27,     ///< float: ParallaxTracer::surfaceOffset
  kMeshNodeOffset = 28,    ///< 0 for a square
  kMeshTriangleOffset = 29,
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

/// A base mesh's BVH and triangles (see the file comment), offsets written into its record.
inline void packMesh(const trace::ParallaxTracer& tracer, const TriangleMesh& mesh, std::vector<std::uint32_t>& words,
                     std::size_t info) {
  using namespace parallax_words;
  const auto floatWord = [](float v) { return std::bit_cast<std::uint32_t>(v); };
  const auto pushVec3 = [&](Vec3f v) {
    for (int a = 0; a < 3; ++a) words.push_back(floatWord(v[a]));
  };
  const TriangleBvh<float>& bvh = tracer.meshBvh();
  words[info + kMeshNodeOffset] = std::uint32_t(words.size());
  for (const auto& node : bvh.nodes()) {
    pushVec3(node.box.min);
    pushVec3(node.box.max);
    words.push_back(node.first);
    words.push_back(node.count);
  }
  words[info + kMeshTriangleOffset] = std::uint32_t(words.size());
  for (const std::uint32_t id : bvh.primitiveIds()) {
    const Vec3u& t = mesh.triangles[id];
    const Vec3f p0 = mesh.positions[t[0]];
    pushVec3(p0);
    pushVec3(mesh.positions[t[1]] - p0);
    pushVec3(mesh.positions[t[2]] - p0);
    for (const trace::ParallaxTracer::Corner& c : tracer.corners(id)) {
      words.push_back(floatWord(c.uv.x));
      words.push_back(floatWord(c.uv.y));
      pushVec3(c.normal);
      pushVec3(c.tangentU);
      pushVec3(c.tangentV);
    }
  }
}

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
             (s->normals.isEmpty() ? 0 : std::uint64_t(s->normals.width()) * s->normals.height()) +
             (s->onMesh() ? std::uint64_t(kTriangleWords + 2 * kNodeWords) * s->baseMesh->triangles.size() : 0);
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
    if (s.onMesh()) packMesh(tracer, *s.baseMesh, out.words, info);
  }
  if (out.words.size() * 4 > maxStorageBytes || out.words.size() >= (1ull << 31))
    throw Error(ErrorKind::ResourceLimit, "the scene's relief surfaces need " + std::to_string(out.words.size() * 4) +
                                              " bytes, beyond the device's storage buffer limit");
  return out;
}

}  // namespace cellrelief::gpu
