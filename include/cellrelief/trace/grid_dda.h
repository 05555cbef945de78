// SPDX-License-Identifier: MIT
/// @file grid_dda.h
/// A ray's walk through the cells of an N^3 grid, cell by cell in the order the ray meets them
/// (Amanatides & Woo 1987), in the manner of OpenVDB's math::DDA: the relief tracer's walk from
/// grey cell to grey cell. The GLSL traversal (relief_trace.comp, advanceCell) mirrors it step for
/// step, so that the GPU backends visit the same cells.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "cellrelief/core/math.h"
#include "cellrelief/core/ray.h"

namespace cellrelief::trace {

template <Real T>
class GridDda {
 public:
  /// Starts in the cell that holds the ray's point at tStart (clamped into the grid: rounding may
  /// put an entry point just outside it) and walks until tEnd. The grid's cells are `cellSize`
  /// wide from `origin`, n a side.
  GridDda(const Ray<T>& ray, const Vec3<T>& origin, T cellSize, int n, T tStart, T tEnd)
      : mN(n), mTEntry(tStart), mTEnd(tEnd) {
    const Vec3<T> entry = (ray.at(tStart) - origin) / cellSize;
    mCell = glm::clamp(Vec3i(glm::floor(entry)), Vec3i(0), Vec3i(n - 1));
    for (int a = 0; a < 3; ++a) {
      // The inverse is computed here, not taken from the ray: a denormal component overflows it
      // (0 * inf would stall the walk), and such an axis is as good as a zero one.
      const T d = ray.direction[a], inverse = T(1) / d;
      if (d == 0 || !std::isfinite(inverse)) continue;
      mStep[a] = d > 0 ? 1 : -1;
      const T boundary = T(mCell[a] + (d > 0 ? 1 : 0)) * cellSize + origin[a];
      mTMax[a] = (boundary - ray.origin[a]) * inverse;
      mTDelta[a] = std::abs(cellSize * inverse);
    }
  }

  /// The cell the ray is in.
  const Vec3i& cell() const { return mCell; }
  /// Where the ray entered the cell (tStart for the first).
  T tEntry() const { return mTEntry; }
  /// Where it leaves the cell, or tEnd if sooner.
  T tExit() const { return std::min({mTMax.x, mTMax.y, mTMax.z, mTEnd}); }
  /// Steps into the next cell; false when the walk has passed tEnd or left the grid.
  bool next() {
    if (tExit() >= mTEnd) return false;
    const int axis = mTMax.x < mTMax.y ? (mTMax.x < mTMax.z ? 0 : 2) : (mTMax.y < mTMax.z ? 1 : 2);
    mCell[axis] += mStep[axis];
    if (mCell[axis] < 0 || mCell[axis] >= mN) return false;
    mTEntry = mTMax[axis];
    mTMax[axis] += mTDelta[axis];
    return true;
  }

 private:
  int mN;
  Vec3i mCell{0};
  Vec3i mStep{0};
  Vec3<T> mTMax{std::numeric_limits<T>::infinity()};
  Vec3<T> mTDelta{std::numeric_limits<T>::infinity()};
  T mTEntry, mTEnd;
};

}  // namespace cellrelief::trace
