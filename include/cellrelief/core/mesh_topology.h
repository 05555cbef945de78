// SPDX-License-Identifier: MIT
/// @file mesh_topology.h
/// What is unusual about a triangle mesh: components, boundary, non-manifold edges and vertices,
/// inconsistent orientation, degenerate triangles, Euler characteristic and genus. Computed from the
/// indexed soup by grouping edges by vertex (linear time), so it works on inputs a half-edge
/// structure rejects.
///
/// Definitions (chosen to match the figures in the test data's SOURCES.md):
/// - an edge is boundary when one triangle uses it, non-manifold when three or more do;
/// - a vertex is non-manifold when the triangles around it, linked through the edges they share at
///   that vertex, fall into more than one fan (an hourglass tip); vertices on non-manifold edges are
///   counted under non-manifold edges only;
/// - a manifold edge is misoriented when both triangles traverse it in the same direction;
/// - components link triangles through shared vertex indices (coincident but distinct vertices stay
///   apart: see duplicatePositions);
/// - chi = V - E + F over referenced vertices; the genus is given only for a single closed,
///   manifold, consistently oriented component: g = (2 - chi) / 2.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <tbb/parallel_sort.h>

#include "cellrelief/core/error.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/core/union_find.h"

namespace cellrelief {

struct MeshTopology {
  std::size_t vertices = 0;
  std::size_t referencedVertices = 0;
  std::size_t unreferencedVertices = 0;
  std::size_t duplicatePositions = 0;  ///< distinct vertices at an already used position
  std::size_t triangles = 0;
  std::size_t edges = 0;
  std::size_t boundaryEdges = 0;
  std::size_t boundaryLoops = 0;  ///< connected components of the boundary edges
  std::size_t nonManifoldEdges = 0;
  std::size_t nonManifoldVertices = 0;
  std::size_t misorientedEdges = 0;
  std::size_t degenerateTriangles = 0;  ///< repeated vertex index or exactly zero area
  std::size_t components = 0;
  long long eulerCharacteristic = 0;
  std::optional<int> genus;

  bool closed() const { return boundaryEdges == 0; }
  bool manifold() const { return nonManifoldEdges == 0 && nonManifoldVertices == 0; }
  bool oriented() const { return misorientedEdges == 0; }
};

namespace detail {
inline constexpr std::uint32_t kNoFan = 0xffffffffu;
/// Exactly zero area: the float inputs are converted to double, where the edge differences are
/// exact; the cross product is then zero only for (numerically) collinear corners.
inline bool hasZeroArea(const TriangleMesh& mesh, const Vec3u& t) {
  const Vec3d a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), c(mesh.positions[t[2]]);
  const Vec3d n = glm::cross(b - a, c - a);
  return n.x == 0 && n.y == 0 && n.z == 0;
}

/// One triangle's use of an edge: the sorted vertex pair, the corners it joins and its direction.
struct EdgeUse {
  std::uint32_t a, b;  // a < b
  std::uint32_t face;
  std::uint8_t cornerA, cornerB;  // corner index (0..2) of a and b in `face`
  bool forward;                   // the face traverses a -> b
};

/// Every edge use of the mesh ordered by (a, b, face), so the uses of one edge are adjacent. A
/// counting sort by a (stable, so faces stay in order) and a stable sort by b within each vertex's
/// few uses: linear in the mesh, where one comparison sort of all uses took a quarter of the
/// analysis of a multi-million-triangle reconstruction.
inline std::vector<EdgeUse> edgeUsesByEdge(const TriangleMesh& mesh) {
  const std::size_t nv = mesh.positions.size();
  std::vector<std::uint32_t> start(nv + 1, 0);
  const auto forEachUse = [&](auto&& use) {
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      const Vec3u& t = mesh.triangles[f];
      for (int k = 0; k < 3; ++k) {
        const int k1 = (k + 1) % 3;
        const std::uint32_t p = t[k], q = t[k1];
        if (p == q) continue;  // a repeated index makes no edge
        const bool fwd = p < q;
        use(EdgeUse{fwd ? p : q, fwd ? q : p, static_cast<std::uint32_t>(f),
                    static_cast<std::uint8_t>(fwd ? k : k1), static_cast<std::uint8_t>(fwd ? k1 : k), fwd});
      }
    }
  };
  forEachUse([&](const EdgeUse& u) { ++start[u.a + 1]; });
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<EdgeUse> uses(start[nv]);
  {
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    forEachUse([&](const EdgeUse& u) { uses[next[u.a]++] = u; });
  }
  const auto byB = [](const EdgeUse& x, const EdgeUse& y) { return x.b < y.b; };
  for (std::size_t v = 0; v < nv; ++v) {
    const auto first = uses.begin() + start[v], last = uses.begin() + start[v + 1];
    if (last - first <= 16) {  // insertion sort: stable, and fastest on a vertex's few uses
      for (auto i = first + (first != last); i < last; ++i)
        for (auto j = i; j > first && byB(*j, *(j - 1)); --j) std::iter_swap(j, j - 1);
    } else {
      std::stable_sort(first, last, byB);
    }
  }
  return uses;
}
}  // namespace detail

/// Analyses the mesh. Indices must be in range (TriangleMesh::validate()).
inline MeshTopology analyzeTopology(const TriangleMesh& mesh) {
  MeshTopology r;
  const std::size_t nv = mesh.positions.size();
  const std::size_t nf = mesh.triangles.size();
  // Corners and edge uses are counted in 32 bits (3 per triangle): refused beyond, not wrapped.
  if (3 * nf >= (std::size_t(1) << 32))
    throw Error(ErrorKind::ResourceLimit, "mesh topology: " + std::to_string(nf) +
                                              " triangles, more than the analysis counts (1,431,655,765)");
  r.vertices = nv;
  r.triangles = nf;

  std::vector<char> referenced(nv, 0);
  UnionFind vertexSets(nv);
  for (std::size_t f = 0; f < nf; ++f) {
    const Vec3u& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) referenced[t[k]] = 1;
    vertexSets.unite(t[0], t[1]);
    vertexSets.unite(t[0], t[2]);
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || detail::hasZeroArea(mesh, t))
      ++r.degenerateTriangles;
  }
  std::vector<char> isRoot(nv, 0);
  for (std::size_t v = 0; v < nv; ++v) {
    if (!referenced[v]) continue;
    ++r.referencedVertices;
    const std::uint32_t root = vertexSets.find(static_cast<std::uint32_t>(v));
    if (!isRoot[root]) {
      isRoot[root] = 1;
      ++r.components;
    }
  }
  r.unreferencedVertices = nv - r.referencedVertices;

  {  // coincident positions among referenced vertices
    std::vector<Vec3f> sorted;  // the positions themselves: sorting indices gathers per comparison
    sorted.reserve(r.referencedVertices);
    for (std::size_t v = 0; v < nv; ++v)
      if (referenced[v]) sorted.push_back(mesh.positions[v]);
    std::sort(sorted.begin(), sorted.end(), [](const Vec3f& p, const Vec3f& q) {
      return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
    });
    for (std::size_t i = 1; i < sorted.size(); ++i)
      if (sorted[i] == sorted[i - 1]) ++r.duplicatePositions;
  }

  const std::vector<detail::EdgeUse> uses = detail::edgeUsesByEdge(mesh);

  // Fans: corners (3 f + k) around the same vertex joined when their faces share an edge there.
  UnionFind corners(3 * nf);
  UnionFind boundarySets(nv);
  std::vector<char> onBoundary(nv, 0);
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].a == uses[i].a && uses[j].b == uses[i].b) ++j;
    const std::size_t count = j - i;
    ++r.edges;
    if (count == 1) {
      ++r.boundaryEdges;
      boundarySets.unite(uses[i].a, uses[i].b);
      onBoundary[uses[i].a] = onBoundary[uses[i].b] = 1;
    } else if (count == 2) {
      if (uses[i].forward == uses[i + 1].forward) ++r.misorientedEdges;
    } else {
      ++r.nonManifoldEdges;
    }
    for (std::size_t k = i + 1; k < j; ++k) {
      corners.unite(3 * uses[i].face + uses[i].cornerA, 3 * uses[k].face + uses[k].cornerA);
      corners.unite(3 * uses[i].face + uses[i].cornerB, 3 * uses[k].face + uses[k].cornerB);
    }
    i = j;
  }

  // A vertex with more than one fan is non-manifold; remember the first fan root seen per vertex.
  std::vector<std::uint32_t> fanRoot(nv, detail::kNoFan);
  std::vector<char> nonManifold(nv, 0);
  for (std::size_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.triangles[f][k];
      const std::uint32_t root = corners.find(static_cast<std::uint32_t>(3 * f + k));
      if (fanRoot[v] == detail::kNoFan)
        fanRoot[v] = root;
      else if (fanRoot[v] != root && !nonManifold[v]) {
        nonManifold[v] = 1;
        ++r.nonManifoldVertices;
      }
    }
  }

  std::vector<char> loopRoot(nv, 0);
  for (std::size_t v = 0; v < nv; ++v) {
    if (!onBoundary[v]) continue;
    const std::uint32_t root = boundarySets.find(static_cast<std::uint32_t>(v));
    if (!loopRoot[root]) {
      loopRoot[root] = 1;
      ++r.boundaryLoops;
    }
  }

  r.eulerCharacteristic = static_cast<long long>(r.referencedVertices) -
                          static_cast<long long>(r.edges) + static_cast<long long>(nf);
  if (r.components == 1 && r.closed() && r.manifold() && r.oriented())
    r.genus = static_cast<int>((2 - r.eulerCharacteristic) / 2);
  return r;
}

/// The edges that only one triangle uses (the rims of holes and the borders of open sheets), as
/// pairs of vertex indices. Vertices at the same position count as one, so a soup (an STL file,
/// where every triangle has its own corners) has the boundary of the surface it makes, not of
/// each triangle; degenerate triangles' repeated corners make no edge.
inline std::vector<std::pair<std::uint32_t, std::uint32_t>> boundaryEdges(const TriangleMesh& mesh) {
  const std::size_t nv = mesh.positions.size();
  std::vector<std::uint32_t> order(nv), canonical(nv);
  for (std::uint32_t v = 0; v < nv; ++v) order[v] = v;
  auto less = [&](std::uint32_t a, std::uint32_t b) {
    const Vec3f &p = mesh.positions[a], &q = mesh.positions[b];
    return std::tie(p.x, p.y, p.z, a) < std::tie(q.x, q.y, q.z, b);
  };
  std::sort(order.begin(), order.end(), less);
  for (std::size_t i = 0; i < nv; ++i)
    canonical[order[i]] = i > 0 && mesh.positions[order[i]] == mesh.positions[order[i - 1]]
                              ? canonical[order[i - 1]]
                              : order[i];
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  edges.reserve(3 * mesh.triangles.size());
  for (const Vec3u& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = canonical[t[k]], b = canonical[t[(k + 1) % 3]];
      if (a != b) edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> once;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if (j - i == 1) once.push_back(edges[i]);
    i = j;
  }
  return once;
}

/// The boundary edges (used by exactly one triangle) as analyzeTopology counts them, without the
/// rest of its analysis: one parallel sort of the packed edge keys. For checks that need only
/// this, e.g. whether a reconstruction came out closed (about a quarter of `cellrelief
/// reconstruct`'s time went to the full analysis of a 4.8M-triangle result).
inline std::size_t countBoundaryEdges(const TriangleMesh& mesh) {
  std::vector<std::uint64_t> keys;
  keys.reserve(3 * mesh.triangles.size());
  for (const Vec3u& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t p = t[k], q = t[(k + 1) % 3];
      if (p == q) continue;  // a repeated index makes no edge
      keys.push_back(std::uint64_t(std::min(p, q)) << 32 | std::max(p, q));
    }
  tbb::parallel_sort(keys.begin(), keys.end());
  std::size_t boundary = 0;
  for (std::size_t i = 0; i < keys.size();) {
    std::size_t j = i + 1;
    while (j < keys.size() && keys[j] == keys[i]) ++j;
    boundary += j - i == 1;
    i = j;
  }
  return boundary;
}

}  // namespace cellrelief
