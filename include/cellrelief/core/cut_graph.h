// SPDX-License-Identifier: MIT
/// @file cut_graph.h
/// The seams that cut a mesh into a topological disk, for parameterizations that need one
/// (LSCM, discrete conformal maps). The dual spanning tree method: the edges no dual spanning
/// tree crosses, with the boundary, form a graph whose complement is a disk; pruning its
/// dangling branches leaves the cut graph (2g + b - 1 independent loops on a surface of genus g
/// with b boundaries: chi(graph) = chi(surface) - 1). A closed surface of genus 0 prunes to
/// nothing, and gets one path between two vertices far apart, which opens it into a disk.
#pragma once

#include <algorithm>
#include <cstdint>
#include <queue>
#include <unordered_map>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/triangle_mesh.h"

namespace cellrelief {

struct MeshEdge {
  std::uint32_t a = 0, b = 0;  ///< a < b
  std::uint32_t faces = 0;     ///< triangles that use it
};

/// The interior edges to cut along (each once, a < b). Throws for an edge of more than two
/// triangles (a non-manifold mesh cannot be cut into a disk) and for a mesh of several pieces.
inline std::vector<MeshEdge> cutGraphSeams(const TriangleMesh& mesh) {
  const std::size_t faceCount = mesh.triangles.size();
  if (faceCount == 0) throw Error(ErrorKind::InvalidArgument, "cut graph: the mesh has no triangles");
  // Edges, and per edge its (up to two) triangles.
  std::unordered_map<std::uint64_t, std::uint32_t> edgeIndex;
  std::vector<MeshEdge> edges;
  std::vector<std::uint32_t> edgeFaces;  // two per edge
  std::vector<std::uint32_t> faceEdges(3 * faceCount);
  for (std::size_t f = 0; f < faceCount; ++f)
    for (int k = 0; k < 3; ++k) {
      std::uint32_t a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
      if (a == b) throw Error(ErrorKind::InvalidInput, "cut graph: a triangle repeats a corner");
      if (a > b) std::swap(a, b);
      const std::uint64_t key = (std::uint64_t(a) << 32) | b;
      auto [it, added] = edgeIndex.emplace(key, std::uint32_t(edges.size()));
      if (added) {
        edges.push_back({a, b, 0});
        edgeFaces.insert(edgeFaces.end(), {0u, 0u});
      }
      MeshEdge& e = edges[it->second];
      if (e.faces == 2) throw Error(ErrorKind::InvalidInput, "cut graph: an edge is shared by more than two triangles");
      edgeFaces[2 * it->second + e.faces++] = std::uint32_t(f);
      faceEdges[3 * f + k] = it->second;
    }
  // A dual spanning tree: breadth first over the triangles, through interior edges.
  std::vector<std::uint8_t> inTree(edges.size(), 0), reached(faceCount, 0);
  std::queue<std::uint32_t> queue;
  queue.push(0);
  reached[0] = 1;
  std::size_t reachedCount = 1;
  while (!queue.empty()) {
    const std::uint32_t f = queue.front();
    queue.pop();
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t e = faceEdges[3 * f + k];
      if (edges[e].faces != 2) continue;
      const std::uint32_t g = edgeFaces[2 * e] == f ? edgeFaces[2 * e + 1] : edgeFaces[2 * e];
      if (reached[g]) continue;
      reached[g] = 1;
      ++reachedCount;
      inTree[e] = 1;
      queue.push(g);
    }
  }
  if (reachedCount != faceCount) throw Error(ErrorKind::InvalidInput, "cut graph: the mesh has several pieces");
  // The rest, pruned of dangling branches.
  std::vector<std::uint32_t> degree(mesh.positions.size(), 0);
  std::vector<std::vector<std::uint32_t>> incident(mesh.positions.size());
  std::vector<std::uint8_t> kept(edges.size(), 0);
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (!inTree[e]) {
      kept[e] = 1;
      ++degree[edges[e].a];
      ++degree[edges[e].b];
      incident[edges[e].a].push_back(std::uint32_t(e));
      incident[edges[e].b].push_back(std::uint32_t(e));
    }
  std::vector<std::uint32_t> leaves;
  for (std::uint32_t v = 0; v < degree.size(); ++v)
    if (degree[v] == 1) leaves.push_back(v);
  std::uint32_t lastLeaf = leaves.empty() ? 0 : leaves.front();
  while (!leaves.empty()) {
    const std::uint32_t v = leaves.back();
    leaves.pop_back();
    if (degree[v] != 1) continue;
    lastLeaf = v;
    for (std::uint32_t e : incident[v]) {
      if (!kept[e]) continue;
      kept[e] = 0;
      const std::uint32_t other = edges[e].a == v ? edges[e].b : edges[e].a;
      --degree[v];
      if (--degree[other] == 1) leaves.push_back(other);
    }
  }
  std::vector<MeshEdge> seams;
  bool anyKept = false;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    anyKept = anyKept || kept[e];
    if (kept[e] && edges[e].faces == 2) seams.push_back(edges[e]);
  }
  if (anyKept) return seams;
  // A closed sphere: cut one path, from the last vertex pruned to the vertex farthest from it
  // in edges (breadth first over the mesh's edges).
  std::vector<std::uint32_t> parentEdge(mesh.positions.size(), std::uint32_t(-1));
  std::vector<std::uint8_t> seen(mesh.positions.size(), 0);
  std::vector<std::vector<std::uint32_t>> around(mesh.positions.size());
  for (std::size_t e = 0; e < edges.size(); ++e) {
    around[edges[e].a].push_back(std::uint32_t(e));
    around[edges[e].b].push_back(std::uint32_t(e));
  }
  std::queue<std::uint32_t> vertices;
  vertices.push(lastLeaf);
  seen[lastLeaf] = 1;
  std::uint32_t farthest = lastLeaf;
  while (!vertices.empty()) {
    const std::uint32_t v = vertices.front();
    vertices.pop();
    farthest = v;
    for (std::uint32_t e : around[v]) {
      const std::uint32_t w = edges[e].a == v ? edges[e].b : edges[e].a;
      if (seen[w]) continue;
      seen[w] = 1;
      parentEdge[w] = e;
      vertices.push(w);
    }
  }
  for (std::uint32_t v = farthest; v != lastLeaf;) {
    const MeshEdge& e = edges[parentEdge[v]];
    seams.push_back(e);
    v = e.a == v ? e.b : e.a;
  }
  return seams;
}

}  // namespace cellrelief
