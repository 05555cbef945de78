// SPDX-License-Identifier: MIT
/// @file surface_samples.h
/// Deterministic area-uniform samples of the surface inside one cell, in the cell's unit
/// coordinates. Used to estimate occlusion and the surface centroid of a cell. Samples follow the
/// R2 low-discrepancy sequence folded into each triangle, so estimates are repeatable and converge
/// faster than random sampling.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "cellrelief/cells/cell_complex.h"
#include "cellrelief/core/low_discrepancy.h"
#include "cellrelief/core/math.h"

namespace cellrelief::relief {

struct SurfaceSample {
  Vec3d p;                 ///< unit-cell coordinates, inside the closed cell
  double weight;           ///< surface area it stands for, in cell units squared
  std::uint32_t triangle;  ///< the mesh triangle it lies on
};

/// Appends samples of the triangles meeting `cell`: `density` samples per unit of area (in cell
/// units) in expectation, at most `maxPerTriangle` per triangle, each standing for 1 / density of
/// area. A triangle smaller than one sample's share gets one with probability area x density (a
/// fixed hash of the triangle decides), so meshes much finer than the sampling cost no more than
/// coarse ones. Samples falling outside the closed cell are dropped (other cells sample them).
inline void sampleCellSurface(const cells::CellComplex& complex, std::span<const Vec3u> triangles,
                              const cells::GreyCell& cell, double density, int maxPerTriangle,
                              std::vector<SurfaceSample>& out) {
  const std::span<const Vec3d> positions = complex.snappedPositionsIS();
  const Vec3d origin(cell.ijk);
  for (const std::uint32_t t : complex.cellTriangles(cell)) {
    const Vec3u& tri = triangles[t];
    const Vec3d a = positions[tri[0]] - origin, b = positions[tri[1]] - origin,
                c = positions[tri[2]] - origin;
    const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
    const double expected = area * density;
    const double jitter = r2Point(t).x;  // a fixed hash of the triangle in [0, 1)
    const int k = int(std::min(std::floor(expected + jitter), double(maxPerTriangle)));
    if (k <= 0) continue;
    const double weight = expected > maxPerTriangle ? area / k : 1.0 / density;
    for (int i = 0; i < k; ++i) {
      const Vec3d p = pointInTriangle(a, b, c, r2Point(std::size_t(i) + 1));
      if (p.x < 0 || p.y < 0 || p.z < 0 || p.x > 1 || p.y > 1 || p.z > 1) continue;
      out.push_back({p, weight, t});
    }
  }
}

/// Area-weighted centroid of samples (the cell centre when there are none).
inline Vec3d sampleCentroid(std::span<const SurfaceSample> samples) {
  Vec3d sum(0);
  double w = 0;
  for (const SurfaceSample& s : samples) {
    sum += s.weight * s.p;
    w += s.weight;
  }
  return w > 0 ? sum / w : Vec3d(0.5);
}

}  // namespace cellrelief::relief
