// SPDX-License-Identifier: MIT
/// @file cell_complex.h
/// The cubic cell complex of a mesh over an OpenVDB grid (Apaza & Andujar, 3.1).
///
/// The mesh's bounding cube (grown by half a cell and shifted where a triangle would lie in a plane
/// that projection lines end in: ComplexOptions::offProjectionPlanes) is split into N^3 cells:
/// grey cells meet the surface (exactly: see triangle_box.h), white cells are outside, black cells
/// inside. Only grey cells are active voxels
/// of the OpenVDB grid (their value indexes the GreyCell array); black cells are inactive voxels of
/// value kBlack, pruned into tiles, and white is the background, so empty and solid space cost
/// tiles only. Construction uses a dense byte per cell as scratch (N^3 bytes), freed afterwards.
///
/// Inside and outside: non-grey cells fall into 6-connected components that the surface does not
/// cross. Components that touch the grid boundary are white. Each other component is black when
/// the generalized winding number at one of its cell centres exceeds 1/2 in magnitude (orientation
/// does not matter), else white. For a closed mesh this is exact: a component is entirely inside or
/// outside, and the winding number there is an integer. Degradation, by design and tested:
/// - an open mesh whose holes are narrower than a cell is sealed by its grey cells and behaves as
///   closed;
/// - an open mesh whose holes are wider than a cell leaks: its inside connects to the boundary and
///   is white (the grey cells still cover the whole surface);
/// - self-intersecting or overlapping shells count as inside where the winding number is >= 1;
/// - non-manifold parts change nothing: classification never uses topology.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <openvdb/tools/Prune.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_sort.h>

#include "cellrelief/cells/configuration.h"
#include "cellrelief/cells/openvdb_grids.h"
#include "cellrelief/cells/triangle_box.h"
#include "cellrelief/cells/winding_number.h"
#include "cellrelief/core/aabb.h"
#include "cellrelief/core/error.h"
#include "cellrelief/core/parallel.h"
#include "cellrelief/core/triangle_mesh.h"

namespace cellrelief::cells {

enum class CellColor : std::uint8_t { White = 0, Black = 1, Grey = 2 };

/// Values of the OpenVDB grid: grey cells hold their index (>= 0).
inline constexpr std::int32_t kWhite = -1;
inline constexpr std::int32_t kBlack = -2;

struct ComplexOptions {
  int gridSize = 32;                             ///< N: cells per side of the bounding cube
  std::size_t memoryLimitBytes = std::size_t(4) << 30;  ///< refuse a build estimated above this
  /// Place the lattice so that no plane holding a whole triangle is one where projection lines end
  /// or run (see detail::placeGrid): what relief maps need. Off, the lattice is the bounding cube.
  bool offProjectionPlanes = true;
};

struct GreyCell {
  Vec3i ijk{0};                     ///< index-space coordinates of the cell
  std::uint8_t configuration = 0;   ///< bit f set: face f is external (shared with white)
  BaseCase baseCase = BaseCase::k0;
  std::uint8_t rotation = 0;        ///< index into kRotations: canonical(baseCase) -> configuration
  std::uint32_t firstTriangle = 0;  ///< range in CellComplex::cellTriangleIndices()
  std::uint32_t triangleCount = 0;

  bool border() const { return configuration != 0; }  ///< BG (true) or IG (false)
  std::uint8_t domainFaces() const { return domainFacesOf(configuration); }
};

/// Counts and timing of a build, for reports.
struct ComplexStats {
  std::size_t white = 0, black = 0, grey = 0, borderGrey = 0, interiorGrey = 0;
  std::array<std::size_t, kBaseCaseCount> perCase{};
  std::size_t cellTrianglePairs = 0;
  std::size_t enclosedComponents = 0;  ///< non-grey components away from the boundary
  double seconds = 0;
};

class CellComplex {
 public:
  using Grid = openvdb::Int32Grid;

  /// Builds the complex. Throws Error: InvalidArgument (N out of range), InvalidInput (empty mesh,
  /// non-finite coordinates, zero extent), ResourceLimit (estimated memory over the limit).
  static CellComplex build(const TriangleMesh& mesh, const ComplexOptions& options = {});

  /// Bytes a build of `triangles` triangles at grid size n needs at its peak (an estimate).
  static std::size_t estimateMemory(std::size_t triangles, int n) {
    const std::size_t cells = std::size_t(n) * n * n;
    // Dense labels and the flood-fill queue, the triangle keys and lists (a triangle meets about
    // 1 + its size in cells), fixed overhead.
    return cells * 5 + triangles * (48 + 12 * 2) + (std::size_t(16) << 20);
  }

  int gridSize() const { return mGridSize; }
  const Aabbd& boundsWS() const { return mBoundsWS; }
  double cellSizeWS() const { return mCellSizeWS; }
  Vec3d cellMinWS(const Vec3i& ijk) const { return mBoundsWS.min + Vec3d(ijk) * mCellSizeWS; }
  Aabbd cellBoxWS(const Vec3i& ijk) const {
    return {cellMinWS(ijk), cellMinWS(ijk) + Vec3d(mCellSizeWS)};
  }
  /// World point to continuous index space, where cell ijk spans [ijk, ijk + 1].
  Vec3d worldToIndex(const Vec3d& pWS) const { return (pWS - mBoundsWS.min) / mCellSizeWS; }
  Vec3d indexToWorld(const Vec3d& pIS) const { return mBoundsWS.min + pIS * mCellSizeWS; }

  /// The sparse grid: voxel ijk is cell ijk (grey: its index into greyCells(), active; black:
  /// inactive tiles; white: the background). Its transform places voxel centres in world space
  /// when hasWorldTransform(cellSizeWS()); OpenVDB cannot hold smaller cells, and then the
  /// transform is the identity and indexToWorld() is the placement.
  const Grid& grid() const { return *mGrid; }
  /// Whether OpenVDB's linear transform can hold this cell size (its ScaleMap takes a voxel
  /// volume under 3e-15 for zero).
  static bool hasWorldTransform(double cellSizeWS) { return cellSizeWS * cellSizeWS * cellSizeWS > 1e-14; }
  std::span<const GreyCell> greyCells() const { return mGreyCells; }
  /// Triangles meeting a grey cell (indices into the mesh).
  std::span<const std::uint32_t> cellTriangles(const GreyCell& cell) const {
    return std::span<const std::uint32_t>(mCellTriangles).subspan(cell.firstTriangle,
                                                                   cell.triangleCount);
  }
  std::span<const std::uint32_t> cellTriangleIndices() const { return mCellTriangles; }
  /// Snapped vertex positions in index space (what classification decided on), as doubles.
  std::span<const Vec3d> snappedPositionsIS() const { return mSnappedIS; }

  CellColor color(const Vec3i& ijk) const {
    const std::int32_t v = mGrid->tree().getValue(openvdb::Coord(ijk.x, ijk.y, ijk.z));
    return v >= 0 ? CellColor::Grey : (v == kBlack ? CellColor::Black : CellColor::White);
  }
  /// Index of the grey cell at ijk, or -1.
  std::int32_t greyIndex(const Vec3i& ijk) const {
    const std::int32_t v = mGrid->tree().getValue(openvdb::Coord(ijk.x, ijk.y, ijk.z));
    return v >= 0 ? v : -1;
  }
  const ComplexStats& stats() const { return mStats; }

 private:
  int mGridSize = 0;
  Aabbd mBoundsWS;
  double mCellSizeWS = 0;
  Grid::Ptr mGrid;
  std::vector<GreyCell> mGreyCells;
  std::vector<std::uint32_t> mCellTriangles;
  std::vector<Vec3d> mSnappedIS;
  ComplexStats mStats;
};

}  // namespace cellrelief::cells

#include "cellrelief/cells/cell_complex.ipp"
