// SPDX-License-Identifier: MIT
/// @file textured_mesh.h
/// A polycube-mapped mesh as a scene holds it: triangles in world space, one 3D texture position
/// per vertex (lattice coordinates on the polycube's surface), and T2 with the look-up table
/// behind it. Several meshes (levels of detail of one shape) may share one T2.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/polycube/polycube_texture.h"

namespace cellrelief::polycube {

/// What T2 holds for the renderer.
enum class TextureUse {
  Color,   ///< the surface's colour; the mesh's vertex normals shade it
  Normal,  ///< world-space unit normals as RGB = 0.5 + 0.5 n (a fine mesh's, on a coarse one)
  None,    ///< not read: the mesh in grey with its vertex normals (what texturing is measured against)
};

struct TexturedMesh {
  TriangleMesh mesh;           ///< world space; vertex normals are computed when absent
  std::vector<Vec3f> texture;  ///< per vertex, lattice coordinates
  std::shared_ptr<const PolycubeTexture> t2;
  TextureUse use = TextureUse::Color;
  TextureFilter filter = TextureFilter::Trilinear;

  /// Throws InvalidInput for an invalid mesh (TriangleMesh::validate), InvalidArgument unless it
  /// has triangles, T2 and one texture position per vertex within P's reach of the surface.
  void validate() const {
    mesh.validate();
    if (mesh.triangles.empty()) throw Error(ErrorKind::InvalidArgument, "textured mesh: no triangles");
    if (!t2) throw Error(ErrorKind::InvalidArgument, "textured mesh: no T2");
    if (texture.size() != mesh.positions.size())
      throw Error(ErrorKind::InvalidArgument, "textured mesh: " + std::to_string(texture.size()) +
                                                  " texture positions for " + std::to_string(mesh.positions.size()) +
                                                  " vertices");
    for (std::size_t v = 0; v < texture.size(); ++v)
      if (!t2->surface().project(Vec3d(texture[v])))
        throw Error(ErrorKind::InvalidArgument, "textured mesh: vertex " + std::to_string(v) +
                                                    "'s texture position is not near the polycube's surface");
  }
};

}  // namespace cellrelief::polycube
