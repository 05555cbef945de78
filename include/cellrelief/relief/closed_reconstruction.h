// SPDX-License-Identifier: MIT
/// @file closed_reconstruction.h
/// A closed triangle mesh rebuilt from a relief model: the zero set of the model's inside/outside
/// field, sampled on a lattice that refines every cell into (T - 1)^3 cubes and polygonized by
/// marching tetrahedra (core/marching_tetrahedra.h).
///
/// Why a field and not the maps' samples joined face by face: neighbouring cells project with
/// different projections, so their boundary samples do not coincide and a per-face mesh leaves
/// slivers and gaps along every cell face. The field is the tracer's: a point is inside when it
/// lies beyond the surface on its projection line (past the stored distance), and a line with no
/// surface is on the side its domain face is on (outside, or the centre's side in interior
/// cells). Three rules make its zero set one closed surface:
/// - every lattice point has one value: a point shared by several grey cells (on their common
///   face, edge or corner) takes the mean of their fields, summed in a fixed order of the cells so
///   every cell computes the same bits;
/// - points of white and black cells take a constant of their color, and the white and black
///   cells around the grey ones are polygonized too, so a surface that reaches a cell face where
///   the neighbour's color disagrees closes in that neighbour's first layer of cubes;
/// - vertices are welded by lattice edge, never by position.
/// The result is then a closed, oriented 2-manifold by construction (a regular level set of a
/// piecewise-linear field); its genus is the field's, less the handles a single lattice point
/// makes, which are removed before polygonizing (closed_lattice.h): a part thinner than a lattice
/// spacing is sampled porous, and each pore is such a handle.
///
/// Accuracy: in parallel and planar cells the lattice points project onto the samples exactly; in
/// central ones the distance is filtered bilinearly. At the rim of a face's covered samples a
/// filter footprint that is at least half covered uses its filled samples (each sample owns half a
/// spacing around it), where the tracer's all-or-nothing footprint would lose a band of one sample.
///
/// Only for closed inputs: through the holes of an open mesh white space reaches both sides of the
/// surface, and the field would close the holes (reconstruct() chooses the per-face method there).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "cellrelief/core/aabb.h"
#include "cellrelief/core/error.h"
#include "cellrelief/core/marching_tetrahedra.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/core/triangle_mesh.h"
#include "cellrelief/core/union_find.h"
#include "cellrelief/relief/closed_lattice.h"
#include "cellrelief/relief/relief_model.h"

namespace cellrelief::relief {

namespace detail {

/// Which cells surround a cell: for each of the 27 offsets (-1..1)^3, a grey cell's index, or the
/// color of a white or black one.
struct CellNeighbourhood {
  static constexpr int kOutside = -1;  ///< white, or beyond the grid
  static constexpr int kInside = -2;   ///< black
  static constexpr int kUnknown = -3;  ///< not next to any grey cell (its color is never needed)
  Vec3i ijk{0};
  std::array<int, 27> cell{};
  static int slot(const Vec3i& d) { return (d.z + 1) * 9 + (d.y + 1) * 3 + (d.x + 1); }
  int at(const Vec3i& d) const { return cell[std::size_t(slot(d))]; }
};

/// The grey cells by coordinates, and the color of every white or black cell that touches one.
class CellColors {
 public:
  explicit CellColors(const ReliefModel& model) : mGridSize(model.gridSize) {
    mGrey.reserve(model.cells.size());
    for (std::size_t i = 0; i < model.cells.size(); ++i) mGrey.emplace(pack(model.cells[i].ijk()), int(i));
    classifyFaceNeighbours(model);
    propagateAcrossFaces();
  }

  bool inGrid(const Vec3i& p) const {
    return p.x >= 0 && p.y >= 0 && p.z >= 0 && p.x < mGridSize && p.y < mGridSize && p.z < mGridSize;
  }
  /// A grey cell's index, or one of CellNeighbourhood's colors.
  int classify(const Vec3i& p) const {
    if (!inGrid(p)) return CellNeighbourhood::kOutside;
    if (const auto it = mGrey.find(pack(p)); it != mGrey.end()) return it->second;
    if (const auto it = mColor.find(pack(p)); it != mColor.end()) return it->second;
    return CellNeighbourhood::kUnknown;
  }
  CellNeighbourhood neighbourhood(const Vec3i& ijk) const {
    CellNeighbourhood n;
    n.ijk = ijk;
    for (int z = -1; z <= 1; ++z)
      for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) n.cell[std::size_t(CellNeighbourhood::slot({x, y, z}))] = classify(ijk + Vec3i(x, y, z));
    return n;
  }
  /// The white and black cells of the grid that touch a grey cell (by a face, edge or corner).
  std::vector<Vec3i> shell() const {
    std::vector<Vec3i> cells;
    cells.reserve(mColor.size());
    for (const auto& [key, color] : mColor) cells.push_back(unpack(key));
    std::sort(cells.begin(), cells.end(), [](const Vec3i& a, const Vec3i& b) {
      return std::tie(a.z, a.y, a.x) < std::tie(b.z, b.y, b.x);
    });
    return cells;
  }

 private:
  static std::uint32_t pack(const Vec3i& p) { return CellRecord::packIjk(p); }
  static Vec3i unpack(std::uint32_t key) { return {int(key & 1023u), int((key >> 10) & 1023u), int((key >> 20) & 1023u)}; }

  /// A grey cell's configuration is the mask of its faces shared with white cells (or the grid's
  /// outside), so its face neighbours' colors are known; its edge and corner neighbours are
  /// recorded, color unknown yet.
  void classifyFaceNeighbours(const ReliefModel& model) {
    for (const CellRecord& r : model.cells)
      for (int z = -1; z <= 1; ++z)
        for (int y = -1; y <= 1; ++y)
          for (int x = -1; x <= 1; ++x) {
            const Vec3i d(x, y, z), p = r.ijk() + d;
            if (!inGrid(p) || mGrey.count(pack(p))) continue;
            int& color = mColor.try_emplace(pack(p), CellNeighbourhood::kUnknown).first->second;
            if (std::abs(x) + std::abs(y) + std::abs(z) != 1 || color != CellNeighbourhood::kUnknown) continue;
            const int axis = x != 0 ? 0 : y != 0 ? 1 : 2;
            const int face = cells::makeFace(axis, d[axis]);
            color = (r.configuration >> face) & 1u ? CellNeighbourhood::kOutside : CellNeighbourhood::kInside;
          }
  }
  /// White and black cells never share a face, so a cell of unknown color takes the color of a
  /// white or black face neighbour. Every edge or corner neighbour of a grey cell is reached in
  /// at most two such steps; any cell left (none in a consistent complex) is taken as white.
  void propagateAcrossFaces() {
    for (bool changed = true; changed;) {
      changed = false;
      for (auto& [key, color] : mColor) {
        if (color != CellNeighbourhood::kUnknown) continue;
        const Vec3i p = unpack(key);
        for (int f = 0; f < cells::kFaceCount && color == CellNeighbourhood::kUnknown; ++f) {
          const Vec3i q = p + cells::faceNormal(f);
          if (!inGrid(q)) continue;  // before packing: a coordinate of 1024 would alias another cell
          const auto it = mColor.find(pack(q));
          if (it != mColor.end() && it->second != CellNeighbourhood::kUnknown) {
            color = it->second;
            changed = true;
          }
        }
      }
    }
    for (auto& [key, color] : mColor)
      if (color == CellNeighbourhood::kUnknown) color = CellNeighbourhood::kOutside;
  }

  int mGridSize = 0;
  std::unordered_map<std::uint32_t, int> mGrey;
  std::unordered_map<std::uint32_t, int> mColor;
};

/// The signed field of one grey cell at lattice points, positive inside (the tracer's sign and
/// rule). Interior cells (case 0) read it as the tracer does, misreads included: a line whose face
/// point lies on the centre's side is taken to start on the other side, which makes the spurious
/// handles measured in docs/relief.md; conversion's choice of centre removes most of them.
class CellField {
 public:
  CellField(const ReliefModel& model, int step) : mModel(model), mCubes((model.texels - 1) / step) {}

  /// Cubes per cell side.
  int cubes() const { return mCubes; }
  int gridSize() const { return mModel.gridSize; }
  /// The value standing for "no surface on this line": one lattice spacing, in cell units.
  double emptyMagnitude() const { return 1.0 / mCubes; }

  /// The field of grey cell `index` at its local lattice point (each coordinate in 0..cubes()).
  double at(int index, const Vec3i& local) const {
    const CellRecord& r = mModel.cells[std::size_t(index)];
    const auto proj = r.projection<double>();
    const Vec3d p = Vec3d(local) / double(mCubes);
    const projection::FacePoint<double> fp = proj.project(p);
    const bool interior = r.configuration == 0;
    const double empty = interior && r.centreInside() ? emptyMagnitude() : -emptyMagnitude();
    const int layer = r.layerOf(fp.face);
    if (layer < 0) return empty;
    const std::optional<double> stored = storedDistance(layer, fp.uv);
    if (!stored) return empty;
    return interior && !r.centreInside() ? *stored - fp.distance : fp.distance - *stored;
  }

  /// Bilinearly filtered distance (cell units) at face coordinates uv over the filled samples of
  /// the footprint, or nullopt when less than half of the footprint's weight is filled.
  std::optional<double> storedDistance(int layer, const Vec2d& uv) const {
    const int last = mModel.texels - 1;
    const double x = std::clamp(uv.x, 0.0, 1.0) * last, y = std::clamp(uv.y, 0.0, 1.0) * last;
    const int a0 = std::min(last - 1, int(x)), b0 = std::min(last - 1, int(y));
    const double fx = x - a0, fy = y - b0;
    const double weight[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
    double sum = 0, filled = 0;
    for (int k = 0; k < 4; ++k) {
      if (weight[k] == 0) continue;
      const float d = mModel.distance(layer, a0 + (k & 1), b0 + (k >> 1));
      if (std::isnan(d)) continue;
      sum += weight[k] * double(d);
      filled += weight[k];
    }
    if (filled < 0.5) return std::nullopt;
    return sum / filled;
  }

  /// Catmull-Rom filtered distance over the 4 x 4 samples around uv, where all of them are filled
  /// and lie within kSmoothSpread sample spacings of each other (no depth jump between two sheets,
  /// where the cubic would overshoot); else the bilinear storedDistance(). Where the surface is
  /// smooth, a cubic filter's error is of higher order than the bilinear one's: vertices placed
  /// with it lie on the input's surface, not on an interpolation of it.
  std::optional<double> smoothDistance(int layer, const Vec2d& uv) const {
    const int last = mModel.texels - 1;
    const double x = std::clamp(uv.x, 0.0, 1.0) * last, y = std::clamp(uv.y, 0.0, 1.0) * last;
    const int a0 = std::min(last - 1, int(x)), b0 = std::min(last - 1, int(y));
    if (a0 < 1 || b0 < 1 || a0 + 2 > last || b0 + 2 > last) return storedDistance(layer, uv);
    auto weights = [](double t, double (&w)[4]) {
      const double t2 = t * t, t3 = t2 * t;
      w[0] = 0.5 * (-t3 + 2 * t2 - t);
      w[1] = 0.5 * (3 * t3 - 5 * t2 + 2);
      w[2] = 0.5 * (-3 * t3 + 4 * t2 + t);
      w[3] = 0.5 * (t3 - t2);
    };
    double wx[4], wy[4];
    weights(x - a0, wx);
    weights(y - b0, wy);
    double sum = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const float d = mModel.distance(layer, a0 - 1 + i, b0 - 1 + j);
        if (std::isnan(d)) return storedDistance(layer, uv);
        lo = std::min(lo, double(d));
        hi = std::max(hi, double(d));
        sum += wx[i] * wy[j] * double(d);
      }
    if (hi - lo > kSmoothSpread / last) return storedDistance(layer, uv);
    return sum;
  }
  static constexpr double kSmoothSpread = 3.0;

 private:
  const ReliefModel& mModel;
  int mCubes = 1;
};

/// The offsets (-1..1 per axis) of the cells whose closure holds a lattice point given in the
/// local coordinates of a cell `side` units wide: -1 where it lies on the low face, +1 on the high.
struct HoldingCells {
  Vec3i lo{0}, hi{0};
  HoldingCells(const Vec3i& point, int side) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = point[a] == 0 ? -1 : 0;
      hi[a] = point[a] == side ? 1 : 0;
    }
  }
};

/// The one value of a lattice point, given as a local point (0..cubes() per axis) of the cell at
/// the centre of `n`: the mean of the grey cells that contain it, in a fixed order of the cells
/// (so the bits do not depend on which cell asks); with no grey cell, the color of the others.
inline float latticeValue(const CellField& field, const CellNeighbourhood& n, const Vec3i& local) {
  const int m = field.cubes();
  const HoldingCells holding(local, m);
  double sum = 0;
  int count = 0, color = CellNeighbourhood::kUnknown;
  for (int z = holding.lo.z; z <= holding.hi.z; ++z)
    for (int y = holding.lo.y; y <= holding.hi.y; ++y)
      for (int x = holding.lo.x; x <= holding.hi.x; ++x) {
        const Vec3i d(x, y, z);
        const int c = n.at(d);
        if (c >= 0) {
          sum += field.at(c, local - d * m);
          ++count;
        } else if (color == CellNeighbourhood::kUnknown) {
          color = c;
        }
      }
  float value = count > 0 ? float(sum / count)
                          : float(color == CellNeighbourhood::kInside ? field.emptyMagnitude() : -field.emptyMagnitude());
  // Nothing beyond the grid is polygonized, so its boundary must read outside to close the
  // surface there. Its points lie on external domain faces (distance 0, outside), but the
  // projection's rounding can leave a positive 1e-17: the rule makes it exact.
  const Vec3i global = n.ijk * m + local;
  const int last = field.gridSize() * m;
  for (int a = 0; a < 3; ++a)
    if (global[a] == 0 || global[a] == last) value = std::min(value, 0.0f);
  return value;
}

/// Every polygonized cell's lattice values (latticeValue), in parallel.
inline void sampleLattice(const CellField& field, const CellColors& colors,
                          LatticeBlocks& lattice) {
  const int m = field.cubes();
  parallelForRange(0, lattice.blockCount(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b) {
      const CellNeighbourhood n = colors.neighbourhood(lattice.cell(b));
      float* values = lattice.block(b);
      for (int c = 0; c <= m; ++c)
        for (int y = 0; y <= m; ++y)
          for (int a = 0; a <= m; ++a)
            values[lattice.offset({a, y, c})] = latticeValue(field, n, {a, y, c});
    }
  }, 1);  // a block is thousands of points: TBB splits down to one
}

/// How far (lattice spacings) a vertex may move onto the stored surface: farther, the cell's
/// projection line meets another sheet than the one the field crossed.
inline constexpr double kMaxSnapSpacings = 1.5;

/// Triangles of one cell's cubes, with their vertices keyed by lattice edge.
struct ClosedPart {
  std::vector<std::uint64_t> keys;
  std::vector<Vec3f> positions;
  std::vector<Vec3f> normals;  ///< a zero vector where no map sample was found
  std::vector<Color8> colors;
  std::vector<char> hasSignal;
  std::vector<Vec3u> triangles;  ///< local indices
};

/// Shading signals of a vertex from the maps: the nearest filled sample (within two samples) of
/// the first grey cell, among those holding an end point of the vertex's lattice edge, whose map
/// has one there.
class SignalLookup {
 public:
  explicit SignalLookup(const ReliefModel& model) : mModel(model) {}
  bool wanted() const { return mModel.normalFormat != NormalFormat::None || mModel.colorFormat != ColorFormat::None; }

  /// `latticePoint` in lattice units relative to the centre cell of n; `ends` the edge's two end
  /// points (local lattice coordinates), inside end first.
  bool find(const CellField& field, const CellNeighbourhood& n, const Vec3d& latticePoint,
            const std::array<Vec3i, 2>& ends, Vec3f& normal, Color8& color) const {
    const int m = field.cubes();
    for (const Vec3i& end : ends) {
      const HoldingCells holding(end, m);
      for (int z = holding.lo.z; z <= holding.hi.z; ++z)
        for (int y = holding.lo.y; y <= holding.hi.y; ++y)
          for (int x = holding.lo.x; x <= holding.hi.x; ++x) {
            const Vec3i d(x, y, z);
            const int c = n.at(d);
            if (c < 0) continue;
            const Vec3d unit = glm::clamp(latticePoint / double(m) - Vec3d(d), Vec3d(0), Vec3d(1));
            if (sampleAt(mModel.cells[std::size_t(c)], unit, normal, color)) return true;
          }
    }
    return false;
  }

 private:
  bool sampleAt(const CellRecord& r, const Vec3d& unit, Vec3f& normal, Color8& color) const {
    const projection::FacePoint<double> fp = r.projection<double>().project(unit);
    const int layer = r.layerOf(fp.face);
    if (layer < 0) return false;
    const int last = mModel.texels - 1;
    const int a = std::clamp(int(std::lround(fp.uv.x * last)), 0, last);
    const int b = std::clamp(int(std::lround(fp.uv.y * last)), 0, last);
    constexpr int kRadius = 2;
    int best = std::numeric_limits<int>::max(), bestA = -1, bestB = -1;
    for (int y = std::max(0, b - kRadius); y <= std::min(last, b + kRadius); ++y)
      for (int x = std::max(0, a - kRadius); x <= std::min(last, a + kRadius); ++x) {
        const int d2 = (x - a) * (x - a) + (y - b) * (y - b);
        if (d2 < best && mModel.distanceCodec.hasSurface(mModel.distanceCode(layer, x, y))) best = d2, bestA = x, bestB = y;
      }
    if (bestA < 0) return false;
    if (mModel.normalFormat != NormalFormat::None) normal = mModel.normal(layer, bestA, bestB);
    if (mModel.colorFormat == ColorFormat::Rgba8)
      for (int k = 0; k < 4; ++k) color[k] = mModel.colors.at(bestA, bestB, layer, k);
    return true;
  }

  const ReliefModel& mModel;
};

/// The zero crossing on lattice edge (in, out) at fraction t, moved along its projection line onto
/// the surface the maps store, when the move is under one and a half lattice spacings. The
/// crossing of the interpolated field is within a fraction of a spacing of the surface; the
/// snapped vertex is on it, as the per-face method's vertices are. An edge in a face shared by
/// several grey cells moves to the mean of their surface points (each cell stands for the
/// surface there); cells that hold the edge compute it up to rounding, and welding keeps one.
inline std::optional<Vec3d> snapToSurface(const ReliefModel& model, const CellField& field, const CellNeighbourhood& n,
                                          const Vec3i& in, const Vec3i& out, double t) {
  const int m = field.cubes();
  const HoldingCells holding(in + out, 2 * m);  // the edge's midpoint, in half spacings
  Vec3d sum(0);
  int count = 0;
  for (int z = holding.lo.z; z <= holding.hi.z; ++z)
    for (int y = holding.lo.y; y <= holding.hi.y; ++y)
      for (int x = holding.lo.x; x <= holding.hi.x; ++x) {
        const Vec3i d(x, y, z);
        const int c = n.at(d);
        if (c < 0) continue;
        const CellRecord& r = model.cells[std::size_t(c)];
        const auto proj = r.projection<double>();
        // The crossing in the cell's unit coordinates, from global lattice coordinates.
        const Vec3d unit = (Vec3d(in) + t * Vec3d(out - in)) / double(m) - Vec3d(d);
        const projection::FacePoint<double> fp = proj.project(glm::clamp(unit, Vec3d(0), Vec3d(1)));
        const int layer = r.layerOf(fp.face);
        if (layer < 0) continue;
        const std::optional<double> stored = field.smoothDistance(layer, fp.uv);
        if (!stored) continue;
        const Vec3d onSurface = proj.unproject(fp.face, fp.uv, *stored);
        if (glm::length(onSurface - unit) > kMaxSnapSpacings / m) continue;
        sum += model.toWorld(n.ijk + d, onSurface);
        ++count;
      }
  if (count == 0) return std::nullopt;
  return sum / double(count);
}

/// Polygonizes the cubes of the cell at the centre of n, whose lattice values are `block` of
/// `lattice`.
inline void polygonizeCell(const ReliefModel& model, const CellField& field, const SignalLookup& signals,
                           const CellNeighbourhood& n, const LatticeBlocks& lattice, std::size_t block,
                           std::unordered_map<std::uint64_t, std::uint32_t>& vertexOf, ClosedPart& part) {
  const int m = field.cubes();
  const float* values = lattice.block(block);
  vertexOf.clear();
  const Vec3i base = n.ijk * m;  // the cell's first lattice point, globally
  const double spacing = model.cellSizeWS / m;
  auto vertex = [&](const Vec3i& cube, const CubeEdge& e) -> std::uint32_t {
    const Vec3i in = cube + cubeCorner(e.inside), out = cube + cubeCorner(e.outside);
    const std::uint64_t key = latticeEdgeKey(base + cube, e.inside, e.outside);
    const auto [it, inserted] = vertexOf.try_emplace(key, std::uint32_t(part.positions.size()));
    if (!inserted) return it->second;
    const float t = zeroCrossing(values[lattice.offset(in)], values[lattice.offset(out)]);
    part.keys.push_back(key);
    const std::optional<Vec3d> onSurface = snapToSurface(model, field, n, in, out, double(t));
    if (onSurface) {
      part.positions.push_back(Vec3f(*onSurface));
    } else {
      // From the global lattice coordinates of both ends, so every cell computes the same bits.
      const Vec3d inWS = model.originWS + Vec3d(base + in) * spacing, outWS = model.originWS + Vec3d(base + out) * spacing;
      part.positions.push_back(Vec3f(inWS + double(t) * (outWS - inWS)));
    }
    Vec3f normal(0);
    Color8 color{200, 200, 200, 255};
    bool found = false;
    if (signals.wanted())
      found = signals.find(field, n, Vec3d(in) + double(t) * Vec3d(out - in), {in, out}, normal, color);
    part.normals.push_back(normal);
    part.colors.push_back(color);
    part.hasSignal.push_back(found ? 1 : 0);
    return it->second;
  };
  for (int c = 0; c < m; ++c)
    for (int b = 0; b < m; ++b)
      for (int a = 0; a < m; ++a) {
        std::array<float, 8> corner;
        for (int k = 0; k < 8; ++k) {
          const Vec3i p = Vec3i(a, b, c) + cubeCorner(k);
          corner[std::size_t(k)] = values[lattice.offset(p)];
        }
        const CubeTriangles& cubeTriangles = kMarchingTetrahedraTable[std::size_t(insideMask(corner))];
        const Vec3i cube(a, b, c);
        for (int t = 0; t < cubeTriangles.count; ++t) {
          const auto& tri = cubeTriangles.triangles[std::size_t(t)];
          part.triangles.emplace_back(vertex(cube, tri[0]), vertex(cube, tri[1]), vertex(cube, tri[2]));
        }
      }
}

/// Removes the closed components that fit in a box of `maxExtent` per side: speckles around one
/// or two lattice points whose field's sign disagrees with all their neighbours (where a cell's
/// projection lines misread the side past an occluded sheet, or two cells disagree), a size no
/// part of the input can be represented at. Keeps the largest component whatever its size.
inline void dropSpeckles(TriangleMesh& mesh, double maxExtent) {
  UnionFind sets(mesh.positions.size());
  for (const Vec3u& t : mesh.triangles) {
    sets.unite(t[0], t[1]);
    sets.unite(t[0], t[2]);
  }
  std::unordered_map<std::uint32_t, Aabb<double>> bounds;
  std::unordered_map<std::uint32_t, std::size_t> size;
  for (const Vec3u& t : mesh.triangles) {
    const std::uint32_t root = sets.find(t[0]);
    ++size[root];
    Aabb<double>& box = bounds[root];
    for (int k = 0; k < 3; ++k) box.extend(Vec3d(mesh.positions[t[k]]));
  }
  std::uint32_t largest = 0;
  std::size_t largestSize = 0;
  for (const auto& [root, count] : size)
    if (count > largestSize) largest = root, largestSize = count;
  auto speckle = [&](std::uint32_t root) {
    const Vec3d extent = bounds[root].max - bounds[root].min;
    return root != largest && std::max({extent.x, extent.y, extent.z}) <= maxExtent;
  };
  std::erase_if(mesh.triangles, [&](const Vec3u& t) { return speckle(sets.find(t[0])); });
  // Renumber the vertices the remaining triangles use, so no unreferenced vertex is written.
  std::vector<std::uint32_t> newIndex(mesh.positions.size(), ~0u);
  std::uint32_t next = 0;
  for (Vec3u& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      if (newIndex[t[k]] == ~0u) newIndex[t[k]] = next++;
      t[k] = newIndex[t[k]];
    }
  auto compact = [&](auto& values) {
    if (values.empty()) return;
    std::remove_reference_t<decltype(values)> kept(next);
    for (std::size_t v = 0; v < newIndex.size(); ++v)
      if (newIndex[v] != ~0u) kept[newIndex[v]] = values[v];
    values.swap(kept);
  };
  compact(mesh.positions);
  compact(mesh.normals);
  compact(mesh.colors);
}

/// Joins the cells' parts into one mesh, welding vertices by lattice edge key.
inline TriangleMesh weldParts(const ReliefModel& model, const std::vector<ClosedPart>& parts) {
  struct Entry {
    std::uint64_t key;
    std::uint32_t part, local;
  };
  std::vector<Entry> entries;
  for (std::uint32_t p = 0; p < parts.size(); ++p)
    for (std::uint32_t v = 0; v < parts[p].keys.size(); ++v) entries.push_back({parts[p].keys[v], p, v});
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.key != b.key ? a.key < b.key : a.part < b.part;
  });
  std::vector<std::vector<std::uint32_t>> globalOf(parts.size());
  for (std::size_t p = 0; p < parts.size(); ++p) globalOf[p].resize(parts[p].keys.size());
  TriangleMesh mesh;
  const bool normals = model.normalFormat != NormalFormat::None, colors = model.colorFormat == ColorFormat::Rgba8;
  std::vector<char> hasSignal;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const Entry& e = entries[i];
    if (i == 0 || e.key != entries[i - 1].key) {
      const ClosedPart& part = parts[e.part];
      mesh.positions.push_back(part.positions[e.local]);
      if (normals) mesh.normals.push_back(part.normals[e.local]);
      if (colors) mesh.colors.push_back(part.colors[e.local]);
      hasSignal.push_back(part.hasSignal[e.local]);
    } else if (!hasSignal.back() && parts[e.part].hasSignal[e.local]) {
      // Another cell holding the same edge found a sample.
      const ClosedPart& part = parts[e.part];
      if (normals) mesh.normals.back() = part.normals[e.local];
      if (colors) mesh.colors.back() = part.colors[e.local];
      hasSignal.back() = 1;
    }
    globalOf[e.part][e.local] = std::uint32_t(mesh.positions.size() - 1);
  }
  for (std::size_t p = 0; p < parts.size(); ++p)
    for (const Vec3u& t : parts[p].triangles)
      mesh.triangles.emplace_back(globalOf[p][t.x], globalOf[p][t.y], globalOf[p][t.z]);
  // Vertices no map sample reached are shaded from the surface itself.
  if (normals) {
    const std::vector<Vec3f> geometric = computeVertexNormals(mesh);
    for (std::size_t v = 0; v < mesh.normals.size(); ++v)
      if (!hasSignal[v]) mesh.normals[v] = geometric[v];
  }
  return mesh;
}

}  // namespace detail

/// Refuses lattices the edge keys cannot address (2^20 points a side) or larger than
/// kMaxLatticeCubes cubes over the cells polygonized (about 2^28: tens of seconds, a gigabyte of
/// lattice values and more of triangles); a coarser level of detail or the per-face method serves
/// such models.
inline constexpr double kMaxLatticeCubes = double(1u << 28);
inline void checkLatticeSize(const ReliefModel& model, int cubes, std::size_t cells) {
  const double total = double(cells) * double(cubes) * double(cubes) * double(cubes);
  if (double(model.gridSize) * cubes >= double(1u << 20) || total > kMaxLatticeCubes)
    throw Error(ErrorKind::ResourceLimit,
                "the closed reconstruction's lattice (" + std::to_string(cells) + " cells of " +
                    std::to_string(cubes) + "^3 cubes) is too large; use a coarser level of detail "
                    "or the per-face method");
}

/// The closed reconstruction at level of detail `lod` (every 2^lod-th sample; the caller checks
/// the range). See the file comment.
inline TriangleMesh reconstructClosed(const ReliefModel& model, int lod = 0) {
  checkLevelOfDetail(model, lod);
  constexpr double kSpeckleSpacings = 3.0;  // lattice spacings: see dropSpeckles
  const detail::CellColors colors(model);
  const detail::CellField field(model, 1 << lod);
  const detail::SignalLookup signals(model);
  // The grey cells and the white and black cells around them, where the surface can close.
  std::vector<Vec3i> cells;
  cells.reserve(model.cells.size());
  for (const CellRecord& r : model.cells) cells.push_back(r.ijk());
  const std::vector<Vec3i> shell = colors.shell();
  cells.insert(cells.end(), shell.begin(), shell.end());
  checkLatticeSize(model, field.cubes(), cells.size());
  detail::LatticeBlocks lattice(std::move(cells), field.cubes(), model.gridSize);
  detail::sampleLattice(field, colors, lattice);
  lattice.findUniformBlocks();
  detail::removeSinglePointHandles(lattice, model.gridSize, float(field.emptyMagnitude()));
  std::vector<detail::ClosedPart> parts(lattice.blockCount());
  parallelForRange(0, lattice.blockCount(), [&](std::size_t begin, std::size_t end) {
    std::unordered_map<std::uint64_t, std::uint32_t> vertexOf;
    for (std::size_t i = begin; i < end; ++i)
      if (!lattice.uniform(i))  // all on one side: no surface
          detail::polygonizeCell(model, field, signals, colors.neighbourhood(lattice.cell(i)), lattice,
                               i, vertexOf, parts[i]);
  }, 1);
  TriangleMesh mesh = detail::weldParts(model, parts);
  detail::dropSpeckles(mesh, kSpeckleSpacings * model.cellSizeWS / field.cubes());
  mesh.sourcePolygons = mesh.triangles.size();
  return mesh;
}

}  // namespace cellrelief::relief
