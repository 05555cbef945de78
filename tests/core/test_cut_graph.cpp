// SPDX-License-Identifier: MIT
// Cut graphs on analytic surfaces: the seams with the boundary form one connected graph with
// chi(graph) = chi(surface) - 1, so cutting along them leaves one disk.
#include <map>
#include <set>

#include <gtest/gtest.h>

#include <cellrelief/core/cut_graph.h>
#include <cellrelief/core/procedural.h>

namespace cellrelief {
namespace {

struct GraphShape {
  long long chi = 0;
  std::size_t pieces = 0;
  std::size_t seams = 0;
};

/// Euler characteristic and pieces of seams plus boundary edges.
GraphShape cutGraphShape(const TriangleMesh& mesh, const std::vector<MeshEdge>& seams) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const Vec3u& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++uses[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  std::vector<std::pair<std::uint32_t, std::uint32_t>> graph;
  for (const auto& [edge, count] : uses)
    if (count == 1) graph.push_back(edge);
  for (const MeshEdge& e : seams) {
    EXPECT_EQ((uses[{e.a, e.b}]), 2) << "a seam must be an interior edge";
    graph.push_back({e.a, e.b});
  }
  std::map<std::uint32_t, std::uint32_t> parent;
  const auto find = [&](std::uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const auto& [a, b] : graph) parent.emplace(a, a), parent.emplace(b, b);
  for (const auto& [a, b] : graph) parent[find(a)] = find(b);
  std::set<std::uint32_t> roots;
  for (const auto& [v, p] : parent) roots.insert(find(v));
  return {(long long)parent.size() - (long long)graph.size(), roots.size(), seams.size()};
}

long long eulerCharacteristic(const TriangleMesh& mesh) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  std::set<std::uint32_t> vertices;
  for (const Vec3u& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      edges.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
      vertices.insert(t[k]);
    }
  return (long long)vertices.size() - (long long)edges.size() + (long long)mesh.triangles.size();
}

TEST(CutGraph, OpensASphereAlongOnePath) {
  const TriangleMesh sphere = makeIcosphere(3);
  const GraphShape g = cutGraphShape(sphere, cutGraphSeams(sphere));
  EXPECT_EQ(g.chi, 1);  // a path: a tree
  EXPECT_EQ(g.pieces, 1u);
  EXPECT_GT(g.seams, 3u);  // between two vertices far apart
}

TEST(CutGraph, CutsATorusAlongTwoLoops) {
  const TriangleMesh torus = makeTorus(1.0f, 0.3f, 32, 16);
  const GraphShape g = cutGraphShape(torus, cutGraphSeams(torus));
  EXPECT_EQ(eulerCharacteristic(torus), 0);
  EXPECT_EQ(g.chi, -1);
  EXPECT_EQ(g.pieces, 1u);
}

TEST(CutGraph, JoinsTheHolesOfAnOpenMeshAndLeavesADiskAlone) {
  TriangleMesh sphere = makeIcosphere(3);
  // Three holes: remove three triangles far apart.
  TriangleMesh holes = sphere;
  holes.triangles.clear();
  for (std::size_t f = 0; f < sphere.triangles.size(); ++f)
    if (f != 0 && f != 400 && f != 900) holes.triangles.push_back(sphere.triangles[f]);
  const GraphShape g = cutGraphShape(holes, cutGraphSeams(holes));
  EXPECT_EQ(g.chi, eulerCharacteristic(holes) - 1);
  EXPECT_EQ(g.pieces, 1u);
  // A disk (the sphere with one hole) needs no seam.
  TriangleMesh disk = sphere;
  disk.triangles.erase(disk.triangles.begin());
  EXPECT_TRUE(cutGraphSeams(disk).empty());
}

TEST(CutGraph, RefusesWhatCannotBeCutIntoOneDisk) {
  EXPECT_THROW(cutGraphSeams(TriangleMesh{}), Error);
  TriangleMesh fin = makeIcosphere(1);
  const Vec3u t = fin.triangles[0];
  fin.positions.push_back(Vec3f(5, 5, 5));
  fin.triangles.push_back({t[0], t[1], std::uint32_t(fin.positions.size() - 1)});  // a third triangle on an edge
  EXPECT_THROW(cutGraphSeams(fin), Error);
  TriangleMesh two = makeIcosphere(1);
  const std::uint32_t offset = std::uint32_t(two.positions.size());
  const TriangleMesh other = makeIcosphere(1);
  for (const Vec3f& p : other.positions) two.positions.push_back(p + Vec3f(3, 0, 0));
  for (const Vec3u& s : other.triangles) two.triangles.push_back(s + Vec3u(offset));
  EXPECT_THROW(cutGraphSeams(two), Error);
}

}  // namespace
}  // namespace cellrelief
