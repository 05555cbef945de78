// SPDX-License-Identifier: MIT
/// @file polycube_layout.h
/// The scene's polycube-mapped meshes in the layout the GPU backends upload: one storage buffer
/// of 32-bit words and one RGBA8 texture holding every mesh's T2 (polycube_texture.h), stacked.
/// The shader (relief_trace.comp, "polycube meshes") reads them with the offsets written here;
/// the word layout's constants go to it as #defines (polycubeLayoutConstants), never typed twice.
///
/// Words: [0] the mesh count; then per mesh kMeshInfoWords of MeshWord fields; then per mesh its
/// BVH nodes (kNodeWords: box min, box max as floats, first, count; trace order of TriangleBvh),
/// its triangles in the BVH's leaf order (kTriangleWords: three vertex indices, the triangle's
/// cubes per world unit), its vertices (kVertexWords: position, normal, texture position) and its
/// look-up table (kLutEntryWords: case | signed permutation of the transform << 3 | squarelet
/// mask << 12, then the first tile; case 7 marks an empty vertex). The transform is written as
/// the signed permutation it is (output axis i = sign * input axis), so the shader needs no table
/// of the 48 symmetries. Meshes that share a T2 share its rows of the texture.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "cellrelief/core/bvh.h"
#include "cellrelief/render/scene.h"
#include "cellrelief/trace/polycube_tracer.h"

namespace cellrelief::gpu {

namespace polycube_words {
inline constexpr int kMeshInfoWords = 32;
inline constexpr int kNodeWords = 8;
inline constexpr int kTriangleWords = 4;
inline constexpr int kVertexWords = 9;
inline constexpr int kLutEntryWords = 2;
inline constexpr int kMaxLevels = 9;  ///< S up to 256
inline constexpr std::uint32_t kEmptyCase = 7;
/// The fields of a mesh's info block.
enum MeshWord : int {
  kNodeOffset = 0,
  kTriangleOffset = 1,
  kVertexOffset = 2,
  kLutOffset = 3,
  kLutOrigin = 4,  ///< 3 ints
  kLutSize = 7,    ///< 3 ints
  kTexels = 10,
  kLevels = 11,
  kTilesPerRow = 12,
  kUse = 13,     ///< 0 colour, 1 normals, 2 none (T2 not read)
  kFilter = 14,  ///< polycube::TextureFilter
  kSurfaceOffset = 15,
  kLevelRow = 16,  ///< kMaxLevels rows of the texture where each level starts
};
static_assert(kLevelRow + kMaxLevels <= kMeshInfoWords);
}  // namespace polycube_words

struct PolycubeGpu {
  std::vector<std::uint32_t> words{0u};  ///< at least the mesh count
  int width = 1, height = 1;             ///< of the T2 texture
  std::vector<std::uint8_t> t2;          ///< RGBA8, rows of `width`; one texel when no mesh
  bool empty() const { return words.size() <= 1; }
  std::size_t bytes() const { return words.size() * 4 + t2.size(); }
};

namespace detail {

inline std::uint32_t floatWord(float v) { return std::bit_cast<std::uint32_t>(v); }

/// A transform as the signed permutation the shader applies: 3 bits per output axis (source axis
/// in bits 0-1, negated in bit 2).
inline std::uint32_t signedPermutation(int transform) {
  std::uint32_t out = 0;
  for (int source = 0; source < 3; ++source) {
    Vec3d e(0.0);
    e[source] = 1.0;
    const Vec3d image = polycube::applyTransform(transform, e);
    for (int axis = 0; axis < 3; ++axis)
      if (image[axis] != 0) out |= std::uint32_t(source | (image[axis] < 0 ? 4 : 0)) << (3 * axis);
  }
  return out;
}

}  // namespace detail

/// Packs the scene's polycube meshes. Throws ResourceLimit when T2s exceed `maxTextureSize` or
/// the words `maxStorageBytes`.
inline PolycubeGpu packPolycubeMeshes(const render::Scene& scene, int maxTextureSize, std::size_t maxStorageBytes) {
  using namespace polycube_words;
  PolycubeGpu out;
  if (scene.polycubeMeshes.empty()) {
    out.t2.assign(4, 0);
    return out;
  }
  const std::size_t meshes = scene.polycubeMeshes.size();
  out.words.assign(1 + meshes * kMeshInfoWords, 0u);
  out.words[0] = std::uint32_t(meshes);
  // T2s, each once, stacked.
  std::map<const polycube::PolycubeTexture*, int> rowOf;
  int rows = 0;
  for (const auto& m : scene.polycubeMeshes) {
    const polycube::PolycubeTexture& t = *m->t2;
    if (!rowOf.emplace(&t, rows).second) continue;
    rows += t.atlas().height();
    out.width = std::max(out.width, t.atlas().width());
  }
  out.height = std::max(rows, 1);
  if (out.width > maxTextureSize || out.height > maxTextureSize)
    throw Error(ErrorKind::ResourceLimit, "the scene's polycube textures need " + std::to_string(out.width) + " x " +
                                              std::to_string(out.height) + " texels, beyond the device's " +
                                              std::to_string(maxTextureSize));
  out.t2.assign(std::size_t(out.width) * out.height * 4, 0);
  for (const auto& [texture, row] : rowOf) {
    const auto texels = texture->atlas().levelData(0);
    const std::size_t rowBytes = std::size_t(texture->atlas().width()) * 4;
    for (int y = 0; y < texture->atlas().height(); ++y)
      std::memcpy(out.t2.data() + (std::size_t(row + y) * out.width) * 4, texels.data() + y * rowBytes, rowBytes);
  }
  for (std::size_t i = 0; i < meshes; ++i) {
    const polycube::TexturedMesh& mesh = *scene.polycubeMeshes[i];
    const trace::PolycubeTracer tracer(scene.polycubeMeshes[i]);  // validates; its BVH, normals and scales
    const polycube::PolycubeTexture& t2 = *mesh.t2;
    const polycube::PolycubeLut& lut = t2.surface().lut();
    const auto setInfo = [&](int field, std::uint32_t v) { out.words[1 + i * kMeshInfoWords + std::size_t(field)] = v; };
    setInfo(kNodeOffset, std::uint32_t(out.words.size()));
    for (const auto& node : tracer.bvh().nodes()) {
      for (int a = 0; a < 3; ++a) out.words.push_back(detail::floatWord(node.box.min[a]));
      for (int a = 0; a < 3; ++a) out.words.push_back(detail::floatWord(node.box.max[a]));
      out.words.push_back(node.first);
      out.words.push_back(node.count);
    }
    setInfo(kTriangleOffset, std::uint32_t(out.words.size()));
    for (const std::uint32_t id : tracer.bvh().primitiveIds()) {
      const Vec3u& t = mesh.mesh.triangles[id];
      out.words.insert(out.words.end(), {t[0], t[1], t[2], detail::floatWord(tracer.cubesPerWorld(id))});
    }
    setInfo(kVertexOffset, std::uint32_t(out.words.size()));
    for (std::size_t v = 0; v < mesh.mesh.positions.size(); ++v) {
      for (int a = 0; a < 3; ++a) out.words.push_back(detail::floatWord(mesh.mesh.positions[v][a]));
      for (int a = 0; a < 3; ++a) out.words.push_back(detail::floatWord(tracer.vertexNormal(v)[a]));
      for (int a = 0; a < 3; ++a) out.words.push_back(detail::floatWord(mesh.texture[v][a]));
    }
    setInfo(kLutOffset, std::uint32_t(out.words.size()));
    for (const polycube::LutEntry& e : lut.entries()) {
      if (e.empty()) {
        out.words.insert(out.words.end(), {kEmptyCase, 0u});
        continue;
      }
      const std::uint32_t head =
          std::uint32_t(e.vertexCase) | (detail::signedPermutation(e.transform) << 3) | (std::uint32_t(e.squarelets()) << 12);
      out.words.insert(out.words.end(), {head, e.firstTile});
    }
    for (int a = 0; a < 3; ++a) {
      setInfo(kLutOrigin + a, std::uint32_t(lut.origin()[a]));
      setInfo(kLutSize + a, std::uint32_t(lut.size()[a]));
    }
    setInfo(kTexels, std::uint32_t(t2.texelsPerSquarelet()));
    setInfo(kLevels, std::uint32_t(t2.levelCount()));
    setInfo(kTilesPerRow, t2.tilesPerRow());
    setInfo(kUse, mesh.use == polycube::TextureUse::Color ? 0u : mesh.use == polycube::TextureUse::Normal ? 1u : 2u);
    setInfo(kFilter, std::uint32_t(mesh.filter));
    setInfo(kSurfaceOffset, detail::floatWord(tracer.surfaceOffset()));
    for (int level = 0; level < t2.levelCount(); ++level)
      setInfo(kLevelRow + level, std::uint32_t(rowOf.at(&t2) + t2.levelRow(level)));
  }
  if (out.words.size() * 4 > maxStorageBytes)
    throw Error(ErrorKind::ResourceLimit, "the scene's polycube meshes need " + std::to_string(out.words.size() * 4) +
                                              " bytes, beyond the device's storage buffer limit");
  return out;
}

}  // namespace cellrelief::gpu
