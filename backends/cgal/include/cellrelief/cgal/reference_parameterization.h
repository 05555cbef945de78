// SPDX-License-Identifier: GPL-3.0-or-later
/// @file reference_parameterization.h
/// CGAL's Surface_mesh_parameterization as the baseline for texture maps: a mesh cut into a disk
/// (core/cut_graph.h) and flattened by LSCM (Levy et al. 2002: free border, two vertices pinned),
/// the discrete conformal map (Eck et al. 1995, "DCP": the border fixed to a circle by arc
/// length) or ARAP (Liu et al. 2008: local-global from LSCM, free border). The map comes back per
/// triangle corner, since a seam vertex has one position per side.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/ARAP_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_conformal_map_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>
#include <CGAL/boost/graph/Seam_mesh.h>

#include <cellrelief/core/cut_graph.h>
#include <cellrelief/core/error.h>
#include <cellrelief/core/triangle_mesh.h>

namespace cellrelief::cgal {

enum class DiskParameterizer { Lscm, DiscreteConformal, Arap };

inline const char* toString(DiskParameterizer p) {
  return p == DiskParameterizer::Lscm ? "CGAL LSCM" : p == DiskParameterizer::Arap ? "CGAL ARAP" : "CGAL DCP";
}

struct DiskMap {
  std::vector<Vec2d> corners;  ///< 3 per triangle, in the mesh's triangle order
  std::size_t seamEdges = 0;
  double seconds = 0;          ///< the cut and CGAL's solve
};

inline DiskMap parameterizeDisk(const TriangleMesh& mesh, DiskParameterizer which) {
  namespace SMP = CGAL::Surface_mesh_parameterization;
  using CartesianKernel = CGAL::Simple_cartesian<double>;
  using CgalMesh = CGAL::Surface_mesh<CartesianKernel::Point_3>;
  using SmVertex = boost::graph_traits<CgalMesh>::vertex_descriptor;
  using SmEdge = boost::graph_traits<CgalMesh>::edge_descriptor;
  using SmHalfedge = boost::graph_traits<CgalMesh>::halfedge_descriptor;
  using SeamEdges = CgalMesh::Property_map<SmEdge, bool>;
  using SeamVertices = CgalMesh::Property_map<SmVertex, bool>;
  using SeamMesh = CGAL::Seam_mesh<CgalMesh, SeamEdges, SeamVertices>;
  using UvMap = CgalMesh::Property_map<SmHalfedge, CartesianKernel::Point_2>;

  const auto start = std::chrono::steady_clock::now();
  DiskMap out;
  const std::vector<MeshEdge> seams = cutGraphSeams(mesh);
  out.seamEdges = seams.size();
  CgalMesh sm;
  std::vector<SmVertex> vertices;
  vertices.reserve(mesh.positions.size());
  for (const Vec3f& p : mesh.positions) vertices.push_back(sm.add_vertex(CartesianKernel::Point_3(p.x, p.y, p.z)));
  std::vector<CgalMesh::Face_index> faces;
  faces.reserve(mesh.triangles.size());
  for (const Vec3u& t : mesh.triangles) {
    faces.push_back(sm.add_face(vertices[t[0]], vertices[t[1]], vertices[t[2]]));
    if (faces.back() == CgalMesh::null_face())
      throw Error(ErrorKind::InvalidInput, "CGAL parameterization: the mesh is not an oriented 2-manifold");
  }
  SeamEdges seamEdges = sm.add_property_map<SmEdge, bool>("e:on_seam", false).first;
  SeamVertices seamVertices = sm.add_property_map<SmVertex, bool>("v:on_seam", false).first;
  SeamMesh seamMesh(sm, seamEdges, seamVertices);
  for (const MeshEdge& e : seams) seamMesh.add_seam(vertices[e.a], vertices[e.b]);
  UvMap uv = sm.add_property_map<SmHalfedge, CartesianKernel::Point_2>("h:uv").first;
  const auto border = CGAL::Polygon_mesh_processing::longest_border(seamMesh).first;
  SMP::Error_code status;
  if (which == DiskParameterizer::Lscm)
    status = SMP::parameterize(seamMesh, SMP::LSCM_parameterizer_3<SeamMesh>(), border, uv);
  else if (which == DiskParameterizer::Arap)
    status = SMP::parameterize(seamMesh, SMP::ARAP_parameterizer_3<SeamMesh>(), border, uv);
  else
    status = SMP::parameterize(seamMesh, SMP::Discrete_conformal_map_parameterizer_3<SeamMesh>(), border, uv);
  if (status != SMP::OK)
    throw Error(ErrorKind::InvalidInput,
                std::string(toString(which)) + " failed: " + SMP::get_error_message(int(status)));
  out.corners.resize(3 * mesh.triangles.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    // The seam mesh's face is the surface mesh's; walk its corners from the one of corner 0.
    const auto first = halfedge(faces[f], seamMesh);
    auto h = first;
    int k = 0;
    do {
      const auto vertex = target(h, seamMesh);
      const std::uint32_t corner = std::uint32_t(sm.target(h.tmhd).idx());
      const CartesianKernel::Point_2 p = get(uv, vertex);
      const Vec3u& t = mesh.triangles[f];
      const int slot = corner == t[0] ? 0 : corner == t[1] ? 1 : 2;
      out.corners[3 * f + slot] = Vec2d(p.x(), p.y());
      h = next(h, seamMesh);
    } while (h != first && ++k < 3);
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace cellrelief::cgal
