// SPDX-License-Identifier: MIT
/// @file levels_of_detail.h
/// One polycube map for several versions of a mesh. `decimate` makes a coarser version (OpenMesh's
/// decimater, quadric error); `transferTexturePositions` gives every vertex of one version the
/// texture position of the nearest point of another (the source triangle's three positions
/// interpolated at that point, then P). The parameterization uses both to start a large mesh from
/// the map of a coarse one; a renderer uses the transfer to texture its levels of detail.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include "cellrelief/core/bvh.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/io/openmesh_triangles.h"
#include "cellrelief/polycube/polycube_surface.h"

namespace cellrelief::polycube {

/// The mesh collapsed to about `targetVertices` vertices by quadric edge collapses, which keep
/// its topology. Triangles OpenMesh cannot add (a non-manifold fan) are left out.
inline TriangleMesh decimate(const TriangleMesh& mesh, std::size_t targetVertices) {
  io::OpenMeshTriangles m = io::toOpenMesh(mesh);
  m.request_vertex_status();
  m.request_edge_status();
  m.request_face_status();
  OpenMesh::Decimater::DecimaterT<io::OpenMeshTriangles> decimater(m);
  OpenMesh::Decimater::ModQuadricT<io::OpenMeshTriangles>::Handle quadric;
  decimater.add(quadric);
  decimater.module(quadric).unset_max_err();
  if (!decimater.initialize()) throw Error(ErrorKind::InvalidInput, "decimate: OpenMesh's decimater did not initialize");
  decimater.decimate_to(targetVertices);
  m.garbage_collection();
  return io::fromOpenMesh(m);
}

/// For each target position (lattice coordinates), the texture position of the nearest point of
/// the source mesh: its triangle's three interpolated there, then P. A point P cannot take
/// (more than half a cube from the surface) keeps the nearest corner's position.
inline std::vector<Vec3d> transferTexturePositions(std::span<const Vec3d> sourceLattice,
                                                   std::span<const Vec3u> sourceTriangles,
                                                   std::span<const Vec3d> sourceTexture,
                                                   std::span<const Vec3d> targetLattice,
                                                   const PolycubeSurface& surface) {
  if (sourceTexture.size() != sourceLattice.size())
    throw Error(ErrorKind::InvalidArgument, "texture transfer: one texture position per source vertex is needed");
  if (sourceTriangles.empty()) throw Error(ErrorKind::InvalidArgument, "texture transfer: the source has no triangles");
  const TriangleBvh<double> bvh(sourceLattice, sourceTriangles);
  std::vector<Vec3d> out(targetLattice.size());
  parallelFor(0, targetLattice.size(), [&](std::size_t v) {
    const Vec3d& x = targetLattice[v];
    const Vec3u& t = sourceTriangles[bvh.closestPoint(x).second];
    const Vec3d a = sourceLattice[t[0]], b = sourceLattice[t[1]], c = sourceLattice[t[2]];
    const Vec3d w = closestPointBarycentrics(x, a, b, c);
    const Vec3d blended = w[0] * sourceTexture[t[0]] + w[1] * sourceTexture[t[1]] + w[2] * sourceTexture[t[2]];
    const int corner = w[0] >= w[1] && w[0] >= w[2] ? 0 : w[1] >= w[2] ? 1 : 2;
    out[v] = surface.project(blended).value_or(sourceTexture[t[corner]]);
  }, 256);
  return out;
}

}  // namespace cellrelief::polycube
