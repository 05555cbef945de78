// SPDX-License-Identifier: MIT
/// @file mesh_signal.h
/// Signals of a mesh to bake into T2 (polycube_texture.h) through its polycube map: the inverse
/// of the map, from a point of the polycube's surface to the point of the mesh that maps there.
///
/// The mesh with its 3D texture positions as vertices is a triangulation of (a neighbourhood of)
/// the polycube's surface; a triangle whose corners lie on different faces is a chord across an
/// edge. The mesh point of a surface point q is found on the triangle of that triangulation
/// closest to q (a BVH over the texture positions), at q's barycentric coordinates there, which
/// is exact inside a face and within the chord's sag across an edge. The mesh may be the full
/// resolution one whose map was transferred (levels_of_detail.h), so a coarse level of detail can
/// be rendered with the fine mesh's normals or shading, as in the paper's figures.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "cellrelief/core/bvh.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/polycube/polycube_texture.h"

namespace cellrelief::polycube {

/// What of the mesh a signal carries.
enum class MeshSignalKind {
  Normal,   ///< the interpolated vertex normal, as RGB = 0.5 + 0.5 n (world space)
  Shading,  ///< grey: ambient 0.18 plus Lambert under the default light of render::Scene
  Color,    ///< the mesh's vertex colours (the mesh must have them)
};

constexpr std::string_view toString(MeshSignalKind k) {
  switch (k) {
    case MeshSignalKind::Normal: return "normals";
    case MeshSignalKind::Shading: return "shading";
    case MeshSignalKind::Color: return "color";
  }
  return "unknown";
}

/// The inverse of a polycube map, shared by the signals made from it.
class InverseMap {
 public:
  /// `texture`: one position per mesh vertex on the polycube's surface (lattice coordinates).
  InverseMap(const TriangleMesh& mesh, std::span<const Vec3d> texture)
      : mMesh(mesh), mTexture(texture.begin(), texture.end()) {
    mesh.validate();
    if (mTexture.size() != mesh.positions.size())
      throw Error(ErrorKind::InvalidArgument, "polycube signal: " + std::to_string(mTexture.size()) +
                                                  " texture positions for " + std::to_string(mesh.positions.size()) +
                                                  " vertices");
    if (mesh.triangles.empty()) throw Error(ErrorKind::InvalidArgument, "polycube signal: the mesh has no triangles");
    mNormals = mesh.normals.size() == mesh.positions.size() ? mesh.normals : computeVertexNormals(mesh);
    mBvh = TriangleBvh<double>(mTexture, mesh.triangles);
  }

  /// The triangle and barycentric coordinates of the mesh point that maps to surface point q.
  std::pair<std::uint32_t, Vec3d> locate(const Vec3d& q) const {
    const std::uint32_t triangle = mBvh.closestPoint(q).second;
    const Vec3u& t = mMesh.triangles[triangle];
    return {triangle, closestPointBarycentrics(q, mTexture[t[0]], mTexture[t[1]], mTexture[t[2]])};
  }

  Vec3f normal(const Vec3d& q) const {
    const auto [triangle, w] = locate(q);
    const Vec3u& t = mMesh.triangles[triangle];
    const Vec3f n = float(w[0]) * mNormals[t[0]] + float(w[1]) * mNormals[t[1]] + float(w[2]) * mNormals[t[2]];
    const float length = glm::length(n);
    return length > 0 ? n / length : Vec3f(0, 0, 1);
  }

  Vec4f color(const Vec3d& q) const {
    const auto [triangle, w] = locate(q);
    const Vec3u& t = mMesh.triangles[triangle];
    Vec4f c(0.0f);
    for (int k = 0; k < 3; ++k) {
      const Color8& v = mMesh.colors[t[k]];
      c += float(w[k]) * Vec4f(v[0], v[1], v[2], v[3]) / 255.0f;
    }
    return c;
  }

  const TriangleMesh& mesh() const { return mMesh; }

 private:
  TriangleMesh mMesh;
  std::vector<Vec3d> mTexture;
  std::vector<Vec3f> mNormals;
  TriangleBvh<double> mBvh;
};

/// A signal of the mesh through its map. Throws InvalidArgument for Color on a mesh without
/// vertex colours.
inline SurfaceSignal meshSignal(std::shared_ptr<const InverseMap> inverse, MeshSignalKind kind) {
  if (!inverse) throw Error(ErrorKind::InvalidArgument, "polycube signal: no map");
  switch (kind) {
    case MeshSignalKind::Normal:
      return [inverse](const Vec3d& q, const Vec3d&) { return Vec4f(0.5f + 0.5f * inverse->normal(q), 1.0f); };
    case MeshSignalKind::Shading:
      return [inverse](const Vec3d& q, const Vec3d&) {
        const Vec3f light = glm::normalize(Vec3f(0.4f, 0.8f, 0.45f));
        const float shade = 0.18f + 0.85f * std::max(0.0f, glm::dot(inverse->normal(q), light));
        return Vec4f(Vec3f(shade), 1.0f);
      };
    case MeshSignalKind::Color:
      if (!inverse->mesh().hasColors())
        throw Error(ErrorKind::InvalidArgument, "polycube signal: the mesh has no vertex colours to bake");
      return [inverse](const Vec3d& q, const Vec3d&) { return inverse->color(q); };
  }
  throw Error(ErrorKind::InvalidArgument, "polycube signal: unknown kind");
}

}  // namespace cellrelief::polycube
