// SPDX-License-Identifier: MIT
/// @file openmesh_exporter.h
/// Feeds a TriangleMesh to OpenMesh's writers through the BaseExporter interface, so that meshes
/// OpenMesh's half-edge structure would refuse (non-manifold, duplicated faces) are written as they
/// are. Positions, vertex normals and vertex colors are exported; per-corner UVs are not.
#pragma once

#include <vector>

#include <OpenMesh/Core/IO/exporter/BaseExporter.hh>
#include <OpenMesh/Core/Mesh/BaseKernel.hh>

#include "cellrelief/io/detail/openmesh_types.h"
#include "cellrelief/core/triangle_mesh.h"

namespace cellrelief::io::detail {

class SoupExporter final : public OpenMesh::IO::BaseExporter, private OpenMeshTypes {
 public:

  explicit SoupExporter(const TriangleMesh& mesh) : mMesh(mesh) {}

  Vec3f point(VertexHandle v) const override {
    const cellrelief::Vec3f& p = mMesh.positions[v.idx()];
    return {p.x, p.y, p.z};
  }
  Vec3d pointd(VertexHandle v) const override { return Vec3d(point(v)); }
  bool is_point_double() const override { return false; }
  Vec3f normal(VertexHandle v) const override {
    if (!mMesh.hasNormals()) return {0, 0, 0};
    const cellrelief::Vec3f& n = mMesh.normals[v.idx()];
    return {n.x, n.y, n.z};
  }
  Vec3d normald(VertexHandle v) const override { return Vec3d(normal(v)); }
  bool is_normal_double() const override { return false; }
  Vec4uc colorA(VertexHandle v) const override {
    if (!mMesh.hasColors()) return {255, 255, 255, 255};
    const Color8& c = mMesh.colors[v.idx()];
    return {c.r, c.g, c.b, c.a};
  }
  Vec3uc color(VertexHandle v) const override {
    const Vec4uc c = colorA(v);
    return {c[0], c[1], c[2]};
  }
  Vec4ui colorAi(VertexHandle v) const override {
    const Vec4uc c = colorA(v);
    return {c[0], c[1], c[2], c[3]};
  }
  Vec3ui colori(VertexHandle v) const override {
    const Vec4uc c = colorA(v);
    return {c[0], c[1], c[2]};
  }
  Vec4f colorAf(VertexHandle v) const override {
    const Vec4uc c = colorA(v);
    return {c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f, c[3] / 255.0f};
  }
  Vec3f colorf(VertexHandle v) const override {
    const Vec4f c = colorAf(v);
    return {c[0], c[1], c[2]};
  }
  Vec2f texcoord(VertexHandle) const override { return {0, 0}; }
  Vec2f texcoord(HalfedgeHandle) const override { return {0, 0}; }
  Status status(VertexHandle) const override { return {}; }

  unsigned int get_vhandles(FaceHandle f, std::vector<VertexHandle>& out) const override {
    const Vec3u& t = mMesh.triangles[f.idx()];
    out.assign({VertexHandle(int(t[0])), VertexHandle(int(t[1])), VertexHandle(int(t[2]))});
    return 3;
  }
  HalfedgeHandle getHeh(FaceHandle, VertexHandle) const override { return HalfedgeHandle(); }
  unsigned int get_face_texcoords(std::vector<Vec2f>&) const override { return 0; }
  Vec3f normal(FaceHandle f) const override {  // STL stores a normal per facet
    const Vec3u& t = mMesh.triangles[f.idx()];
    const cellrelief::Vec3f n = glm::cross(mMesh.positions[t[1]] - mMesh.positions[t[0]],
                                           mMesh.positions[t[2]] - mMesh.positions[t[0]]);
    const float len = glm::length(n);
    return len > 0 ? Vec3f(n.x / len, n.y / len, n.z / len) : Vec3f(0, 0, 0);
  }
  Vec3d normald(FaceHandle f) const override { return Vec3d(normal(f)); }
  Vec3uc color(FaceHandle) const override { return {0, 0, 0}; }
  Vec4uc colorA(FaceHandle) const override { return {0, 0, 0, 0}; }
  Vec3ui colori(FaceHandle) const override { return {0, 0, 0}; }
  Vec4ui colorAi(FaceHandle) const override { return {0, 0, 0, 0}; }
  Vec3f colorf(FaceHandle) const override { return {0, 0, 0}; }
  Vec4f colorAf(FaceHandle) const override { return {0, 0, 0, 0}; }
  Status status(FaceHandle) const override { return {}; }
  Vec3uc color(EdgeHandle) const override { return {0, 0, 0}; }
  Vec4uc colorA(EdgeHandle) const override { return {0, 0, 0, 0}; }
  Vec3ui colori(EdgeHandle) const override { return {0, 0, 0}; }
  Vec4ui colorAi(EdgeHandle) const override { return {0, 0, 0, 0}; }
  Vec3f colorf(EdgeHandle) const override { return {0, 0, 0}; }
  Vec4f colorAf(EdgeHandle) const override { return {0, 0, 0, 0}; }
  Status status(EdgeHandle) const override { return {}; }
  int get_halfedge_id(VertexHandle) override { return -1; }
  int get_halfedge_id(FaceHandle) override { return -1; }
  int get_next_halfedge_id(HalfedgeHandle) override { return -1; }
  int get_to_vertex_id(HalfedgeHandle) override { return -1; }
  int get_face_id(HalfedgeHandle) override { return -1; }
  Status status(HalfedgeHandle) const override { return {}; }

  size_t n_vertices() const override { return mMesh.positions.size(); }
  size_t n_faces() const override { return mMesh.triangles.size(); }
  size_t n_edges() const override { return 0; }
  bool is_triangle_mesh() const override { return true; }
  bool has_vertex_normals() const override { return mMesh.hasNormals(); }
  bool has_vertex_colors() const override { return mMesh.hasColors(); }
  bool has_face_normals() const override { return true; }
  // OpenMesh's PLY writer looks up custom properties on the kernel unconditionally: give it one
  // that has none.
  const OpenMesh::BaseKernel* kernel() override { return &mNoProperties; }

 private:
  const TriangleMesh& mMesh;
  OpenMesh::BaseKernel mNoProperties;
};

}  // namespace cellrelief::io::detail
