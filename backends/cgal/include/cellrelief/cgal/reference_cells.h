// SPDX-License-Identifier: GPL-3.0-or-later
/// @file reference_cells.h
/// CGAL's answer for the cell complex, computed independently of cellrelief's own tests: grey cells
/// by exact do_intersect(Triangle_3, Iso_cuboid_3), black and white by Side_of_triangle_mesh at
/// cell centres. Both run on the snapped index-space coordinates the complex itself used, with
/// closed boxes [i, i+1]^3, so the comparison is exact. Licensed GPL because CGAL is.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/intersections.h>

#include <cellrelief/core/math.h>

namespace cellrelief::cgal {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

inline std::uint64_t cellId(int n, int x, int y, int z) {
  return (std::uint64_t(z) * n + y) * n + x;
}

/// Whether a triangle meets a closed box. CGAL's triangle test assumes a proper triangle, so a
/// degenerate one (collinear corners, as in the robustness meshes) is tested as the segment between
/// its two farthest corners, or as a point.
inline bool meets(const Kernel::Triangle_3& tri, const Kernel::Iso_cuboid_3& cell) {
  if (!tri.is_degenerate()) return CGAL::do_intersect(tri, cell);
  const Point p[3] = {tri.vertex(0), tri.vertex(1), tri.vertex(2)};
  int a = 0, b = 1;
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      if (CGAL::squared_distance(p[i], p[j]) > CGAL::squared_distance(p[a], p[b])) a = i, b = j;
  if (p[a] == p[b]) return !cell.has_on_unbounded_side(p[a]);
  return CGAL::do_intersect(Kernel::Segment_3(p[a], p[b]), cell);
}

/// Grey flags of the n^3 cells: true where some triangle meets the closed cell.
inline std::vector<char> referenceGreyCells(std::span<const Vec3d> positionsIS,
                                            std::span<const Vec3u> triangles, int n) {
  std::vector<char> grey(std::size_t(n) * n * n, 0);
  for (const Vec3u& t : triangles) {
    const Point a(positionsIS[t[0]].x, positionsIS[t[0]].y, positionsIS[t[0]].z);
    const Point b(positionsIS[t[1]].x, positionsIS[t[1]].y, positionsIS[t[1]].z);
    const Point c(positionsIS[t[2]].x, positionsIS[t[2]].y, positionsIS[t[2]].z);
    const Kernel::Triangle_3 tri(a, b, c);
    const CGAL::Bbox_3 box = tri.bbox();
    const int x0 = std::max(0, int(std::floor(box.xmin())) - 1), x1 = std::min(n - 1, int(box.xmax()));
    const int y0 = std::max(0, int(std::floor(box.ymin())) - 1), y1 = std::min(n - 1, int(box.ymax()));
    const int z0 = std::max(0, int(std::floor(box.zmin())) - 1), z1 = std::min(n - 1, int(box.zmax()));
    for (int z = z0; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          char& g = grey[cellId(n, x, y, z)];
          if (g) continue;
          const Kernel::Iso_cuboid_3 cell(Point(x, y, z), Point(x + 1, y + 1, z + 1));
          if (meets(tri, cell)) g = 1;
        }
  }
  return grey;
}

/// CGAL's inside/outside test for a closed mesh, on the same coordinates.
class ReferenceSide {
 public:
  ReferenceSide(std::span<const Vec3d> positionsIS, std::span<const Vec3u> triangles) {
    std::vector<SurfaceMesh::Vertex_index> v;
    v.reserve(positionsIS.size());
    for (const Vec3d& p : positionsIS) v.push_back(mMesh.add_vertex(Point(p.x, p.y, p.z)));
    for (const Vec3u& t : triangles) mMesh.add_face(v[t[0]], v[t[1]], v[t[2]]);
    mSide = std::make_unique<CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel>>(mMesh);
  }
  bool closed() const { return CGAL::is_closed(mMesh); }
  /// Strictly inside (on the boundary counts as not inside; cell centres never lie on it here).
  bool inside(const Vec3d& p) const {
    return (*mSide)(Point(p.x, p.y, p.z)) == CGAL::ON_BOUNDED_SIDE;
  }

 private:
  SurfaceMesh mMesh;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel>> mSide;
};

}  // namespace cellrelief::cgal
