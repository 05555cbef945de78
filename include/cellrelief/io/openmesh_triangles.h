// SPDX-License-Identifier: MIT
/// @file openmesh_triangles.h
/// A TriangleMesh as OpenMesh's triangle mesh and back, for OpenMesh's tools (subdivision,
/// decimation). Only positions and triangles travel. Triangles OpenMesh cannot add (a repeated
/// corner, a non-manifold fan) are left out, as OpenMesh itself does; indices out of range are
/// refused.
#pragma once

#include <cstdint>
#include <vector>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "cellrelief/core/error.h"
#include "cellrelief/core/triangle_mesh.h"

namespace cellrelief::io {

using OpenMeshTriangles = OpenMesh::TriMesh_ArrayKernelT<>;

inline OpenMeshTriangles toOpenMesh(const TriangleMesh& mesh) {
  OpenMeshTriangles om;
  std::vector<OpenMeshTriangles::VertexHandle> handles;
  handles.reserve(mesh.positions.size());
  for (const Vec3f& p : mesh.positions) handles.push_back(om.add_vertex(OpenMeshTriangles::Point(p.x, p.y, p.z)));
  for (const Vec3u& t : mesh.triangles) {
    if (t[0] >= handles.size() || t[1] >= handles.size() || t[2] >= handles.size())
      throw Error(ErrorKind::InvalidArgument, "OpenMesh conversion: a triangle refers to a missing vertex");
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
    om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
  }
  return om;
}

/// The live vertices and faces (call garbage_collection() first after deleting any).
inline TriangleMesh fromOpenMesh(const OpenMeshTriangles& om) {
  TriangleMesh out;
  out.positions.reserve(om.n_vertices());
  for (const auto v : om.vertices()) {
    const OpenMeshTriangles::Point& p = om.point(v);
    out.positions.emplace_back(p[0], p[1], p[2]);
  }
  for (const auto f : om.faces()) {
    Vec3u t;
    int k = 0;
    for (const auto v : om.fv_range(f)) t[k++] = std::uint32_t(v.idx());
    out.triangles.push_back(t);
  }
  out.sourcePolygons = out.triangles.size();
  return out;
}

}  // namespace cellrelief::io
