// SPDX-License-Identifier: MIT
/// @file geotex_test_meshes.h
/// Small analytic meshes for the geometry-texture tests, and a ray grid that looks at a mesh from
/// several directions.
#pragma once

#include <vector>

#include <cellrelief/core/procedural.h>
#include <cellrelief/core/ray.h>
#include <cellrelief/core/triangle_mesh.h>

namespace cellrelief::geotex::test {

/// An axis-aligned cube [lo, hi]^3 of 12 triangles, outward-facing, split in four `levels` times.
inline TriangleMesh makeCube(float lo = -1, float hi = 1, int levels = 2) {
  TriangleMesh m;
  for (int c = 0; c < 8; ++c) m.positions.push_back({(c & 1) ? hi : lo, (c & 2) ? hi : lo, (c & 4) ? hi : lo});
  const unsigned quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({q[0], q[1], q[2]});
    m.triangles.push_back({q[0], q[2], q[3]});
  }
  splitTrianglesInFour(m, levels, [](const Vec3f& a, const Vec3f& b) { return 0.5f * (a + b); });
  m.sourcePolygons = m.triangles.size();
  return m;
}

/// The same triangles with every corner its own vertex (an STL-like soup).
inline TriangleMesh unweld(const TriangleMesh& mesh) {
  TriangleMesh soup;
  for (const Vec3u& t : mesh.triangles) {
    const auto base = std::uint32_t(soup.positions.size());
    for (int k = 0; k < 3; ++k) soup.positions.push_back(mesh.positions[t[k]]);
    soup.triangles.push_back({base, base + 1, base + 2});
  }
  soup.sourcePolygons = soup.triangles.size();
  return soup;
}

/// Orthographic rays on a `side` x `side` grid through the bounds, from each of `views` directions
/// spread over the sphere; ray r of view v is rays[v * side * side + r].
inline std::vector<Rayd> viewRays(const Aabbf& bounds, int side, int views) {
  std::vector<Rayd> rays;
  const Vec3d centre(bounds.center());
  const double radius = 0.5 * bounds.diagonal() * 1.05;
  for (int v = 0; v < views; ++v) {
    // Directions on a Fibonacci spiral: even coverage without axis-aligned special cases.
    const double z = 1 - (2.0 * v + 1) / views, r = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = v * 2.39996322972865332;
    const Vec3d d(r * std::cos(phi), r * std::sin(phi), z);
    const Vec3d helper = std::abs(d.z) < 0.9 ? Vec3d(0, 0, 1) : Vec3d(1, 0, 0);
    const Vec3d u = glm::normalize(glm::cross(helper, d)), w = glm::cross(d, u);
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) {
        const double a = (2.0 * (i + 0.5) / side - 1) * radius, b = (2.0 * (j + 0.5) / side - 1) * radius;
        rays.emplace_back(centre - 2 * radius * d + a * u + b * w, d);
      }
  }
  return rays;
}

}  // namespace cellrelief::geotex::test
