// SPDX-License-Identifier: MIT
/// @file closed_lattice.h
/// The closed reconstruction's lattice (closed_reconstruction.h): the field's value at every
/// lattice point of the polygonized cells, and the removal of the handles a single lattice point
/// makes.
///
/// Why handles are removed: a part of the input thinner than a lattice spacing, or two sheets
/// closer than one, is sampled as a porous sheet or a bridge, and every pore or bridge is a handle
/// the input does not have (the knight's flange, docs/relief.md). Where one lattice point is all
/// that opens a pore or holds a bridge (its link on the other side is one circle, KuhnLink), moving
/// it to the other side removes exactly that handle and nothing else; it moves the surface by less
/// than a spacing. At that size the lattice cannot tell a real handle from one that sampling made,
/// so every such handle goes. Larger handles are left: they are the input's, or a misread no
/// single point explains.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <optional>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "cellrelief/core/lattice_topology.h"
#include "cellrelief/core/math.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/core/union_find.h"

namespace cellrelief::relief::detail {

/// Lattice values, one block of (cubes + 1)^3 per cell, x fastest; a point on a face shared by two
/// cells has a copy in each, with the same bits.
class LatticeBlocks {
 public:
  LatticeBlocks(std::vector<Vec3i> cells, int cubes, int gridSize)
      : mCells(std::move(cells)), mCubes(cubes), mGridSize(gridSize) {
    mBlockOf.reserve(mCells.size());
    for (std::size_t b = 0; b < mCells.size(); ++b)
      mBlockOf.emplace(pack(mCells[b]), std::uint32_t(b));
    mPointCount = mCells.size() * pointsPerBlock();
    allocateValues();
  }

  int cubes() const { return mCubes; }
  std::size_t blockCount() const { return mCells.size(); }
  const Vec3i& cell(std::size_t block) const { return mCells[block]; }
  std::size_t pointsPerBlock() const {
    return std::size_t(mCubes + 1) * std::size_t(mCubes + 1) * std::size_t(mCubes + 1);
  }
  std::size_t pointCount() const { return mPointCount; }
  /// The offset of a local point (0..cubes() per axis) within its block.
  std::size_t offset(const Vec3i& local) const {
    const std::size_t s = std::size_t(mCubes + 1);
    return (std::size_t(local.z) * s + std::size_t(local.y)) * s + std::size_t(local.x);
  }
  /// The index of a block's local point among all the lattice's values.
  std::size_t index(std::size_t block, const Vec3i& local) const {
    return block * pointsPerBlock() + offset(local);
  }
  float* block(std::size_t b) { return mValues.get() + b * pointsPerBlock(); }
  const float* block(std::size_t b) const { return mValues.get() + b * pointsPerBlock(); }
  float value(std::size_t index) const { return mValues[index]; }

  /// The block of a cell of the grid, or nullopt when the cell is not polygonized.
  std::optional<std::size_t> blockOf(const Vec3i& cell) const {
    for (int a = 0; a < 3; ++a)
      if (cell[a] < 0 || cell[a] >= mGridSize) return std::nullopt;  // before packing: no aliasing
    const auto it = mBlockOf.find(pack(cell));
    if (it == mBlockOf.end()) return std::nullopt;
    return it->second;
  }
  /// Calls f(index) for every copy of a lattice point given in global lattice coordinates: per
  /// axis, the cell the point is the low end of and, on a cell face, the cell below.
  template <class F>
  void forEachCopy(const Vec3i& global, F&& f) const {
    int count[3] = {0, 0, 0}, cellOf[3][2], localOf[3][2];
    for (int a = 0; a < 3; ++a) {
      if (global[a] < 0) return;
      const int q = global[a] / mCubes, r = global[a] % mCubes;
      if (q < mGridSize) cellOf[a][count[a]] = q, localOf[a][count[a]++] = r;
      if (r == 0 && q > 0) cellOf[a][count[a]] = q - 1, localOf[a][count[a]++] = mCubes;
    }
    for (int i = 0; i < count[0]; ++i)
      for (int j = 0; j < count[1]; ++j)
        for (int k = 0; k < count[2]; ++k)
          if (const auto b = blockOf(Vec3i(cellOf[0][i], cellOf[1][j], cellOf[2][k])))
            f(index(*b, Vec3i(localOf[0][i], localOf[1][j], localOf[2][k])));
  }
  /// The index of one copy of a lattice point, or nullopt when no polygonized cell holds it: the
  /// copy in the cell the point is the low corner of when there is one, as for most points.
  std::optional<std::size_t> find(const Vec3i& global) const {
    const Vec3i cell = global / mCubes;
    if (glm::all(glm::greaterThanEqual(global, Vec3i(0))))
      if (const std::optional<std::size_t> b = blockOf(cell))
        return index(*b, global - cell * mCubes);
    std::optional<std::size_t> found;
    forEachCopy(global, [&](std::size_t i) {
      if (!found) found = i;
    });
    return found;
  }
  /// Records which blocks have all their points on one side; call after filling the values.
  /// Such a block holds no surface, and no handle point but on its faces.
  void findUniformBlocks() {
    mUniform.assign(mCells.size(), 0);
    parallelForRange(
        0, mCells.size(),
        [&](std::size_t begin, std::size_t end) {
          for (std::size_t b = begin; b < end; ++b) {
            const float* v = block(b);
            const bool inside = v[0] > 0;
            auto sameSide = [inside](float x) { return (x > 0) == inside; };
            mUniform[b] = std::all_of(v, v + pointsPerBlock(), sameSide) ? 1 : 0;
          }
        },
        1);
  }
  bool uniformBlocksFound() const { return !mUniform.empty(); }
  /// Whether every point of the block is on one side (findUniformBlocks).
  bool uniform(std::size_t b) const { return mUniform[b] != 0; }
  /// Sets every copy of a point; the blocks that hold one are no longer taken as uniform.
  void set(const Vec3i& global, float v) {
    forEachCopy(global, [&](std::size_t i) {
      mValues[i] = v;
      if (!mUniform.empty()) mUniform[i / pointsPerBlock()] = 0;
    });
  }

 private:
  /// Not zeroed (sampling writes every value, in parallel), and in huge pages where the system
  /// gives them on request: a lattice of 10^7 to 10^8 points otherwise spends a tenth of the
  /// reconstruction's time in page faults (measured: 2.32 s -> 2.16 s on 3holes).
  void allocateValues() {
    constexpr std::size_t kHugePage = std::size_t(2) << 20;
    const std::size_t bytes = (mPointCount * sizeof(float) + kHugePage - 1) / kHugePage * kHugePage;
    mValues.reset(static_cast<float*>(std::aligned_alloc(kHugePage, std::max(bytes, kHugePage))));
    if (!mValues) throw std::bad_alloc();
#if defined(__linux__)
    madvise(mValues.get(), bytes, MADV_HUGEPAGE);  // a hint: without it, ordinary pages
#endif
  }
  static std::uint32_t pack(const Vec3i& c) {
    return std::uint32_t(c.x) | (std::uint32_t(c.y) << 10) | (std::uint32_t(c.z) << 20);
  }

  std::vector<Vec3i> mCells;
  int mCubes = 1, mGridSize = 0;
  std::unordered_map<std::uint32_t, std::uint32_t> mBlockOf;
  std::size_t mPointCount = 0;
  struct Free {
    void operator()(float* p) const { std::free(p); }
  };
  std::unique_ptr<float[], Free> mValues;
  std::vector<char> mUniform;
};

/// A key for a lattice point in global coordinates (below 2^21 a side).
inline std::uint64_t latticePointKey(const Vec3i& g) {
  return std::uint64_t(std::uint32_t(g.x)) | (std::uint64_t(std::uint32_t(g.y)) << 21) |
         (std::uint64_t(std::uint32_t(g.z)) << 42);
}

/// Above this many lattice points (copies counted) the handles are left as they are: finding the
/// sides' components costs a byte a point and 8 bytes a point of the blocks with both sides in
/// them (up to 2.3 GiB here).
inline constexpr std::size_t kMaxHandleRemovalPoints = std::size_t(1) << 28;

/// A lattice point whose move to the other side would cone off a circle of its link.
struct HandlePoint {
  Vec3i global{0};
  float magnitude = 0;  ///< |field|: the points the field is least sure of are moved first
};

/// The inside neighbours of a lattice point (KuhnLink's order), or nullopt when one of them lies
/// in no polygonized cell.
inline std::optional<KuhnLink::Mask> insideNeighbours(const LatticeBlocks& blocks,
                                                      const Vec3i& global) {
  KuhnLink::Mask mask = 0;
  for (int v = 0; v < KuhnLink::kSize; ++v) {
    const std::optional<std::size_t> i = blocks.find(global + KuhnLink::offsets()[std::size_t(v)]);
    if (!i) return std::nullopt;
    if (blocks.value(*i) > 0) mask |= KuhnLink::Mask(1u << v);
  }
  return mask;
}

/// The link part of the side a point would join.
inline KuhnLink::Mask joinedSide(KuhnLink::Mask insideMask, bool pointInside) {
  return pointInside ? KuhnLink::Mask(KuhnLink::kAll & ~insideMask) : insideMask;
}

/// Every lattice point whose move would cone off a circle, least sure first. Points on the grid's
/// boundary stay outside (the surface closes there) and are not listed.
inline std::vector<HandlePoint> findHandlePoints(const LatticeBlocks& blocks, int gridSize) {
  const int m = blocks.cubes(), last = gridSize * m, side = m + 1;
  std::array<std::ptrdiff_t, KuhnLink::kSize> step;  // a neighbour's offset within a block
  for (int v = 0; v < KuhnLink::kSize; ++v) {
    const Vec3i& d = KuhnLink::offsets()[std::size_t(v)];
    step[std::size_t(v)] = (std::ptrdiff_t(d.z) * side + d.y) * side + d.x;
  }
  std::array<std::size_t, 8> cornerStep;
  for (int k = 0; k < 8; ++k) cornerStep[std::size_t(k)] = blocks.offset(cubeCorner(k));
  // Only a point with a neighbour on the other side can be a handle point, and the edge to that
  // neighbour lies in a cube of a block that holds both: only the corners of cubes with both
  // sides in them need the full test, and blocks all on one side none.
  auto markCornersOfMixedCubes = [&](const float* values, std::vector<char>& marked) {
    marked.assign(blocks.pointsPerBlock(), 0);
    for (int z = 0; z < m; ++z)
      for (int y = 0; y < m; ++y)
        for (int x = 0; x < m; ++x) {
          const std::size_t first = blocks.offset(Vec3i(x, y, z));
          int inside = 0;
          for (int k = 0; k < 8; ++k) inside += values[first + cornerStep[std::size_t(k)]] > 0;
          if (inside == 0 || inside == 8) continue;
          for (int k = 0; k < 8; ++k) marked[first + cornerStep[std::size_t(k)]] = 1;
        }
  };
  auto interior = [m](int c) { return c > 0 && c < m; };
  auto insideInBlock = [&](const float* at) {
    KuhnLink::Mask mask = 0;
    for (int v = 0; v < KuhnLink::kSize; ++v)
      if (at[step[std::size_t(v)]] > 0) mask |= KuhnLink::Mask(1u << v);
    return std::optional<KuhnLink::Mask>(mask);
  };
  std::vector<std::vector<HandlePoint>> perBlock(blocks.blockCount());
  parallelForRange(
      0, blocks.blockCount(),
      [&](std::size_t begin, std::size_t end) {
        std::vector<char> marked;
        for (std::size_t b = begin; b < end; ++b) {
          if (blocks.uniform(b)) continue;
          const float* values = blocks.block(b);
          markCornersOfMixedCubes(values, marked);
          const Vec3i base = blocks.cell(b) * m;
          for (int z = 0; z <= m; ++z)
            for (int y = 0; y <= m; ++y)
              for (int x = 0; x <= m; ++x) {
                if (!marked[blocks.offset(Vec3i(x, y, z))]) continue;
                const Vec3i global = base + Vec3i(x, y, z);
                if (glm::any(glm::equal(global, Vec3i(0))) ||
                    glm::any(glm::equal(global, Vec3i(last))))
                  continue;
                const float v = values[blocks.offset(Vec3i(x, y, z))];
                const std::optional<KuhnLink::Mask> inside =
                    interior(x) && interior(y) && interior(z)
                        ? insideInBlock(values + blocks.offset(Vec3i(x, y, z)))
                        : insideNeighbours(blocks, global);
                if (!inside) continue;
                const KuhnLink::Mask joined = joinedSide(*inside, v > 0);
                if (joined == 0 || !KuhnLink::isCircle(joined)) continue;
                perBlock[b].push_back({global, std::abs(v)});
              }
        }
      },
      1);  // a block is thousands of points: TBB splits down to one
  std::vector<HandlePoint> points;
  for (const auto& list : perBlock) points.insert(points.end(), list.begin(), list.end());
  auto key = [](const HandlePoint& p) {
    return std::make_tuple(p.magnitude, p.global.z, p.global.y, p.global.x);
  };
  std::sort(points.begin(), points.end(),
            [&](const HandlePoint& a, const HandlePoint& b) { return key(a) < key(b); });
  points.erase(
      std::unique(points.begin(), points.end(),
                  [](const HandlePoint& a, const HandlePoint& b) { return a.global == b.global; }),
      points.end());
  return points;
}

/// The connected parts of each side, handle points left out (their side may change): a set of
/// same-side lattice points joined by the triangulation's edges, every copy of a point in one set.
/// A block all on one side is one node (it stays connected without any one of its points).
class SideComponents {
 public:
  SideComponents(const LatticeBlocks& blocks, const std::vector<HandlePoint>& handlePoints)
      : mBlocks(blocks),
        mFirstNode(blocks.blockCount() + 1, 0),
        mLeftOut(blocks.pointCount(), 0),
        mSets(countNodes()) {
    for (const HandlePoint& p : handlePoints)
      blocks.forEachCopy(p.global, [&](std::size_t i) { mLeftOut[i] = 1; });
    joinWithinBlocks();
    joinCopies();
  }
  std::uint32_t component(std::size_t index) { return mSets.find(node(index)); }

 private:
  std::size_t countNodes() {
    for (std::size_t b = 0; b < mBlocks.blockCount(); ++b)
      mFirstNode[b + 1] = mFirstNode[b] + (mBlocks.uniform(b) ? 1 : mBlocks.pointsPerBlock());
    return mFirstNode.back();
  }
  std::uint32_t node(std::size_t index) const {
    const std::size_t b = index / mBlocks.pointsPerBlock();
    return std::uint32_t(mFirstNode[b] +
                         (mBlocks.uniform(b) ? 0 : index - b * mBlocks.pointsPerBlock()));
  }
  /// Along the 7 edge directions with no negative component: every edge of the triangulation lies
  /// in a cube, and every cube in a block.
  void joinWithinBlocks() {
    const int m = mBlocks.cubes();
    std::vector<Vec3i> forward;
    for (const Vec3i& d : KuhnLink::offsets())
      if (d.x >= 0 && d.y >= 0 && d.z >= 0) forward.push_back(d);
    for (std::size_t b = 0; b < mBlocks.blockCount(); ++b) {
      if (mBlocks.uniform(b)) continue;
      for (int z = 0; z <= m; ++z)
        for (int y = 0; y <= m; ++y)
          for (int x = 0; x <= m; ++x) {
            const std::size_t i = mBlocks.index(b, Vec3i(x, y, z));
            if (mLeftOut[i]) continue;
            const bool inside = mBlocks.value(i) > 0;
            for (const Vec3i& d : forward) {
              const Vec3i q = Vec3i(x, y, z) + d;
              if (q.x > m || q.y > m || q.z > m) continue;
              const std::size_t j = mBlocks.index(b, q);
              if (!mLeftOut[j] && (mBlocks.value(j) > 0) == inside) mSets.unite(node(i), node(j));
            }
          }
    }
  }
  /// A point on a block's low face is also the neighbouring block's high-face point.
  void joinCopies() {
    const int m = mBlocks.cubes();
    for (std::size_t b = 0; b < mBlocks.blockCount(); ++b)
      for (int a = 0; a < 3; ++a) {
        Vec3i below = mBlocks.cell(b);
        below[a] -= 1;
        const std::optional<std::size_t> other = mBlocks.blockOf(below);
        if (!other || (mBlocks.uniform(b) && mBlocks.uniform(*other) && find(b) == find(*other)))
          continue;
        for (int v = 0; v <= m; ++v)
          for (int u = 0; u <= m; ++u) {
            Vec3i local(0);
            local[(a + 1) % 3] = u;
            local[(a + 2) % 3] = v;
            Vec3i mirrored = local;
            mirrored[a] = m;
            const std::size_t i = mBlocks.index(b, local);
            if (!mLeftOut[i]) mSets.unite(node(i), node(mBlocks.index(*other, mirrored)));
          }
      }
  }
  std::uint32_t find(std::size_t block) { return mSets.find(std::uint32_t(mFirstNode[block])); }

  const LatticeBlocks& mBlocks;
  std::vector<std::size_t> mFirstNode;
  std::vector<char> mLeftOut;  ///< per lattice point copy
  UnionFind mSets;
};

/// Whether the two discs of a point's link on its own side (labels 0 and 1) are joined without
/// the point: a search over the handle points now on that side and the side's components, which
/// handle points join where they neighbour a member.
class SideConnection {
 public:
  SideConnection(const LatticeBlocks& blocks, const std::vector<HandlePoint>& handlePoints,
                 SideComponents& sides)
      : mBlocks(blocks),
        mPoints(handlePoints),
        mSides(sides),
        mHandleNeighbours(handlePoints.size()),
        mComponentNeighbours(handlePoints.size()),
        mVisited(handlePoints.size(), 0) {
    for (std::size_t h = 0; h < mPoints.size(); ++h)
      mHandleIndex.emplace(key(mPoints[h].global), h);
    for (std::size_t h = 0; h < mPoints.size(); ++h)
      for (const Vec3i& d : KuhnLink::offsets()) {
        const Vec3i q = mPoints[h].global + d;
        if (const auto it = mHandleIndex.find(key(q)); it != mHandleIndex.end()) {
          mHandleNeighbours[h].push_back(it->second);
        } else {
          const std::size_t i = *mBlocks.find(q);  // handle points have all their neighbours
          const std::uint32_t c = sides.component(i);
          mComponentInside.emplace(c, mBlocks.value(i) > 0);
          mComponentNeighbours[h].push_back(c);
          mHandlesOf[c].push_back(h);
        }
      }
  }

  bool joined(std::size_t handle, const std::array<std::int8_t, KuhnLink::kSize>& label) {
    const Vec3i point = mPoints[handle].global;
    const bool side = inside(point);
    std::unordered_set<std::uint32_t> components;
    std::vector<std::size_t> stack, touched{handle};
    mVisited[handle] = 1;
    auto visitHandle = [&](std::size_t h) {
      if (mVisited[h] || inside(mPoints[h].global) != side) return;
      mVisited[h] = 1;
      touched.push_back(h);
      stack.push_back(h);
    };
    auto visitComponent = [&](std::uint32_t c) {
      if (mComponentInside.at(c) != side || !components.insert(c).second) return;
      for (std::size_t h : mHandlesOf[c]) visitHandle(h);
    };
    auto visitLinkVertex = [&](int v) {
      const Vec3i q = point + KuhnLink::offsets()[std::size_t(v)];
      if (const auto it = mHandleIndex.find(key(q)); it != mHandleIndex.end())
        visitHandle(it->second);
      else
        visitComponent(mSides.component(*mBlocks.find(q)));
    };
    for (int v = 0; v < KuhnLink::kSize; ++v)
      if (label[std::size_t(v)] == 0) visitLinkVertex(v);
    while (!stack.empty()) {
      const std::size_t h = stack.back();
      stack.pop_back();
      for (std::size_t n : mHandleNeighbours[h]) visitHandle(n);
      for (std::uint32_t c : mComponentNeighbours[h]) visitComponent(c);
    }
    bool reached = false;
    for (int v = 0; v < KuhnLink::kSize && !reached; ++v) {
      if (label[std::size_t(v)] != 1) continue;
      const Vec3i q = point + KuhnLink::offsets()[std::size_t(v)];
      if (const auto it = mHandleIndex.find(key(q)); it != mHandleIndex.end())
        reached = mVisited[it->second] && it->second != handle;
      else
        reached = components.count(mSides.component(*mBlocks.find(q))) > 0;
    }
    for (std::size_t h : touched) mVisited[h] = 0;
    return reached;
  }

 private:
  static std::uint64_t key(const Vec3i& g) { return latticePointKey(g); }
  bool inside(const Vec3i& g) const { return mBlocks.value(*mBlocks.find(g)) > 0; }

  const LatticeBlocks& mBlocks;
  const std::vector<HandlePoint>& mPoints;
  SideComponents& mSides;
  std::unordered_map<std::uint64_t, std::size_t> mHandleIndex;
  std::vector<std::vector<std::size_t>> mHandleNeighbours;
  std::vector<std::vector<std::uint32_t>> mComponentNeighbours;
  std::unordered_map<std::uint32_t, std::vector<std::size_t>> mHandlesOf;
  std::unordered_map<std::uint32_t, bool> mComponentInside;
  std::vector<char> mVisited;
};

/// Whether the link's disc `from` (label 0 or 1) reaches the other disc on the point's side
/// without the point, by a search over at most `budget` lattice points. Most handle points decide
/// here: a pore's two sides meet a few spacings away, a pocket's points run out.
enum class Reach { Joined, Apart, Unknown };
inline Reach searchSide(const LatticeBlocks& blocks, const Vec3i& point,
                        const std::array<std::int8_t, KuhnLink::kSize>& label, int from,
                        std::size_t budget) {
  const auto key = latticePointKey;
  const bool side = blocks.value(*blocks.find(point)) > 0;
  std::unordered_set<std::uint64_t> visited{key(point)}, targets;
  std::vector<Vec3i> queue;
  for (int v = 0; v < KuhnLink::kSize; ++v) {
    const Vec3i q = point + KuhnLink::offsets()[std::size_t(v)];
    if (label[std::size_t(v)] == from) {
      visited.insert(key(q));
      queue.push_back(q);
    } else if (label[std::size_t(v)] >= 0) {
      targets.insert(key(q));
    }
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    if (queue.size() > budget) return Reach::Unknown;
    for (const Vec3i& d : KuhnLink::offsets()) {
      const Vec3i q = queue[head] + d;
      if (visited.count(key(q))) continue;
      const std::optional<std::size_t> i = blocks.find(q);
      if (!i || (blocks.value(*i) > 0) != side) continue;
      if (targets.count(key(q))) return Reach::Joined;
      visited.insert(key(q));
      queue.push_back(q);
    }
  }
  return Reach::Apart;
}

/// Lattice points a local search visits before the sides' components are built instead.
inline constexpr std::size_t kSideSearchBudget = std::size_t(1) << 15;

/// Moves every lattice point that alone makes a handle to the other side (see the file comment),
/// least sure first, each checked again when its turn comes. Returns the number of handles removed.
inline int removeSinglePointHandles(LatticeBlocks& blocks, int gridSize, float spacing,
                                    std::size_t searchBudget = kSideSearchBudget) {
  if (blocks.pointCount() > kMaxHandleRemovalPoints) return 0;
  if (!blocks.uniformBlocksFound()) blocks.findUniformBlocks();
  const std::vector<HandlePoint> points = findHandlePoints(blocks, gridSize);
  if (points.empty()) return 0;
  // The sides' components, built only when a search runs out of budget.
  std::optional<SideComponents> sides;
  std::optional<SideConnection> connection;
  auto sidesJoined = [&](std::size_t h, const std::array<std::int8_t, KuhnLink::kSize>& label) {
    for (const int from : {0, 1}) {
      const Reach r = searchSide(blocks, points[h].global, label, from, searchBudget);
      if (r != Reach::Unknown) return r == Reach::Joined;
    }
    if (!connection) {
      sides.emplace(blocks, points);
      connection.emplace(blocks, points, *sides);
    }
    return connection->joined(h, label);
  };
  // A moved point keeps its distance to the zero crossing, and at least a thousandth of a
  // spacing, so the surface passes by it on the other side.
  const float least = 1e-3f * spacing;
  int removed = 0;
  for (std::size_t h = 0; h < points.size(); ++h) {
    const HandlePoint& p = points[h];
    const float v = blocks.value(*blocks.find(p.global));
    const bool pointInside = v > 0;
    const KuhnLink::Mask joined = joinedSide(*insideNeighbours(blocks, p.global), pointInside);
    if (!KuhnLink::isCircle(joined)) continue;  // an earlier move changed its link
    std::array<std::int8_t, KuhnLink::kSize> label;
    if (KuhnLink::components(KuhnLink::Mask(KuhnLink::kAll & ~joined), &label) != 2) continue;
    if (!sidesJoined(h, label)) continue;  // moving it would cut a piece off
    blocks.set(p.global, pointInside ? std::min(-v, -least) : std::max(-v, least));
    ++removed;
  }
  return removed;
}

}  // namespace cellrelief::relief::detail
