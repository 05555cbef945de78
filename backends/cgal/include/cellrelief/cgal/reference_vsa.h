// SPDX-License-Identifier: GPL-3.0-or-later
/// @file reference_vsa.h
/// CGAL's Variational Shape Approximation (Surface_mesh_approximation, L2,1 metric, hierarchical
/// seeding) as the peer of geotex::partitionVsa: the same mesh, the same proxy count, the
/// partition back per triangle so both are scored by one error function.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_approximation/approximate_triangle_mesh.h>

#include <cellrelief/core/error.h>
#include <cellrelief/core/triangle_mesh.h>

namespace cellrelief::cgal {

struct CgalVsa {
  std::vector<std::uint32_t> regionOfFace;  ///< in the mesh's triangle order
  std::size_t proxies = 0;
  double seconds = 0;  ///< CGAL's seeding and iterations (the mesh copy excluded)
};

/// Partitions the mesh into `proxies` regions with `iterations` Lloyd iterations after seeding.
/// Throws Error(InvalidInput) when the mesh is not a surface CGAL's halfedge mesh can hold.
inline CgalVsa cgalVsa(const TriangleMesh& mesh, int proxies, int iterations) {
  namespace VSA = CGAL::Surface_mesh_approximation;
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using CgalMesh = CGAL::Surface_mesh<Kernel::Point_3>;
  using Face = boost::graph_traits<CgalMesh>::face_descriptor;
  CgalMesh sm;
  std::vector<CgalMesh::Vertex_index> vertices;
  vertices.reserve(mesh.positions.size());
  for (const Vec3f& p : mesh.positions) vertices.push_back(sm.add_vertex(Kernel::Point_3(p.x, p.y, p.z)));
  std::vector<Face> faces;
  faces.reserve(mesh.triangles.size());
  for (const Vec3u& t : mesh.triangles) {
    const Face f = sm.add_face(vertices[t[0]], vertices[t[1]], vertices[t[2]]);
    if (f == CgalMesh::null_face())
      throw Error(ErrorKind::InvalidInput, "CGAL VSA", "the mesh is not a manifold surface CGAL can hold");
    faces.push_back(f);
  }
  auto proxyOf = sm.add_property_map<Face, std::size_t>("f:proxy_id", 0).first;
  CgalVsa out;
  const auto start = std::chrono::steady_clock::now();
  VSA::approximate_triangle_mesh(sm, CGAL::parameters::seeding_method(VSA::HIERARCHICAL)
                                         .max_number_of_proxies(std::size_t(proxies))
                                         .number_of_iterations(std::size_t(iterations))
                                         .face_proxy_map(proxyOf));
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.regionOfFace.reserve(faces.size());
  for (const Face f : faces) {
    out.regionOfFace.push_back(std::uint32_t(proxyOf[f]));
    out.proxies = std::max(out.proxies, std::size_t(proxyOf[f]) + 1);
  }
  return out;
}

}  // namespace cellrelief::cgal
