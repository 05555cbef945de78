// SPDX-License-Identifier: MIT
/// @file triangle_mesh.h
/// An indexed triangle mesh with optional per-vertex normals and colors and per-corner UVs. It is a
/// plain triangle soup with shared vertices, not a half-edge structure: real inputs are non-manifold,
/// open or self-intersecting, and must load as they are (mesh_topology.h reports what is unusual).
/// UVs are per corner because texture seams (OBJ `vt` indices) give one vertex several UVs.
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/error.h"
#include "cellrelief/core/math.h"

namespace cellrelief {

struct TriangleMesh {
  std::vector<Vec3f> positions;
  std::vector<Vec3u> triangles;
  std::vector<Vec3f> normals;  ///< per vertex; empty or positions.size()
  std::vector<Color8> colors;  ///< per vertex, RGBA8; empty or positions.size()
  std::vector<Vec2f> uvs;      ///< per corner (3 per triangle); empty or 3 * triangles.size()
  /// Polygons in the source before triangulation (equals triangles.size() for triangle inputs).
  std::size_t sourcePolygons = 0;

  std::size_t vertexCount() const { return positions.size(); }
  std::size_t triangleCount() const { return triangles.size(); }
  bool hasNormals() const { return !normals.empty(); }
  bool hasColors() const { return !colors.empty(); }
  bool hasUVs() const { return !uvs.empty(); }

  Aabbf bounds() const {
    Aabbf box;
    for (const Vec3f& p : positions) box.extend(p);
    return box;
  }
  /// Bounds of the vertices that triangles use (unreferenced ones, as in the bunny, do not count):
  /// the extent of the surface.
  Aabbf surfaceBounds() const {
    Aabbf box;
    for (const Vec3u& t : triangles)
      for (int k = 0; k < 3; ++k) box.extend(positions[t[k]]);
    return box;
  }

  /// Throws Error(InvalidInput) naming the first problem: an attribute array of the wrong size, a
  /// triangle index out of range, a non-finite coordinate. `source` prefixes the message (a path).
  void validate(const std::string& source = "mesh") const {
    auto fail = [&](const std::string& problem) {
      throw Error(ErrorKind::InvalidInput, source, problem);
    };
    if (!normals.empty() && normals.size() != positions.size())
      fail("normal count " + std::to_string(normals.size()) + " differs from vertex count " +
           std::to_string(positions.size()));
    if (!colors.empty() && colors.size() != positions.size())
      fail("color count " + std::to_string(colors.size()) + " differs from vertex count " +
           std::to_string(positions.size()));
    if (!uvs.empty() && uvs.size() != 3 * triangles.size())
      fail("UV count " + std::to_string(uvs.size()) + " is not 3 per triangle");
    for (std::size_t i = 0; i < positions.size(); ++i)
      if (!isFinite(positions[i]))
        fail("vertex " + std::to_string(i) + " has a non-finite coordinate (NaN or infinity)");
    const auto n = static_cast<unsigned>(positions.size());
    for (std::size_t f = 0; f < triangles.size(); ++f)
      for (int k = 0; k < 3; ++k)
        if (triangles[f][k] >= n)
          fail("triangle " + std::to_string(f) + " refers to vertex " +
               std::to_string(triangles[f][k]) + " (0-based) but there are only " + std::to_string(n) +
               " vertices");
  }
};

/// Area-weighted vertex normals (the cross product of two edges weights each face by its area).
inline std::vector<Vec3f> computeVertexNormals(const TriangleMesh& mesh) {
  std::vector<Vec3f> normals(mesh.positions.size(), Vec3f(0));
  for (const Vec3u& t : mesh.triangles) {
    const Vec3f n = glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]],
                               mesh.positions[t[2]] - mesh.positions[t[0]]);
    for (int k = 0; k < 3; ++k) normals[t[k]] += n;
  }
  for (Vec3f& n : normals) {
    const float len = glm::length(n);
    n = len > 0 ? n / len : Vec3f(0, 0, 1);
  }
  return normals;
}

/// Total surface area, accumulated in double.
inline double surfaceArea(const TriangleMesh& mesh) {
  double area = 0;
  for (const Vec3u& t : mesh.triangles) {
    const Vec3d a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), c(mesh.positions[t[2]]);
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
  }
  return area;
}

}  // namespace cellrelief
