// SPDX-License-Identifier: MIT
/// @file openmesh_importer.h
/// An OpenMesh importer that keeps the file as it is. OpenMesh's own importers build a half-edge
/// mesh and silently drop faces that would make it non-manifold; real inputs have such faces, so
/// this importer receives OpenMesh's parsed vertices, polygons, normals, colors and UVs through the
/// BaseImporter interface and stores them as a polygon soup, without topology.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <OpenMesh/Core/IO/importer/BaseImporter.hh>

#include "cellrelief/io/detail/openmesh_types.h"
#include "cellrelief/core/math.h"

namespace cellrelief::io::detail {

struct PolygonSoup {
  std::vector<Vec3f> positions;
  std::vector<Vec3f> normals;          // per vertex, sized with positions when present
  std::vector<Color8> colors;          // per vertex
  std::vector<Vec2f> vertexUVs;        // per vertex
  std::vector<std::uint32_t> corners;  // polygon corner vertex indices, concatenated
  std::vector<std::uint32_t> offsets{0};  // polygon p spans corners[offsets[p], offsets[p+1])
  std::vector<Vec2f> cornerUVs;        // per corner when the file has face texture coordinates
  bool hasNormals = false, hasColors = false, hasVertexUVs = false, hasCornerUVs = false;
  std::size_t rejectedFaces = 0;       // faces with fewer than 3 corners or invalid handles

  std::size_t polygonCount() const { return offsets.size() - 1; }
};

class SoupImporter final : public OpenMesh::IO::BaseImporter, private OpenMeshTypes {
 public:

  explicit SoupImporter(PolygonSoup& soup) : mSoup(soup) {}

  VertexHandle add_vertex(const Vec3f& p) override { return addVertex({p[0], p[1], p[2]}); }
  VertexHandle add_vertex(const Vec3d& p) override {
    return addVertex({float(p[0]), float(p[1]), float(p[2])});
  }
  VertexHandle add_vertex() override { return addVertex({0, 0, 0}); }
  void set_point(VertexHandle v, const Vec3f& p) override {
    if (valid(v)) mSoup.positions[v.idx()] = {p[0], p[1], p[2]};
  }

  FaceHandle add_face(const VHandles& handles) override {
    if (handles.size() < 3) {
      ++mSoup.rejectedFaces;
      return FaceHandle();
    }
    for (const VertexHandle& h : handles) {
      // Out-of-range indices are kept (as the largest index) so that validation reports them.
      mSoup.corners.push_back(h.idx() < 0 ? 0xffffffffu : std::uint32_t(h.idx()));
    }
    mSoup.offsets.push_back(std::uint32_t(mSoup.corners.size()));
    return FaceHandle(int(mSoup.polygonCount() - 1));
  }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }

  void add_face_texcoords(FaceHandle f, VertexHandle, const std::vector<Vec2f>& uvs) override {
    if (!f.is_valid() || std::size_t(f.idx()) + 1 != mSoup.polygonCount()) return;
    const std::size_t n = mSoup.offsets[f.idx() + 1] - mSoup.offsets[f.idx()];
    if (uvs.size() != n) return;
    if (!mSoup.hasCornerUVs) {  // earlier polygons had none: pad them
      mSoup.cornerUVs.assign(mSoup.offsets[f.idx()], {0, 0});
      mSoup.hasCornerUVs = true;
    }
    mSoup.cornerUVs.resize(mSoup.offsets[f.idx()]);
    for (const Vec2f& t : uvs) mSoup.cornerUVs.push_back({t[0], t[1]});
  }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void request_face_texcoords2D() override {}
  void add_texture_information(int, std::string) override {}

  void set_normal(VertexHandle v, const Vec3f& n) override {
    if (!valid(v)) return;
    ensure(mSoup.normals, mSoup.hasNormals, cellrelief::Vec3f(0));
    mSoup.normals[v.idx()] = {n[0], n[1], n[2]};
  }
  void set_normal(VertexHandle v, const Vec3d& n) override {
    set_normal(v, Vec3f(float(n[0]), float(n[1]), float(n[2])));
  }
  void set_color(VertexHandle v, const Vec3uc& c) override { setColor(v, {c[0], c[1], c[2], 255}); }
  void set_color(VertexHandle v, const Vec4uc& c) override {
    setColor(v, {c[0], c[1], c[2], c[3]});
  }
  void set_color(VertexHandle v, const Vec3f& c) override {
    set_color(v, Vec4f(c[0], c[1], c[2], 1.0f));
  }
  void set_color(VertexHandle v, const Vec4f& c) override {
    Color8 q;
    for (int k = 0; k < 4; ++k)
      q[k] = static_cast<std::uint8_t>(glm::round(glm::clamp(c[k], 0.0f, 1.0f) * 255.0f));
    setColor(v, q);
  }
  void set_texcoord(VertexHandle v, const Vec2f& t) override {
    if (!valid(v)) return;
    ensure(mSoup.vertexUVs, mSoup.hasVertexUVs, cellrelief::Vec2f(0));
    mSoup.vertexUVs[v.idx()] = {t[0], t[1]};
  }
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}

  // Topology, status, edge and face attributes: not part of a soup.
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void set_status(VertexHandle, const Status&) override {}
  void set_status(HalfedgeHandle, const Status&) override {}
  void set_status(EdgeHandle, const Status&) override {}
  void set_status(FaceHandle, const Status&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}

  size_t n_vertices() const override { return mSoup.positions.size(); }
  size_t n_faces() const override { return mSoup.polygonCount(); }
  size_t n_edges() const override { return 0; }
  void reserve(unsigned int nv, unsigned int, unsigned int nf) override {
    // Headers can lie (truncated or hostile files): reserve only what is plausible.
    constexpr unsigned kCap = 1u << 24;
    mSoup.positions.reserve(std::min(nv, kCap));
    mSoup.corners.reserve(3ull * std::min(nf, kCap));
    mSoup.offsets.reserve(std::min(nf, kCap) + 1ull);
  }

 private:
  VertexHandle addVertex(cellrelief::Vec3f p) {
    mSoup.positions.push_back(p);
    if (mSoup.hasNormals) mSoup.normals.emplace_back(0);
    if (mSoup.hasColors) mSoup.colors.emplace_back(255);
    if (mSoup.hasVertexUVs) mSoup.vertexUVs.emplace_back(0);
    return VertexHandle(int(mSoup.positions.size() - 1));
  }
  bool valid(VertexHandle v) const {
    return v.is_valid() && std::size_t(v.idx()) < mSoup.positions.size();
  }
  template <class T>
  void ensure(std::vector<T>& attribute, bool& present, const T& fill) {
    if (!present) {
      attribute.assign(mSoup.positions.size(), fill);
      present = true;
    }
  }
  void setColor(VertexHandle v, Color8 c) {
    if (!valid(v)) return;
    ensure(mSoup.colors, mSoup.hasColors, Color8(255));
    mSoup.colors[v.idx()] = c;
  }

  PolygonSoup& mSoup;
};

}  // namespace cellrelief::io::detail
