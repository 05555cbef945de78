// SPDX-License-Identifier: MIT
/// @file relief_surface.h
/// A height-mapped square in world space, the scene element of parallax occlusion mapping with an
/// indirection map (McGuire & Whitson, section 5): the relief map, and optionally the indirection
/// map I, a colour map and a tangent-space normal map. A renderer marches rays through the slab
/// over the square (trace/parallax_tracer.h on the CPU, the shared GLSL on the GPUs) and fetches
/// the colour at (u, v) + I(u, v) instead of (u, v).
///
/// The square is placed by an origin and two orthogonal edges of equal length: the map's metric
/// (and so the indirection map, which is conformal for it) is that of a square tile; a rectangle
/// would stretch it. Heights are in tile widths (ReliefMap's height scale), so they grow with the
/// square. A surface holds its maps by value; the scene shares the surface by pointer.
///
/// Instead of the square, a surface may lie on a base mesh with UVs (`baseMesh`): the classic
/// per-fragment POM of a textured mesh. The mesh is the top of the relief, which is carved below
/// it (the highest heights lie on the mesh, so the silhouette is the mesh's); a tile width there is
/// the mesh's world length per unit of UV at the hit, and `uvScale` repeats the maps over the UVs.
#pragma once

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/error.h"
#include "cellrelief/core/image.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/indirection/indirection_file.h"
#include "cellrelief/indirection/relief_map.h"
#include "cellrelief/io/image_io.h"
#include "cellrelief/io/mesh_io.h"

namespace cellrelief::indirection {

struct ReliefSurface {
  ReliefMap relief;                  ///< the heights, pre-scaled, and their wrap mode
  Image<float> indirection;          ///< I = M^-1 - id, 2 channels; empty: plain POM
  Image<std::uint8_t> colors;        ///< RGB(A) colour map fetched at (u, v) + I; empty: a checkerboard
  Image<std::uint8_t> normals;       ///< tangent-space normals, RGB = (n + 1) / 2, x along u, y along v;
                                     ///< empty: the normals of the height interpolant
  int checkerSquares = 16;           ///< the checkerboard's squares per side when there is no colour map
  Vec3f originWS{0.0f};              ///< the corner (u, v) = (0, 0)
  Vec3f uAxisWS{1.0f, 0.0f, 0.0f};   ///< the edge to (1, 0)
  Vec3f vAxisWS{0.0f, 1.0f, 0.0f};   ///< the edge to (0, 1); the relief rises along u x v
  /// A base mesh with per-corner UVs in place of the square (the placement above is then unused);
  /// one-sided: rays see its front faces only, as a rasterizer culling back faces draws it.
  std::shared_ptr<const TriangleMesh> baseMesh;
  float uvScale = 1.0f;              ///< the mesh's UVs times this (the maps repeat this often)

  float sideWS() const { return glm::length(uAxisWS); }
  Vec3f normalWS() const { return glm::normalize(glm::cross(uAxisWS, vAxisWS)); }
  bool hasIndirection() const { return !indirection.isEmpty(); }
  bool onMesh() const { return baseMesh != nullptr; }

  /// The slab over the square, or the base mesh's bounds (the relief lies below it), in world space.
  Aabbd boundsWS() const {
    Aabbd box;
    if (onMesh()) {
      const Aabbf b = baseMesh->surfaceBounds();
      box.extend(Vec3d(b.min));
      box.extend(Vec3d(b.max));
      return box;
    }
    const Vec3f up = normalWS() * (relief.maxHeight() * sideWS());
    for (int corner = 0; corner < 8; ++corner)
      box.extend(Vec3d(originWS + float(corner & 1) * uAxisWS + float((corner >> 1) & 1) * vAxisWS +
                       float((corner >> 2) & 1) * up));
    return box;
  }

  std::size_t byteSize() const {
    const std::size_t mesh = onMesh() ? baseMesh->positions.size() * sizeof(Vec3f) +
                                            baseMesh->triangles.size() * sizeof(Vec3u) +
                                            baseMesh->uvs.size() * sizeof(Vec2f)
                                      : 0;
    return std::size_t(relief.width()) * relief.height() * sizeof(float) + indirection.byteSize() + colors.byteSize() +
           normals.byteSize() + mesh;
  }

  /// Throws InvalidArgument (naming the problem) when the placement is not a square of finite,
  /// non-zero size or a map has the wrong channel count.
  void validate() const {
    if (onMesh()) {
      validateMesh();
    } else {
      validatePlacement();
    }
    if (relief.width() < 2)
      throw Error(ErrorKind::InvalidArgument, "relief surface: no relief map");
    if (hasIndirection() && indirection.channels() != 2)
      throw Error(ErrorKind::InvalidArgument, "relief surface: the indirection map needs 2 channels, not " +
                                                  std::to_string(indirection.channels()));
    if (!colors.isEmpty() && colors.channels() < 3)
      throw Error(ErrorKind::InvalidArgument, "relief surface: the colour map needs 3 or 4 channels");
    if (!normals.isEmpty() && normals.channels() < 3)
      throw Error(ErrorKind::InvalidArgument, "relief surface: the normal map needs 3 or 4 channels");
    if (checkerSquares < 1 || checkerSquares > 4096)
      throw Error(ErrorKind::InvalidArgument, "relief surface: checker squares must be 1 to 4096");
  }

 private:
  void validateMesh() const {
    baseMesh->validate();
    if (baseMesh->triangles.empty())
      throw Error(ErrorKind::InvalidArgument, "relief surface: the base mesh has no triangles");
    if (!baseMesh->hasUVs())
      throw Error(ErrorKind::InvalidArgument, "relief surface: the base mesh has no texture coordinates");
    for (const Vec2f& uv : baseMesh->uvs)
      if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
        throw Error(ErrorKind::InvalidArgument, "relief surface: the base mesh has a texture coordinate that is not finite");
    if (!(uvScale > 0) || !std::isfinite(uvScale))
      throw Error(ErrorKind::InvalidArgument, "relief surface: the UV scale must be positive and finite");
  }

  void validatePlacement() const {
    const auto finite = [](Vec3f v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
    if (!finite(originWS) || !finite(uAxisWS) || !finite(vAxisWS))
      throw Error(ErrorKind::InvalidArgument, "relief surface: a placement vector is not finite");
    const float a = glm::length(uAxisWS), b = glm::length(vAxisWS);
    if (!(a > 0) || !(b > 0) || !std::isfinite(a * b))
      throw Error(ErrorKind::InvalidArgument, "relief surface: an edge has zero or overflowing length");
    if (std::abs(a - b) > 1e-4f * a || std::abs(glm::dot(uAxisWS, vAxisWS)) > 1e-4f * a * b)
      throw Error(ErrorKind::InvalidArgument,
                  "relief surface: the edges must be orthogonal and of equal length (a square tile; lengths " +
                      std::to_string(a) + " and " + std::to_string(b) + ")");
  }
};

/// The files of a relief surface. Empty paths: no such map.
struct ReliefSurfaceFiles {
  std::filesystem::path heightmap;    ///< grey image, or the alpha of a DirectX SDK normal+height TGA
  std::filesystem::path indirection;  ///< as `cellrelief indirect` writes it (PNG + sidecar)
  std::filesystem::path colors;       ///< colour map (8 or 16 bit, grey or RGB(A))
  std::filesystem::path normals;      ///< tangent-space normal map; when empty and the heights come
                                      ///< from a 4-channel TGA's alpha, its RGB is the normal map
  std::filesystem::path baseMesh;     ///< a mesh with UVs to carve the relief into; empty: the unit square
  float uvScale = 1.0f;
  std::optional<float> heightScale;   ///< default: the indirection map's (its sidecar), else 0.1
  Wrap wrap = Wrap::Clamp;
};

namespace detail {
/// An image file as 8-bit RGB, or RGBA when it has alpha and `keepAlpha` (grey repeated, 16 bits
/// rounded).
inline Image<std::uint8_t> rgb8(const io::ImageFile& file, bool keepAlpha = true) {
  const int channels = keepAlpha && file.channels() == 4 ? 4 : 3;
  Image<std::uint8_t> out(file.width(), file.height(), channels);
  for (int y = 0; y < file.height(); ++y)
    for (int x = 0; x < file.width(); ++x) {
      const Vec4f t = file.fetch(x, y);
      const bool grey = file.channels() < 3;
      for (int c = 0; c < channels; ++c)
        out.at(x, y, c) = quantizeUnorm<std::uint8_t>(grey && c < 3 ? t.x : t[c]);
    }
  return out;
}
}  // namespace detail

/// Reads a relief surface's maps (placed as the unit square at the origin). Throws Error naming
/// the file and the problem; an indirection map computed for another height scale than the one
/// asked for is refused, since it is conformal only for its own relief.
inline ReliefSurface loadReliefSurface(const ReliefSurfaceFiles& files) {
  ReliefSurface surface;
  std::optional<IndirectionFile> indirection;
  if (!files.indirection.empty()) indirection = readIndirectionMap(files.indirection);
  float heightScale = files.heightScale.value_or(0.1f);
  if (indirection && indirection->provenance.heightScale > 0) {
    const float computedFor = indirection->provenance.heightScale;
    if (files.heightScale && std::abs(*files.heightScale - computedFor) > 1e-6f * std::max(1.0f, computedFor))
      throw Error(ErrorKind::InvalidArgument, files.indirection,
                  "computed for height scale " + std::to_string(computedFor) + ", not " +
                      std::to_string(*files.heightScale) + " (compute it again, or leave the height scale out)");
    heightScale = computedFor;
  }
  const io::ImageFile heights = io::readImage(files.heightmap);
  surface.relief = reliefMapOf(heights, files.heightmap, {.heightScale = heightScale, .wrap = files.wrap});
  if (indirection) surface.indirection = std::move(indirection->map);
  if (!files.colors.empty()) surface.colors = detail::rgb8(io::readImage(files.colors));
  if (!files.normals.empty())
    surface.normals = detail::rgb8(io::readImage(files.normals), false);
  else if (heights.channels() == 4 && heights.format == "tga")  // a DirectX SDK normal+height map
    surface.normals = detail::rgb8(heights, false);
  if (!files.baseMesh.empty()) {
    auto mesh = std::make_shared<TriangleMesh>(io::readMesh(files.baseMesh));
    if (!mesh->hasUVs())
      throw Error(ErrorKind::InvalidInput, files.baseMesh,
                  "has no texture coordinates (an OBJ's vt, a PLY's texcoords), which relief mapping needs");
    surface.baseMesh = std::move(mesh);
    surface.uvScale = files.uvScale;
  }
  surface.validate();
  return surface;
}

}  // namespace cellrelief::indirection
