// SPDX-License-Identifier: MIT
/// @file flat_mesh.h
/// A flat mesh (a sheet: every vertex in one axis plane) as the thin solid a relief model can hold.
///
/// A relief model stores the boundary of a solid: each map says where, along a projection line
/// from a face bordering empty space, the inside begins. A sheet has no inside, so its cells would
/// read as solid behind it (a wedge or a block where there is a plane). Closing the sheet into a
/// slab, its two sides `halfThickness` above and below the plane and its rim stitched by side walls
/// along the boundary edges, gives the tracer a solid whose surface is the sheet's to within that
/// distance. The slab's faces lie off the projection planes (see CellComplex's grid placement), so
/// each side is seen from its own face of the cells.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <optional>
#include <unordered_map>
#include <vector>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/error.h"
#include "cellrelief/core/triangle_mesh.h"

namespace cellrelief::relief {

/// Thickness of the slab a flat mesh becomes, as a fraction of its longest extent (0.2%: far below
/// what a picture of the model shows, above a 16-bit distance code at every grid size).
inline constexpr double kFlatSlabThickness = 2e-3;

/// The axis along which every referenced vertex shares one coordinate, or nullopt. An exact test:
/// a sheet written in floats is flat exactly, and anything thicker is a solid the grid can resolve.
inline std::optional<int> flatAxis(const TriangleMesh& mesh) {
  if (mesh.triangles.empty()) return std::nullopt;
  const Vec3f first = mesh.positions[mesh.triangles.front()[0]];
  std::array<bool, 3> flat{true, true, true};
  for (const Vec3u& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) flat[a] = flat[a] && mesh.positions[t[k]][a] == first[a];
  const int count = int(flat[0]) + int(flat[1]) + int(flat[2]);
  if (count != 1) return std::nullopt;  // 0: not flat; 2 or 3: a line or a point, no surface
  return int(std::find(flat.begin(), flat.end(), true) - flat.begin());
}

/// The closed slab of a flat mesh (flatAxis(mesh) == axis): the non-degenerate triangles turned to
/// face +axis, moved halfThickness up, a copy facing -axis moved down, and two triangles on every
/// boundary edge (an edge of one triangle only) joining them. Vertex normals, colors and corner
/// UVs are carried over. Throws InvalidInput when no triangle has area.
inline TriangleMesh slabOfFlatMesh(const TriangleMesh& mesh, int axis, float halfThickness) {
  const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
  // The surviving triangles, wound counter-clockwise seen from +axis; with their UV corners.
  std::vector<Vec3u> tris;
  std::vector<std::array<std::size_t, 3>> corners;  // indices into mesh.uvs, when it has them
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    Vec3u t = mesh.triangles[i];
    std::array<std::size_t, 3> c{3 * i, 3 * i + 1, 3 * i + 2};
    const Vec3f &p0 = mesh.positions[t[0]], &p1 = mesh.positions[t[1]], &p2 = mesh.positions[t[2]];
    const double area2 = (double(p1[ua]) - p0[ua]) * (double(p2[va]) - p0[va]) -
                         (double(p1[va]) - p0[va]) * (double(p2[ua]) - p0[ua]);
    if (area2 == 0) continue;
    if (area2 < 0) {
      std::swap(t[1], t[2]);
      std::swap(c[1], c[2]);
    }
    tris.push_back(t);
    corners.push_back(c);
  }
  if (tris.empty())
    throw Error(ErrorKind::InvalidInput, "the flat mesh has no triangle with area: no surface to model");

  const auto nv = std::uint32_t(mesh.positions.size());
  TriangleMesh slab;
  slab.positions.resize(2 * std::size_t(nv));
  for (std::uint32_t v = 0; v < nv; ++v) {
    Vec3f up = mesh.positions[v], down = up;
    up[axis] += halfThickness;
    down[axis] -= halfThickness;
    slab.positions[v] = up;
    slab.positions[nv + v] = down;
  }
  if (mesh.hasNormals()) {
    slab.normals.resize(slab.positions.size());
    Vec3f n(0);
    n[axis] = 1;
    for (std::uint32_t v = 0; v < nv; ++v) slab.normals[v] = n, slab.normals[nv + v] = -n;
  }
  if (mesh.hasColors()) {
    slab.colors = mesh.colors;
    slab.colors.insert(slab.colors.end(), mesh.colors.begin(), mesh.colors.end());
  }
  const bool uvs = mesh.hasUVs();
  auto add = [&](Vec3u t, std::array<Vec2f, 3> uv) {
    slab.triangles.push_back(t);
    if (uvs) slab.uvs.insert(slab.uvs.end(), uv.begin(), uv.end());
  };
  auto uvOf = [&](std::size_t corner) { return uvs ? mesh.uvs[corner] : Vec2f(0); };

  // Boundary edges: an undirected edge used once, between vertices welded by position (copies of
  // one vertex, as in meshes split for attributes, must not open a seam of walls inside the slab).
  std::unordered_map<std::uint64_t, std::uint32_t> firstAt;  // position bits -> first vertex there
  std::vector<std::uint32_t> welded(nv);
  for (std::uint32_t v = 0; v < nv; ++v) {
    const float u = mesh.positions[v][ua] + 0.0f, w = mesh.positions[v][va] + 0.0f;  // -0 is +0
    std::uint32_t bits[2];
    std::memcpy(&bits[0], &u, 4);
    std::memcpy(&bits[1], &w, 4);
    welded[v] = firstAt.try_emplace((std::uint64_t(bits[0]) << 32) | bits[1], v).first->second;
  }
  std::unordered_map<std::uint64_t, int> uses;
  auto key = [&](std::uint32_t a, std::uint32_t b) {
    a = welded[a], b = welded[b];
    return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
  };
  for (const Vec3u& t : tris)
    for (int k = 0; k < 3; ++k) ++uses[key(t[k], t[(k + 1) % 3])];

  for (std::size_t i = 0; i < tris.size(); ++i) {
    const Vec3u& t = tris[i];
    const std::array<Vec2f, 3> uv{uvOf(corners[i][0]), uvOf(corners[i][1]), uvOf(corners[i][2])};
    add(t, uv);                                                      // top, facing +axis
    add(Vec3u(t[0] + nv, t[2] + nv, t[1] + nv), {uv[0], uv[2], uv[1]});  // bottom, facing -axis
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      if (uses[key(a, b)] != 1) continue;
      // The interior lies left of a -> b (counter-clockwise from +axis): the wall faces right.
      const Vec2f ua2 = uv[k], ub2 = uv[(k + 1) % 3];
      add(Vec3u(a, a + nv, b), {ua2, ua2, ub2});
      add(Vec3u(b, a + nv, b + nv), {ub2, ua2, ub2});
    }
  }
  slab.sourcePolygons = slab.triangles.size();
  return slab;
}

/// The slab convert() models a flat mesh by (kFlatSlabThickness of its longest extent thick), or nullopt when the mesh is not flat. `thicknessWS` receives the
/// thickness (0 when not flat).
inline std::optional<TriangleMesh> slabIfFlat(const TriangleMesh& mesh, double* thicknessWS = nullptr) {
  if (thicknessWS) *thicknessWS = 0;
  const std::optional<int> axis = flatAxis(mesh);
  if (!axis) return std::nullopt;
  const Vec3f extent = mesh.surfaceBounds().extent();
  const double thickness = kFlatSlabThickness * double(std::max({extent.x, extent.y, extent.z}));
  if (thicknessWS) *thicknessWS = thickness;
  return slabOfFlatMesh(mesh, *axis, float(0.5 * thickness));
}

}  // namespace cellrelief::relief
