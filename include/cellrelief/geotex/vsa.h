// SPDX-License-Identifier: MIT
/// @file vsa.h
/// Variational Shape Approximation (Cohen-Steiner, Alliez, Desbrun, SIGGRAPH 2004): the faces of a
/// mesh partitioned into K connected regions, each approximated by a plane proxy, by Lloyd
/// iterations of (1) geometry partitioning: flooding from one seed face per proxy through a
/// priority queue ordered by the face's error against the proxy, and (2) proxy fitting. The error
/// is L2,1 (area times squared normal deviation: charts that a height map along the proxy normal
/// represents well) or L2 (squared distance to the plane, integrated over the face).
///
/// Seeding is farthest-point (geodesic over the face graph: even coverage) or hierarchical
/// (proxies added where the error is largest, a few relaxations after each round: fewer
/// iterations to a low error). Region teleports (the paper's section 3.3), when asked for, move
/// proxies from cheap merges to the worst regions where the iterations settle. Every connected
/// component gets at least one proxy, so a mesh of more components than requested proxies gets
/// one per component (reported in the result).
/// Faces are joined across edges whose end points coincide in position, so a triangle soup (an
/// STL file) partitions like the welded mesh. The flooding is sequential (a priority queue);
/// proxy fitting and error evaluation run in parallel over faces.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <unordered_map>
#include <vector>

#include "cellrelief/core/error.h"
#include "cellrelief/core/hit.h"
#include "cellrelief/core/math.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/core/symmetric_eigen.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/core/union_find.h"

namespace cellrelief::geotex {

enum class VsaMetric { L21, L2 };
enum class VsaSeeding { FarthestPoint, Hierarchical };

struct VsaOptions {
  int proxies = 64;
  VsaMetric metric = VsaMetric::L21;
  VsaSeeding seeding = VsaSeeding::Hierarchical;
  int maxIterations = 50;   ///< Lloyd iterations after seeding
  double tolerance = 1e-4;  ///< stop when an iteration changes the error by less than this fraction
  /// Stop as soon as the partition's error (the metric's sum over faces, VsaPartition::error) is
  /// at most this; 0: no target. For timing a run to a peer's error (bench_geotex against CGAL).
  double targetError = 0;
  /// Region teleportation (the paper's section 3.3) where the iterations settle: the cheapest
  /// merges of two neighbouring regions each free a proxy that starts again at the worst face of
  /// one of the regions of largest error (a tenth of the proxies at once); the iterations go on
  /// from there and the best partition seen is kept. A teleport is made only where its merge costs
  /// less than half that region's error, as in the paper. At most this many in all; 0: none.
  int teleports = 0;
  /// Called with the fraction done (seeding counts as the first half).
  std::function<void(double)> progress;
};

/// A plane proxy: a point on it and its unit normal.
struct Proxy {
  Vec3d point{0};
  Vec3d normal{0, 0, 1};
};

struct VsaPartition {
  std::vector<std::uint32_t> regionOfFace;  ///< one region (proxy) index per triangle
  std::vector<Proxy> proxies;
  std::vector<double> regionError;          ///< the metric's error per region
  double error = 0;                         ///< total, the sum of regionError
  std::vector<double> errorPerIteration;    ///< after each Lloyd iteration (non-increasing)
  int requestedProxies = 0;
  int components = 0;                       ///< connected components of the face graph
  int teleports = 0;                        ///< region teleports made (VsaOptions::teleports)
};

/// The face graph, with geometry per face, in the form every VSA step reads.
struct FaceGraph {
  std::vector<double> area;
  std::vector<Vec3d> normal;    ///< unit; zero for a degenerate face
  std::vector<Vec3d> centroid;
  std::vector<std::uint32_t> neighbourStart;  ///< CSR: neighbours of f in [start[f], start[f+1])
  std::vector<std::uint32_t> neighbours;
  std::vector<std::uint32_t> componentOfFace;
  int components = 0;
  /// The centre of the face centroids' bounds: second moments are summed about it, so that a mesh
  /// far from the origin keeps its precision in the covariance (moment - A p p^T).
  Vec3d centre{0};

  std::size_t faceCount() const { return area.size(); }
};

/// For each vertex, the first vertex at its exact position: vertex identity as the face graph and
/// the charts' rings see it, so that a soup (an STL file) joins like its welded mesh.
inline std::vector<std::uint32_t> weldByPosition(const TriangleMesh& mesh) {
  struct PositionHash {
    std::size_t operator()(const Vec3f& p) const {
      const auto bits = [](float x) { return std::hash<float>{}(x == 0.0f ? 0.0f : x); };
      return bits(p.x) * 73856093u ^ bits(p.y) * 19349663u ^ bits(p.z) * 83492791u;
    }
  };
  std::vector<std::uint32_t> weld(mesh.positions.size());
  std::unordered_map<Vec3f, std::uint32_t, PositionHash> first;
  first.reserve(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    weld[v] = first.try_emplace(mesh.positions[v], std::uint32_t(v)).first->second;
  return weld;
}

/// Builds the face graph: faces are neighbours when they share an edge, with vertices identified
/// by position (a soup joins like its welded mesh); a non-manifold edge joins all its faces.
inline FaceGraph buildFaceGraph(const TriangleMesh& mesh) {
  FaceGraph g;
  const std::size_t nf = mesh.triangles.size();
  g.area.resize(nf);
  g.normal.resize(nf);
  g.centroid.resize(nf);
  parallelFor(0, nf, [&](std::size_t f) {
    const Vec3u& t = mesh.triangles[f];
    const Vec3d a(mesh.positions[t[0]]), b(mesh.positions[t[1]]), c(mesh.positions[t[2]]);
    const Vec3d n = glm::cross(b - a, c - a);
    const double len = glm::length(n);
    g.area[f] = 0.5 * len;
    g.normal[f] = len > 0 ? n / len : Vec3d(0);
    g.centroid[f] = (a + b + c) / 3.0;
  });
  if (nf > 0) {
    Vec3d lo = g.centroid[0], hi = g.centroid[0];
    for (const Vec3d& c : g.centroid) lo = glm::min(lo, c), hi = glm::max(hi, c);
    g.centre = 0.5 * (lo + hi);
  }
  const std::vector<std::uint32_t> weld = weldByPosition(mesh);  // so that edges of a soup are found
  struct EdgeUse {
    std::uint64_t key;
    std::uint32_t face;
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      std::uint32_t a = weld[mesh.triangles[f][k]], b = weld[mesh.triangles[f][(k + 1) % 3]];
      if (a == b) continue;
      if (a > b) std::swap(a, b);
      uses.push_back({(std::uint64_t(a) << 32) | b, std::uint32_t(f)});
    }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.key != y.key ? x.key < y.key : x.face < y.face;
  });
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    for (std::size_t p = i; p < j; ++p)
      for (std::size_t q = p + 1; q < j; ++q)
        if (uses[p].face != uses[q].face) {
          pairs.emplace_back(uses[p].face, uses[q].face);
          pairs.emplace_back(uses[q].face, uses[p].face);
        }
    i = j;
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  g.neighbourStart.assign(nf + 1, 0);
  for (const auto& [f, n] : pairs) ++g.neighbourStart[f + 1];
  for (std::size_t f = 0; f < nf; ++f) g.neighbourStart[f + 1] += g.neighbourStart[f];
  g.neighbours.resize(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) g.neighbours[i] = pairs[i].second;  // sorted by f
  UnionFind sets(nf);
  for (const auto& [f, n] : pairs) sets.unite(f, n);
  g.componentOfFace.resize(nf);
  std::unordered_map<std::size_t, std::uint32_t> componentOfRoot;
  for (std::size_t f = 0; f < nf; ++f)
    g.componentOfFace[f] =
        componentOfRoot.try_emplace(sets.find(f), std::uint32_t(componentOfRoot.size())).first->second;
  g.components = int(componentOfRoot.size());
  return g;
}

namespace detail {

/// The metric's error of face f against a proxy.
inline double faceError(const TriangleMesh& mesh, const FaceGraph& g, VsaMetric metric,
                        std::size_t f, const Proxy& proxy) {
  if (metric == VsaMetric::L21) {
    const Vec3d d = g.normal[f] - proxy.normal;
    return g.area[f] * glm::dot(d, d);
  }
  // L2: the integral over the triangle of the squared distance to the plane, exact for the
  // linear distance function: A/6 (d1^2 + d2^2 + d3^2 + d1 d2 + d2 d3 + d3 d1).
  const Vec3u& t = mesh.triangles[f];
  double d[3];
  for (int k = 0; k < 3; ++k) d[k] = glm::dot(Vec3d(mesh.positions[t[k]]) - proxy.point, proxy.normal);
  return g.area[f] / 6.0 *
         (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

/// What a region's best proxy and its error follow from: sums over its faces, positions taken
/// about `about` (FaceGraph::centre).
struct RegionMoments {
  Vec3d about{0};
  double area = 0;
  Vec3d weightedNormal{0};    ///< sum of area * unit normal
  Vec3d weightedCentroid{0};  ///< sum of area * (centroid - about)
  glm::dmat3 moment{0};       ///< L2 only: the integral of x x^T over the faces, x = position - about

  RegionMoments& operator+=(const RegionMoments& o) {
    area += o.area;
    weightedNormal += o.weightedNormal;
    weightedCentroid += o.weightedCentroid;
    moment += o.moment;
    return *this;
  }
};

inline std::vector<RegionMoments> regionMoments(const TriangleMesh& mesh, const FaceGraph& g, VsaMetric metric,
                                                const std::vector<std::uint32_t>& regionOfFace, std::size_t regions) {
  std::vector<RegionMoments> m(regions);
  for (RegionMoments& r : m) r.about = g.centre;
  for (std::size_t f = 0; f < g.faceCount(); ++f) {
    RegionMoments& r = m[regionOfFace[f]];
    const Vec3d centroid = g.centroid[f] - g.centre;
    r.area += g.area[f];
    r.weightedNormal += g.area[f] * g.normal[f];
    r.weightedCentroid += g.area[f] * centroid;
    if (metric == VsaMetric::L2) {
      // The integral of x x^T over a triangle: A/12 (sum v v^T + 9 c c^T), c the centroid.
      const Vec3u& t = mesh.triangles[f];
      glm::dmat3 x = 9.0 * glm::outerProduct(centroid, centroid);
      for (int c = 0; c < 3; ++c) {
        const Vec3d v = Vec3d(mesh.positions[t[c]]) - g.centre;
        x += glm::outerProduct(v, v);
      }
      r.moment += (g.area[f] / 12.0) * x;
    }
  }
  return m;
}

/// The region's best proxy (L2,1: the area-weighted mean normal; L2: the least-squares plane of
/// its triangles, from their exact second moments) and its error against it. A region whose
/// normals cancel (a closed surface in one region) keeps the normal it had.
struct Fit {
  Proxy proxy;
  double error = 0;
};
inline Fit fitRegion(const RegionMoments& r, VsaMetric metric, const Proxy& previous) {
  Fit fit{previous, 0};
  if (r.area <= 0) return fit;  // a region of degenerate faces keeps its proxy
  const Vec3d mean = r.weightedCentroid / r.area;  // about r.about
  fit.proxy.point = r.about + mean;
  if (metric == VsaMetric::L21) {
    // sum A |n - p|^2 = sum A (2 - 2 n.p) over unit normals (a degenerate face has no area).
    const double len = glm::length(r.weightedNormal);
    if (len > 1e-12 * r.area) fit.proxy.normal = r.weightedNormal / len;
    fit.error = std::max(0.0, 2 * r.area - 2 * glm::dot(r.weightedNormal, fit.proxy.normal));
  } else {
    const glm::dmat3 covariance = r.moment - r.area * glm::outerProduct(mean, mean);
    const SymmetricEigen3 e = symmetricEigen3(covariance);
    fit.proxy.normal = glm::dot(e.vectors[0], r.weightedNormal) < 0 ? -e.vectors[0] : e.vectors[0];
    fit.error = std::max(0.0, e.values[0]);
  }
  return fit;
}

/// Fits each region's proxy (fitRegion).
inline void fitProxies(const TriangleMesh& mesh, const FaceGraph& g, VsaMetric metric,
                       const std::vector<std::uint32_t>& regionOfFace, std::vector<Proxy>& proxies) {
  const std::vector<RegionMoments> m = regionMoments(mesh, g, metric, regionOfFace, proxies.size());
  for (std::size_t r = 0; r < proxies.size(); ++r) proxies[r] = fitRegion(m[r], metric, proxies[r]).proxy;
}

/// The face of each region with the lowest error against its proxy: the flooding's seeds.
inline std::vector<std::uint32_t> regionSeeds(const std::vector<double>& errorOfFace,
                                              const std::vector<std::uint32_t>& regionOfFace,
                                              std::size_t regions) {
  std::vector<std::uint32_t> seed(regions, kInvalidId);
  std::vector<double> best(regions, std::numeric_limits<double>::infinity());
  for (std::size_t f = 0; f < regionOfFace.size(); ++f) {
    const std::uint32_t r = regionOfFace[f];
    if (errorOfFace[f] < best[r] || seed[r] == kInvalidId) {
      best[r] = errorOfFace[f];
      seed[r] = std::uint32_t(f);
    }
  }
  return seed;
}

/// Geometry partitioning: grows every region from its seed through a priority queue of (error,
/// face, region), a face going to the first region that pops it. Regions stay connected.
inline std::vector<std::uint32_t> flood(const TriangleMesh& mesh, const FaceGraph& g, VsaMetric metric,
                                        const std::vector<std::uint32_t>& seeds,
                                        const std::vector<Proxy>& proxies) {
  // Ordered by error, then face, then region (one 64-bit key for the two ids: fewer branches).
  struct Candidate {
    double error;
    std::uint64_t faceRegion;
    std::uint32_t face() const { return std::uint32_t(faceRegion >> 32); }
    std::uint32_t region() const { return std::uint32_t(faceRegion); }
    bool operator>(const Candidate& o) const { return error != o.error ? error > o.error : faceRegion > o.faceRegion; }
  };
  std::vector<Candidate> storage;
  storage.reserve(2 * g.faceCount());
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>> queue(std::greater<>(), std::move(storage));
  std::vector<std::uint32_t> region(g.faceCount(), kInvalidId);
  // The last region that queued each face: a face beside two faces of one region is queued once
  // for it (the second entry would be the same candidate; the partition does not change).
  std::vector<std::uint32_t> queuedFor(g.faceCount(), kInvalidId);
  auto pushNeighbours = [&](std::uint32_t f, std::uint32_t r) {
    for (std::uint32_t i = g.neighbourStart[f]; i < g.neighbourStart[f + 1]; ++i) {
      const std::uint32_t n = g.neighbours[i];
      if (region[n] != kInvalidId || queuedFor[n] == r) continue;
      queuedFor[n] = r;
      queue.push({faceError(mesh, g, metric, n, proxies[r]), std::uint64_t(n) << 32 | r});
    }
  };
  for (std::uint32_t r = 0; r < seeds.size(); ++r) region[seeds[r]] = r;
  for (std::uint32_t r = 0; r < seeds.size(); ++r) pushNeighbours(seeds[r], r);
  while (!queue.empty()) {
    const Candidate c = queue.top();
    queue.pop();
    if (region[c.face()] != kInvalidId) continue;
    region[c.face()] = c.region();
    pushNeighbours(c.face(), c.region());
  }
  return region;
}

/// Multi-source geodesic distance (Dijkstra over face centroids) from the given faces, lowered in
/// place: adding a seed relaxes only the faces it comes closer to.
inline void lowerDistances(const FaceGraph& g, std::uint32_t source, std::vector<double>& distance) {
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  distance[source] = 0;
  queue.push({0.0, source});
  while (!queue.empty()) {
    const auto [d, f] = queue.top();
    queue.pop();
    if (d > distance[f]) continue;
    for (std::uint32_t i = g.neighbourStart[f]; i < g.neighbourStart[f + 1]; ++i) {
      const std::uint32_t n = g.neighbours[i];
      const double nd = d + glm::length(g.centroid[n] - g.centroid[f]);
      if (nd < distance[n]) {
        distance[n] = nd;
        queue.push({nd, n});
      }
    }
  }
}

/// The index of the largest value, the first on ties (infinity counts: an unseeded component).
inline std::uint32_t argMax(const std::vector<double>& values) {
  return std::uint32_t(std::max_element(values.begin(), values.end()) - values.begin());
}

/// The partition as the Lloyd iterations carry it from step to step.
struct LloydState {
  std::vector<std::uint32_t> regionOfFace;
  std::vector<Proxy> proxies;
  std::vector<double> errorOfFace;  ///< against the face's own region's proxy
  double error = 0;
};

inline void evaluate(const TriangleMesh& mesh, const FaceGraph& g, VsaMetric metric, LloydState& s) {
  s.errorOfFace.resize(g.faceCount());
  parallelFor(0, g.faceCount(), [&](std::size_t f) {
    s.errorOfFace[f] = faceError(mesh, g, metric, f, s.proxies[s.regionOfFace[f]]);
  });
  s.error = 0;
  for (const double e : s.errorOfFace) s.error += e;
}

/// Each region's error (the sum over its faces) and its worst face, where a new proxy splits it.
/// On ties the last such face, so that a region of equal errors (a proxy midway between two
/// planes) still splits away from its seed, which is the first face of least error.
struct RegionErrors {
  std::vector<double> error;
  std::vector<std::uint32_t> worstFace;
};
inline RegionErrors regionErrors(const FaceGraph& g, const LloydState& s) {
  RegionErrors e{std::vector<double>(s.proxies.size(), 0), std::vector<std::uint32_t>(s.proxies.size(), kInvalidId)};
  for (std::uint32_t f = 0; f < g.faceCount(); ++f) {
    const std::uint32_t r = s.regionOfFace[f];
    e.error[r] += s.errorOfFace[f];
    if (e.worstFace[r] == kInvalidId || s.errorOfFace[f] >= s.errorOfFace[e.worstFace[r]]) e.worstFace[r] = f;
  }
  return e;
}

/// One Lloyd iteration: flood from the current regions' best faces, then refit and re-evaluate.
inline void lloydIteration(const TriangleMesh& mesh, const FaceGraph& g, VsaMetric metric, LloydState& s) {
  const auto seeds = regionSeeds(s.errorOfFace, s.regionOfFace, s.proxies.size());
  s.regionOfFace = flood(mesh, g, metric, seeds, s.proxies);
  fitProxies(mesh, g, metric, s.regionOfFace, s.proxies);
  evaluate(mesh, g, metric, s);
}

/// Starts from the given seed faces: each seed's proxy is its face's plane, then one flood.
inline LloydState startFromSeeds(const TriangleMesh& mesh, const FaceGraph& g, VsaMetric metric,
                                 const std::vector<std::uint32_t>& seeds) {
  LloydState s;
  s.proxies.resize(seeds.size());
  for (std::size_t r = 0; r < seeds.size(); ++r)
    s.proxies[r] = {g.centroid[seeds[r]],
                    g.area[seeds[r]] > 0 ? g.normal[seeds[r]] : Vec3d(0, 0, 1)};
  s.regionOfFace = flood(mesh, g, metric, seeds, s.proxies);
  fitProxies(mesh, g, metric, s.regionOfFace, s.proxies);
  evaluate(mesh, g, metric, s);
  return s;
}

/// One seed per component (its first face), then the face farthest from all seeds, until k.
inline std::vector<std::uint32_t> farthestPointSeeds(const FaceGraph& g, std::size_t k) {
  std::vector<double> distance(g.faceCount(), std::numeric_limits<double>::infinity());
  std::vector<std::uint32_t> seeds;
  while (seeds.size() < k) {
    const std::uint32_t next = argMax(distance);
    if (distance[next] == 0) break;  // every face is a seed
    seeds.push_back(next);
    lowerDistances(g, next, distance);
  }
  return seeds;
}

/// Hierarchical seeding: one proxy per component, then rounds that add up to half as many proxies
/// again, each in the region of largest remaining error (at its worst face), with a few Lloyd
/// iterations after each round.
inline LloydState hierarchicalSeeds(const TriangleMesh& mesh, const FaceGraph& g, VsaMetric metric,
                                    std::size_t k, const std::function<void(double)>& progress) {
  // Component ids are numbered in order of their first face.
  std::vector<std::uint32_t> seeds;
  for (std::uint32_t f = 0; f < g.faceCount(); ++f)
    if (g.componentOfFace[f] == seeds.size()) seeds.push_back(f);
  LloydState s = startFromSeeds(mesh, g, metric, seeds);
  constexpr int kRelaxationsPerRound = 3;
  while (s.proxies.size() < k) {
    const std::size_t add = std::min(k - s.proxies.size(), std::max<std::size_t>(1, s.proxies.size() / 2));
    RegionErrors errors = regionErrors(g, s);
    std::vector<double>& regionError = errors.error;
    const std::vector<std::uint32_t>& worst = errors.worstFace;
    auto nextSeeds = regionSeeds(s.errorOfFace, s.regionOfFace, s.proxies.size());
    std::size_t added = 0;
    for (std::size_t attempt = 0; attempt < regionError.size() && added < add; ++attempt) {
      const std::uint32_t r = argMax(regionError);
      if (regionError[r] <= 0) break;  // every region is exact: more proxies buy nothing
      regionError[r] = 0;              // one new proxy per region per round
      if (worst[r] == nextSeeds[r]) continue;  // its error sits at its seed: nothing to split
      nextSeeds.push_back(worst[r]);
      s.proxies.push_back({g.centroid[worst[r]], g.area[worst[r]] > 0 ? g.normal[worst[r]] : Vec3d(0, 0, 1)});
      ++added;
    }
    if (added == 0) break;
    s.regionOfFace = flood(mesh, g, metric, nextSeeds, s.proxies);
    fitProxies(mesh, g, metric, s.regionOfFace, s.proxies);
    evaluate(mesh, g, metric, s);
    for (int i = 0; i < kRelaxationsPerRound; ++i) lloydIteration(mesh, g, metric, s);
    if (progress) progress(0.5 * double(s.proxies.size()) / double(k));
  }
  return s;
}

/// Pairs of regions that share an edge, each once (lower id first).
inline std::vector<std::pair<std::uint32_t, std::uint32_t>> neighbouringRegions(const FaceGraph& g,
                                                                                const std::vector<std::uint32_t>& regionOfFace) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::uint32_t f = 0; f < g.faceCount(); ++f)
    for (std::uint32_t i = g.neighbourStart[f]; i < g.neighbourStart[f + 1]; ++i) {
      const std::uint32_t a = regionOfFace[f], b = regionOfFace[g.neighbours[i]];
      if (a < b) pairs.emplace_back(a, b);
    }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

/// Region teleports (the paper's section 3.3), up to `count` at once: the cheapest merges of two
/// neighbouring regions (the merged region's fitted error less the two regions' own), each freeing
/// a proxy that starts again at the worst face of one of the regions of largest error, the worst
/// first; a merge is made only where it costs less than half that region's error (the paper's
/// test), and no region takes part twice. Then one flood, fit and evaluation. Returns how many
/// were made (0: s unchanged).
inline int teleport(const TriangleMesh& mesh, const FaceGraph& g, VsaMetric metric, LloydState& s, int count) {
  const std::size_t k = s.proxies.size();
  const std::vector<RegionMoments> moments = regionMoments(mesh, g, metric, s.regionOfFace, k);
  const RegionErrors errors = regionErrors(g, s);
  const std::vector<double>& regionError = errors.error;  // a reference, not a binding: lambdas capture it
  const std::vector<std::uint32_t>& worstFace = errors.worstFace;
  std::vector<std::uint32_t> seeds = regionSeeds(s.errorOfFace, s.regionOfFace, k);
  // A region whose worst face is where its own flooding starts has nothing to split, and regions
  // already exact (to rounding) gain nothing from a proxy more.
  const double negligible = 1e-12 * s.error;
  std::vector<std::uint32_t> worst;
  for (std::uint32_t r = 0; r < k; ++r)
    if (regionError[r] > negligible && worstFace[r] != kInvalidId && worstFace[r] != seeds[r]) worst.push_back(r);
  std::sort(worst.begin(), worst.end(), [&](std::uint32_t a, std::uint32_t b) {
    return regionError[a] != regionError[b] ? regionError[a] > regionError[b] : a < b;
  });
  if (worst.size() > std::size_t(count)) worst.resize(std::size_t(count));
  std::vector<char> busy(k, 0);
  for (const std::uint32_t r : worst) busy[r] = 1;
  struct Merge {
    double cost;
    std::uint32_t kept, freed;
    Fit fit;
  };
  std::vector<double> fittedError(k);  // each region's own, as the merges' costs subtract it
  for (std::uint32_t r = 0; r < k; ++r) fittedError[r] = fitRegion(moments[r], metric, s.proxies[r]).error;
  std::vector<Merge> merges;
  for (const auto& [a, b] : neighbouringRegions(g, s.regionOfFace)) {
    if (busy[a] || busy[b]) continue;
    RegionMoments both = moments[a];
    both += moments[b];
    const Fit fit = fitRegion(both, metric, s.proxies[a]);
    // Never below 0 (a merge cannot lower the error; rounding in the difference can).
    merges.push_back({std::max(0.0, fit.error - fittedError[a] - fittedError[b]), a, b, fit});
  }
  std::sort(merges.begin(), merges.end(), [](const Merge& x, const Merge& y) {
    return x.cost != y.cost ? x.cost < y.cost : std::pair(x.kept, x.freed) < std::pair(y.kept, y.freed);
  });
  int made = 0;
  std::vector<std::uint32_t> freedFor(k, kInvalidId);  // region merged away -> the worst region it serves
  std::vector<std::uint32_t> mergedInto(k);            // each region's after the merges
  for (std::uint32_t r = 0; r < k; ++r) mergedInto[r] = r;
  auto next = merges.begin();
  for (const std::uint32_t target : worst) {
    while (next != merges.end() && (busy[next->kept] || busy[next->freed])) ++next;
    if (next == merges.end() || !(next->cost < 0.5 * regionError[target])) break;
    busy[next->kept] = busy[next->freed] = 1;
    s.proxies[next->kept] = next->fit.proxy;
    const std::uint32_t f = worstFace[target];
    s.proxies[next->freed] = {g.centroid[f], g.area[f] > 0 ? g.normal[f] : Vec3d(0, 0, 1)};
    freedFor[next->freed] = target;
    mergedInto[next->freed] = next->kept;
    ++made;
  }
  if (made == 0) return 0;
  for (std::uint32_t& r : s.regionOfFace) r = mergedInto[r];
  evaluate(mesh, g, metric, s);
  seeds = regionSeeds(s.errorOfFace, s.regionOfFace, k);
  for (std::uint32_t r = 0; r < k; ++r)
    if (freedFor[r] != kInvalidId) seeds[r] = worstFace[freedFor[r]];
  s.regionOfFace = flood(mesh, g, metric, seeds, s.proxies);
  fitProxies(mesh, g, metric, s.regionOfFace, s.proxies);
  evaluate(mesh, g, metric, s);
  return made;
}

}  // namespace detail

/// The metric's error of a partition made elsewhere (CGAL's, say), each region's proxy fitted to
/// it as a Lloyd iteration would: partitions from two implementations scored by one measure.
inline double partitionError(const TriangleMesh& mesh, const std::vector<std::uint32_t>& regionOfFace,
                             VsaMetric metric) {
  if (regionOfFace.size() != mesh.triangles.size())
    throw Error(ErrorKind::InvalidArgument, "partitionError: one region per triangle is needed");
  const FaceGraph g = buildFaceGraph(mesh);
  const std::uint32_t regions = regionOfFace.empty() ? 0 : *std::max_element(regionOfFace.begin(), regionOfFace.end()) + 1;
  detail::LloydState s;
  s.regionOfFace = regionOfFace;
  s.proxies.resize(regions);
  detail::fitProxies(mesh, g, metric, s.regionOfFace, s.proxies);
  detail::evaluate(mesh, g, metric, s);
  return s.error;
}

/// Partitions the mesh into options.proxies regions (at least one per connected component).
/// Throws Error(InvalidInput) for a mesh without triangles or of zero area.
inline VsaPartition partitionVsa(const TriangleMesh& mesh, const VsaOptions& options = {}) {
  mesh.validate();
  if (mesh.triangles.empty()) throw Error(ErrorKind::InvalidInput, "VSA", "the mesh has no triangles");
  if (options.proxies < 1) throw Error(ErrorKind::InvalidInput, "VSA", "the proxy count must be at least 1");
  const FaceGraph g = buildFaceGraph(mesh);
  double total = 0;
  for (const double a : g.area) total += a;
  if (!(total > 0)) throw Error(ErrorKind::InvalidInput, "VSA", "every triangle has zero area");
  const std::size_t k = std::min(std::max<std::size_t>(std::size_t(options.proxies), std::size_t(g.components)),
                                 g.faceCount());
  detail::LloydState s =
      options.seeding == VsaSeeding::FarthestPoint
          ? detail::startFromSeeds(mesh, g, options.metric, detail::farthestPointSeeds(g, k))
          : detail::hierarchicalSeeds(mesh, g, options.metric, k, options.progress);
  VsaPartition result;
  result.requestedProxies = options.proxies;
  result.components = g.components;
  result.errorPerIteration.push_back(s.error);
  // Flooding is a heuristic step: an iteration may raise the error and a later one lower it below
  // where it was, so the iterations go on through a rise (as CGAL's do) and the best partition
  // seen is kept; they stop when one changes the error by less than the tolerance.
  // Teleports, when asked for, start where the iterations have settled: they changed the error by
  // less than the tolerance, or have not lowered the best for a few iterations (they may cycle).
  // A batch moves a tenth of the proxies at once (on the bunny at 200 proxies CGAL's error is
  // reached after 22 iterations, against 55 one at a time: measured), and the iterations go on
  // from the best partition with them moved. A batch after which the best has not improved by the
  // time they settle again halves the next; once a single teleport fails, they stop.
  constexpr int kSettledAfter = 10;
  constexpr double kStill = 1e-4;  // a change this small (relative) has settled, whatever the tolerance
  int batch = options.teleports > 0 ? int(std::max<std::size_t>(1, k / 10)) : 0;
  int teleportsLeft = std::max(0, options.teleports), sinceBest = 0;
  double bestBeforeTeleport = std::numeric_limits<double>::infinity();
  detail::LloydState current = s;
  for (int i = 0; i < options.maxIterations && !(s.error <= options.targetError); ++i) {
    const double before = current.error;
    detail::lloydIteration(mesh, g, options.metric, current);
    sinceBest = current.error < s.error ? 0 : sinceBest + 1;
    if (current.error < s.error) s = current;
    result.errorPerIteration.push_back(s.error);
    if (options.progress) options.progress(0.5 + 0.5 * double(i + 1) / double(options.maxIterations));
    const double change = std::abs(before - current.error);
    const bool settled = change <= options.tolerance * before;
    if (!settled && change > kStill * before && sinceBest < kSettledAfter) continue;
    if (!(s.error < bestBeforeTeleport)) batch /= 2;  // the last batch did not pay
    int made = 0;
    detail::LloydState moved;
    if (batch > 0 && teleportsLeft > 0) {
      moved = s;  // teleports start from the best partition
      made = detail::teleport(mesh, g, options.metric, moved, std::min(teleportsLeft, batch));
    }
    if (made == 0) {
      if (settled) break;
      batch = 0;
      continue;
    }
    current = std::move(moved);
    bestBeforeTeleport = s.error;
    teleportsLeft -= made;
    result.teleports += made;
    sinceBest = 0;
    if (current.error < s.error) {
      s = current;
      result.errorPerIteration.back() = s.error;  // the best after this iteration and its teleports
    }
  }
  result.regionOfFace = std::move(s.regionOfFace);
  result.proxies = std::move(s.proxies);
  result.regionError.assign(result.proxies.size(), 0);
  for (std::size_t f = 0; f < g.faceCount(); ++f) result.regionError[result.regionOfFace[f]] += s.errorOfFace[f];
  result.error = s.error;
  return result;
}

}  // namespace cellrelief::geotex
