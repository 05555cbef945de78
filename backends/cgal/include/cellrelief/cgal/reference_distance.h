// SPDX-License-Identifier: GPL-3.0-or-later
/// @file reference_distance.h
/// CGAL's AABB tree as the independent reference for geometric error: squared distances from
/// points to a triangle soup, exact predicates and double-precision constructions.
#pragma once

#include <cmath>
#include <list>
#include <vector>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cellrelief/core/triangle_mesh.h>
#include <cellrelief/metrics/geometric_error.h>

namespace cellrelief::cgal {

class ReferenceDistance {
 public:
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Triangles = std::vector<K::Triangle_3>;
  using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

  explicit ReferenceDistance(const TriangleMesh& mesh) {
    mTriangles.reserve(mesh.triangles.size());
    auto point = [&](std::uint32_t v) {
      const Vec3f& p = mesh.positions[v];
      return K::Point_3(p.x, p.y, p.z);
    };
    for (const Vec3u& t : mesh.triangles) {
      K::Triangle_3 tri(point(t[0]), point(t[1]), point(t[2]));
      if (!tri.is_degenerate()) mTriangles.push_back(tri);
    }
    mTree.insert(mTriangles.begin(), mTriangles.end());
    mTree.accelerate_distance_queries();
  }
  double distance(const Vec3d& p) const {
    return std::sqrt(CGAL::to_double(mTree.squared_distance(K::Point_3(p.x, p.y, p.z))));
  }
  /// Max, RMS and mean distance of the points to this surface.
  metrics::OneSidedError fromPoints(const std::vector<Vec3d>& points) const {
    metrics::OneSidedError e;
    double sum = 0, sum2 = 0;
    for (const Vec3d& p : points) {
      const double d = distance(p);
      e.max = std::max(e.max, d);
      sum += d;
      sum2 += d * d;
    }
    e.samples = points.size();
    if (!points.empty()) {
      e.mean = sum / double(points.size());
      e.rms = std::sqrt(sum2 / double(points.size()));
    }
    return e;
  }

 private:
  Triangles mTriangles;
  Tree mTree;
};

}  // namespace cellrelief::cgal
