// SPDX-License-Identifier: MIT
/// @file polycube.ipp
/// Bodies of polycube.h.
#pragma once

#include <optional>
#include <span>
#include <unordered_map>
#include <unordered_set>

#include "cellrelief/core/union_find.h"

namespace cellrelief::polycube {

namespace detail {

constexpr Vec3i kAxisStep[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
/// The step to the neighbour across face f (0 = -x, 1 = +x, ... as cells::faceNormal).
inline Vec3i faceStep(int face) { return (face & 1) ? kAxisStep[face >> 1] : -kAxisStep[face >> 1]; }

inline bool lessZyx(const Vec3i& a, const Vec3i& b) {
  if (a.z != b.z) return a.z < b.z;
  if (a.y != b.y) return a.y < b.y;
  return a.x < b.x;
}

/// The cube at octant o of the block around lattice vertex v.
inline Vec3i octantCube(const Vec3i& v, int octant) {
  return v - Vec3i(1) + Vec3i(octant & 1, (octant >> 1) & 1, (octant >> 2) & 1);
}

}  // namespace detail

inline Polycube::Polycube(std::vector<Vec3i> cubes) : mCubes(std::move(cubes)) {
  for (const Vec3i& c : mCubes)
    for (int a = 0; a < 3; ++a)
      if (c[a] < -kMaxCoordinate + 2 || c[a] > kMaxCoordinate - 2)
        throw Error(ErrorKind::InvalidArgument,
                    "polycube: cube coordinate " + std::to_string(c[a]) + " is out of range (|c| < " +
                        std::to_string(kMaxCoordinate - 1) + ")");
  std::sort(mCubes.begin(), mCubes.end(), detail::lessZyx);
  mCubes.erase(std::unique(mCubes.begin(), mCubes.end()), mCubes.end());
  mSet.reserve(mCubes.size() * 2);
  for (const Vec3i& c : mCubes) mSet.insert(key(c));
  if (!mCubes.empty()) {
    mMin = mMax = mCubes.front();
    for (const Vec3i& c : mCubes) mMin = glm::min(mMin, c), mMax = glm::max(mMax, c);
  }
}

inline std::uint8_t Polycube::vertexConfiguration(const Vec3i& v) const {
  std::uint8_t octants = 0;
  for (int o = 0; o < 8; ++o)
    if (contains(detail::octantCube(v, o))) octants |= std::uint8_t(1u << o);
  return octants;
}

inline std::vector<Vec3i> Polycube::surfaceVertices() const {
  std::vector<Vec3i> corners;
  corners.reserve(mCubes.size() * 8);
  for (const Vec3i& c : mCubes)
    for (int o = 0; o < 8; ++o) corners.push_back(c + Vec3i(o & 1, (o >> 1) & 1, (o >> 2) & 1));
  std::sort(corners.begin(), corners.end(), detail::lessZyx);
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  std::erase_if(corners, [&](const Vec3i& v) { return vertexConfiguration(v) == 255; });
  return corners;
}

inline std::vector<Vec3i> Polycube::nonManifoldVertices() const {
  std::vector<Vec3i> out;
  for (const Vec3i& v : surfaceVertices())
    if (!kVertexConfigurations[vertexConfiguration(v)].manifold) out.push_back(v);
  return out;
}

template <class Visit>
void Polycube::forEachSurfaceFace(Visit&& visit) const {
  for (const Vec3i& c : mCubes)
    for (int face = 0; face < 6; ++face) {
      if (contains(c + detail::faceStep(face))) continue;
      const int axis = face >> 1;
      const bool positive = (face & 1) != 0;
      visit(positive ? c + detail::kAxisStep[axis] : c, axis, positive);
    }
}

inline SurfaceStats Polycube::surfaceStats() const {
  SurfaceStats stats;
  // Faces, and the lattice edges they hold (an edge: its lower vertex and its axis).
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> facesOfEdge;
  std::uint32_t faceCount = 0;
  forEachSurfaceFace([&](const Vec3i& base, int axis, bool) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    const Vec3i corners[3] = {base, base + detail::kAxisStep[a], base + detail::kAxisStep[b]};
    const std::pair<Vec3i, int> edges[4] = {{corners[0], a}, {corners[0], b}, {corners[1], b}, {corners[2], a}};
    for (const auto& [v, edgeAxis] : edges) facesOfEdge[key(v) * 3 + std::uint64_t(edgeAxis)].push_back(faceCount);
    ++faceCount;
  });
  stats.faces = faceCount;
  stats.edges = facesOfEdge.size();
  UnionFind pieces(faceCount);
  for (const auto& [edge, faces] : facesOfEdge)
    for (std::size_t i = 1; i < faces.size(); ++i) pieces.unite(faces[0], faces[i]);
  for (std::uint32_t f = 0; f < faceCount; ++f) stats.components += pieces.find(f) == f;
  for (const Vec3i& v : surfaceVertices()) {
    ++stats.vertices;
    const VertexConfigurationInfo& info = kVertexConfigurations[vertexConfiguration(v)];
    if (info.manifold)
      ++stats.perCase[static_cast<int>(info.vertexCase)];
    else
      ++stats.nonManifoldVertices;
  }
  return stats;
}

inline TriangleMesh Polycube::surfaceMesh(const PolycubeFrame& frame) const {
  TriangleMesh mesh;
  std::unordered_map<std::uint64_t, std::uint32_t> index;
  auto vertex = [&](const Vec3i& v) {
    const auto [it, inserted] = index.try_emplace(key(v), std::uint32_t(mesh.positions.size()));
    if (inserted) mesh.positions.push_back(Vec3f(frame.origin + frame.cubeSize * Vec3d(v)));
    return it->second;
  };
  forEachSurfaceFace([&](const Vec3i& base, int axis, bool positive) {
    const Vec3i ea = detail::kAxisStep[(axis + 1) % 3], eb = detail::kAxisStep[(axis + 2) % 3];
    // (ea, eb) turns about +axis, so p0 p1 p2 faces +axis.
    const std::uint32_t p0 = vertex(base), p1 = vertex(base + ea), p2 = vertex(base + ea + eb), p3 = vertex(base + eb);
    if (positive) {
      mesh.triangles.push_back({p0, p1, p2});
      mesh.triangles.push_back({p0, p2, p3});
    } else {
      mesh.triangles.push_back({p0, p2, p1});
      mesh.triangles.push_back({p0, p3, p2});
    }
  });
  return mesh;
}

inline std::vector<std::vector<Vec3i>> Polycube::components() const {
  std::vector<std::vector<Vec3i>> pieces;
  std::unordered_set<std::uint64_t> seen;
  for (const Vec3i& start : mCubes) {
    if (!seen.insert(key(start)).second) continue;
    std::vector<Vec3i> piece{start};
    for (std::size_t i = 0; i < piece.size(); ++i)
      for (int face = 0; face < 6; ++face) {
        const Vec3i n = piece[i] + detail::faceStep(face);
        if (contains(n) && seen.insert(key(n)).second) piece.push_back(n);
      }
    pieces.push_back(std::move(piece));
  }
  std::stable_sort(pieces.begin(), pieces.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return pieces;
}

template <class Preference>
std::size_t makeManifold(Polycube& polycube, Preference&& prefer, std::size_t maxAdded) {
  // Subsets of the 8 octants by size, so the first manifold one found is one of the smallest.
  static const std::array<std::uint8_t, 256> bySize = [] {
    std::array<std::uint8_t, 256> order{};
    for (int i = 0; i < 256; ++i) order[i] = std::uint8_t(i);
    std::stable_sort(order.begin(), order.end(), [](int a, int b) { return popcount8(a) < popcount8(b); });
    return order;
  }();
  std::size_t added = 0;
  for (;;) {
    const std::vector<Vec3i> bad = polycube.nonManifoldVertices();
    if (bad.empty()) return added;
    std::vector<Vec3i> cubes(polycube.cubes().begin(), polycube.cubes().end());
    std::unordered_set<std::uint64_t> pending;
    for (const Vec3i& v : bad) {
      // Octants taken by a cube already, or by one this pass adds.
      std::uint8_t octants = polycube.vertexConfiguration(v);
      for (int o = 0; o < 8; ++o) {
        const Vec3i c = detail::octantCube(v, o);
        if (pending.count(Polycube::key(c)))
          octants |= std::uint8_t(1u << o);
      }
      if (isManifold(octants)) continue;
      int best = -1;
      double bestScore = 0;
      for (std::uint8_t subset : bySize) {
        if ((subset & octants) != 0 || !isManifold(std::uint8_t(octants | subset))) continue;
        if (best >= 0 && popcount8(subset) > popcount8(std::uint8_t(best))) break;
        double score = 0;
        for (int o = 0; o < 8; ++o)
          if (subset & (1u << o)) score += double(prefer(detail::octantCube(v, o)));
        if (best < 0 || score > bestScore) best = subset, bestScore = score;
      }
      for (int o = 0; o < 8; ++o)
        if (best & (1 << o)) {
          const Vec3i c = detail::octantCube(v, o);
          pending.insert(Polycube::key(c));
          cubes.push_back(c);
          ++added;
        }
    }
    if (added > maxAdded)
      throw Error(ErrorKind::InvalidArgument, "polycube: making the surface manifold added more than " +
                                                  std::to_string(maxAdded) + " cubes; the cube set is too ragged");
    polycube = Polycube(std::move(cubes));
  }
}

inline std::size_t makeManifold(Polycube& polycube) {
  return makeManifold(polycube, [](const Vec3i&) { return 0.0; });
}

inline std::vector<Vec3i> verticesOfCase(const Polycube& polycube, VertexCase vertexCase) {
  std::vector<Vec3i> out;
  for (const Vec3i& v : polycube.surfaceVertices()) {
    const VertexConfigurationInfo& info = kVertexConfigurations[polycube.vertexConfiguration(v)];
    if (info.manifold && info.vertexCase == vertexCase) out.push_back(v);
  }
  return out;
}

namespace detail {

inline bool isOfCase(const Polycube& p, const Vec3i& v, VertexCase vertexCase) {
  const VertexConfigurationInfo& info = kVertexConfigurations[p.vertexConfiguration(v)];
  return info.surface && info.manifold && info.vertexCase == vertexCase;
}

/// Vertices of the case among the corners of the cubes, and whether all those corners are
/// manifold.
inline std::pair<int, bool> caseCountAround(const Polycube& p, std::span<const Vec3i> cubes, VertexCase vertexCase) {
  std::vector<Vec3i> corners;
  for (const Vec3i& c : cubes)
    for (int k = 0; k < 8; ++k) corners.push_back(c + Vec3i(k & 1, (k >> 1) & 1, (k >> 2) & 1));
  std::sort(corners.begin(), corners.end(), lessZyx);
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  int count = 0;
  bool manifold = true;
  for (const Vec3i& v : corners) {
    manifold = manifold && kVertexConfigurations[p.vertexConfiguration(v)].manifold;
    count += isOfCase(p, v, vertexCase);
  }
  return {count, manifold};
}

/// The polycube with these cubes toggled, when that keeps it one manifold piece of the same
/// genus and lowers the case's vertices among those it changes; with that count.
inline std::optional<std::pair<Polycube, int>> toggledIfBetter(const Polycube& polycube, std::span<const Vec3i> toggle,
                                                               VertexCase vertexCase, std::optional<int> genus) {
  const int before = caseCountAround(polycube, toggle, vertexCase).first;
  std::vector<Vec3i> cubes(polycube.cubes().begin(), polycube.cubes().end());
  for (const Vec3i& c : toggle)
    if (polycube.contains(c)) std::erase(cubes, c);
    else cubes.push_back(c);
  if (cubes.empty()) return std::nullopt;
  Polycube candidate(std::move(cubes));
  const auto [after, manifold] = caseCountAround(candidate, toggle, vertexCase);
  if (!manifold || after >= before) return std::nullopt;
  const SurfaceStats stats = candidate.surfaceStats();
  if (stats.components != 1 || stats.genus() != genus) return std::nullopt;
  return std::pair<Polycube, int>{std::move(candidate), after};
}

}  // namespace detail

template <class Preference>
std::size_t removeVerticesOfCase(Polycube& polycube, VertexCase vertexCase, Preference&& prefer, int maxRounds) {
  std::size_t toggled = 0;
  const std::optional<int> genus = polycube.surfaceStats().genus();
  auto score = [&](std::span<const Vec3i> toggle) {
    double sum = 0;
    for (const Vec3i& c : toggle) sum += polycube.contains(c) ? 1.0 - double(prefer(c)) : double(prefer(c));
    return sum;
  };
  // One cube of the vertex's block first; where none helps, two cubes within two of the vertex.
  for (const int cubesAtOnce : {1, 2})
    for (int round = 0; round < maxRounds; ++round) {
      bool progressed = false;
      for (const Vec3i& v : verticesOfCase(polycube, vertexCase)) {
        if (!detail::isOfCase(polycube, v, vertexCase)) continue;  // a neighbour's change fixed it
        std::vector<Vec3i> near;
        const int reach = cubesAtOnce == 1 ? 1 : 2;
        for (int z = -reach; z < reach; ++z)
          for (int y = -reach; y < reach; ++y)
            for (int x = -reach; x < reach; ++x) near.push_back(v + Vec3i(x, y, z));
        std::optional<std::pair<Polycube, int>> best;
        double bestScore = 0;
        auto consider = [&](std::span<const Vec3i> toggle) {
          auto candidate = detail::toggledIfBetter(polycube, toggle, vertexCase, genus);
          if (!candidate) return;
          const double s = score(toggle);
          if (!best || candidate->second < best->second || (candidate->second == best->second && s > bestScore)) {
            best = std::move(candidate);
            bestScore = s;
          }
        };
        for (std::size_t i = 0; i < near.size(); ++i) {
          if (cubesAtOnce == 1) {
            consider(std::span<const Vec3i>(&near[i], 1));
            continue;
          }
          for (std::size_t j = i + 1; j < near.size(); ++j) {
            const Vec3i pair[2] = {near[i], near[j]};
            consider(pair);
          }
        }
        if (best) {
          polycube = std::move(best->first);
          toggled += std::size_t(cubesAtOnce);
          progressed = true;
        }
      }
      if (!progressed) break;
    }
  return toggled;
}

inline Polycube keepLargestAndFill(const Polycube& polycube) {
  if (polycube.empty()) return polycube;
  const Polycube largest(polycube.components().front());
  // Flood the empty space of the box one cube larger than the piece from its corner: what the
  // flood does not reach is a cavity and becomes solid.
  const Vec3i lo = largest.minCube() - Vec3i(1), hi = largest.maxCube() + Vec3i(1);
  const Vec3i extent = hi - lo + Vec3i(1);
  const double boxCubes = double(extent.x) * double(extent.y) * double(extent.z);
  if (boxCubes > double(std::size_t(1) << 30))
    throw Error(ErrorKind::ResourceLimit, "polycube: the piece spans " + std::to_string(extent.x) + " x " +
                                              std::to_string(extent.y) + " x " + std::to_string(extent.z) +
                                              " cubes, too large a box to fill its cavities");
  auto at = [&](const Vec3i& c) {
    const Vec3i l = c - lo;
    return (std::size_t(l.z) * std::size_t(extent.y) + std::size_t(l.y)) * std::size_t(extent.x) + std::size_t(l.x);
  };
  std::vector<std::uint8_t> outside(std::size_t(extent.x) * extent.y * extent.z, 0);
  std::vector<Vec3i> queue{lo};
  outside[at(lo)] = 1;
  for (std::size_t i = 0; i < queue.size(); ++i)
    for (int face = 0; face < 6; ++face) {
      const Vec3i n = queue[i] + detail::faceStep(face);
      if (glm::any(glm::lessThan(n, lo)) || glm::any(glm::greaterThan(n, hi))) continue;
      if (outside[at(n)] || largest.contains(n)) continue;
      outside[at(n)] = 1;
      queue.push_back(n);
    }
  std::vector<Vec3i> cubes;
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x)
        if (!outside[at({x, y, z})]) cubes.push_back({x, y, z});
  return Polycube(std::move(cubes));
}

}  // namespace cellrelief::polycube
